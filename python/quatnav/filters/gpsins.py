"""Loosely coupled GPS/INS feedback Kalman filter with altimeter and compass (paper 004).

:class:`GpsInsFilter` wraps ``quatnav._core.GpsInsFilter_f64`` / ``_f32`` (chosen by ``dtype``);
:meth:`GpsInsFilter.run` executes the whole record in C++ with the GIL released. The numpy twin
is :class:`quatnav.reference.GpsInsFilter`. The model (15 error states: NED position, velocity,
phi-angle attitude error, accelerometer and gyro biases; feedback of the estimate into the
strapdown mechanization after every correction) is described in ``quatnav/gps_ins.hpp``.
"""
from __future__ import annotations

import numbers
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate as V
from ._base import (AidResult, Filter, NavResult, aid_times, check_aid, check_imu_order, check_swapped, core,
                    no_mag, skipped_imu_rows, times_of)
from .tables import GPSINS_FLAGS, GPSINS_PARAMS, STATUS_NAMES

__all__ = ["GpsInsFilter", "GpsInsResult", "GPSINS_FLAGS", "STATE_NAMES", "PARAM_NAMES"]

#: Names of the 15 error states, in order (units: m, m/s, rad, m/s^2, rad/s).
STATE_NAMES = ("dp_n", "dp_e", "dp_d", "dv_n", "dv_e", "dv_d", "psi_n", "psi_e", "psi_d",
               "ba_x", "ba_y", "ba_z", "bg_x", "bg_y", "bg_z")

#: Parameter names (the table ``quatnav.filters.tables.GPSINS_PARAMS``: units and defaults).
PARAM_NAMES = tuple(p.name for p in GPSINS_PARAMS)


@dataclass(repr=False, eq=False)
class GpsInsResult(NavResult):
    """Output of :meth:`GpsInsFilter.run`: the fields of :class:`~quatnav.NavResult` (``position``
    ``[lat, lon, h]`` of the IMU, ``velocity``, ``quat``, the biases and ``sigma`` of the 15 error
    states :data:`STATE_NAMES`; NaN before navigation starts, ``quat`` NaN while aligning) and

    Attributes
    ----------
    counters : dict
        Per measurement kind (gps_pos, gps_vel, baro, baro_vd, compass): accepted, rejected by
        the chi-square gate, skipped as invalid; gps_pos and gps_vel also count ``resets``
        (gate lockout: after ``gps_reset_after`` consecutive rejections the next rejected fix
        resets the position or velocity to it).

    ``aids`` holds ``gps_pos`` and ``gps_vel`` (innovations (K, 3): INS minus aid, m and m/s),
    ``baro`` (height, (B, 1), m), ``baro_vd`` (the altimeter's vertical velocity, (B, 1), m/s)
    and ``compass`` ((C, 1), rad), for the aids given.
    """

    FLAGS: ClassVar[dict] = GPSINS_FLAGS
    counters: dict | None = None

    @property
    def navigating(self) -> np.ndarray:
        """(N,) bool: navigation running at each sample."""
        return self.flag("navigating")

    @property
    def rejections(self) -> dict:
        """Number of gate rejections per measurement kind."""
        return {k: v["rejected"] for k, v in self.counters.items()}


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


