"""13-state navigation filter of paper 002 (Seong 2012): velocity, attitude quaternion and
accelerometer and gyro biases, aided by NED velocity and yaw, with three time updates.

:class:`NavFilter13` wraps the C++ classes ``quatnav._core.NavFilter13{Ekf,SecondOrder,Ukf}_f64``
(and ``_f32``), chosen by ``time_update=`` and ``dtype=``; batch runs execute in C++ with the GIL
released. The plain numpy twin is :class:`quatnav.reference.NavFilter13`. The algorithm, its
equations and every deviation from the paper are documented in
``cpp/include/quatnav/nav_filter13.hpp``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate as V
from ..core import quaternion as Q
from ._compiled import compiled
from ._base import (AidResult, Filter, NavResult, aid_times, check_aid, check_imu_order, check_run_inputs, check_swapped,
                    no_mag, skipped_imu_rows, smoother_info, warn_aid_outside)
from .tables import NAV13_FLAGS, NAV13_PARAMS, STATUS_NAMES

__all__ = ["NavFilter13", "NavFilter13Result", "NAV13_FLAGS", "TIME_UPDATES", "initial_covariance"]

TIME_UPDATES = ("ekf", "second_order", "ukf")
_STATUS_CODE = {name: i for i, name in enumerate(STATUS_NAMES)}


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


@dataclass(repr=False, eq=False)
class NavFilter13Result(NavResult):
    """Output of :meth:`NavFilter13.run`: the fields of :class:`~quatnav.NavResult` (``position``
    is None: the filter carries its position for the Earth terms only) and

    Attributes
    ----------
    x : (N, 13) ndarray
        State ``[v_n (m/s), q_nb, b_a (m/s^2), b_g (rad/s)]`` after each sample and the
        measurements applied with it.
    P : (N, 13, 13) ndarray or None
        Covariances (only with ``return_covariance=True``).

    ``aids["gps_vel"]`` (innovation (K, 3), m/s) and ``aids["yaw"]`` (innovation (M, 1), rad,
    wrapped) hold the per-measurement diagnostics.
    """

    FLAGS: ClassVar[dict] = NAV13_FLAGS
    x: np.ndarray | None = None
    P: np.ndarray | None = None


class NavFilter13(Filter):
    """13-state navigation filter ``[v_n, q_nb, b_a, b_g]`` of paper 002.

    Mechanization eq. (1)-(3) with Earth rate, transport rate and WGS-84 gravity at a carried
    position (integrated from the estimated velocity; :meth:`set_position` replaces it), one Euler
    step per IMU sample; NED-velocity and yaw updates (eq. 13-14, 21-23).

    ``run`` continues from the current state: call :meth:`reset` first (the navigation filters
    start from a given state), and again (or use a new filter) for an unrelated log. The
    parameters' ``time_update``: ``"ekf"``: f(x_mean) and F P F^T + G Q G^T; ``"second_order"``:
    the mean corrected by 1/2 sum_ij P_ij d2f/dx_i dx_j (eq. 16-17), covariance as the EKF;
    ``"ukf"``: unscented transform in a 12-dimensional attitude-error state (25 sigma points).
    """

    n_states = 13
    PARAMS = NAV13_PARAMS
    FLAGS = NAV13_FLAGS
    _core_params = "NavFilter13Params"
    _fresh = True  # no step since reset/set_state: run applies a measurement at the start time

    def _make(self, p):
        f = compiled("NavFilter13 " + self._opts["time_update"], self.dtype)(p)
        if not f.params_valid:
            raise ValueError("ukf_alpha, ukf_kappa: alpha^2 (12 + kappa) must be positive")
        return f

    @property
    def time_update(self) -> str:
        return self._opts["time_update"]

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
    def acc_bias(self) -> np.ndarray:
        """Accelerometer bias, m/s^2."""
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

    def reset(self, v_n, q_nb, acc_bias=None, gyro_bias=None, P=None, lat=0.0, lon=0.0, h=0.0) -> None:
        """Start from a given state.

        Parameters
        ----------
        v_n : (3,) array_like
            NED velocity, m/s.
        q_nb : (4,) array_like
            Attitude [w, x, y, z] (normalized here).
        acc_bias, gyro_bias : (3,) array_like, optional
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
        ba = np.zeros(3, self.dtype) if acc_bias is None else V.vector(acc_bias, "acc_bias", dtype=self.dtype)
        bg = np.zeros(3, self.dtype) if gyro_bias is None else V.vector(gyro_bias, "gyro_bias", dtype=self.dtype)
        if P is None:
            P = initial_covariance(q, 0.3048, np.radians([10.0, 10.0, 20.0]), 2000e-6 * 9.80665,
                                   np.radians(2.0) / 3600.0)
        P = V._numeric(P, "P")
        if P.shape != (13, 13) or not np.all(np.isfinite(P)):
            raise ValueError(f"P: expected a finite 13x13 matrix, got shape {P.shape}")
        _check_position(lat, lon, h)
        status = self._f.reset(v, q, ba, bg, np.asarray(P, self.dtype), float(lat), float(lon), float(h))
        if status != "ok":
            raise ValueError(f"reset: refused ({status})")
        self._fresh = True

    def set_state(self, state: dict) -> None:
        super().set_state(state)
        self._fresh = True

    set_state.__doc__ = Filter.set_state.__doc__

    def set_position(self, lat: float, lon: float, h: float) -> None:
        """Replace the carried position (lat, lon in rad, h in m) used for the Earth terms."""
        _check_position(lat, lon, h)
        status = self._f.set_position(float(lat), float(lon), float(h))
        if status != "ok":
            raise ValueError(f"lat, lon, h: refused ({status})")

    # -- single steps ----------------------------------------------------------------------------
    def predict(self, gyr, acc, dt: float) -> str:
        """Time update with one IMU sample: angular rate (rad/s), specific force (m/s^2), ``dt`` (s)."""
        wb = V.vector(gyr, "gyr", dtype=self.dtype)
        fb = V.vector(acc, "acc", dtype=self.dtype)
        d = V.positive(dt, "dt")
        status = self._f.predict(wb, fb, d)
        self._fresh = False
        if status == "not_initialized":
            raise ValueError("predict: the filter is not initialized (call reset first)")
        if status == "invalid_dt":
            raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
        return status

    def update_velocity(self, v_n, gate: float = 0.0):
        """NED velocity update (m/s); returns an UpdateResult (status, innovation, innovation_cov, nis)."""
        self._require_init("update_velocity")
        self._fresh = False
        return self._f.update_velocity(V.vector(v_n, "v_n", dtype=self.dtype), float(gate))

    def update_yaw(self, yaw: float, gate: float = 0.0):
        """Yaw update (rad); the innovation is wrapped to (-pi, pi]."""
        self._require_init("update_yaw")
        self._fresh = False
        y = float(yaw)
        if not np.isfinite(y):
            raise ValueError(f"yaw: expected a finite angle, got {yaw!r}")
        return self._f.update_yaw(y, float(gate))

    def update_velocity_yaw(self, v_n, yaw: float, gate: float = 0.0):
        """Joint velocity + yaw update (eq. 13), one 4-row correction."""
        self._require_init("update_velocity_yaw")
        self._fresh = False
        y = float(yaw)
        if not np.isfinite(y):
            raise ValueError(f"yaw: expected a finite angle, got {yaw!r}")
        return self._f.update_velocity_yaw(V.vector(v_n, "v_n", dtype=self.dtype), y, float(gate))

    def _require_init(self, what: str) -> None:
        if not self._f.initialized:
            raise ValueError(f"{what}: the filter is not initialized (call reset first)")

    # -- batch -----------------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_vel=None, yaw=None, return_covariance: bool = False,
            on_invalid: str = "raise", smooth: bool = False) -> NavFilter13Result:
        """Run the filter over N IMU samples and the measurements that fall among them (in C++),
        continuing from the current state (given by :meth:`reset` or the previous run).

        A measurement is applied after the first IMU sample that ends at or after its time
        (within 1e-4 of the step). One older than the state (before ``t[0] - dt[0]``) is never
        applied (status ``not_initialized``, as for one after the last sample). One at the
        state's time is applied before the first step when the run starts from :meth:`reset` or
        :meth:`set_state`, and not when it continues a previous run or steps (which applied it
        after its last sample): a record run in chunks, each given the whole aid record, gives
        the run of the whole record, each measurement applied once.

        Parameters
        ----------
        gyr : (N, 3) array_like
            Measured angular rate, rad/s (mean over each sample interval).
        acc : (N, 3) array_like
            Measured specific force, m/s^2.
        mag : None
            The filter uses no magnetometer (its place in the shape shared by every filter); a
            value is a TypeError.
        t : (N,) array_like, keyword
            Strictly increasing end time of every IMU sample, s; the state given to :meth:`reset`
            is at ``t[0] - (t[1] - t[0])``. Or
        dt : float or (N,) array_like, keyword
            Step lengths, s (then ``t = cumsum(dt)``, the state at time 0).
        gps_vel : Aid, optional
            ``Aid(t, v_n)``: times (K,), s, non-decreasing, and NED velocities (K, 3), m/s (one-sigma:
            the ``gps_vel_sigma`` parameter; gate ``gate_gps_vel``).
        yaw : Aid, optional
            ``Aid(t, yaw)``: times (M,), s, non-decreasing, and yaw angles (M,), rad (``yaw_sigma``,
            ``gate_yaw``).
        return_covariance : bool
            Also return the (N, 13, 13) covariances.
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite IMU or measurement row raises ``ValueError`` naming the
            argument and row. "skip": such rows skip their step (an IMU row its predict, a
            measurement its update) and are reported in ``flags``, the aids' statuses and
            ``skipped_rows`` (keys ``"predict_skipped"``, ``"saturated"`` (IMU rows),
            ``"gps_vel"``, ``"yaw"`` (measurement rows)). Timestamps must be finite and ordered in
            both modes. A saturated IMU row (``gyro_range`` / ``acc_range``) is skipped and
            reported in both modes.
        smooth : bool
            Also run the Rauch-Tung-Striebel backward pass (in C++, after the forward pass; see
            ``docs/SMOOTHING.md``): the result's estimates, ``sigma``, ``att_sigma`` (and ``P``)
            are then the smoothed ones, each using every sample of the run, and ``forward``
            holds the causal result. The forward pass's decisions (rejected measurements,
            skipped samples) are kept. The filter's state afterwards is the forward one at the
            last sample (where the two agree).

        Returns
        -------
        NavFilter13Result
        """
        mode = V.on_invalid(on_invalid)
        strict = mode == "raise"
        self._require_init("run")
        wb = V.vectors(check_imu_order(gyr, acc), "gyr", dtype=self.dtype, finite=strict)
        no_mag(mag, "NavFilter13")
        n = wb.shape[0]
        fb = V.vectors(acc, "acc", n=n, dtype=self.dtype, finite=strict)
        check_swapped(wb, fb)
        steps = V.time_steps(n, dt=dt, t=t, dtype=np.float64, max_dt=float(self._f.params.max_dt))
        check_run_inputs(self, wb, fb, steps=steps, axes="frd")
        times = np.asarray(t, dtype=np.float64) if t is not None else np.cumsum(steps)
        vt, vv = self._measurements(check_aid(gps_vel, "gps_vel"), "gps_vel", 3, strict)
        yt, yv = self._measurements(check_aid(yaw, "yaw"), "yaw", 1, strict)
        if n:
            for name, at in (("gps_vel", vt), ("yaw", yt)):
                warn_aid_outside("NavFilter13", name, at, float(times[0] - steps[0]), float(times[-1]))
        out = self._f.run(wb, fb, times, steps.astype(self.dtype), vt, vv, yt, yv[:, 0],
                          float(self._opts["gate_gps_vel"]), float(self._opts["gate_yaw"]), bool(return_covariance),
                          bool(smooth), apply_at_start=self._fresh)
        if n:
            self._fresh = False
        flags = out["flags"]
        skipped = skipped_imu_rows(flags, NAV13_FLAGS)
        for name, status in (("gps_vel", out["vel_status"]), ("yaw", out["yaw_status"])):
            # Updates refused for their input (not the gate, not the not-yet-reached ones).
            rows = np.flatnonzero(np.isin(status, [_STATUS_CODE["non_finite"], _STATUS_CODE["numerical_failure"],
                                                   _STATUS_CODE["solve_failed"]]))
            if rows.size:
                skipped[name] = rows
        aids = {}
        if gps_vel is not None:
            aids["gps_vel"] = AidResult(vt.astype(np.float64), out["vel_innovation"], out["vel_nis"], out["vel_status"])
        if yaw is not None:
            aids["yaw"] = AidResult(yt.astype(np.float64), np.asarray(out["yaw_innovation"]).reshape(-1, 1),
                                    out["yaw_nis"], out["yaw_status"])
        def result(o, **kw):
            x = o["x"]
            return NavFilter13Result("NavFilter13", times, x[:, 3:7], x[:, 10:13], o["sigma"], flags, aids=aids,
                                     skipped_rows=skipped, sigma_names=_SIGMA_NAMES, velocity=x[:, 0:3],
                                     acc_bias=x[:, 7:10], att_sigma=o["att_sigma"], x=x, P=o["P"], **kw)

        fwd = result(out)
        if not smooth:
            return fwd
        sm = out["smoothed"]
        return result(sm, forward=fwd, smoother=smoother_info(sm["info"]))

    def _measurements(self, aid, name, cols, strict=True):
        if aid is None:
            return np.zeros(0), np.zeros((0, cols), self.dtype)
        tname, vname = f"{name}.t", f"{name}.value"
        ta = aid_times(aid.t, tname, strict_increasing=False)
        va = np.asarray(aid.value)
        if cols == 1 and va.ndim == 1:
            va = va[:, None]
        va = V.vectors(va, vname, cols=cols, n=ta.shape[0], dtype=self.dtype, finite=strict, like=tname)
        return ta, va  # aid_times gives contiguous float64: times stay double whatever the dtype


def _check_position(lat, lon, h) -> None:
    for name, val in (("lat", lat), ("lon", lon), ("h", h)):
        if not np.isfinite(float(val)):
            raise ValueError(f"{name}: expected a finite number, got {val!r}")
    V.angle(float(lat), "lat", 1.5)  # the Earth terms' limit, short of the pole


_SIGMA_NAMES = ("v_n", "v_e", "v_d", "q0", "q1", "q2", "q3", "ba_x", "ba_y", "ba_z", "bg_x", "bg_y", "bg_z")
