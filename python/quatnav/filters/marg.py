"""MARG attitude filter of paper 001: :class:`MargFilter`.

Gauss-Newton attitude from gravity and the magnetic field (eq. 1-5) blended with gyro
integration (eq. 6); the accelerometer is corrected for the vehicle's acceleration with the GPS
antenna acceleration and the lever-arm terms (eq. 7, corrected form in ``marg_filter.hpp``)::

    f_b + w_dot x d + w x (w x d) = C_bn (a_g_n - g_n)

Wraps the C++ class of ``quatnav._core`` (float64 or float32, chosen by ``dtype``); batch runs
execute in C++ with the GIL released. The plain numpy twin is :class:`quatnav.reference.MargFilter`.
"""
from __future__ import annotations

import numbers
from dataclasses import dataclass, field

import numpy as np

from .. import _core, _validate as V
from .. import quaternion as Q
from .attitude import FLAGS as _ATT_FLAGS

__all__ = ["MargFilter", "MargResult", "MARG_FLAGS"]

#: Bits of :attr:`MargResult.flags`: those of :data:`quatnav.FLAGS` plus two of this filter.
MARG_FLAGS = dict(_ATT_FLAGS, gps_corrected=1 << 16, gn_not_converged=1 << 17)


@dataclass
class MargResult:
    """Output of :meth:`MargFilter.run`.

    Attributes
    ----------
    quat : (N, 4) ndarray
        ``q_nb`` [w, x, y, z] after each sample (NED, x magnetic north).
    bias : (N, 3) ndarray
        Gyro bias estimate, rad/s (zero unless ``bias_gain > 0``).
    gps_acc_n : (N, 3) ndarray
        GPS antenna acceleration used by eq. (7) at each sample, m/s^2 NED; NaN where the
        accelerometer was not corrected.
    residual : (N,) ndarray
        Norm of the Gauss-Newton error vector eq. (3) at the predicted attitude (dimensionless;
        NaN where no update was made).
    flags : (N,) uint32 ndarray
        Bits of :data:`MARG_FLAGS` per sample.
    """

    quat: np.ndarray
    bias: np.ndarray
    gps_acc_n: np.ndarray
    residual: np.ndarray
    flags: np.ndarray
    skipped_rows: dict = field(default_factory=dict)

    @property
    def euler(self) -> np.ndarray:
        """(N, 3) ZYX Euler angles [roll, pitch, yaw], rad."""
        return Q.to_euler(self.quat)

    def flag(self, name: str) -> np.ndarray:
        """Boolean (N,) array: where flag ``name`` (a key of :data:`MARG_FLAGS`) is set."""
        return (self.flags & MARG_FLAGS[name]) != 0


_FLOAT_PARAMS = ("gain", "bias_gain", "gn_tol", "gravity", "gps_acc_tau", "omega_dot_tau",
                 "gps_timeout", "max_dt", "declination")
_ZERO_OK = ("gain", "bias_gain", "gps_acc_tau", "omega_dot_tau")


