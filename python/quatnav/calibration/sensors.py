"""Sensor calibration: magnetometer ellipsoid fit, accelerometer multi-pose fit, gyroscope bias
and scale from rest and known rotations.

Every model is ``calibrated = matrix @ (raw - offset)`` per sample (rows of ``(N, 3)`` arrays),
in the sensor's own unit; see ``docs/CALIBRATION.md``.
"""
from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["SensorCalibration", "magnetometer", "accelerometer", "gyroscope", "rest_segments",
           "sphere_coverage", "STANDARD_GRAVITY"]

STANDARD_GRAVITY = 9.80665  #: m/s^2

#: coverage (fraction of equal-area sphere cells holding a direction) below which
#: :func:`magnetometer` warns; a full hand rotation reaches 0.7-0.9, a yaw-only sweep about 0.2.
MIN_COVERAGE = 0.35
#: Below this coverage around the fitted centre no magnetometer model is determined (a 20 deg cap
#: or less): magnetometer() refuses the samples.
MIN_DETERMINED_COVERAGE = 0.03


@dataclass
class SensorCalibration:
    """One sensor's calibration: ``calibrated = matrix @ (raw - offset)``.

    Attributes
    ----------
    sensor : str
        ``"mag"``, ``"acc"`` or ``"gyro"``.
    model : str
        The fitted model.
    offset : ndarray, shape (3,)
        Bias / hard-iron offset, in the raw unit.
    matrix : ndarray, shape (3, 3)
        Scale, misalignment and soft-iron correction (dimensionless).
    residual : float
        RMS residual of the fit, in the calibrated unit (mag, acc: of the magnitude; gyro: of the
        known rotations, rad).
    info : dict
        Model-specific figures (``field_strength``, ``coverage``, poses used and rejected, ...).
    """

    sensor: str
    model: str
    offset: np.ndarray
    matrix: np.ndarray
    residual: float = float("nan")
    info: dict = field(default_factory=dict)

    def apply(self, x: ArrayLike) -> np.ndarray:
        """Calibrated samples ``(raw - offset) @ matrix.T`` of ``x`` (shape (N, 3) or (3,))."""
        x = np.asarray(x, float)
        return (x - self.offset) @ self.matrix.T

    @property
    def field_strength(self):
        return self.info.get("field_strength")

    @property
    def coverage(self):
        return self.info.get("coverage")

    def to_dict(self) -> dict:
        d = {"model": self.model, "offset": [float(v) for v in self.offset],
             "matrix": [[float(v) for v in row] for row in self.matrix],
             "residual": float(self.residual)}
        for k, v in self.info.items():
            if k == "rejected":  # list of {"pose", "std"}: two arrays in the file
                d["rejected_poses"] = [int(r["pose"]) for r in v]
                d["rejected_std"] = [float(r["std"]) for r in v]
            elif isinstance(v, (int, float, str, bool, np.floating, np.integer)):
                d[k] = v.item() if isinstance(v, np.generic) else v
            elif isinstance(v, (list, tuple, np.ndarray)):
                d[k] = np.asarray(v).tolist()
        return d

    @classmethod
    def from_dict(cls, sensor: str, d: dict) -> "SensorCalibration":
        try:
            offset = np.asarray(d.get("offset", [0.0, 0.0, 0.0]), float).reshape(3)
            matrix = np.asarray(d.get("matrix", np.eye(3)), float).reshape(3, 3)
        except ValueError:
            raise ValueError(f"[{sensor}]: offset must have 3 numbers and matrix 3 rows of 3") from None
        if not (np.isfinite(offset).all() and np.isfinite(matrix).all()):
            raise ValueError(f"[{sensor}]: offset and matrix must be finite")
        info = {k: v for k, v in d.items() if k not in ("model", "offset", "matrix", "residual")}
        return cls(sensor, str(d.get("model", "full")), offset, matrix,
                   float(d.get("residual", float("nan"))), info)

    def __repr__(self):
        return (f"SensorCalibration({self.sensor}, model={self.model!r}, offset={np.round(self.offset, 6).tolist()}, "
                f"residual={self.residual:.3g})")


