"""Loosely coupled GPS/INS feedback Kalman filter with altimeter and compass (paper 004).

:class:`GpsInsFilter` wraps ``quatnav._core.GpsInsFilter_f64`` / ``_f32`` (chosen by ``dtype``);
:meth:`GpsInsFilter.run` executes the whole record in C++ with the GIL released. The numpy twin
is :class:`quatnav.reference.GpsInsFilter`. The model (15 error states: NED position, velocity,
phi-angle attitude error, accelerometer and gyro biases; feedback of the estimate into the
strapdown mechanization after every correction) is described in ``quatnav/gps_ins.hpp``.
"""
from __future__ import annotations

import numbers

from dataclasses import dataclass, field

import numpy as np

from .. import _core, _validate as V
from .. import quaternion as Q

__all__ = ["GpsInsFilter", "GpsInsResult", "GPSINS_FLAGS", "STATE_NAMES", "PARAM_NAMES"]

#: Bits of :attr:`GpsInsResult.flags` (``quatnav::gpsins_flags``).
GPSINS_FLAGS = {
    "aligning": 1 << 0, "levelled": 1 << 1, "navigating": 1 << 2, "initialized": 1 << 3,
    "predict_skipped": 1 << 4, "gps_pos_used": 1 << 5, "gps_pos_rejected": 1 << 6,
    "gps_vel_used": 1 << 7, "gps_vel_rejected": 1 << 8, "baro_used": 1 << 9,
    "baro_rejected": 1 << 10, "baro_vd_used": 1 << 11, "baro_vd_rejected": 1 << 12,
    "compass_used": 1 << 13, "compass_rejected": 1 << 14, "aid_skipped": 1 << 15,
    "gps_reset": 1 << 16, "saturated": 1 << 17,
}

#: Names of the 15 error states, in order (units: m, m/s, rad, m/s^2, rad/s).
STATE_NAMES = ("dp_n", "dp_e", "dp_d", "dv_n", "dv_e", "dv_d", "psi_n", "psi_e", "psi_d",
               "ba_x", "ba_y", "ba_z", "bg_x", "bg_y", "bg_z")

#: Parameter names (see ``quatnav::GpsInsParams`` for units and defaults).
PARAM_NAMES = ("gyro_noise", "accel_noise", "gyro_bias_rw", "accel_bias_rw", "gyro_bias_tau",
               "accel_bias_tau", "init_gyro_bias_sigma", "init_accel_bias_sigma", "init_level_sigma",
               "init_yaw_sigma", "init_vel_sigma", "gps_pos_sigma_h", "gps_pos_sigma_v",
               "gps_vel_sigma", "lever_arm_b", "baro_sigma", "baro_rate_baseline", "baro_vd_sigma", "baro_offset_fixes",
               "compass_sigma", "declination", "gate_gps_pos", "gate_gps_vel", "gate_baro",
               "gate_compass", "gps_reset_after", "align_time", "min_speed_for_heading", "heading_from_gps",
               "earth_rotation", "max_dt", "gyro_range", "acc_range", "cov_floor")

#: Angle parameters (rad) and their accepted ranges; a value outside is most likely in degrees.
ANGLE_LIMITS = {"declination": (-np.pi, np.pi), "compass_sigma": (0.0, 1.0),
                "init_level_sigma": (0.0, np.pi / 2), "init_yaw_sigma": (0.0, np.pi)}
_RANGE_TEXT = {-np.pi: "-pi", 0.0: "0", 1.0: "1", np.pi / 2: "pi/2", np.pi: "pi"}


def _angle(value, name) -> float:
    """An angle parameter in radians within :data:`ANGLE_LIMITS`; else a ValueError that names
    the parameter and suggests ``np.radians`` when the value reads as degrees."""
    v = _finite(value, name)
    lo, hi = ANGLE_LIMITS[name]
    if not lo <= v <= hi:
        rng = f"[{_RANGE_TEXT[lo]}, {_RANGE_TEXT[hi]}]"
        hint = (f"; angles are in radians: for {v:g} deg pass np.radians({v:g}) = {np.radians(v):.6g}"
                if abs(v) > hi and abs(v) <= 360.0 else "")
        raise ValueError(f"{name}: {v:g} is outside {rng} rad{hint}")
    return v