class GpsInsFilter(Filter):
    """15-state loosely coupled GPS/INS feedback filter with altimeter and compass (paper 004).

    The geodetic position is double in both precisions. An angle parameter outside its range
    raises ``ValueError``: it was most likely given in degrees (use ``np.radians``).

    ``run`` continues from the current state: a new filter (or one after :meth:`reset`) starts
    with the static alignment; a second call continues the navigation, its first IMU sample only
    fixing the clock (sample k holds the mean over ``(t[k-1], t[k]]``). For an unrelated log call
    :meth:`reset` or use a new filter.

    Examples
    --------
    >>> f = GpsInsFilter(gps_pos_sigma_h=3.0)            # doctest: +SKIP
    >>> res = f.run(gyr, acc, t=t, gps_pos=Aid(tg, llh), gps_vel=Aid(tg, vel))  # doctest: +SKIP
    >>> res.position, res.euler, res.sigma, res.counters   # doctest: +SKIP
    """

    n_states = 15
    PARAMS = GPSINS_PARAMS
    FLAGS = GPSINS_FLAGS
    _core_params = "GpsInsParams"

    def _make(self, p):
        return getattr(core(), "GpsInsFilter" + self._suffix)(p)

    # --- state --------------------------------------------------------------------------------
    @property
    def navigating(self) -> bool:
        return bool(self._f.navigating)

    @property
    def quat(self) -> np.ndarray:
        """Attitude ``q_nb`` [w, x, y, z], body to NED."""
        return np.array(self._f.q_nb)

    @property
    def v_n(self) -> np.ndarray:
        return np.array(self._f.v_n)

    @property
    def llh(self) -> np.ndarray:
        """[lat (rad), lon (rad), h (m)] of the IMU."""
        return np.array(self._f.llh)

    @property
    def acc_bias(self) -> np.ndarray:
        """Accelerometer bias, m/s^2."""
        return np.array(self._f.acc_bias)

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

    def clear(self) -> None:
        """Back to the start of alignment (parameters kept): the next IMU samples align again."""
        self._f.clear()

    def reset(self, q_nb, v_n, llh, acc_bias=(0.0, 0.0, 0.0), gyro_bias=(0.0, 0.0, 0.0), P=None) -> None:
        """Start navigation from a given state, skipping the static alignment (e.g. from a
        dataset's own initial alignment when the vehicle is not at rest at the start). As in every
        filter, ``reset`` starts from a state and ``initialize`` (attitude filters) from sensor
        readings.

        Parameters
        ----------
        q_nb : (4,) array_like
            Attitude [w, x, y, z], body to NED.
        v_n : (3,) array_like
            NED velocity of the IMU, m/s.
        llh : (3,) array_like
            IMU [lat (rad), lon (rad), h (m)].
        acc_bias, gyro_bias : (3,) array_like
            Initial bias estimates, m/s^2 and rad/s.
        P : (15, 15) array_like, optional
            Error-state covariance (:data:`STATE_NAMES`); default: the parameters' initial sigmas
            with GPS position sigmas ``gps_pos_sigma_h``/``_v`` and ``init_vel_sigma``.
        """
        q = V.vector(q_nb, "q_nb", 4, self.dtype)
        v = V.vector(v_n, "v_n", 3, self.dtype)
        llh = V.vector(llh, "llh", 3, np.float64)
        ba = V.vector(acc_bias, "acc_bias", 3, self.dtype)
        bg = V.vector(gyro_bias, "gyro_bias", 3, self.dtype)
        if P is None:
            p = self._f.params
            d = np.array([p.gps_pos_sigma_h, p.gps_pos_sigma_h, p.gps_pos_sigma_v] + [p.init_vel_sigma] * 3
                         + [p.init_level_sigma] * 2 + [p.init_yaw_sigma] + [p.init_acc_bias_sigma] * 3
                         + [p.init_gyro_bias_sigma] * 3)
            P = np.diag(d ** 2)
        P = np.asarray(V._numeric(P, "P"), dtype=self.dtype)
        if P.shape != (15, 15):
            raise ValueError(f"P: expected shape (15, 15), got {P.shape}")
        s = self._f.reset(q, v, float(llh[0]), float(llh[1]), float(llh[2]), ba, bg, P)
        if s != "ok":
            raise ValueError(f"q_nb, v_n, llh, P: rejected by the filter ({s})")

    # --- steps --------------------------------------------------------------------------------
    def predict(self, gyr, acc, dt: float) -> str:
        """One IMU interval: mean rate (rad/s), specific force (m/s^2), dt (s). Returns the status."""
        d = V.positive(dt, "dt")
        if d > float(self._f.params.max_dt):
            raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
        return self._f.predict(V.vector(gyr, "gyr", 3, self.dtype), V.vector(acc, "acc", 3, self.dtype), d)

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
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
            outages=(), on_invalid: str = "raise") -> GpsInsResult:
        """Run over an IMU record and aiding records at their own times (C++ loop, GIL released).

        Parameters
        ----------
        gyr : (N, 3) array_like
            Body rate omega_ib_b, rad/s (sample k: the mean over ``(t[k-1], t[k]]``).
        acc : (N, 3) array_like
            Specific force f_ib_b, m/s^2.
        mag : None
            The filter uses no magnetometer (heading from the compass aid or the GPS track); a
            value is a TypeError.
        t : (N,) array_like, keyword
            IMU times, s, strictly increasing; or
        dt : float or (N,) array_like, keyword
            Step lengths, s (``t = 0`` and the cumulated steps after the first).
        gps_pos : Aid, optional
            ``Aid(t, llh, sigma)``: times of validity (K,), s, strictly increasing; the antenna's
            ``[lat (rad), lon (rad), h (m)]`` (K, 3), an all-NaN row is no fix; optional one-sigma
            (K, 3), NED m, NaN entries take ``gps_pos_sigma_h`` / ``_v``.
        gps_vel : Aid, optional
            ``Aid(t, v_n, sigma)``: the antenna's NED velocity (K, 3), m/s, at the times of
            ``gps_pos`` (the filter takes a velocity with a position fix; all-NaN rows: no
            velocity); optional one-sigma (K, 3), m/s (NaN: ``gps_vel_sigma``).
        baro : Aid, optional
            ``Aid(t, h)``: altimeter times (B,), s, and heights (B,), m.
        compass : Aid, optional
            ``Aid(t, heading)``: compass times (C,), s, and magnetic headings (C,), rad (the
            ``declination`` parameter is added).
        outages : sequence of (t_start, t_end), optional
            GPS fixes with t_start <= t < t_end are dropped (simulated outages).
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite row (IMU, a partly-NaN or infinite GPS row, altimeter,
            compass) or IMU step above ``max_dt`` raises ``ValueError`` naming the argument and
            row. "skip": such rows skip their step and are reported in ``flags``
            (``predict_skipped``, ``aid_skipped``), the aids' ``status`` and ``skipped_rows``
            (keys ``"predict_skipped"``, ``"saturated"`` (IMU rows), ``"gps_pos"``, ``"baro"``,
            ``"compass"`` (aiding rows)). Times must be finite and strictly increasing in both
            modes. A saturated IMU row (``gyro_range`` / ``acc_range``) is skipped and reported in
            both modes.

        Returns
        -------
        GpsInsResult
        """
        strict = V.on_invalid(on_invalid) == "raise"
        gyr = check_imu_order(gyr, acc)
        no_mag(mag, "GpsInsFilter")
        if t is not None and dt is None:
            t = aid_times(t, "t")
            n = len(t)
            if n < 2:
                raise ValueError("t: need at least two IMU samples")
        else:
            n = len(V.vectors(gyr, "gyr", 3, dtype=self.dtype, finite=False))
            t = times_of(n, None, V.time_steps(n, dt=dt, t=t))
        gyro = V.vectors(gyr, "gyr", 3, n, self.dtype, finite=strict)
        accel = V.vectors(acc, "acc", 3, n, self.dtype, finite=strict)
        check_swapped(gyro, accel)
        if strict:
            big = np.flatnonzero(np.diff(t) > float(self._f.params.max_dt))
            if big.size:
                k = int(big[0]) + 1
                raise ValueError(f"t: step {float(t[k] - t[k - 1])!r} s in row {k} exceeds "
                                 f"max_dt={float(self._f.params.max_dt)!r} s")
        pos, vel = check_aid(gps_pos, "gps_pos", sigma_ok=True), check_aid(gps_vel, "gps_vel", sigma_ok=True)
        if vel is not None and pos is None:
            raise ValueError("gps_vel: needs gps_pos (the filter takes a velocity with a position fix)")
        if pos is None:
            gps_t, gps_llh = np.zeros(0), np.zeros((0, 3))
        else:
            gps_t = aid_times(pos.t, "gps_pos.t")
            gps_llh = pos.value
        ng = len(gps_t)
        gps_llh = _rows(gps_llh, "gps_pos.value", ng, 3, np.float64, True, strict)
        if strict and ng:
            bad = np.flatnonzero(np.abs(gps_llh[:, 0]) > np.pi / 2)
            if bad.size:
                raise ValueError(f"gps_pos.value: latitude beyond +-pi/2 rad in row {int(bad[0])}: {gps_llh[bad[0]]}")
        if vel is not None:
            vt = aid_times(vel.t, "gps_vel.t")
            if vt.shape != gps_t.shape or np.any(vt != gps_t):
                raise ValueError("gps_vel.t: expected the times of gps_pos (give NaN rows where a fix has no velocity)")
        gps_vel_v = _rows(None if vel is None else vel.value, "gps_vel.value", ng, 3, self.dtype, True, strict)
        gps_pos_sigma = _sigmas(None if pos is None else pos.sigma, "gps_pos.sigma", ng, self.dtype)
        gps_vel_sigma = _sigmas(None if vel is None else vel.sigma, "gps_vel.sigma", ng, self.dtype)
        if len(outages):
            gps_llh = gps_llh.copy()
            for o in outages:
                if len(o) != 2 or not o[1] > o[0]:
                    raise ValueError(f"outages: expected (t_start, t_end) pairs, got {o!r}")
                gps_llh[(gps_t >= o[0]) & (gps_t < o[1])] = np.nan
        b, c = check_aid(baro, "baro"), check_aid(compass, "compass")
        baro_t = np.zeros(0) if b is None else aid_times(b.t, "baro.t")
        baro_h = _rows(np.zeros(0) if b is None else b.value, "baro.value", len(baro_t), 1, np.float64, False, strict)
        compass_t = np.zeros(0) if c is None else aid_times(c.t, "compass.t")
        compass_yaw = _rows(np.zeros(0) if c is None else c.value, "compass.value", len(compass_t), 1, self.dtype,
                            False, strict)
        d = self._f.run(t, gyro, accel, gps_t, gps_llh, gps_vel_v, gps_pos_sigma, gps_vel_sigma,
                        baro_t, baro_h, compass_t, compass_yaw)
        flags = d["flags"]
        skipped = skipped_imu_rows(flags, GPSINS_FLAGS, drop_first=True)  # sample 0 only fixes the start time
        refused = [STATUS_NAMES.index(x) for x in ("non_finite", "numerical_failure", "solve_failed", "invalid_argument")]
        for name, key in (("gps_pos", "gps_status"), ("baro", "baro_status"), ("compass", "compass_status")):
            s_ = d[key].reshape(len(d[key]), -1) if len(d[key]) else np.zeros((0, 1), np.uint8)
            rows = np.flatnonzero(np.isin(s_, refused).any(axis=1))
            if name == "gps_pos" and ng:  # an all-NaN position row is an absent fix, not a refused one
                rows = rows[~np.isnan(gps_llh[rows]).all(axis=1)]
            if rows.size:
                skipped[name] = rows
        aids = {}
        if pos is not None:
            gi, gn, gs = d["gps_innov"].reshape(ng, 6), d["gps_nis"].reshape(ng, 2), d["gps_status"].reshape(ng, 2)
            aids["gps_pos"] = AidResult(gps_t, gi[:, 0:3], gn[:, 0], gs[:, 0])
            if vel is not None:
                aids["gps_vel"] = AidResult(gps_t, gi[:, 3:6], gn[:, 1], gs[:, 1])
        if b is not None:
            nb = len(baro_t)
            bi, bn, bs = d["baro_innov"].reshape(nb, 2), d["baro_nis"].reshape(nb, 2), d["baro_status"].reshape(nb, 2)
            aids["baro"] = AidResult(baro_t, bi[:, 0:1], bn[:, 0], bs[:, 0])
            aids["baro_vd"] = AidResult(baro_t, bi[:, 1:2], bn[:, 1], bs[:, 1])
        if c is not None:
            aids["compass"] = AidResult(compass_t, np.asarray(d["compass_innov"]).reshape(-1, 1), d["compass_nis"],
                                        d["compass_status"])
        return GpsInsResult("GpsInsFilter", t, d["q_nb"], d["gyro_bias"], d["sigma"], flags, aids=aids,
                            skipped_rows=skipped, sigma_names=STATE_NAMES, velocity=d["v_n"],
                            acc_bias=d["acc_bias"], position=d["llh"], counters=self.counters)
