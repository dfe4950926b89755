"""Loosely coupled GPS/INS feedback Kalman filter with altimeter and compass (paper 004).

:class:`GpsInsFilter` wraps ``quatnav._core.GpsInsFilter_f64`` / ``_f32`` (chosen by ``dtype``;
``GpsInsFilterScale_f64`` / ``_f32`` with ``scale_factors=True``);
:meth:`GpsInsFilter.run` executes the whole record in C++ with the GIL released. The numpy twin
is :class:`quatnav.reference.GpsInsFilter`. The model (16 error states: NED position, velocity,
phi-angle attitude error, accelerometer and gyro biases, altimeter offset; with
``scale_factors=True`` also the accelerometer and gyro scale factors, 22 states; feedback of the
estimate into the strapdown mechanization after every correction; one gated correction path
for every aid with outlier isolation, covariance inflation and process-noise adaptation) is
described in ``cpp/include/quatnav/nav/gps_ins.hpp``.
"""
from __future__ import annotations

import numbers
import warnings
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate as V
from ._compiled import compiled
from ._base import (AidResult, Filter, NavResult, accel_unit, aid_times, check_aid, check_imu_order, check_run_inputs,
                    check_swapped, skipped_imu_rows, smoother_info, times_of, warn_aid_outside)
from .tables import GNSS_SOLUTIONS, GPSINS_DECISIONS, GPSINS_FLAGS, GPSINS_PARAMS, STATUS_NAMES

__all__ = ["GpsInsFilter", "GpsInsResult", "GpsInsAidResult", "NavigationWarning", "GPSINS_FLAGS", "GPSINS_DECISIONS",
           "GNSS_SOLUTIONS", "SOLUTION_CODES", "STATE_NAMES", "SCALE_STATE_NAMES", "PARAM_NAMES", "gnss_solution"]

#: Names of the 16 error states, in order (units: m, m/s, rad, m/s^2, rad/s, m).
STATE_NAMES = ("dp_n", "dp_e", "dp_d", "dv_n", "dv_e", "dv_d", "psi_n", "psi_e", "psi_d",
               "ba_x", "ba_y", "ba_z", "bg_x", "bg_y", "bg_z", "baro_offset")
#: With ``scale_factors=True``: the 16 and the accelerometer and gyro scale factors (1), 22.
SCALE_STATE_NAMES = STATE_NAMES + ("sa_x", "sa_y", "sa_z", "sg_x", "sg_y", "sg_z")

#: Parameter names (the table ``quatnav.filters.tables.GPSINS_PARAMS``: units and defaults).
PARAM_NAMES = tuple(p.name for p in GPSINS_PARAMS)


#: The receivers' solution quality codes by format (``quatnav.io.Gnss.quality_kind``) as
#: :data:`GNSS_SOLUTIONS` names: RTKLIB's Q, NMEA GGA's fix quality, PX4's fix_type, ROS
#: NavSatStatus (whose GBAS fix may be RTK fixed or float: unknown).
SOLUTION_CODES = {
    "rtklib": {1: "rtk_fixed", 2: "rtk_float", 3: "dgnss", 4: "dgnss", 5: "single", 6: "dgnss"},
    "nmea-gga": {1: "single", 2: "dgnss", 3: "single", 4: "rtk_fixed", 5: "rtk_float", 9: "dgnss"},
    "px4-fix_type": {2: "single", 3: "single", 4: "dgnss", 5: "rtk_float", 6: "rtk_fixed"},
    "navsatstatus": {0: "single", 1: "dgnss"},
}


def gnss_solution(quality, quality_kind: str) -> np.ndarray:
    """The solution kind of each fix (codes of :data:`GNSS_SOLUTIONS`, for ``run(...,
    gps_solution=)``) from a receiver's quality codes ``quality`` (K,) in the format
    ``quality_kind`` (a key of :data:`SOLUTION_CODES`, as ``quatnav.io.Gnss.quality_kind``);
    unknown codes and formats give ``unknown`` (the floor ``gps_pos_sigma_min``)."""
    table = SOLUTION_CODES.get(quality_kind, {})
    q = np.asarray(quality).reshape(-1)
    return np.array([GNSS_SOLUTIONS.index(table.get(int(c), "unknown")) for c in q], dtype=np.uint8)