_STATUS = ("ok", "not_initialized", "non_finite", "zero_norm", "invalid_dt", "saturated",
           "solve_failed", "rejected", "numerical_failure", "invalid_argument")


@dataclass
class GpsInsResult:
    """Output of :meth:`GpsInsFilter.run`.

    Attributes
    ----------
    t : (N,) ndarray
        IMU times, s.
    llh : (N, 3) ndarray
        IMU position [lat (rad), lon (rad), h (m)]; NaN before navigation starts.
    v_n : (N, 3) ndarray
        NED velocity, m/s (NaN before navigation starts).
    q_nb : (N, 4) ndarray
        Attitude [w, x, y, z], body to NED (NaN while aligning).
    accel_bias, gyro_bias : (N, 3) ndarray
        Bias estimates, m/s^2 and rad/s.
    sigma : (N, 15) ndarray
        One-sigma of the error states (:data:`STATE_NAMES`); NaN before navigation starts.
    flags : (N,) uint32 ndarray
        Bits of :data:`GPSINS_FLAGS`.
    gps, baro, compass : dict
        Per aiding sample: ``t``, ``innovation`` (INS minus aid; GPS (K, 6) position then
        velocity, altimeter (K, 2) height then vertical velocity, compass (K,)), ``nis`` and
        ``status`` (strings), NaN where no update was made.
    counters : dict
        Per measurement kind (gps_pos, gps_vel, baro, baro_vd, compass): accepted, rejected by
        the chi-square gate, skipped as invalid; gps_pos and gps_vel also count ``resets``
        (gate lockout: after ``gps_reset_after`` consecutive rejections the next rejected fix
        resets the position or velocity to it).
    """

    t: np.ndarray
    llh: np.ndarray
    v_n: np.ndarray
    q_nb: np.ndarray
    accel_bias: np.ndarray
    gyro_bias: np.ndarray
    sigma: np.ndarray
    flags: np.ndarray
    gps: dict = field(default_factory=dict)
    baro: dict = field(default_factory=dict)
    compass: dict = field(default_factory=dict)
    counters: dict = field(default_factory=dict)
    skipped_rows: dict = field(default_factory=dict)

    @property
    def euler(self) -> np.ndarray:
        """(N, 3) ZYX Euler angles [roll, pitch, yaw], rad (NaN while aligning)."""
        out = np.full((len(self.t), 3), np.nan)
        ok = np.isfinite(self.q_nb[:, 0])
        if ok.any():
            out[ok] = Q.to_euler(self.q_nb[ok])
        return out

    @property
    def navigating(self) -> np.ndarray:
        """(N,) bool: navigation running at each sample."""
        return self.flag("navigating")

    def flag(self, name: str) -> np.ndarray:
        """Boolean (N,) array: where flag ``name`` (a key of :data:`GPSINS_FLAGS`) is set."""
        return (self.flags & GPSINS_FLAGS[name]) != 0

    @property
    def rejections(self) -> dict:
        """Number of gate rejections per measurement kind."""
        return {k: v["rejected"] for k, v in self.counters.items()}


def _times(x, name):
    a = V._numeric(x, name)
    if a.ndim != 1:
        raise ValueError(f"{name}: expected shape (K,), got {a.shape}")
    a = np.ascontiguousarray(a, dtype=np.float64)
    r = V.first_bad_row(a)
    if r is not None:
        raise ValueError(f"{name}: non-finite value in row {r}")
    d = np.diff(a)
    bad = np.flatnonzero(~(d > 0))
    if bad.size:
        k = int(bad[0]) + 1
        kind = "duplicate" if d[bad[0]] == 0 else "unsorted"
        raise ValueError(f"{name}: times must be strictly increasing ({kind}); row {k} ({float(a[k])!r}) "
                         f"does not follow row {k - 1} ({float(a[k - 1])!r})")
    return a


def _rows(x, name, k, cols, dtype, allow_nan_rows, finite=True):
    if x is None:
        return np.full((k, cols), np.nan, dtype=dtype) if cols > 1 else np.full(k, np.nan, dtype=dtype)
    if cols == 1:
        a = V._numeric(x, name)
        if a.shape != (k,):
            raise ValueError(f"{name}: expected shape ({k},), got {a.shape}")
        a = np.ascontiguousarray(a, dtype=dtype)
        r = V.first_bad_row(a)
        if finite and r is not None:
            raise ValueError(f"{name}: non-finite value in row {r}")
        return a
    if not k:
        a = V._numeric(x, name)
        if a.shape not in ((0, cols), (0,)):
            raise ValueError(f"{name}: expected shape (0, {cols}), got {a.shape}")
        return np.zeros((0, cols), dtype=dtype)
    return V.vectors(x, name, cols=cols, n=k, dtype=dtype, finite=finite, allow_nan_rows=allow_nan_rows)


