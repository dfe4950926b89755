"""13-state navigation filter of paper 002 (Seong 2012): velocity, attitude quaternion and
accelerometer and gyro biases, aided by NED velocity and yaw, with three time updates.

:class:`NavFilter13` wraps the C++ classes ``quatnav._core.NavFilter13{Ekf,SecondOrder,Ukf}_f64``
(and ``_f32``), chosen by ``time_update=`` and ``dtype=``; batch runs execute in C++ with the GIL
released. The plain numpy twin is :class:`quatnav.reference.NavFilter13`. The algorithm, its
equations and every deviation from the paper are documented in
``cpp/include/quatnav/nav_filter13.hpp``.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .. import _core, _validate as V
from .. import quaternion as Q

__all__ = ["NavFilter13", "NavResult", "NAV13_FLAGS", "TIME_UPDATES", "STATUS_NAMES", "initial_covariance"]

TIME_UPDATES = ("ekf", "second_order", "ukf")
_CORE = {"ekf": "NavFilter13Ekf", "second_order": "NavFilter13SecondOrder", "ukf": "NavFilter13Ukf"}

#: ``quatnav::Status`` names by code (the ``*_status`` arrays of :class:`NavResult`).
STATUS_NAMES = ("ok", "not_initialized", "non_finite", "zero_norm", "invalid_dt", "saturated", "solve_failed",
                "rejected", "numerical_failure", "invalid_argument")

_STATUS_CODE = {name: i for i, name in enumerate(STATUS_NAMES)}

#: Bits of :attr:`NavResult.flags`.
NAV13_FLAGS = {
    "predict_skipped": 1 << 1,
    "solve_failed": 1 << 6,
    "saturated": 1 << 10,
    "vel_updated": 1 << 16,
    "vel_rejected": 1 << 17,
    "vel_skipped": 1 << 18,
    "yaw_updated": 1 << 19,
    "yaw_rejected": 1 << 20,
    "yaw_skipped": 1 << 21,
}

_PARAMS = ("accel_noise", "gyro_noise", "accel_bias_noise", "gyro_bias_noise", "vel_noise", "yaw_noise",
           "ukf_alpha", "ukf_beta", "ukf_kappa", "max_dt", "gyro_range", "acc_range", "cov_floor",
           "earth_rotation")
_ZERO_OK = ("accel_bias_noise", "gyro_bias_noise", "accel_noise", "gyro_noise", "ukf_beta", "gyro_range",
            "acc_range", "cov_floor")


def euler_rate_matrix(rpy) -> np.ndarray:
    """M (3x3) with omega_nb_b = M [roll_dot, pitch_dot, yaw_dot] for ZYX Euler angles (rad)."""
    r, p, _ = rpy
    return np.array([[1.0, 0.0, -np.sin(p)],
                     [0.0, np.cos(r), np.sin(r) * np.cos(p)],
                     [0.0, -np.sin(r), np.cos(r) * np.cos(p)]])


def initial_covariance(q_nb, vel_sigma, euler_sigma, accel_bias_sigma, gyro_bias_sigma) -> np.ndarray:
    """A 13x13 covariance of ``[v_n, q_nb, b_a, b_g]`` from one-sigma values.

    Parameters
    ----------
    q_nb : (4,) array_like
        Attitude about which the quaternion block is built.
    vel_sigma : float or (3,) array_like
        Velocity one-sigma, m/s.
    euler_sigma : (3,) array_like
        One-sigma of the ZYX Euler angles ``[roll, pitch, yaw]``, rad (mapped to the quaternion
        through ``dq = 1/2 Xi(q) M d(rpy)``, M of :func:`euler_rate_matrix`).
    accel_bias_sigma : float or (3,) array_like
        m/s^2.
    gyro_bias_sigma : float or (3,) array_like
        rad/s.
    """
    q = np.asarray(q_nb, float)
    q = q / np.linalg.norm(q)
    P = np.zeros((13, 13))
    P[0:3, 0:3] = np.diag(np.broadcast_to(np.asarray(vel_sigma, float) ** 2, 3))
    J = 0.5 * Q.xi(q) @ euler_rate_matrix(Q.to_euler(q))
    P[3:7, 3:7] = J @ np.diag(np.asarray(euler_sigma, float) ** 2) @ J.T
    P[7:10, 7:10] = np.diag(np.broadcast_to(np.asarray(accel_bias_sigma, float) ** 2, 3))
    P[10:13, 10:13] = np.diag(np.broadcast_to(np.asarray(gyro_bias_sigma, float) ** 2, 3))
    return P


@dataclass
class NavResult:
    """Output of :meth:`NavFilter13.run`.

    Attributes
    ----------
    t : (N,) ndarray
        Time of each IMU sample (end of its interval), s.
    x : (N, 13) ndarray
        State ``[v_n (m/s), q_nb, b_a (m/s^2), b_g (rad/s)]`` after each sample and the
        measurements applied with it.
    sigma : (N, 13) ndarray
        Square roots of the covariance diagonal.
    att_sigma : (N, 3) ndarray
        One-sigma of the attitude error as a body-frame rotation vector, rad.
    P : (N, 13, 13) ndarray or None
        Covariances (only with ``return_covariance=True``).
    flags : (N,) uint32 ndarray
        Bits of :data:`NAV13_FLAGS`.
    vel_innovation, vel_nis, vel_status : (K, 3), (K,), (K,) uint8
        Per velocity measurement: innovation (m/s), normalized innovation squared, status code
        (index into :data:`STATUS_NAMES`).
    yaw_innovation, yaw_nis, yaw_status : (M,), (M,), (M,) uint8
        Per yaw measurement: innovation (rad, wrapped), NIS, status code.
    """

    t: np.ndarray
    x: np.ndarray
    sigma: np.ndarray
    att_sigma: np.ndarray
    P: np.ndarray | None
    flags: np.ndarray
    vel_innovation: np.ndarray
    vel_nis: np.ndarray
    vel_status: np.ndarray
    yaw_innovation: np.ndarray
    yaw_nis: np.ndarray
    yaw_status: np.ndarray
    skipped_rows: dict = field(default_factory=dict)

    @property
    def v_n(self) -> np.ndarray:
        """(N, 3) NED velocity, m/s."""
        return self.x[:, 0:3]

    @property
    def quat(self) -> np.ndarray:
        """(N, 4) ``q_nb`` [w, x, y, z]."""
        return self.x[:, 3:7]

    @property
    def accel_bias(self) -> np.ndarray:
        """(N, 3) accelerometer bias, m/s^2."""
        return self.x[:, 7:10]

    @property
    def gyro_bias(self) -> np.ndarray:
        """(N, 3) gyro bias, rad/s."""
        return self.x[:, 10:13]

    @property
    def euler(self) -> np.ndarray:
        """(N, 3) ZYX Euler angles [roll, pitch, yaw], rad."""
        return Q.to_euler(self.quat)

    def flag(self, name: str) -> np.ndarray:
        """Boolean (N,) array: where flag ``name`` (a key of :data:`NAV13_FLAGS`) is set."""
        return (self.flags & NAV13_FLAGS[name]) != 0


class NavFilter13:
    """13-state navigation filter ``[v_n, q_nb, b_a, b_g]`` of paper 002.

    Mechanization eq. (1)-(3) with Earth rate, transport rate and WGS-84 gravity at a carried
    position (integrated from the estimated velocity; :meth:`set_position` replaces it), one Euler
    step per IMU sample; NED-velocity and yaw updates (eq. 13-14, 21-23).

    Parameters
    ----------
    time_update : {"ekf", "second_order", "ukf"}
        ``"ekf"``: f(x_mean) and F P F^T + G Q G^T. ``"second_order"``: the mean corrected by
        1/2 sum_ij P_ij d2f/dx_i dx_j (eq. 16-17), covariance as the EKF. ``"ukf"``: unscented
        transform in a 12-dimensional attitude-error state (25 sigma points).
    dtype : float64 or float32
        Precision of the C++ filter.
    accel_noise : float, default 2.942e-5
        Accelerometer white-noise density, m/s^2/sqrt(Hz) (the paper's (30 ug)^2 per 100 Hz sample).
    gyro_noise : float, default 1.4544e-7
        Gyro white-noise density, rad/s/sqrt(Hz) (the paper's (0.3 deg/h)^2 per 100 Hz sample).
    accel_bias_noise, gyro_bias_noise : float, default 0
        Bias random-walk densities, m/s^3/sqrt(Hz) and rad/s^2/sqrt(Hz) (the paper: constant biases).
    vel_noise : float, default 0.03048
        One-sigma of each measured velocity component, m/s (0.1 ft/s).
    yaw_noise : float, default 0.0349
        One-sigma of the measured yaw, rad (2 deg).
    ukf_alpha, ukf_beta, ukf_kappa : float, default 1, 2, 0
        Unscented transform parameters (lambda = alpha^2 (12 + kappa) - 12 must exceed -12).
    max_dt : float, default 1
        Longest accepted IMU step, s.
    gyro_range, acc_range : float, default 0
        Sensor ranges per axis, rad/s and m/s^2: an IMU sample with any ``|w_i| >= gyro_range``
        or ``|f_i| >= acc_range`` is saturated and its predict is skipped (status
        ``"saturated"``). 0: unlimited.
    cov_floor : float, default 0
        Eigenvalue floor of the 12-state error covariance ``[dv, dtheta, db_a, db_g]``, applied
        only when that covariance is not positive definite above it. 0: off.
    earth_rotation : bool, default True
        Include the Earth rate, transport rate and Coriolis terms.
    """

    def __init__(self, time_update: str = "ekf", dtype=np.float64, **params):
        if time_update not in TIME_UPDATES:
            raise ValueError(f"time_update: expected one of {TIME_UPDATES}, got {time_update!r}")
        self.time_update = time_update
        self.dtype = V.resolve_dtype(dtype)
        suffix = "_f32" if self.dtype == np.float32 else "_f64"
        p = getattr(_core, "NavFilter13Params" + suffix)()
        for name, value in params.items():
            if name not in _PARAMS:
                raise TypeError(f"NavFilter13: unknown parameter {name!r}; known: {', '.join(_PARAMS)}")
            if name == "earth_rotation":
                if not isinstance(value, (bool, np.bool_)):
                    raise TypeError(f"earth_rotation: expected a bool, got {type(value).__name__}")
                setattr(p, name, bool(value))
            elif name == "ukf_kappa":  # may be negative; checked with alpha below
                k = V._numeric(value, name)
                if k.ndim != 0 or not np.isfinite(k):
                    raise ValueError(f"{name}: expected a finite number, got {value!r}")
                setattr(p, name, float(k))
            else:
                setattr(p, name, V.positive(value, name, allow_zero=name in _ZERO_OK))
        self._f = getattr(_core, _CORE[time_update] + suffix)(p)
        if not self._f.params_valid:
            raise ValueError("ukf_alpha, ukf_kappa: alpha^2 (12 + kappa) must be positive")

    # -- parameters and state ---------------------------------------------------------------
    @property
    def params(self) -> dict:
        p = self._f.params
        return {name: getattr(p, name) for name in _PARAMS}

    @property
    def initialized(self) -> bool:
        return bool(self._f.initialized)

    @property
    def x(self) -> np.ndarray:
        """(13,) state ``[v_n, q_nb, b_a, b_g]``."""
        return np.asarray(self._f.x, dtype=float)

    @property
    def v_n(self) -> np.ndarray:
        return self.x[0:3]

    @property
    def quat(self) -> np.ndarray:
        return self.x[3:7]

    @property
    def accel_bias(self) -> np.ndarray:
        return self.x[7:10]

    @property
    def gyro_bias(self) -> np.ndarray:
        return self.x[10:13]

    @property
    def covariance(self) -> np.ndarray:
        """(13, 13) covariance of ``[v_n, q_nb, b_a, b_g]``."""
        return np.asarray(self._f.covariance, dtype=float)

    @property
    def error_covariance(self) -> np.ndarray:
        """(12, 12) covariance of ``[dv, dtheta, db_a, db_g]`` (dtheta: body-frame attitude error, rad)."""
        return np.asarray(self._f.error_covariance, dtype=float)

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

    def reset(self, v_n, q_nb, accel_bias=None, gyro_bias=None, P=None, lat=0.0, lon=0.0, h=0.0) -> None:
        """Start from a given state.

        Parameters
        ----------
        v_n : (3,) array_like
            NED velocity, m/s.
        q_nb : (4,) array_like
            Attitude [w, x, y, z] (normalized here).
        accel_bias, gyro_bias : (3,) array_like, optional
            m/s^2 and rad/s; zero when omitted.
        P : (13, 13) array_like, optional
            Covariance; default :func:`initial_covariance` with 0.3 m/s, 10/10/20 deg,
            2000 ug and 2 deg/h (the paper's initial errors).
        lat, lon : float
            Geodetic latitude and longitude, rad.
        h : float
            Height above the ellipsoid, m.
        """
        v = V.vector(v_n, "v_n", dtype=self.dtype)
        q = V.vector(q_nb, "q_nb", 4, dtype=self.dtype, nonzero=True)
        ba = np.zeros(3, self.dtype) if accel_bias is None else V.vector(accel_bias, "accel_bias", dtype=self.dtype)
        bg = np.zeros(3, self.dtype) if gyro_bias is None else V.vector(gyro_bias, "gyro_bias", dtype=self.dtype)
        if P is None:
            P = initial_covariance(q, 0.3048, np.radians([10.0, 10.0, 20.0]), 2000e-6 * 9.80665,
                                   np.radians(2.0) / 3600.0)
        P = V._numeric(P, "P")
        if P.shape != (13, 13) or not np.all(np.isfinite(P)):
            raise ValueError(f"P: expected a finite 13x13 matrix, got shape {P.shape}")
        for name, val in (("lat", lat), ("lon", lon), ("h", h)):
            if not np.isfinite(float(val)):
                raise ValueError(f"{name}: expected a finite number, got {val!r}")
        if not abs(float(lat)) < 1.5:
            raise ValueError(f"lat: expected |lat| < 1.5 rad, got {lat!r}")
        status = self._f.reset(v, q, ba, bg, np.asarray(P, self.dtype), float(lat), float(lon), float(h))
        if status != "ok":
            raise ValueError(f"reset: refused ({status})")

    def set_position(self, lat: float, lon: float, h: float) -> None:
        """Replace the carried position (lat, lon in rad, h in m) used for the Earth terms."""
        status = self._f.set_position(float(lat), float(lon), float(h))
        if status != "ok":
            raise ValueError(f"lat, lon, h: refused ({status})")

    # -- single steps ----------------------------------------------------------------------------
    def predict(self, f_ib_b, omega_ib_b, dt: float) -> str:
        """Time update with one IMU sample: specific force (m/s^2), angular rate (rad/s), ``dt`` (s)."""
        fb = V.vector(f_ib_b, "f_ib_b", dtype=self.dtype)
        wb = V.vector(omega_ib_b, "omega_ib_b", dtype=self.dtype)
        d = V.positive(dt, "dt")
        status = self._f.predict(fb, wb, d)
        if status == "not_initialized":
            raise ValueError("predict: the filter is not initialized (call reset first)")
        if status == "invalid_dt":
            raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
        return status

    def update_velocity(self, v_n, gate: float = 0.0):
        """NED velocity update (m/s); returns an UpdateResult (status, innovation, innovation_cov, nis)."""
        self._require_init("update_velocity")
        return self._f.update_velocity(V.vector(v_n, "v_n", dtype=self.dtype), float(gate))

    def update_yaw(self, yaw: float, gate: float = 0.0):
        """Yaw update (rad); the innovation is wrapped to (-pi, pi]."""
        self._require_init("update_yaw")
        y = float(yaw)
        if not np.isfinite(y):
            raise ValueError(f"yaw: expected a finite angle, got {yaw!r}")
        return self._f.update_yaw(y, float(gate))

    def update_velocity_yaw(self, v_n, yaw: float, gate: float = 0.0):
        """Joint velocity + yaw update (eq. 13), one 4-row correction."""
        self._require_init("update_velocity_yaw")
        y = float(yaw)
        if not np.isfinite(y):
            raise ValueError(f"yaw: expected a finite angle, got {yaw!r}")
        return self._f.update_velocity_yaw(V.vector(v_n, "v_n", dtype=self.dtype), y, float(gate))

    def _require_init(self, what: str) -> None:
        if not self._f.initialized:
            raise ValueError(f"{what}: the filter is not initialized (call reset first)")

    # -- batch -----------------------------------------------------------------------------------
    def run(self, f_ib_b, omega_ib_b, t=None, dt=None, vel_t=None, vel=None, yaw_t=None, yaw=None,
            gate_vel: float = 0.0, gate_yaw: float = 0.0, return_covariance: bool = False,
            on_invalid: str = "raise") -> NavResult:
        """Run the filter over N IMU samples and the measurements that fall among them (in C++).

        Parameters
        ----------
        f_ib_b : (N, 3) array_like
            Measured specific force, m/s^2 (mean over each sample interval).
        omega_ib_b : (N, 3) array_like
            Measured angular rate, rad/s.
        t : (N,) array_like, optional
            Strictly increasing end time of every IMU sample, s; the state given to :meth:`reset`
            is at ``t[0] - (t[1] - t[0])``. Or
        dt : float or (N,) array_like, optional
            Step lengths, s (then ``t = cumsum(dt)``, the state at time 0).
        vel_t, vel : (K,), (K, 3) array_like, optional
            Times (s, non-decreasing) and NED velocities (m/s).
        yaw_t, yaw : (M,), (M,) array_like, optional
            Times (s, non-decreasing) and yaw angles (rad).
        gate_vel, gate_yaw : float
            Chi-square gates on the NIS (0: no gate).
        return_covariance : bool
            Also return the (N, 13, 13) covariances.
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite IMU or measurement row raises ``ValueError`` naming the
            argument and row. "skip": such rows skip their step (an IMU row its predict, a
            measurement its update) and are reported in ``flags``, the per-measurement statuses
            and ``skipped_rows`` (keys ``"predict_skipped"``, ``"saturated"`` (IMU rows),
            ``"vel"``, ``"yaw"`` (measurement rows)). Timestamps must be finite and ordered in
            both modes. A saturated IMU row (``gyro_range`` / ``acc_range``) is skipped and
            reported in both modes.

        Returns
        -------
        NavResult
        """
        mode = V.on_invalid(on_invalid)
        strict = mode == "raise"
        self._require_init("run")
        fb = V.vectors(f_ib_b, "f_ib_b", dtype=self.dtype, finite=strict)
        n = fb.shape[0]
        wb = V.vectors(omega_ib_b, "omega_ib_b", n=n, dtype=self.dtype, finite=strict)
        steps = V.time_steps(n, dt=dt, t=t, dtype=np.float64, max_dt=float(self._f.params.max_dt))
        times = np.asarray(t, dtype=np.float64) if t is not None else np.cumsum(steps)
        vt, vv = self._measurements(vel_t, vel, "vel_t", "vel", 3, strict)
        yt, yv = self._measurements(yaw_t, yaw, "yaw_t", "yaw", 1, strict)
        out = self._f.run(fb, wb, times.astype(self.dtype), steps.astype(self.dtype), vt, vv, yt, yv[:, 0],
                          float(V.positive(gate_vel, "gate_vel", allow_zero=True)),
                          float(V.positive(gate_yaw, "gate_yaw", allow_zero=True)), bool(return_covariance))
        flags = out["flags"]
        skipped = {}
        for name in ("predict_skipped", "saturated"):
            rows = np.flatnonzero(flags & NAV13_FLAGS[name])
            if rows.size:
                skipped[name] = rows
        for name, status in (("vel", out["vel_status"]), ("yaw", out["yaw_status"])):
            # Updates refused for their input (not the gate, not the not-yet-reached ones).
            rows = np.flatnonzero(np.isin(status, [_STATUS_CODE["non_finite"], _STATUS_CODE["numerical_failure"],
                                                   _STATUS_CODE["solve_failed"]]))
            if rows.size:
                skipped[name] = rows
        return NavResult(t=times, x=out["x"], sigma=out["sigma"], att_sigma=out["att_sigma"], P=out["P"],
                         flags=flags, vel_innovation=out["vel_innovation"], vel_nis=out["vel_nis"],
                         vel_status=out["vel_status"], yaw_innovation=out["yaw_innovation"], yaw_nis=out["yaw_nis"],
                         yaw_status=out["yaw_status"], skipped_rows=skipped)

    def _measurements(self, times, values, tname, vname, cols, strict=True):
        if (times is None) != (values is None):
            raise ValueError(f"{tname}, {vname}: give both or neither")
        if times is None:
            return np.zeros(0, self.dtype), np.zeros((0, cols), self.dtype)
        ta = V._numeric(times, tname).astype(np.float64)
        if ta.ndim != 1:
            raise ValueError(f"{tname}: expected shape (K,), got {ta.shape}")
        r = V.first_bad_row(ta)
        if r is not None:
            raise ValueError(f"{tname}: non-finite value in row {r}")
        bad = np.flatnonzero(np.diff(ta) < 0)
        if bad.size:
            raise ValueError(f"{tname}: times must be non-decreasing; row {int(bad[0]) + 1} precedes row {int(bad[0])}")
        va = np.asarray(values)
        if cols == 1 and va.ndim == 1:
            va = va[:, None]
        va = V.vectors(va, vname, cols=cols, n=ta.shape[0], dtype=self.dtype, finite=strict)
        return ta.astype(self.dtype), va