def _solutions(x, n: int):
    """``gps_solution`` as (n,) uint8 codes (names of GNSS_SOLUTIONS or codes), or None."""
    if x is None:
        return None
    a = np.asarray(x)
    if a.shape != (n,):
        raise ValueError(f"gps_solution: expected shape ({n},) (one per gps_pos fix), got {a.shape}")
    if a.dtype.kind in "OUS":
        bad = [v for v in a if v not in GNSS_SOLUTIONS]
        if bad:
            raise ValueError(f"gps_solution: unknown kind {bad[0]!r}; known: {', '.join(GNSS_SOLUTIONS)}")
        return np.array([GNSS_SOLUTIONS.index(v) for v in a], dtype=np.uint8)
    if a.dtype.kind not in "iu" or (n and (a.min() < 0 or a.max() >= len(GNSS_SOLUTIONS))):
        raise ValueError(f"gps_solution: expected codes 0..{len(GNSS_SOLUTIONS) - 1} or names {GNSS_SOLUTIONS}")
    return a.astype(np.uint8)


class NavigationWarning(UserWarning):
    """:meth:`GpsInsFilter.run` ended without navigating over a record long enough to align (the
    result's ``alignment["reason"]`` says why)."""


@dataclass(repr=False, eq=False)
class GpsInsAidResult(AidResult):
    """The diagnostics of one GpsInsFilter aid (:class:`~quatnav.AidResult`: ``t``, ``innovation``
    INS minus aid, ``nis`` the NIS its gate saw, ``status``) and what the filter did with each sample.

    Attributes
    ----------
    decision : (K,) uint8 ndarray
        Code of :data:`GPSINS_DECISIONS` (``decision_names``): ``accepted``, ``weighted``
        (applied with its far components down-weighted: ``gps_robust_k``), ``rejected`` (a gross
        outlier, isolated), ``inflated`` (applied after the covariance was inflated: the INS had
        drifted), ``reset`` (the state put on the fix), ``skipped`` (invalid), ``aligned`` (used
        by the alignment), ``none`` (no update).
    inflation : (K,) ndarray
        Factor applied to the position, velocity and attitude covariance (1 unless inflated).
    """

    decision: np.ndarray | None = None
    inflation: np.ndarray | None = None

    @property
    def decision_names(self) -> np.ndarray:
        """(K,) the decisions as strings."""
        return np.array([GPSINS_DECISIONS[int(d)] for d in self.decision], dtype=object)

    def decisions(self) -> dict:
        """Number of samples per decision name (only those that occur)."""
        codes, n = np.unique(self.decision, return_counts=True)
        return {GPSINS_DECISIONS[int(c)]: int(k) for c, k in zip(codes, n)}

    def to_dataframe(self):
        """As :meth:`AidResult.to_dataframe`, with ``decision`` (names) and ``inflation``."""
        df = super().to_dataframe()
        df["decision"] = self.decision_names
        df["inflation"] = self.inflation
        return df

    def __repr__(self) -> str:
        return f"GpsInsAidResult({len(self.t)} samples, {self.decisions()})"


@dataclass(repr=False, eq=False)
class GpsInsResult(NavResult):
    """Output of :meth:`GpsInsFilter.run`: the fields of :class:`~quatnav.NavResult` (``position``
    ``[lat, lon, h]`` of the IMU, ``velocity``, ``quat``, the biases and ``sigma`` of the 16 error
    states :data:`STATE_NAMES`; NaN before navigation starts, ``quat`` NaN while aligning) and
    the attributes below.

    ``aids`` holds :class:`GpsInsAidResult` (with each sample's ``decision`` and ``inflation``):
    ``gps_pos`` and ``gps_vel`` (innovations (K, 3): INS minus aid, m and m/s), ``baro`` (height,
    (B, 1), m), ``baro_vd`` (the altimeter's vertical velocity, (B, 1), m/s) and ``compass`` ((C,
    1), rad), ``mag`` (the magnetometer heading, (M, 1), rad), ``odometer`` ((O, 1), m/s) for
    the aids given, and the pseudo-measurements ``zupt`` ((Z, 3), m/s), ``zaru`` ((Z, 3), rad/s)
    and ``nhc`` ((H, 2), m/s) at the IMU samples where they were made.

    Attributes
    ----------
    counters : dict
        Per measurement kind (gps_pos, gps_vel, baro, baro_vd, compass): accepted, rejected by
        the gate, skipped as invalid, ``inflated`` (applied after a covariance inflation),
        ``resets`` (the state put on the fix) and ``weighted`` (applied down-weighted, counted in
        accepted too).
    baro_offset : (N,) ndarray
        The altimeter offset estimate (its reading minus the ellipsoidal height), m; NaN until
        the first altimeter sample in navigation.
    q_scale : (N,) ndarray
        The process-noise scale of the innovation-based adaptation (1: the configured noise).
    acc_scale, gyro_scale : (N, 3) ndarray or None
        The scale-factor estimates (``scale_factors=True``; else None): the sensor reads
        ``(1 + s) * x + b`` per axis. Their one-sigmas are the last six columns of ``sigma``.
    alignment : dict
        How the filter was aligned: ``method`` (``"static"``: levelled at rest from the
        accelerometer; ``"gnss_velocity"``: in motion, the GNSS velocity change against the
        specific force; ``"gnss_course"``: in motion with positions only, level from the mean
        specific force; ``"given"``: :meth:`GpsInsFilter.set_initial` or ``reset``; ``"none"``),
        ``heading`` (``"compass"``, ``"magnetometer"``, ``"gnss_velocity"``, ``"gnss_course"``,
        ``"given"``, ``"none"``), ``level_t`` and ``navigation_t`` (the times of the first
        levelled and the first navigating sample of this run, s; None when not reached) and
        ``reason``: when navigation did not start, one sentence saying which step of the
        alignment was not reached and what it needed (None otherwise).
    """

    FLAGS: ClassVar[dict] = GPSINS_FLAGS
    counters: dict | None = None
    baro_offset: np.ndarray | None = None
    q_scale: np.ndarray | None = None
    acc_scale: np.ndarray | None = None
    gyro_scale: np.ndarray | None = None
    alignment: dict | None = None

    def _columns(self) -> dict:
        cols = super()._columns()
        if self.acc_scale is not None:
            for i, c in enumerate("xyz"):
                cols[f"acc_scale_{c}"] = self.acc_scale[:, i]
            for i, c in enumerate("xyz"):
                cols[f"gyro_scale_{c}"] = self.gyro_scale[:, i]
        return cols

    @property
    def navigating(self) -> np.ndarray:
        """(N,) bool: navigation running at each sample."""
        return self.flag("navigating")

    @property
    def rejections(self) -> dict:
        """Number of gate rejections per measurement kind."""
        return {k: v["rejected"] for k, v in self.counters.items()}