def _sigmas(x, name, k, dtype):
    """Per-fix one-sigma (K, 3): NaN entries take the parameters; else positive and finite."""
    if x is None:
        return np.full((k, 3), np.nan, dtype)
    a = np.ascontiguousarray(V._numeric(x, name), dtype)
    if a.shape != (k, 3):
        raise ValueError(f"{name}: expected shape ({k}, 3), got {a.shape}")
    bad = np.flatnonzero((~np.isnan(a) & ~(np.isfinite(a) & (a > 0))).any(axis=1))
    if bad.size:
        raise ValueError(f"{name}: expected positive finite values or NaN; row {int(bad[0])} is {a[bad[0]]}")
    return a


def _finite(x, name) -> float:
    if isinstance(x, bool) or not isinstance(x, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected a real number, got {type(x).__name__}")
    v = float(x)
    if not np.isfinite(v):
        raise ValueError(f"{name}: expected a finite number, got {V.num(x)}")
    return v


class GpsInsFilter:
    """15-state loosely coupled GPS/INS feedback filter with altimeter and compass (paper 004).

    Parameters
    ----------
    dtype : {numpy.float64, numpy.float32}
        Precision of the C++ filter (the geodetic position is double in both).
    **params
        Any of :data:`PARAM_NAMES` (``quatnav::GpsInsParams``), e.g. ``gyro_noise`` (rad/s/sqrt(Hz)),
        ``accel_noise`` (m/s^2/sqrt(Hz)), ``gyro_bias_rw`` (rad/s/sqrt(s)), ``accel_bias_rw``
        (m/s^2/sqrt(s)), ``gyro_bias_tau``/``accel_bias_tau`` (s; 0: random walk),
        ``lever_arm_b`` (3,) m, ``gps_pos_sigma_h``/``_v`` (m), ``gps_vel_sigma`` (m/s),
        ``baro_sigma`` (m), ``baro_rate_baseline`` (s), ``compass_sigma`` (rad, [0, 1]),
        ``declination`` (rad, [-pi, pi], east of true north), ``init_level_sigma`` (rad,
        [0, pi/2]), ``init_yaw_sigma`` (rad, [0, pi]) (an angle outside its range raises
        ``ValueError``: it was most likely given in degrees, use ``np.radians``), chi-square gates ``gate_*`` (0: off), ``align_time`` (s),
        ``min_speed_for_heading`` (m/s), ``heading_from_gps``, ``earth_rotation``, ``max_dt`` (s),
        ``gps_reset_after`` (consecutive gate rejections before a GPS reset; 0: never).

    Examples
    --------
    >>> f = GpsInsFilter(gps_pos_sigma_h=3.0)            # doctest: +SKIP
    >>> res = f.run(t, gyro, accel, gps_t=tg, gps_llh=llh, gps_vel=vel)  # doctest: +SKIP
    >>> res.llh, res.euler, res.sigma, res.counters   # doctest: +SKIP
    """

    n_states = 15

    def __init__(self, dtype=np.float64, **params):
        self.dtype = V.resolve_dtype(dtype)
        suffix = "_f32" if self.dtype == np.float32 else "_f64"
        p = getattr(_core, "GpsInsParams" + suffix)()
        for name, value in params.items():
            if name not in PARAM_NAMES:
                raise TypeError(f"GpsInsFilter: unknown parameter {name!r}; known: {', '.join(PARAM_NAMES)}")
            if name == "lever_arm_b":
                value = V.vector(value, "lever_arm_b", 3)
            elif name in ("heading_from_gps", "earth_rotation"):
                if not isinstance(value, (bool, np.bool_)):
                    raise TypeError(f"{name}: expected a bool, got {type(value).__name__}")
                value = bool(value)
            elif name in ANGLE_LIMITS:
                value = _angle(value, name)
            else:
                value = V.positive(value, name, allow_zero=True)
            setattr(p, name, value)
        self._f = getattr(_core, "GpsInsFilter" + suffix)(p)

    # --- state --------------------------------------------------------------------------------
    @property
    def params(self) -> dict:
        p = self._f.params
        return {n: (np.array(getattr(p, n)) if n == "lever_arm_b" else getattr(p, n)) for n in PARAM_NAMES}

    @property
    def navigating(self) -> bool:
        return bool(self._f.navigating)

    @property
    def q_nb(self) -> np.ndarray:
        """Attitude [w, x, y, z], body to NED."""
        return np.array(self._f.q_nb)

    @property
    def v_n(self) -> np.ndarray:
        return np.array(self._f.v_n)

    @property
    def llh(self) -> np.ndarray:
        """[lat (rad), lon (rad), h (m)] of the IMU."""
        return np.array(self._f.llh)

    @property
    def accel_bias(self) -> np.ndarray:
        return np.array(self._f.accel_bias)

    @property
    def gyro_bias(self) -> np.ndarray:
        return np.array(self._f.gyro_bias)

    @property
    def covariance(self) -> np.ndarray:
        """(15, 15) error-state covariance."""
        return np.array(self._f.covariance)

    @property
    def counters(self) -> dict:
        """Accepted / rejected / skipped counts per measurement kind."""
        return self._f.counters

    def get_state(self) -> dict:
        """Everything the filter holds, as a dict that :meth:`set_state` takes back exactly."""
        return self._f.get_state()

    def set_state(self, state: dict) -> None:
        s = self._f.set_state(state)
        if s != "ok":
            raise ValueError(f"state: rejected by the filter ({s})")

    def reset(self) -> None:
        """Back to the start of alignment (parameters kept)."""
        self._f.reset()

    def initialize(self, q_nb, v_n, llh, accel_bias=(0.0, 0.0, 0.0), gyro_bias=(0.0, 0.0, 0.0),
                   P=None) -> None:
        """Start navigation directly, skipping the static alignment (e.g. from a dataset's own
        initial alignment when the vehicle is not at rest at the start).

        Parameters
        ----------
        q_nb : (4,) array_like
            Attitude [w, x, y, z], body to NED.
        v_n : (3,) array_like
            NED velocity of the IMU, m/s.
        llh : (3,) array_like
            IMU [lat (rad), lon (rad), h (m)].
        accel_bias, gyro_bias : (3,) array_like
            Initial bias estimates, m/s^2 and rad/s.
        P : (15, 15) array_like, optional
            Error-state covariance (:data:`STATE_NAMES`); default: the parameters' initial sigmas
            with GPS position sigmas ``gps_pos_sigma_h``/``_v`` and ``init_vel_sigma``.
        """
        q = V.vector(q_nb, "q_nb", 4, self.dtype)
        v = V.vector(v_n, "v_n", 3, self.dtype)
        llh = V.vector(llh, "llh", 3, np.float64)
        ba = V.vector(accel_bias, "accel_bias", 3, self.dtype)
        bg = V.vector(gyro_bias, "gyro_bias", 3, self.dtype)
        if P is None:
            p = self._f.params
            d = np.array([p.gps_pos_sigma_h, p.gps_pos_sigma_h, p.gps_pos_sigma_v] + [p.init_vel_sigma] * 3
                         + [p.init_level_sigma] * 2 + [p.init_yaw_sigma] + [p.init_accel_bias_sigma] * 3
                         + [p.init_gyro_bias_sigma] * 3)
            P = np.diag(d ** 2)
        P = np.asarray(V._numeric(P, "P"), dtype=self.dtype)
        if P.shape != (15, 15):
            raise ValueError(f"P: expected shape (15, 15), got {P.shape}")
        s = self._f.initialize(q, v, float(llh[0]), float(llh[1]), float(llh[2]), ba, bg, P)
        if s != "ok":
            raise ValueError(f"q_nb, v_n, llh, P: rejected by the filter ({s})")

    # --- steps --------------------------------------------------------------------------------
    def predict(self, omega_ib_b, f_ib_b, dt: float) -> str:
        """One IMU interval: mean rate (rad/s), specific force (m/s^2), dt (s). Returns the status."""
        d = V.positive(dt, "dt")
        if d > float(self._f.params.max_dt):
            raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
        return self._f.predict(V.vector(omega_ib_b, "omega_ib_b", 3, self.dtype),
                               V.vector(f_ib_b, "f_ib_b", 3, self.dtype), d)

    def update_gps(self, lat, lon, h, v_n=None, pos_sigma=None, vel_sigma=None):
        """One GPS fix (rad, rad, m; NED m/s or None). Returns (position result, velocity result)."""
        nan3 = np.full(3, np.nan, self.dtype)
        la, lo, hh = _finite(lat, "lat"), _finite(lon, "lon"), _finite(h, "h")
        if not abs(la) <= np.pi / 2:
            raise ValueError(f"lat: expected |lat| <= pi/2 rad, got {V.num(lat)}")
        v = nan3 if v_n is None else V.vector(v_n, "v_n", 3, self.dtype)
        ps = nan3 if pos_sigma is None else _sigmas(np.reshape(V._numeric(pos_sigma, "pos_sigma"), (1, -1))
                                                    if np.ndim(pos_sigma) == 1 else pos_sigma, "pos_sigma", 1,
                                                    self.dtype)[0]
        vs = nan3 if vel_sigma is None else _sigmas(np.reshape(V._numeric(vel_sigma, "vel_sigma"), (1, -1))
                                                    if np.ndim(vel_sigma) == 1 else vel_sigma, "vel_sigma", 1,
                                                    self.dtype)[0]
        return self._f.update_gps(la, lo, hh, v, ps, vs)

    def update_baro(self, h: float):
        """Altimeter height (m). Returns (height result, vertical-velocity result)."""
        return self._f.update_baro(_finite(h, "h"))

    def update_compass(self, heading: float):
        """Compass heading (rad). Returns the update result."""
        return self._f.update_compass(_finite(heading, "heading"))

    # --- batch --------------------------------------------------------------------------------
    def run(self, t, gyro, accel, gps_t=None, gps_llh=None, gps_vel=None, gps_pos_sigma=None,
            gps_vel_sigma=None, baro_t=None, baro_h=None, compass_t=None, compass_yaw=None,
            outages=(), on_invalid: str = "raise") -> GpsInsResult:
        """Run over an IMU record and aiding records at their own times (C++ loop, GIL released).

        Parameters
        ----------
        t : (N,) array_like
            IMU times, s, strictly increasing; sample k holds the mean over (t[k-1], t[k]].
        gyro : (N, 3) array_like
            Body rate omega_ib_b, rad/s.
        accel : (N, 3) array_like
            Specific force f_ib_b, m/s^2.
        gps_t : (K,) array_like, optional
            GPS times of validity, s, strictly increasing.
        gps_llh : (K, 3) array_like
            Antenna [lat (rad), lon (rad), h (m)]; an all-NaN row is skipped.
        gps_vel : (K, 3) array_like, optional
            Antenna NED velocity, m/s; all-NaN rows mean "no velocity".
        gps_pos_sigma, gps_vel_sigma : (K, 3) array_like, optional
            One-sigma per fix (NED m, m/s); NaN entries take the parameters.
        baro_t, baro_h : (B,) array_like, optional
            Altimeter times (s) and heights (m).
        compass_t, compass_yaw : (C,) array_like, optional
            Compass times (s) and magnetic headings (rad).
        outages : sequence of (t_start, t_end), optional
            GPS fixes with t_start <= t < t_end are dropped (simulated outages).
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite row (IMU, a partly-NaN or infinite GPS row, altimeter,
            compass) or IMU step above ``max_dt`` raises ``ValueError`` naming the argument and
            row. "skip": such rows skip their step and are reported in ``flags``
            (``predict_skipped``, ``aid_skipped``), the aids' ``status`` and ``skipped_rows``
            (keys ``"predict_skipped"``, ``"saturated"`` (IMU rows), ``"gps"``, ``"baro"``,
            ``"compass"`` (aiding rows)). Times must be finite and strictly increasing in both
            modes. A saturated IMU row (``gyro_range`` / ``acc_range``) is skipped and reported in
            both modes.

        Returns
        -------
        GpsInsResult
        """
        strict = V.on_invalid(on_invalid) == "raise"
        t = _times(t, "t")
        n = len(t)
        if n < 2:
            raise ValueError("t: need at least two IMU samples")
        gyro = V.vectors(gyro, "gyro", 3, n, self.dtype, finite=strict)
        accel = V.vectors(accel, "accel", 3, n, self.dtype, finite=strict)
        if strict:
            big = np.flatnonzero(np.diff(t) > float(self._f.params.max_dt))
            if big.size:
                k = int(big[0]) + 1
                raise ValueError(f"t: step {float(t[k] - t[k - 1])!r} s in row {k} exceeds "
                                 f"max_dt={float(self._f.params.max_dt)!r} s")
        if gps_t is None:
            gps_t = np.zeros(0)
            gps_llh = np.zeros((0, 3))
        elif gps_llh is None:
            raise ValueError("gps_llh: required with gps_t")
        gps_t = _times(gps_t, "gps_t")
        ng = len(gps_t)
        gps_llh = _rows(gps_llh, "gps_llh", ng, 3, np.float64, True, strict)
        if strict and ng:
            bad = np.flatnonzero(np.abs(gps_llh[:, 0]) > np.pi / 2)
            if bad.size:
                raise ValueError(f"gps_llh: latitude beyond +-pi/2 rad in row {int(bad[0])}: {gps_llh[bad[0]]}")
        gps_vel = _rows(gps_vel, "gps_vel", ng, 3, self.dtype, True, strict)
        gps_pos_sigma = _sigmas(gps_pos_sigma, "gps_pos_sigma", ng, self.dtype)
        gps_vel_sigma = _sigmas(gps_vel_sigma, "gps_vel_sigma", ng, self.dtype)
        if len(outages):
            gps_llh = gps_llh.copy()
            for o in outages:
                if len(o) != 2 or not o[1] > o[0]:
                    raise ValueError(f"outages: expected (t_start, t_end) pairs, got {o!r}")
                gps_llh[(gps_t >= o[0]) & (gps_t < o[1])] = np.nan
        if baro_t is None:
            baro_t, baro_h = np.zeros(0), np.zeros(0)
        elif baro_h is None:
            raise ValueError("baro_h: required with baro_t")
        baro_t = _times(baro_t, "baro_t")
        baro_h = _rows(baro_h, "baro_h", len(baro_t), 1, np.float64, False, strict)
        if compass_t is None:
            compass_t, compass_yaw = np.zeros(0), np.zeros(0)
        elif compass_yaw is None:
            raise ValueError("compass_yaw: required with compass_t")
        compass_t = _times(compass_t, "compass_t")
        compass_yaw = _rows(compass_yaw, "compass_yaw", len(compass_t), 1, self.dtype, False, strict)
        d = self._f.run(t, gyro, accel, gps_t, gps_llh, gps_vel, gps_pos_sigma, gps_vel_sigma,
                        baro_t, baro_h, compass_t, compass_yaw)
        st = lambda a: np.array([_STATUS[int(x)] for x in a.ravel()], dtype=object).reshape(a.shape)  # noqa: E731
        flags = d["flags"]
        skipped = {}
        for name in ("predict_skipped", "saturated"):
            rows = np.flatnonzero(flags & GPSINS_FLAGS[name])
            rows = rows[rows > 0]  # sample 0 only fixes the start time
            if rows.size:
                skipped[name] = rows
        refused = [_STATUS.index(x) for x in ("non_finite", "numerical_failure", "solve_failed", "invalid_argument")]
        for name, key in (("gps", "gps_status"), ("baro", "baro_status"), ("compass", "compass_status")):
            s_ = d[key].reshape(len(d[key]), -1) if len(d[key]) else np.zeros((0, 1), np.uint8)
            rows = np.flatnonzero(np.isin(s_, refused).any(axis=1))
            if name == "gps" and ng:  # an all-NaN position row is an absent fix, not a refused one
                rows = rows[~np.isnan(gps_llh[rows]).all(axis=1)]
            if rows.size:
                skipped[name] = rows
        return GpsInsResult(
            t=t, llh=d["llh"], v_n=d["v_n"], q_nb=d["q_nb"], accel_bias=d["accel_bias"],
            gyro_bias=d["gyro_bias"], sigma=d["sigma"], flags=d["flags"],
            gps={"t": gps_t, "innovation": d["gps_innov"], "nis": d["gps_nis"], "status": st(d["gps_status"])},
            baro={"t": baro_t, "innovation": d["baro_innov"], "nis": d["baro_nis"], "status": st(d["baro_status"])},
            compass={"t": compass_t, "innovation": d["compass_innov"], "nis": d["compass_nis"],
                     "status": st(d["compass_status"])},
            counters=self.counters, skipped_rows=skipped)