def _as_n3(x, name, min_rows=1):
    a = np.asarray(x, float)
    if a.ndim != 2 or a.shape[1] != 3:
        raise ValueError(f"{name} must have shape (N, 3), got {a.shape}")
    if a.shape[0] < min_rows:
        raise ValueError(f"{name} needs at least {min_rows} samples, got {a.shape[0]}")
    bad = np.flatnonzero(~np.isfinite(a).all(axis=1))
    if len(bad):
        raise ValueError(f"{name}: row {bad[0]} is not finite ({a[bad[0]].tolist()})")
    return a


def _fibonacci_sphere(n):
    i = np.arange(n) + 0.5
    z = 1.0 - 2.0 * i / n
    r = np.sqrt(1.0 - z * z)
    phi = np.pi * (3.0 - np.sqrt(5.0)) * i
    return np.column_stack([r * np.cos(phi), r * np.sin(phi), z])


def sphere_coverage(directions: ArrayLike, cells: int = 100, min_count: int = 1) -> float:
    """Fraction of ``cells`` near-equal-area cells of the unit sphere (Voronoi cells of a
    Fibonacci lattice) that hold at least ``min_count`` of ``directions`` ((N, 3), any norm)."""
    d = np.asarray(directions, float)
    d = d / np.linalg.norm(d, axis=1, keepdims=True)
    c = _fibonacci_sphere(cells)
    idx = np.argmax(d @ c.T, axis=1)
    counts = np.bincount(idx, minlength=cells)
    return float(np.mean(counts >= min_count))


# ----------------------------------------------------------------------------------------------
# magnetometer
# ----------------------------------------------------------------------------------------------
_MAG_MODELS = ("offset", "diagonal", "full")


def _algebraic_fit(x, model):
    """Linear least-squares ellipsoid: returns (offset, W) with |W (x - offset)| ~ 1."""
    xc = x.mean(axis=0)
    s = np.abs(x - xc).max() or 1.0
    y = (x - xc) / s  # conditioning
    X, Y, Z = y.T
    if model == "offset":
        # |y|^2 = 2 y.b + c
        A = np.column_stack([2 * X, 2 * Y, 2 * Z, np.ones_like(X)])
        sol = np.linalg.lstsq(A, (y * y).sum(axis=1), rcond=None)[0]
        b = sol[:3]
        r2 = sol[3] + b @ b
        M = np.eye(3) / max(r2, 1e-12)
    else:
        if model == "diagonal":
            A = np.column_stack([X * X, Y * Y, Z * Z, X, Y, Z])
        else:
            A = np.column_stack([X * X, Y * Y, Z * Z, 2 * X * Y, 2 * X * Z, 2 * Y * Z, X, Y, Z])
        sol = np.linalg.lstsq(A, np.ones_like(X), rcond=None)[0]
        if model == "diagonal":
            Q = np.diag(sol[:3])
            u = sol[3:6]
        else:
            a, bb, c, d, e, f = sol[:6]
            Q = np.array([[a, d, e], [d, bb, f], [e, f, c]])
            u = sol[6:9]
        try:
            b = -0.5 * np.linalg.solve(Q, u)
        except np.linalg.LinAlgError:
            b = np.zeros(3)
        k = 1.0 + b @ Q @ b
        M = Q / k
    w, V = np.linalg.eigh(0.5 * (M + M.T))
    if np.any(w <= 0):  # not an ellipsoid (poor coverage): fall back to a sphere
        return _algebraic_fit(x, "offset") if model != "offset" else (xc, np.eye(3) / s)
    W = V @ np.diag(np.sqrt(w)) @ V.T
    return xc + s * b, W / s