def _rows(x, name, k, cols, dtype, allow_nan_rows, finite=True, like=None):
    if x is None:
        return np.full((k, cols), np.nan, dtype=dtype) if cols > 1 else np.full(k, np.nan, dtype=dtype)
    if cols == 1:
        a = V._numeric(x, name)
        if a.shape == (k, 1):  # one column (a DataFrame's df[["h"]]): the (K, m) form of Aid, m = 1
            a = a[:, 0]
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
    return V.vectors(x, name, cols=cols, n=k, dtype=dtype, finite=finite, allow_nan_rows=allow_nan_rows,
                     like=like or name.split(".")[0] + ".t")


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


def _aid_results(rep: dict, t, names, m: int) -> dict:
    """The :class:`GpsInsAidResult` of each update column of one aid's report (a GPS fix holds
    position and velocity, an altimeter sample height and vertical velocity)."""
    out = {}
    for c, name in enumerate(names):
        out[name] = GpsInsAidResult(t, rep["innovation"][:, c * m:(c + 1) * m], rep["nis"][:, c], rep["status"][:, c],
                                    decision=rep["decision"][:, c], inflation=rep["inflation"][:, c])
    return out


def _take(rep: dict, rows) -> dict:
    """The rows of an aid's report."""
    return {k: v[rows] for k, v in rep.items()}