class MargFilter:
    """Gauss-Newton MARG attitude filter with GPS acceleration correction (paper 001).

    Parameters (keyword, SI units)
    ------------------------------
    gain : float, default 1.0
        k of eq. (6): rate at which the estimate is pulled towards the Gauss-Newton attitude,
        1/s (0: gyro integration only).
    bias_gain : float, default 0.0
        Gyro-bias integral gain, 1/s^2; 0 disables the bias estimate.
    gn_max_iter : int, default 3
        Gauss-Newton iterations per update, at most.
    gn_tol : float, default 1e-6
        The iteration stops when the step |dq| is below this.
    gravity : float, default 9.80665
        Magnitude of gravity in eq. (7), m/s^2.
    lever_arm_b : (3,) array_like, default zeros
        Position of the GPS antenna relative to the IMU, body frame FRD, m.
    gps_correction : bool, default True
        Apply eq. (7) when a GPS acceleration is available.
    gps_acc_tau : float, default 0.05
        Low-pass time constant of the GPS acceleration (differences of GPS velocity), s. The
        acceleration lags by about half the fix interval plus this; in a turn the lagged vector
        points behind the true one (an along-track error of a_c * yaw_rate * lag), so keep it
        short when the GPS velocity is precise.
    omega_dot_tau : float, default 0.1
        Low-pass time constant of the angular acceleration (differences of gyro rate), s.
    gps_timeout : float, default 0.5
        A GPS acceleration older than this is not used; a fix gap longer than this restarts the
        differencing, s.
    max_dt : float, default 1.0
        Longest accepted time step, s.
    mag_ref_samples : int, default 100
        Magnetometer samples over which the reference field's dip is averaged (from
        initialization on, as for the other attitude filters) unless :meth:`set_mag_dip` fixes it.
    declination : float, default 0.0
        Magnetic declination (east of true north), rad. The filter's navigation frame has x along
        magnetic north; GPS velocities (true NED) are rotated into it. Leaving it at zero where
        the declination is not puts the GPS acceleration in the wrong direction.
    dtype : float64 or float32
        Precision of the C++ filter.

    Notes
    -----
    The accelerometer must be in m/s^2 when the correction is used (the GPS acceleration is
    compared with it); the magnetometer may be in any unit.
    """

    n_states = 7  # q and the gyro bias

    def __init__(self, dtype=np.float64, **params):
        self.dtype = V.resolve_dtype(dtype)
        self._suffix = "_f32" if self.dtype == np.float32 else "_f64"
        p = getattr(_core, "MargFilterParams" + self._suffix)()
        self._apply_params(p, params)
        self._f = getattr(_core, "MargFilter" + self._suffix)(p)

    def _apply_params(self, p, params: dict) -> None:
        for name, value in params.items():
            if name == "declination":
                d = float(value)
                if not np.isfinite(d) or abs(d) > np.pi:
                    raise ValueError(f"declination: expected a finite angle in [-pi, pi] rad, got {value!r}")
                p.declination = d
            elif name in _FLOAT_PARAMS:
                setattr(p, name, V.positive(value, name, allow_zero=name in _ZERO_OK))
            elif name == "mag_ref_samples":
                if isinstance(value, bool) or not isinstance(value, (numbers.Integral, np.integer)) or value < 1:
                    raise ValueError(f"mag_ref_samples: expected a positive integer, got {value!r}")
                p.mag_ref_samples = int(value)
            elif name == "gn_max_iter":
                if isinstance(value, bool) or not isinstance(value, (numbers.Integral, np.integer)):
                    raise TypeError(f"gn_max_iter: expected an integer, got {type(value).__name__}")
                if not 1 <= int(value) <= 100:
                    raise ValueError(f"gn_max_iter: expected 1..100, got {value!r}")
                p.gn_max_iter = int(value)
            elif name == "gps_correction":
                if not isinstance(value, (bool, np.bool_)):
                    raise TypeError(f"gps_correction: expected a bool, got {type(value).__name__}")
                p.gps_correction = bool(value)
            elif name == "lever_arm_b":
                p.lever_arm_b = V.vector(value, "lever_arm_b", dtype=self.dtype)
            else:
                known = _FLOAT_PARAMS + ("gn_max_iter", "gps_correction", "lever_arm_b", "mag_ref_samples")
                raise TypeError(f"MargFilter: unknown parameter {name!r}; known: {', '.join(known)}")

    # -- parameters and state -------------------------------------------------------------
    @property
    def params(self) -> dict:
        p = self._f.params
        out = {name: getattr(p, name) for name in _FLOAT_PARAMS + ("gn_max_iter", "gps_correction", "mag_ref_samples")}
        out["lever_arm_b"] = np.array(p.lever_arm_b, dtype=float)
        return out

    @property
    def quat(self) -> np.ndarray:
        """Current ``q_nb`` [w, x, y, z]."""
        return np.asarray(self._f.quat, dtype=float)

    @property
    def bias(self) -> np.ndarray:
        """Current gyro bias, rad/s."""
        return np.asarray(self._f.bias, dtype=float)

    @property
    def gps_acc_n(self) -> np.ndarray | None:
        """The GPS antenna acceleration eq. (7) would use now (m/s^2 NED), or None."""
        return np.asarray(self._f.gps_acc_n, dtype=float) if self._f.gps_acc_available else None

    @property
    def initialized(self) -> bool:
        return bool(self._f.initialized)

    def get_state(self) -> dict:
        """A copy of the complete state; :meth:`set_state` restores it exactly."""
        return {k: (np.array(v) if isinstance(v, np.ndarray) else v) for k, v in self._f.get_state().items()}

    def set_state(self, state: dict) -> None:
        if not isinstance(state, dict):
            raise TypeError(f"state: expected a dict from get_state(), got {type(state).__name__}")
        missing = [k for k in self._f.get_state() if k not in state]
        if missing:
            raise ValueError(f"state: missing keys {missing}")
        status = self._f.set_state(state)
        if status != "ok":
            raise ValueError(f"state: refused ({status})")

    def set_mag_dip(self, dip: float) -> None:
        """Fix the reference field ``[cos(dip), 0, sin(dip)]`` (dip positive down, rad)."""
        dip = float(dip)
        if not np.isfinite(dip) or abs(dip) > np.pi / 2:
            raise ValueError(f"dip: expected a finite angle in [-pi/2, pi/2] rad, got {dip!r}")
        self._f.set_mag_dip(dip)

    # -- single steps --------------------------------------------------------------------
    def initialize(self, acc, mag=None) -> None:
        """Tilt from one accelerometer sample, heading from one magnetometer sample."""
        a = V.vector(acc, "acc", dtype=self.dtype, nonzero=True)
        m = None if mag is None else V.vector(mag, "mag", dtype=self.dtype, nonzero=True)
        status = self._f.initialize(a, m)
        if status != "ok":
            raise ValueError(f"acc, mag: cannot initialize ({status})")

    def reset(self, quat, bias=None) -> None:
        """Start from a given ``q_nb`` and gyro bias (rad/s)."""
        q = V.vector(quat, "quat", 4, dtype=self.dtype, nonzero=True)
        b = np.zeros(3, self.dtype) if bias is None else V.vector(bias, "bias", dtype=self.dtype)
        status = self._f.reset(q, b)
        if status != "ok":
            raise ValueError(f"quat: refused ({status})")

    def predict(self, gyr, dt: float) -> str:
        """Gyro integration with one sample (rad/s) over ``dt`` seconds."""
        self._require_init("predict")
        g = V.vector(gyr, "gyr", dtype=self.dtype)
        d = V.positive(dt, "dt")
        status = self._f.predict(g, d)
        if status == "invalid_dt":
            raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
        return status

    def update_gps_velocity(self, v_n, t: float) -> str:
        """One GPS velocity fix ``v_n`` (antenna, true NED, m/s) valid at time ``t`` (s, increasing)."""
        v = V.vector(v_n, "v_n", dtype=self.dtype)
        tt = float(t)
        if not np.isfinite(tt):
            raise ValueError(f"t: expected a finite time, got {t!r}")
        status = self._f.update_gps_velocity(v, tt)
        if status == "invalid_dt":
            raise ValueError(f"t: {tt} s does not follow the previous fix's time")
        return status

    def update_acc(self, acc):
        """Gauss-Newton update with the accelerometer only (6D; m/s^2). Returns the C++ result
        (status, iterations, converged, gps_corrected, residual, residual_final, correction)."""
        self._require_init("update_acc")
        return self._f.update_acc(V.vector(acc, "acc", dtype=self.dtype, nonzero=True))

    def update_acc_mag(self, acc, mag):
        """Gauss-Newton update with accelerometer (m/s^2) and magnetometer, eq. (1)-(6)."""
        self._require_init("update_acc_mag")
        return self._f.update_acc_mag(V.vector(acc, "acc", dtype=self.dtype, nonzero=True),
                                      V.vector(mag, "mag", dtype=self.dtype, nonzero=True))

    def _require_init(self, what: str) -> None:
        if not self._f.initialized:
            raise ValueError(f"{what}: the filter is not initialized (call initialize or reset first)")

    # -- batch ---------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, dt=None, t=None, gps_vel_n=None, gps_t=None, lever_arm_b=None,
            on_invalid: str = "raise") -> MargResult:
        """Run the filter over N IMU samples and M GPS velocity fixes (in C++, GIL released).

        Parameters
        ----------
        gyr : (N, 3) array_like
            Angular rate, rad/s, body frame.
        acc : (N, 3) array_like
            Specific force, m/s^2, body frame.
        mag : (N, 3) array_like, optional
            Magnetic field (any unit). All-NaN rows mean "no sample"; without ``mag`` the
            filter runs in 6D mode and heading is free.
        dt : float or (N,) array_like, optional
            Step length in seconds (sample k is then at time ``sum(dt[1:k+1])``, sample 0 at 0); or
        t : (N,) array_like, optional
            Strictly increasing IMU timestamps, seconds.
        gps_vel_n : (M, 3) array_like, optional
            GPS antenna velocity, true NED, m/s (rotated by ``declination`` into the filter's frame).
        gps_t : (M,) array_like, optional
            Strictly increasing times of validity of the fixes, seconds, same clock as the IMU.
            A fix is used from the first IMU sample at or after its time and held until the next.
        lever_arm_b : (3,) array_like, optional
            IMU-to-antenna lever arm (body, m) for this and later runs (replaces the parameter).
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite or zero-norm row raises ``ValueError`` naming the
            argument and row. "skip": such samples skip the affected step (see ``flags``).

        Returns
        -------
        MargResult
        """
        mode = V.on_invalid(on_invalid)
        strict = mode == "raise"
        g = V.vectors(gyr, "gyr", dtype=self.dtype, finite=strict)
        n = g.shape[0]
        a = V.vectors(acc, "acc", n=n, dtype=self.dtype, finite=strict)
        m = None
        if mag is not None:
            m = V.vectors(mag, "mag", n=n, dtype=self.dtype, finite=strict, allow_nan_rows=True)
        if strict:
            V.nonzero_rows(a, "acc")
            if m is not None:
                V.nonzero_rows(m, "mag")
        steps = V.time_steps(n, dt=dt, t=t, dtype=np.float64,
                             max_dt=float(self._f.params.max_dt) if strict else None)
        if t is not None:
            times = np.asarray(t, dtype=np.float64)
        else:
            times = np.concatenate([[0.0], np.cumsum(steps[1:])])
        if (gps_vel_n is None) != (gps_t is None):
            raise ValueError("gps_vel_n, gps_t: give both or neither")
        if gps_vel_n is not None:
            gv = V.vectors(gps_vel_n, "gps_vel_n", dtype=self.dtype, finite=strict)
            gt = V._numeric(gps_t, "gps_t")
            if gt.shape != (gv.shape[0],):
                raise ValueError(f"gps_t: expected shape ({gv.shape[0]},) (as many as gps_vel_n), got {gt.shape}")
            gt = gt.astype(np.float64)
            r = V.first_bad_row(gt)
            if r is not None:
                raise ValueError(f"gps_t: non-finite value in row {r}")
            bad = np.flatnonzero(~(np.diff(gt) > 0))
            if bad.size:
                k = int(bad[0]) + 1
                raise ValueError(f"gps_t: times must be strictly increasing; row {k} ({gt[k]!r}) "
                                 f"does not follow row {k - 1} ({gt[k - 1]!r})")
        else:
            gv = np.zeros((0, 3), self.dtype)
            gt = np.zeros(0)
        if lever_arm_b is not None:
            self._replace_params(lever_arm_b=lever_arm_b)
        quat, bias, gps_acc, resid, flags = self._f.run(
            np.ascontiguousarray(times, self.dtype), np.ascontiguousarray(steps, self.dtype), g, a, m,
            np.ascontiguousarray(gt, self.dtype), np.ascontiguousarray(gv, self.dtype))
        skipped = {}
        for name in ("predict_skipped", "acc_skipped", "mag_skipped"):
            rows = np.flatnonzero(flags & MARG_FLAGS[name])
            if rows.size:
                skipped[name] = rows
        return MargResult(quat, bias, gps_acc, resid, flags, skipped)

    def _replace_params(self, **changes) -> None:
        """New parameters, same state."""
        p = getattr(_core, "MargFilterParams" + self._suffix)()
        old = self._f.params
        for name in _FLOAT_PARAMS + ("gn_max_iter", "gps_correction", "lever_arm_b", "mag_ref_samples"):
            setattr(p, name, getattr(old, name))
        self._apply_params(p, changes)
        state = self._f.get_state()
        f = getattr(_core, "MargFilter" + self._suffix)(p)
        if f.set_state(state) != "ok":  # pragma: no cover - a state read from a filter is valid
            raise RuntimeError("internal: state not restored")
        self._f = f