def _trimmed_algebraic_fit(x, model, iterations=4, k=4.0):
    """The algebraic fit, refitted on the samples whose radial residual is within ``k`` robust
    sigmas (gross outliers pull a linear fit far more than a robust loss can undo). The first
    passes fit a sphere (4 unknowns, hard to mislead), the later ones the model."""
    keep = np.ones(len(x), bool)
    for it in range(2 * iterations):
        b, W = _algebraic_fit(x[keep], "offset" if it < iterations else model)
        r = np.linalg.norm((x - b) @ W.T, axis=1) - 1.0
        med = np.median(r[keep])
        sig = 1.4826 * np.median(np.abs(r[keep] - med))
        new = np.abs(r - med) <= max(k * sig, 1e-9)
        if new.sum() < 12:
            break
        keep = new
    return b, W


def _pack(model, W):
    if model == "offset":
        return np.array([np.cbrt(np.linalg.det(W))])
    if model == "diagonal":
        return np.diag(W).copy()
    iu = np.triu_indices(3)
    return W[iu].copy()


def _unpack(model, p):
    if model == "offset":
        return np.eye(3) * p[0]
    if model == "diagonal":
        return np.diag(p)
    W = np.zeros((3, 3))
    iu = np.triu_indices(3)
    W[iu] = p
    return W + np.triu(W, 1).T


def magnetometer(mag: ArrayLike, model: str = "full", robust: bool = True,
                 coverage_min: float = MIN_COVERAGE) -> SensorCalibration:
    """Fit a magnetometer calibration from samples taken while rotating the sensor.

    The samples of a constant field under rotation lie on an ellipsoid
    ``|matrix (raw - offset)| = field_strength``. An algebraic linear least-squares fit of the
    quadric gives a first estimate; a robust refinement (``scipy.optimize.least_squares`` with a
    soft-L1 loss on the radial residual ``|W (raw - offset)| - 1``, scaled by the residuals'
    MAD) then removes the pull of outliers (a magnet passing by, a spike).

    Parameters
    ----------
    mag : array_like, shape (N, 3)
        Raw magnetometer samples (any unit; the result is in that unit).
    model : {"offset", "diagonal", "full"}
        ``offset``: hard iron only (sphere, 4 unknowns); ``diagonal``: plus a scale per axis (6);
        ``full``: plus a symmetric soft-iron matrix (9).
    robust : bool
        Run the robust refinement (needs scipy); False: the algebraic fit only.
    coverage_min : float
        Below this coverage of the sphere of directions: a ``UserWarning``, and the
        ``diagonal``/``full`` models fall back to ``offset`` (a cap of directions determines the
        hard iron but not the soft iron; ``model`` of the result says what was fitted).

    Returns
    -------
    SensorCalibration
        ``offset`` (hard iron), ``matrix`` (symmetric soft-iron inverse, scaled to determinant 1
        so the field strength is kept on average), ``field_strength`` (the calibrated magnitude),
        ``residual`` (RMS of ``|calibrated| - field_strength``), ``coverage`` and ``outliers``
        (samples whose radial residual exceeds 5 robust sigmas) in ``info``.
    """
    if model not in _MAG_MODELS:
        raise ValueError(f"model must be one of {', '.join(_MAG_MODELS)}, got {model!r}")
    x = _as_n3(mag, "mag", min_rows={"offset": 4, "diagonal": 6, "full": 9}[model] * 3)
    b0, W0 = _trimmed_algebraic_fit(x, "offset")
    cov = sphere_coverage(x - b0)
    fitted = model
    if cov < coverage_min and model != "offset":
        # a cap of directions does not determine the soft iron (the quadric degenerates towards
        # a slab far away); the hard-iron offset alone stays well determined
        fitted = "offset"
        b, W = b0, W0
    else:
        b, W = _trimmed_algebraic_fit(x, model)
        if model != "offset" and sphere_coverage(x - b) < coverage_min:
            # around the fitted centre the samples may still be a cap (the offset fit can land
            # inside a small cluster and make it look covered): the same fall-back
            fitted = "offset"
            b, W = b0, W0
    if robust:
        from scipy.optimize import least_squares

        def res(p):
            return np.linalg.norm((x - p[:3]) @ _unpack(fitted, p[3:]).T, axis=1) - 1.0

        p0 = np.concatenate([b, _pack(fitted, W)])
        r0 = res(p0)
        mad = 1.4826 * np.median(np.abs(r0 - np.median(r0)))
        f_scale = max(2.0 * mad, 1e-6)
        sol = least_squares(res, p0, loss="soft_l1", f_scale=f_scale, x_scale="jac")
        b, W = sol.x[:3], _unpack(fitted, sol.x[3:])
    # scale: det(matrix) = 1, field strength = the calibrated magnitude
    det = np.linalg.det(W)
    if not det > 0:
        raise ValueError("mag: the fit did not converge to an ellipsoid (too few or degenerate samples)")
    g = np.cbrt(det)
    matrix = W / g
    cal = (x - b) @ matrix.T
    norm = np.linalg.norm(cal, axis=1)
    field_strength = 1.0 / g
    r = norm - field_strength
    sig = 1.4826 * np.median(np.abs(r - np.median(r)))
    outl = np.abs(r) > max(5 * sig, 1e-12 * field_strength)
    cov = sphere_coverage(cal)
    if cov < MIN_DETERMINED_COVERAGE:
        raise ValueError(f"mag: the samples cover {cov:.0%} of the directions around the fitted centre (fewer than "
                         f"{MIN_DETERMINED_COVERAGE:.0%}): no calibration is determined by them; rotate the sensor "
                         "through more orientations")
    info = {"field_strength": float(field_strength), "coverage": cov, "requested_model": model,
            "samples": int(len(x)), "outliers": int(outl.sum())}
    out = SensorCalibration("mag", fitted, b, matrix, float(np.sqrt(np.mean(r[~outl] ** 2))), info)
    if cov < coverage_min or fitted != model:
        warnings.warn(f"magnetometer calibration: the samples cover {cov:.0%} of the sphere of directions "
                      f"(less than {coverage_min:.0%}); rotate the sensor through more orientations; "
                      + (f"the {model} model is not determined by them: fitted the offset (hard iron) only."
                         if fitted != model else f"the {model} fit may be poorly determined."),
                      UserWarning, stacklevel=2)
    return out