def _finite(x, name) -> float:
    if isinstance(x, bool) or not isinstance(x, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected a real number, got {type(x).__name__}")
    v = float(x)
    if not np.isfinite(v):
        raise ValueError(f"{name}: expected a finite number, got {V.num(x)}")
    return v


def _outages(x) -> np.ndarray:
    """The (K, 2) ``(t_start, t_end)`` rows of ``run(outages=...)`` (None: none)."""
    if x is None:
        return np.zeros((0, 2))
    a = V._numeric(x, "outages")
    if a.size == 0:
        return np.zeros((0, 2))
    if a.ndim == 1 and a.shape == (2,):
        raise ValueError(f"outages: expected a sequence of (t_start, t_end) pairs, got one pair {tuple(a.tolist())}: "
                         f"give [{tuple(a.tolist())}]")
    if a.ndim != 2 or a.shape[1] != 2:
        raise ValueError(f"outages: expected a sequence of (t_start, t_end) pairs, got shape {a.shape}")
    a = a.astype(np.float64)
    bad = np.flatnonzero(~(a[:, 1] > a[:, 0]))
    if bad.size:
        raise ValueError(f"outages: expected (t_start, t_end) pairs with t_end > t_start; row {int(bad[0])} is "
                         f"{tuple(a[bad[0]].tolist())}")
    return a


class GpsInsFilter(Filter):
    """16-state loosely coupled GPS/INS feedback filter with altimeter and compass (paper 004); 22
    states with ``scale_factors=True`` (:attr:`state_names`).

    The geodetic position is double in both precisions. An angle parameter outside its range
    raises ``ValueError``: it was most likely given in degrees (use ``np.radians``).

    ``run`` continues from the current state: a new filter (or one after :meth:`clear`) starts
    with the alignment, one after :meth:`reset` or :meth:`set_initial` from the state given; a
    second call continues the navigation, its first IMU sample only fixing the clock (sample k
    holds the mean over ``(t[k-1], t[k]]``). For an unrelated log call :meth:`clear` or use a new
    filter.

    Examples
    --------
    >>> f = GpsInsFilter(gps_pos_sigma_h=3.0)            # doctest: +SKIP
    >>> res = f.run(gyr, acc, t=t, gps_pos=Aid(tg, llh), gps_vel=Aid(tg, vel))  # doctest: +SKIP
    >>> res.position, res.euler, res.sigma, res.counters   # doctest: +SKIP
    """

    PARAMS = GPSINS_PARAMS
    FLAGS = GPSINS_FLAGS
    _core_params = "GpsInsParams"

    def _make(self, p):
        name = "GpsInsFilter scale_factors" if self._opts["scale_factors"] else "GpsInsFilter"
        return compiled(name, self.dtype)(p)

    @property
    def state_names(self) -> tuple:
        """Names of the error states (:data:`STATE_NAMES`, or :data:`SCALE_STATE_NAMES` with
        ``scale_factors=True``)."""
        return SCALE_STATE_NAMES if self._opts["scale_factors"] else STATE_NAMES

    @property
    def n_states(self) -> int:
        """Number of error states: 16, or 22 with ``scale_factors=True``."""
        return len(self.state_names)

    # --- state --------------------------------------------------------------------------------
    @property
    def navigating(self) -> bool:
        return bool(self._f.navigating)

    @property
    def initialized(self) -> bool:
        """True while navigating: the filter has a full state (the ``initialized`` flag marks the
        sample where navigation started)."""
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
    def acc_scale(self) -> np.ndarray:
        """Accelerometer scale-factor estimate (1; zero without ``scale_factors``)."""
        return np.array(self._f.acc_scale)

    @property
    def gyro_scale(self) -> np.ndarray:
        """Gyro scale-factor estimate (1; zero without ``scale_factors``)."""
        return np.array(self._f.gyro_scale)

    @property
    def baro_offset(self) -> float:
        """Altimeter offset estimate (its reading minus the ellipsoidal height), m."""
        return float(self._f.baro_offset)

    @property
    def q_scale(self) -> float:
        """Process-noise scale of the innovation-based adaptation (1: the configured noise)."""
        return float(self._f.q_scale)

    @property
    def covariance(self) -> np.ndarray:
        """(16, 16) error-state covariance (:attr:`state_names`; (22, 22) with ``scale_factors``)."""
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
        P : (16, 16) array_like, optional
            Error-state covariance (:attr:`state_names`; (22, 22) with ``scale_factors``);
            default: the parameters' initial sigmas with GPS position sigmas
            ``gps_pos_sigma_h``/``_v`` and ``init_vel_sigma`` (the altimeter offset is
            initialized by the first altimeter sample). The scale-factor estimates start at zero.
        """
        q = V.vector(q_nb, "q_nb", 4, self.dtype)
        v = V.vector(v_n, "v_n", 3, self.dtype)
        llh = V.vector(llh, "llh", 3, np.float64)
        V.angle(llh[0], "llh: latitude", np.pi / 2)
        ba = V.vector(acc_bias, "acc_bias", 3, self.dtype)
        bg = V.vector(gyro_bias, "gyro_bias", 3, self.dtype)
        if P is None:
            p = self._f.params
            d = np.array([p.gps_pos_sigma_h, p.gps_pos_sigma_h, p.gps_pos_sigma_v] + [p.init_vel_sigma] * 3
                         + [p.init_level_sigma] * 2 + [p.init_yaw_sigma] + [p.init_acc_bias_sigma] * 3
                         + [p.init_gyro_bias_sigma] * 3 + [0.0])
            if self._opts["scale_factors"]:
                d = np.concatenate([d, [p.init_acc_scale_sigma] * 3 + [p.init_gyro_scale_sigma] * 3])
            P = np.diag(d ** 2)
        P = np.asarray(V._numeric(P, "P"), dtype=self.dtype)
        n = len(self.state_names)
        if P.shape != (n, n):
            raise ValueError(f"P: expected shape ({n}, {n}), got {P.shape}")
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

    def update_gps(self, lat, lon, h, v_n=None, pos_sigma=None, vel_sigma=None, age=0.0, solution="unknown"):
        """One GPS fix (rad, rad, m; NED m/s or None), valid ``age`` seconds before the filter's
        time, of the receiver's solution kind ``solution`` (a name of :data:`GNSS_SOLUTIONS` or its
        code: it sets the floor of the position one-sigma). Returns (position result, velocity result), each with its ``decision`` code
        (:data:`GPSINS_DECISIONS`) and ``inflation``."""
        nan3 = np.full(3, np.nan, self.dtype)
        la, lo, hh = V.angle(_finite(lat, "lat"), "lat", np.pi / 2), _finite(lon, "lon"), _finite(h, "h")
        v = nan3 if v_n is None else V.vector(v_n, "v_n", 3, self.dtype)
        ps = nan3 if pos_sigma is None else _sigmas(np.reshape(V._numeric(pos_sigma, "pos_sigma"), (1, -1))
                                                    if np.ndim(pos_sigma) == 1 else pos_sigma, "pos_sigma", 1,
                                                    self.dtype)[0]
        vs = nan3 if vel_sigma is None else _sigmas(np.reshape(V._numeric(vel_sigma, "vel_sigma"), (1, -1))
                                                    if np.ndim(vel_sigma) == 1 else vel_sigma, "vel_sigma", 1,
                                                    self.dtype)[0]
        return self._f.update_gps(la, lo, hh, v, ps, vs, _finite(age, "age"), int(_solutions([solution], 1)[0]))

    @property
    def at_rest(self) -> bool:
        """The rest detector's state (the IMU still for ``rest_time``)."""
        return bool(self._f.at_rest)

    @property
    def alignment(self) -> dict:
        """How the filter was aligned: ``method`` and ``heading`` (see :class:`GpsInsResult`)."""
        return {"method": self._f.align_method, "heading": self._f.heading_source}

    def set_initial(self, q_nb=None, *, euler=None, v_n=None, acc_bias=(0.0, 0.0, 0.0),
                    gyro_bias=(0.0, 0.0, 0.0)) -> None:
        """Start from a given attitude instead of the alignment (a vehicle already moving, an
        attitude known from elsewhere): the filter waits levelled, with its heading, for the
        first GNSS fix, which gives the position and (unless ``v_n`` is given) the velocity. The
        initial one-sigma values are the parameters ``init_level_sigma``, ``init_yaw_sigma``,
        ``init_vel_sigma``, ``init_acc_bias_sigma``, ``init_gyro_bias_sigma``.

        Parameters
        ----------
        q_nb : (4,) array_like, optional
            Attitude [w, x, y, z], body to NED; or
        euler : (3,) array_like, optional
            ZYX Euler angles [roll, pitch, yaw], rad.
        v_n : (3,) array_like, optional
            NED velocity, m/s (default: the first fix's, or zero).
        acc_bias, gyro_bias : (3,) array_like
            Initial bias estimates, m/s^2 and rad/s.
        """
        from ..core import quaternion as Q
        if (q_nb is None) == (euler is None):
            raise TypeError("set_initial: give exactly one of q_nb and euler")
        if euler is not None:
            e = V.euler(euler, "euler")
            q = Q.from_euler(e).astype(self.dtype)
        else:
            q = V.vector(q_nb, "q_nb", 4, self.dtype, nonzero=True)
        v = np.zeros(3, self.dtype) if v_n is None else V.vector(v_n, "v_n", 3, self.dtype)
        st = self._f.set_initial(q, v, v_n is not None, V.vector(acc_bias, "acc_bias", 3, self.dtype),
                                 V.vector(gyro_bias, "gyro_bias", 3, self.dtype))
        if st != "ok":
            raise ValueError(f"set_initial: refused by the filter ({st}; only before navigation starts)")

    def update_mag(self, m):
        """One raw magnetometer sample (IMU axes, any unit). Returns the update result."""
        return self._f.update_mag(V.vector(m, "m", 3, self.dtype))

    def update_odometer(self, speed: float):
        """One odometer speed along the body x axis, m/s. Returns the update result."""
        return self._f.update_odometer(_finite(speed, "speed"))

    def update_constraints(self):
        """The pseudo-measurements after a :meth:`predict`: ZUPT and ZARU at rest (``zupt``),
        the non-holonomic constraint while moving (``nhc``). Returns (zupt, zaru, nhc) results."""
        return self._f.update_constraints()

    def update_baro(self, h: float):
        """Altimeter height (m). Returns (height result, vertical-velocity result)."""
        return self._f.update_baro(_finite(h, "h"))

    def update_compass(self, heading: float):
        """Compass heading (rad). Returns the update result."""
        return self._f.update_compass(_finite(heading, "heading"))

    # --- batch --------------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
            odometer=None, outages=(), imu_input: str = "rate", on_invalid: str = "raise",
            smooth: bool = False, gps_solution=None) -> GpsInsResult:
        """Run over an IMU record and aiding records at their own times (C++ loop, GIL released).

        Parameters
        ----------
        gyr : (N, 3) array_like
            Angular rate, rad/s (sample k: the mean over ``(t[k-1], t[k]]``), in the IMU's axes
            (``imu_rotation`` turns them into the body's); with ``imu_input="increment"`` the
            angle increment over the interval, rad.
        acc : (N, 3) array_like
            Specific force, m/s^2 (or the velocity increment, m/s), IMU axes.
        mag : (N, 3) array_like, optional
            Raw magnetometer at the IMU samples, IMU axes, any unit; all-NaN rows: no sample. Its
            heading is tilt-compensated with the filter's attitude (``declination`` added),
            gated and tested for disturbances (``mag_norm_tol``, ``mag_dip_tol``).
        t : (N,) array_like, keyword
            IMU times, s, strictly increasing; or
        dt : float or (N,) array_like, keyword
            Step lengths, s (``t = 0`` and the cumulated steps after the first).
        gps_pos : Aid, optional
            ``Aid(t, llh, sigma)``: times of validity (K,), s, strictly increasing, on the GNSS
            clock (``gps_time_offset`` is added to put them on the IMU's); the antenna's
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
        odometer : Aid, optional
            ``Aid(t, speed)``: odometer times (O,), s, and speeds along the body x axis (O,), m/s.
        gps_solution : (K,) array_like, optional
            The receiver's solution kind of each ``gps_pos`` fix, names of
            :data:`GNSS_SOLUTIONS` (``"rtk_fixed"``, ``"rtk_float"``, ``"dgnss"``, ``"single"``,
            ``"unknown"``) or their codes (:func:`gnss_solution` maps RTKLIB's Q, NMEA's fix
            quality, PX4's fix_type): it sets the floor of the fix's one-sigma
            (``gps_pos_sigma_min``, ``gps_float_sigma_min``, ``gps_dgnss_sigma_min``,
            ``gps_single_sigma_min``). None: every fix ``unknown``.
        outages : sequence of (t_start, t_end), optional
            GPS fixes with t_start <= t < t_end are dropped (simulated outages), e.g.
            ``[(20.0, 30.0)]``; None or empty: none.
        imu_input : {"rate", "increment"}
            Whether ``gyr``/``acc`` hold mean rates and specific forces or increments (rad, m/s).
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite row (IMU, a partly-NaN or infinite GPS row, altimeter,
            compass, odometer) or IMU step above ``max_coast`` raises ``ValueError`` naming the
            argument and row (a step above ``max_dt`` up to ``max_coast`` is coasted in steps of
            at most ``max_dt`` and flagged ``coasted``, in both modes). "skip": such rows skip
            their step and are reported in ``flags``
            (``predict_skipped``, ``aid_skipped``), the aids' ``status`` and ``skipped_rows``
            (keys ``"predict_skipped"``, ``"saturated"`` (IMU rows), ``"gps_pos"``, ``"baro"``,
            ``"compass"`` (aiding rows)). Times must be finite and strictly increasing in both
            modes. A saturated IMU row (``gyro_range`` / ``acc_range``) is skipped and reported in
            both modes.
        smooth : bool
            Also run the Rauch-Tung-Striebel backward pass (in C++, after the forward pass; see
            ``docs/SMOOTHING.md`` and ``nav/gps_ins/smoother.hpp``): the result's ``position``,
            ``velocity``, ``quat``, biases, ``baro_offset`` and ``sigma`` are then the smoothed
            ones over the navigating samples (each using every sample of the run), ``forward``
            holds the causal result and ``smoother`` the record's size. The forward pass's
            decisions (gated, inflated, reset fixes; rest; skipped samples) are kept: ``flags``,
            ``aids``, ``counters`` and ``q_scale`` are the forward pass's. A reset of the state to
            a fix, a covariance inflation (fixes that kept failing their gate) and the
            initialization of the altimeter offset are not crossed (before one, the smoothed
            estimate uses the data up to it). The filter's state afterwards is the
            forward one at the last sample (where the two agree).

        Returns
        -------
        GpsInsResult
        """
        strict = V.on_invalid(on_invalid) == "raise"
        if imu_input not in ("rate", "increment"):
            raise ValueError(f"imu_input: expected 'rate' or 'increment', got {imu_input!r}")
        gyr = check_imu_order(gyr, acc)
        if t is not None and dt is None:
            t = aid_times(t, "t")
            n = len(t)
            if n < 2:
                raise ValueError("t: need at least two IMU samples")
        else:
            n = len(V.vectors(gyr, "gyr", 3, dtype=self.dtype, finite=False))
            t = times_of(n, None, V.time_steps(n, dt=dt, t=t))
        like = "gyr" if dt is not None else "t"
        gyro = V.vectors(gyr, "gyr", 3, n, self.dtype, finite=strict, like=like)
        accel = V.vectors(acc, "acc", 3, n, self.dtype, finite=strict, like=like)
        if imu_input == "rate":
            check_swapped(gyro, accel)
        check_run_inputs(self, gyro, accel, t=t, axes="frd", rotation=self.params["imu_rotation"],
                         rotation_fix="the imu_rotation parameter", increments=imu_input == "increment")
        mag_a = None if mag is None else V.vectors(mag, "mag", 3, n, self.dtype, finite=strict, allow_nan_rows=True,
                                                   like=like)
        if strict:
            limit = max(float(self._f.params.max_dt), float(self._f.params.max_coast))
            big = np.flatnonzero(np.diff(t) > limit)
            if big.size:
                k = int(big[0]) + 1
                raise ValueError(f"t: step {float(t[k] - t[k - 1])!r} s in row {k} exceeds "
                                 f"max_coast={float(self._f.params.max_coast)!r} s (gaps up to it are coasted)")
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
        solution = _solutions(gps_solution, ng)
        out = _outages(outages)
        if len(out):
            gps_llh = gps_llh.copy()
            for t0, t1 in out:
                gps_llh[(gps_t >= t0) & (gps_t < t1)] = np.nan
        b, c = check_aid(baro, "baro"), check_aid(compass, "compass")
        baro_t = np.zeros(0) if b is None else aid_times(b.t, "baro.t")
        baro_h = _rows(np.zeros(0) if b is None else b.value, "baro.value", len(baro_t), 1, np.float64, False, strict)
        compass_t = np.zeros(0) if c is None else aid_times(c.t, "compass.t")
        compass_yaw = _rows(np.zeros(0) if c is None else c.value, "compass.value", len(compass_t), 1, self.dtype,
                            False, strict)
        o = check_aid(odometer, "odometer")
        odo_t = np.zeros(0) if o is None else aid_times(o.t, "odometer.t")
        for name, at in (("baro", baro_t), ("compass", compass_t), ("odometer", odo_t)):
            # (The GNSS fixes: alignment["reason"] and NavigationWarning, with gps_time_offset.)
            warn_aid_outside("GpsInsFilter", name, at, float(t[0]), float(t[-1]))
        odo_v = _rows(np.zeros(0) if o is None else o.value, "odometer.value", len(odo_t), 1, self.dtype, False, strict)
        d = self._f.run(t, gyro, accel, mag_a, imu_input == "increment", gps_t, gps_llh, gps_vel_v, gps_pos_sigma,
                        gps_vel_sigma, baro_t, baro_h, compass_t, compass_yaw, odo_t, odo_v, bool(smooth),
                        gps_solution=solution)
        flags = d["flags"]
        skipped = skipped_imu_rows(flags, GPSINS_FLAGS, drop_first=True)  # sample 0 only fixes the start time
        refused = [STATUS_NAMES.index(x) for x in ("non_finite", "numerical_failure", "solve_failed", "invalid_argument")]
        for name, key in (("gps_pos", "gps"), ("baro", "baro"), ("compass", "compass"), ("odometer", "odometer"),
                          ("mag", "mag")):
            st = d[key]["status"]
            rows = np.flatnonzero(np.isin(st, refused).any(axis=1))
            if name == "gps_pos" and ng:  # an all-NaN position row is an absent fix, not a refused one
                rows = rows[~np.isnan(gps_llh[rows]).all(axis=1)]
            if rows.size:
                skipped[name] = rows
        aids = {}
        if pos is not None:
            aids.update(_aid_results(d["gps"], gps_t, ("gps_pos", "gps_vel") if vel is not None else ("gps_pos",), 3))
        if b is not None:
            aids.update(_aid_results(d["baro"], baro_t, ("baro", "baro_vd"), 1))
        if c is not None:
            aids.update(_aid_results(d["compass"], compass_t, ("compass",), 1))
        if o is not None:
            aids.update(_aid_results(d["odometer"], odo_t, ("odometer",), 1))
        if mag_a is not None:
            rows = ~np.isnan(mag_a).all(axis=1)
            aids.update(_aid_results(_take(d["mag"], rows), t[rows], ("mag",), 1))
        for name, m in (("zupt", 3), ("zaru", 3), ("nhc", 2)):
            made = d[name]["status"][:, 0] != STATUS_NAMES.index("not_initialized")
            if made.any():
                aids.update(_aid_results(_take(d[name], made), t[made], (name,), m))
        coasted = np.flatnonzero(flags & GPSINS_FLAGS["coasted"])
        if coasted.size:
            skipped["coasted"] = coasted
        phase = flags & (GPSINS_FLAGS["levelled"] | GPSINS_FLAGS["navigating"])
        nav_rows = np.flatnonzero(flags & GPSINS_FLAGS["navigating"])
        alignment = {"method": d["align_method"], "heading": d["heading_source"],
                     "level_t": float(t[np.argmax(phase != 0)]) if phase.any() else None,
                     "navigation_t": float(t[nav_rows[0]]) if nav_rows.size else None}
        alignment["reason"] = None if nav_rows.size else _not_navigating(
            self._f.params, alignment, t, accel, flags,
            gps_t[~np.isnan(gps_llh).all(axis=1)] + float(self._f.params.gps_time_offset), vel is not None,
            mag_a, len(compass_t), aids)
        p = self._f.params
        if alignment["reason"] and t[-1] - t[0] >= float(p.align_time) + float(p.align_motion_max):
            fix = ("; give mag or compass, move with GNSS velocity, or set the attitude with set_initial()"
                   if alignment["method"] != "none" and alignment["heading"] == "none" else "")
            warnings.warn(f"GpsInsFilter: no navigation over t = {t[0]:.6g}..{t[-1]:.6g} s: {alignment['reason']}{fix}",
                          NavigationWarning, stacklevel=2)
        counters = self.counters

        def result(o, **kw):
            return GpsInsResult("GpsInsFilter", t, o["q_nb"], o["gyro_bias"], o["sigma"], flags, aids=aids,
                                skipped_rows=skipped, sigma_names=self.state_names, velocity=o["v_n"],
                                acc_bias=o["acc_bias"], position=o["llh"], counters=counters,
                                baro_offset=o["baro_offset"], q_scale=d["q_scale"], acc_scale=o.get("acc_scale"),
                                gyro_scale=o.get("gyro_scale"), alignment=alignment, **kw)

        fwd = result(d)
        if not smooth:
            return fwd
        sm = d["smoothed"]
        return result(sm, forward=fwd, smoother=smoother_info(sm["info"]))