# ----------------------------------------------------------------------------------------------
# rest detection
# ----------------------------------------------------------------------------------------------
def _moving_std(x, w):
    """Standard deviation over a centred window of w samples, per row (norm over columns)."""
    n = len(x)
    w = max(2, min(int(w), n))
    c1 = np.concatenate([np.zeros((1, x.shape[1])), np.cumsum(x, axis=0)])
    c2 = np.concatenate([np.zeros((1, x.shape[1])), np.cumsum(x * x, axis=0)])
    lo = np.clip(np.arange(n) - w // 2, 0, n - w)
    hi = lo + w
    m = (c1[hi] - c1[lo]) / w
    v = (c2[hi] - c2[lo]) / w - m * m
    return np.sqrt(np.maximum(v, 0.0).sum(axis=1))


def rest_segments(t: ArrayLike, acc: ArrayLike | None = None, gyr: ArrayLike | None = None, window_s: float = 0.5,
                  acc_std: float | None = 0.05, gyr_std: float | None = 0.02,
                  min_duration_s: float = 1.0) -> list[tuple[int, int]]:
    """Intervals where the sensor is at rest: windowed standard deviation (norm over the axes)
    of the accelerometer below ``acc_std`` (m/s^2) and of the gyroscope below ``gyr_std``
    (rad/s), for at least ``min_duration_s``.

    ``None`` scales a threshold to the sensor's own noise: 1.5 times the windowed deviation of
    the quietest 1 % of the log (at rest, the white noise), at least 0.05 m/s^2 / 0.02 rad/s and
    at most ten times that. A consumer IMU's accelerometer noise alone can exceed 0.05 m/s^2 (the
    BROAD IMU at rest: 0.086), so that a fixed threshold finds no rest in its log.

    Returns
    -------
    list of (start, stop) sample index pairs (stop exclusive), in time order.
    """
    t = np.asarray(t, float)
    n = len(t)
    if n < 2:
        return []
    dt = float(np.median(np.diff(t)))
    w = max(2, int(round(window_s / dt)))
    still = np.ones(n, bool)
    for x, th, base in ((acc, acc_std, 0.05), (gyr, gyr_std, 0.02)):
        if x is None:
            continue
        sd = _moving_std(np.asarray(x, float), w)
        if th is None:
            q = np.nanpercentile(sd, 1.0) if np.isfinite(sd).any() else base
            th = min(max(base, 1.5 * float(q)), 10.0 * base)
        still &= sd < th
    edges = np.flatnonzero(np.diff(np.concatenate([[0], still.astype(int), [0]])))
    segs = []
    for a, b in zip(edges[::2], edges[1::2]):
        # trim half a window at each end (the window straddles the motion there)
        a2, b2 = a + w // 2, b - w // 2
        if b2 > a2 and (t[b2 - 1] - t[a2]) >= min_duration_s - 1.5 * dt:
            segs.append((int(a2), int(b2)))
    return segs


# ----------------------------------------------------------------------------------------------
# accelerometer
# ----------------------------------------------------------------------------------------------
_ACC_MODELS = ("diagonal", "triangular", "six_position")


def _tri_unpack(p):
    T = np.zeros((3, 3))
    T[np.triu_indices(3)] = p
    return T


def accelerometer(poses: ArrayLike | None = None, *, acc: ArrayLike | None = None, t: ArrayLike | None = None,
                  gyr: ArrayLike | None = None, g: float = STANDARD_GRAVITY, model: str | None = None,
                  still_std: float | None = None, min_duration_s: float = 1.0) -> SensorCalibration:
    """Accelerometer bias, scale factors and misalignment from static poses.

    Give either ``poses`` (a list of (N_i, 3) arrays, one per static orientation) or a whole log
    ``acc`` with ``t`` (and ``gyr`` if available), from which the static poses are found by
    :func:`rest_segments` (its thresholds from the sensor's own noise, as ``quatnav allan
    --rest-only`` and :func:`gyroscope` find rest). A pose whose per-axis standard deviation
    exceeds ``still_std`` (m/s^2) is rejected (the sensor moved) and reported in
    ``info["rejected"]``; None: four times the median of the poses' own, at least 0.05 (a real
    IMU's noise is that already: BROAD's at rest, 0.05 per axis, was rejected by a fixed 0.05).

    Models (``calibrated = matrix @ (raw - offset)``):

    * ``diagonal``: bias and one scale per axis, 6 unknowns, at least 6 poses (six-position);
    * ``triangular``: bias and an upper-triangular matrix (scale and the three non-orthogonality
      angles; the body x axis is the sensor x axis, y in the sensor x-y plane), 9 unknowns, at
      least 9 poses in general orientations. Both fit ``|calibrated| = g`` robustly;
    * ``six_position``: the classic known-orientation method: each of the six poses has one axis
      along gravity, up or down; the reference specific force of a pose is ``+g`` or ``-g`` on that
      axis (the sign of the measured mean: at rest an FRD accelerometer reads ``-g`` on the axis
      pointing down), and a linear least-squares fit gives the full 3x3 matrix (scale,
      misalignment and the small mounting rotation relative to the fixture).

    Default: ``triangular`` with 9 or more accepted poses, else ``diagonal``.

    Returns
    -------
    SensorCalibration
        ``info``: ``poses`` (used), ``rejected`` (list of ``{"pose", "std"}``), ``g``.
    """
    if poses is None:
        if acc is None or t is None:
            raise ValueError("accelerometer: give poses, or acc and t to find the static poses")
        acc = _as_n3(acc, "acc", 2)
        segs = rest_segments(t, acc, gyr, acc_std=None if still_std is None else max(still_std * 2, 0.05),
                             gyr_std=None, min_duration_s=min_duration_s)
        poses = [acc[a:b] for a, b in segs]
    poses = [_as_n3(p, f"poses[{i}]", 1) for i, p in enumerate(poses)]
    stds = [float(p.std(axis=0).max()) if len(p) > 1 else 0.0 for p in poses]
    if still_std is None:
        still_std = max(0.05, 4.0 * float(np.median(stds))) if stds else 0.05
    means, rejected = [], []
    for i, p in enumerate(poses):
        s = stds[i]
        if s > still_std:
            rejected.append({"pose": i, "std": s})
        else:
            means.append(p.mean(axis=0))
    m = np.array(means).reshape(-1, 3)
    k = len(m)
    if model is None:
        model = "triangular" if k >= 9 else "diagonal"
    if model not in _ACC_MODELS:
        raise ValueError(f"model must be one of {', '.join(_ACC_MODELS)}, got {model!r}")
    need = {"diagonal": 6, "triangular": 9, "six_position": 6}[model]
    if k < need:
        raise ValueError(f"accelerometer: the {model} model needs at least {need} static poses, got {k}"
                         + (f" ({len(rejected)} rejected as moving: std above {still_std} m/s^2)" if rejected else ""))
    if model == "six_position":
        ref = np.zeros_like(m)
        ax = np.argmax(np.abs(m), axis=1)
        ref[np.arange(k), ax] = np.sign(m[np.arange(k), ax]) * g
        if len({(a, np.sign(m[i, a])) for i, a in enumerate(ax)}) < 6:
            raise ValueError("accelerometer: six_position needs each axis up and down once (6 distinct poses)")
        # raw = A ref + b  ->  [ref 1] [A^T; b^T] = raw
        X = np.column_stack([ref, np.ones(k)])
        sol = np.linalg.lstsq(X, m, rcond=None)[0]
        A, b = sol[:3].T, sol[3]
        matrix = np.linalg.inv(A)
    else:
        from scipy.optimize import least_squares
        if model == "diagonal":
            unpack = np.diag
            p0 = np.concatenate([np.zeros(3), np.ones(3)])
        else:
            unpack = _tri_unpack
            p0 = np.concatenate([np.zeros(3), np.eye(3)[np.triu_indices(3)]])

        def res(p):
            return np.linalg.norm((m - p[:3]) @ unpack(p[3:]).T, axis=1) / g - 1.0

        sol = least_squares(res, p0, x_scale="jac", xtol=1e-14, ftol=1e-14, gtol=1e-14)
        b, matrix = sol.x[:3], unpack(sol.x[3:])
    r = np.linalg.norm((m - b) @ matrix.T, axis=1) - g
    return SensorCalibration("acc", model, np.asarray(b, float), np.asarray(matrix, float),
                             float(np.sqrt(np.mean(r ** 2))), {"poses": k, "rejected": rejected, "g": float(g)})


# ----------------------------------------------------------------------------------------------
# gyroscope
# ----------------------------------------------------------------------------------------------
def gyroscope(gyr: ArrayLike, t: ArrayLike, *, acc: ArrayLike | None = None,
              rotations: Sequence[tuple[float, float, ArrayLike]] | None = None,
              rates: Sequence[tuple[float, float, ArrayLike]] | None = None,
              rest: tuple[float, float] | None = None, gyr_std: float | None = None, acc_std: float | None = None,
              min_duration_s: float = 1.0) -> SensorCalibration:
    """Gyroscope bias from rest, and scale/misalignment from known rotations.

    Parameters
    ----------
    gyr : array_like, shape (N, 3)
        Raw rates, rad/s.
    t : array_like, shape (N,)
        Times, s.
    acc : array_like, shape (N, 3), optional
        Accelerometer samples; the rest detection uses both when given.
    rotations : list of (t0, t1, angle_b), optional
        Known rotations about a fixed axis: the rotation vector (rad, body axes) turned between
        ``t0`` and ``t1`` (e.g. a turntable turned by a known angle). Three or more independent
        ones determine the full matrix, fewer only a scale per axis they excite.
    rates : list of (t0, t1, omega_b), optional
        Known constant rates (rad/s) between ``t0`` and ``t1`` (a turntable at a set rate); each is
        the rotation ``omega_b (t1 - t0)``.
    rest : (t0, t1), optional
        A rest interval to use for the bias instead of the automatic detection (the longest
        segment of :func:`rest_segments`). A turn at a constant rate is as still as rest to a
        variance test: when the log has turntable segments longer than its rest, give ``rest``.
    gyr_std, acc_std : float, optional
        The thresholds of :func:`rest_segments` (rad/s, m/s^2); None (default): from the sensor's
        own noise, as ``quatnav allan --rest-only`` and :func:`accelerometer` find rest (fixed
        ones for an ideal sensor found no rest in BROAD's trials, still for 40 s).

    Returns
    -------
    SensorCalibration
        ``offset``: the bias (rad/s); ``matrix``: identity without known rotations.
        ``info``: ``rest`` (the interval used, s), ``bias_sigma`` (rad/s, standard error of the
        mean), ``rotations`` (number used).
    """
    gyr = _as_n3(gyr, "gyr", 2)
    t = np.asarray(t, float).reshape(-1)
    if t.shape[0] != gyr.shape[0]:
        raise ValueError(f"t has {t.shape[0]} samples, gyr {gyr.shape[0]}")
    if np.any(np.diff(t) <= 0):
        raise ValueError("t must be strictly increasing")
    if rest is None:
        segs = rest_segments(t, None if acc is None else _as_n3(acc, "acc", 2), gyr, acc_std=acc_std,
                             gyr_std=gyr_std, min_duration_s=min_duration_s)
        if not segs:
            raise ValueError("gyroscope: no rest segment found (sensor never still for "
                             f"{min_duration_s} s); give rest=(t0, t1)")
        a, b_ = max(segs, key=lambda s: s[1] - s[0])
    else:
        a, b_ = np.searchsorted(t, rest[0]), np.searchsorted(t, rest[1], side="right")
        if b_ - a < 2:
            raise ValueError(f"gyroscope: rest interval {rest} holds fewer than 2 samples")
    seg = gyr[a:b_]
    bias = seg.mean(axis=0)
    info = {"rest": [float(t[a]), float(t[b_ - 1])], "bias_sigma": (seg.std(axis=0) / np.sqrt(len(seg))).tolist()}
    known = []
    for t0, t1, ang in rotations or ():
        known.append((t0, t1, np.asarray(ang, float).reshape(3)))
    for t0, t1, w in rates or ():
        known.append((t0, t1, np.asarray(w, float).reshape(3) * (t1 - t0)))
    matrix = np.eye(3)
    residual = float("nan")
    if known:
        meas, ref = [], []
        dt = np.diff(t)
        for t0, t1, ang in known:
            i0, i1 = np.searchsorted(t, t0), np.searchsorted(t, t1)
            if i1 - i0 < 2:
                raise ValueError(f"gyroscope: known rotation ({t0}, {t1}) holds fewer than 2 samples")
            # trapezoid of the bias-corrected rate over [t0, t1]
            g = gyr[i0:i1 + 1] - bias
            meas.append(0.5 * ((g[1:] + g[:-1]) * dt[i0:i1, None]).sum(axis=0))
            ref.append(ang)
        meas, ref = np.array(meas), np.array(ref)
        if np.linalg.matrix_rank(ref, tol=1e-9 * np.abs(ref).max()) == 3:
            # ref = M meas  ->  meas M^T = ref
            matrix = np.linalg.lstsq(meas, ref, rcond=None)[0].T
        else:  # scale per excited axis only
            d = np.ones(3)
            for ax in range(3):
                if np.abs(ref[:, ax]).max() > 0:
                    d[ax] = (meas[:, ax] @ ref[:, ax]) / (meas[:, ax] @ meas[:, ax])
            matrix = np.diag(d)
        residual = float(np.sqrt(np.mean(np.sum((meas @ matrix.T - ref) ** 2, axis=1))))
        info["rotations"] = len(known)
    return SensorCalibration("gyro", "full" if known else "bias", bias, matrix, residual, info)