def _not_navigating(p, alignment, t, accel, flags, fixes, have_vel, mag, n_compass, aids) -> str:
    """Why a run did not start navigating: the first step of the alignment it did not reach
    (levelling, a heading, a GNSS fix after them) and what that step needs, with the inputs'
    evidence (``fixes``: the times of the GNSS position fixes given, on the IMU's clock)."""
    inside = fixes[(fixes >= t[0]) & (fixes <= t[-1])]
    if not fixes.size:
        return ("no GNSS position fix was given (gps_pos): navigation starts at the first fix after the "
                "alignment")
    if not inside.size:
        return (f"the GNSS fixes (t = {fixes[0]:.6g}..{fixes[-1]:.6g} s with gps_time_offset = "
                f"{float(p.gps_time_offset):g} s) do not overlap the IMU's times (give both on one clock)")
    ms = f"{float(p.align_motion_time):g}"
    if alignment["method"] == "none":
        unit, m = accel_unit(accel)
        g = {"g": f"acc looks like g (median |acc| {m:.4g}): give m/s^2 (multiply by 9.80665)",
             "mg": f"acc looks like milli-g (median |acc| {m:.4g}): give m/s^2 (multiply by 0.00980665)",
             "far": f"the median |acc| {m:.4g} m/s^2 is far from gravity: check its unit"}.get(unit)
        still = bool(np.any(flags & GPSINS_FLAGS["at_rest"]))
        why = (g + "; " if g else "") + (
            "the IMU was never still " if not still else "the IMU was still, but not ")
        return ("it never levelled: " + why + f"for align_time = {float(p.align_time):g} s (rates within "
                f"rest_gyr_th = {float(p.rest_gyr_th):g} rad/s and specific force within rest_acc_th = "
                f"{float(p.rest_acc_th):g} m/s^2 of their low-passes and of gravity), and no alignment in motion "
                f"completed (GNSS {'velocity' if have_vel else 'positions'} while moving, over at least "
                f"align_motion_time = {ms} s" + ("" if have_vel else
                f" and align_course_distance = {float(p.align_course_distance):g} m") + ")")
    lt = alignment["level_t"]
    at = f" at t = {lt:.6g} s" if lt is not None else ""
    if alignment["heading"] == "none":
        src = []
        if mag is None:
            src.append("no magnetometer")
        else:
            a = aids.get("mag")
            n_rej = int(a.rejected.sum()) if a is not None else 0
            src.append("every magnetometer sample after levelling failed its disturbance tests" if n_rej
                       else "no magnetometer sample after levelling")
        if not n_compass:
            src.append("no compass")
        if not p.heading_from_gps:
            src.append("heading_from_gps is off")
        elif not have_vel:
            src.append("no GNSS velocity for the course")
        else:
            src.append(f"the GNSS speed never reached min_speed_for_heading = {float(p.min_speed_for_heading):g} m/s")
        return f"levelled ({alignment['method']}){at}, but no heading: " + ", ".join(src)
    return (f"aligned ({alignment['method']}, heading from {alignment['heading']}){at}, but no GNSS position fix "
            f"came after it (the last at t = {inside[-1]:.6g} s)")
