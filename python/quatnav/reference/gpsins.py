"""Plain numpy twin of ``cpp/include/quatnav/gps_ins.hpp``: the 15-state feedback GPS/INS filter
of paper 004 with altimeter and compass.

Same method names and the same algorithm step by step as the C++ class (see the header comment
there for the equations, the error definitions and the paper's slips). Written to be read and
compared with the C++, not to be fast: per-sample Python.

Error state ``dx = [dp_n (m), dv_n (m/s), psi (rad), db_a (m/s^2), db_g (rad/s)]``, estimate minus
truth, attitude error the phi-angle ``C_nb_est = (I + [psi x]) C_nb``.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from types import SimpleNamespace

import numpy as np

from ..core import earth
from ..core import quaternion as Q
from ..core.strapdown import StrapdownState, strapdown_step
from ..filters.tables import FLAGS, GPSINS_PARAMS
from .kalman import kalman_correct

__all__ = ["DEFAULTS", "GpsInsParams", "GpsInsFilter", "gpsins_F", "ALIGNING", "LEVELLED", "NAVIGATING"]

ALIGNING, LEVELLED, NAVIGATING = 0, 1, 2
KINDS = ("gps_pos", "gps_vel", "baro", "baro_vd", "compass")


#: The parameters of the C++ filter with its defaults (the one table, quatnav.filters.tables).
DEFAULTS = {p.name: p.default for p in GPSINS_PARAMS if p.core_name is not None}


def GpsInsParams(**params) -> SimpleNamespace:
    """The parameters: the names, units and defaults of ``quatnav::GpsInsParams`` (the table
    :data:`quatnav.filters.tables.GPSINS_PARAMS`); an unknown name is a TypeError."""
    unknown = sorted(set(params) - set(DEFAULTS))
    if unknown:
        raise TypeError(f"GpsInsFilter: unknown parameter {unknown[0]!r}; known: {', '.join(DEFAULTS)}")
    p = SimpleNamespace(**{**DEFAULTS, **params})
    p.lever_arm_b = np.asarray(p.lever_arm_b, float).reshape(3)
    return p


def _radii(lat):
    r = earth.radii(lat)
    return float(np.asarray(r[0])), float(np.asarray(r[1]))


def gpsins_F(nav: StrapdownState, f_b, p) -> np.ndarray:
    """Continuous error dynamics F (15 x 15) at ``nav`` for the bias-corrected specific force."""
    F = np.zeros((15, 15))
    L, h = float(nav.lat), float(nav.h)
    R_M, R_N = _radii(L)
    Rm, Rn = R_M + h, R_N + h
    v = np.asarray(nav.v_n, float)
    tL, sL, cL = math.tan(L), math.sin(L), math.cos(L)
    C = Q.to_rotmat(nav.q_nb)
    f_n = C @ np.asarray(f_b, float)
    # eq. (9)
    F[0, 0] = -v[2] / Rm
    F[0, 2] = v[0] / Rm
    F[1, 0] = v[1] * tL / Rm
    F[1, 1] = -v[2] / Rn - v[0] * tL / Rm
    F[1, 2] = v[1] / Rn
    F[0:3, 3:6] = np.eye(3)
    dg_dh = earth.G2 + earth.G3 * sL * sL
    dg_dL = (earth.G1 + earth.G3 * h) * 2.0 * sL * cL
    Fvp = np.zeros((3, 3))
    Fvp[2, 2] = -dg_dh
    Fvp[2, 0] = dg_dL / Rm
    Fvv = np.zeros((3, 3))
    Fpsi_p = np.zeros((3, 3))
    Fpsi_v = np.zeros((3, 3))
    w_in = np.zeros(3)
    if p.earth_rotation:
        w_ie = np.array([earth.OMEGA_IE * cL, 0.0, -earth.OMEGA_IE * sL])
        w_en = np.array([v[1] / Rn, -v[0] / Rm, -v[1] * tL / Rn])
        w_in = w_ie + w_en
        Wv = np.array([[0.0, 1.0 / Rn, 0.0], [-1.0 / Rm, 0.0, 0.0], [0.0, -tL / Rn, 0.0]])
        Wie_p = np.zeros((3, 3))
        Wie_p[0, 0] = -earth.OMEGA_IE * sL / Rm
        Wie_p[2, 0] = -earth.OMEGA_IE * cL / Rm
        Wen_p = np.zeros((3, 3))
        Wen_p[2, 0] = -v[1] / (Rn * cL * cL * Rm)
        Wen_p[0, 2] = v[1] / (Rn * Rn)
        Wen_p[1, 2] = -v[0] / (Rm * Rm)
        Wen_p[2, 2] = -v[1] * tL / (Rn * Rn)
        Vx = Q.skew(v)
        Fvv = -Q.skew(2.0 * w_ie + w_en) + Vx @ Wv
        Fvp = Fvp + Vx @ (2.0 * Wie_p + Wen_p)
        Fpsi_v = -Wv
        Fpsi_p = -(Wie_p + Wen_p)
    F[3:6, 0:3] = Fvp
    F[3:6, 3:6] = Fvv
    F[3:6, 6:9] = -Q.skew(f_n)
    F[3:6, 9:12] = -C
    F[6:9, 0:3] = Fpsi_p
    F[6:9, 3:6] = Fpsi_v
    F[6:9, 6:9] = -Q.skew(w_in)
    F[6:9, 12:15] = -C
    if p.acc_bias_tau > 0:
        F[9:12, 9:12] = -np.eye(3) / p.acc_bias_tau
    if p.gyro_bias_tau > 0:
        F[12:15, 12:15] = -np.eye(3) / p.gyro_bias_tau
    return F


def _qc_diag(p):
    return np.concatenate([np.zeros(3), np.full(3, p.acc_noise ** 2), np.full(3, p.gyro_noise ** 2),
                           np.full(3, p.acc_bias_noise ** 2), np.full(3, p.gyro_bias_noise ** 2)])


def geodetic_diff(lat_a, lon_a, h_a, lat_b, lon_b, h_b):
    """NED displacement (m) from point b to point a, about b."""
    R_M, R_N = _radii(lat_b)
    return np.array([(lat_a - lat_b) * (R_M + h_b),
                     float(Q.wrap_pi(lon_a - lon_b)) * (R_N + h_b) * math.cos(lat_b), -(h_a - h_b)])


def geodetic_add(lat, lon, h, d):
    """Point (lat, lon, h) moved by the NED displacement d (m)."""
    R_M, R_N = _radii(lat)
    return lat + d[0] / (R_M + h), lon + d[1] / ((R_N + h) * math.cos(lat)), h - d[2]


def _from_euler(r, p, y):
    return Q.from_euler(np.array([r, p, y]))


@dataclass
class _State:
    nav: StrapdownState
    acc_bias: np.ndarray
    gyro_bias: np.ndarray
    P: np.ndarray
    t: float = 0.0
    omega_b: np.ndarray = field(default_factory=lambda: np.zeros(3))
    f_b: np.ndarray = field(default_factory=lambda: np.zeros(3))
    phase: int = ALIGNING
    align_sum: np.ndarray = field(default_factory=lambda: np.zeros(3))
    align_time: float = 0.0
    heading_known: bool = False
    baro_offset_valid: bool = False
    baro_offset: float = 0.0
    baro_last: float = 0.0
    baro_last_valid: bool = False
    baro_ref_valid: bool = False
    baro_ref_h: float = 0.0
    baro_ref_t: float = 0.0
    baro_offset_n: float = 0.0
    gps_pos_reject_run: int = 0
    gps_vel_reject_run: int = 0
    counters: dict = field(default_factory=lambda: {k: {"accepted": 0, "rejected": 0, "skipped": 0, "resets": 0}
                                                    for k in KINDS})

    def copy(self):
        return replace(self, nav=self.nav.copy(), acc_bias=self.acc_bias.copy(), gyro_bias=self.gyro_bias.copy(),
                       P=self.P.copy(), omega_b=self.omega_b.copy(), f_b=self.f_b.copy(),
                       align_sum=self.align_sum.copy(),
                       counters={k: dict(v) for k, v in self.counters.items()})


def _new_state():
    return _State(nav=StrapdownState(q_nb=np.array([1.0, 0, 0, 0]), v_n=np.zeros(3), lat=0.0,
                                     lon=0.0, h=0.0),
                  acc_bias=np.zeros(3), gyro_bias=np.zeros(3), P=np.zeros((15, 15)))


@dataclass
class Result:
    status: str
    innovation: np.ndarray
    innovation_cov: np.ndarray
    nis: float

    @property
    def accepted(self):
        return self.status == "ok"


def _result(status, m):
    return Result(status, np.zeros(m), np.zeros((m, m)), 0.0)


class GpsInsFilter:
    """Numpy twin of ``quatnav::GpsInsFilter`` (see the C++ header for the model)."""

    n_states = 15

    def __init__(self, **params):
        self.p = GpsInsParams(**params)
        self.s = _new_state()

    # --- accessors ------------------------------------------------------------------------
    @property
    def phase(self):
        return self.s.phase

    @property
    def navigating(self):
        return self.s.phase == NAVIGATING

    @property
    def q_nb(self):
        return self.s.nav.q_nb.copy()

    @property
    def v_n(self):
        return self.s.nav.v_n.copy()

    @property
    def llh(self):
        return np.array([self.s.nav.lat, self.s.nav.lon, self.s.nav.h])

    @property
    def acc_bias(self):
        return self.s.acc_bias.copy()

    @property
    def gyro_bias(self):
        return self.s.gyro_bias.copy()

    @property
    def covariance(self):
        return self.s.P.copy()

    @property
    def counters(self):
        return {k: dict(v) for k, v in self.s.counters.items()}

    def clear(self):
        self.s = _new_state()

    def initial_covariance(self, pos_sigma, vel_sigma):
        p = self.p
        d = np.concatenate([np.asarray(pos_sigma, float), np.full(3, vel_sigma),
                            [p.init_level_sigma, p.init_level_sigma, p.init_yaw_sigma],
                            np.full(3, p.init_acc_bias_sigma), np.full(3, p.init_gyro_bias_sigma)])
        return np.diag(d ** 2)

    def reset(self, q_nb, v_n, lat, lon, h, acc_bias, gyro_bias, P):
        s = self.s.copy()
        q = np.asarray(q_nb, float)
        s.nav = StrapdownState(q_nb=q / np.linalg.norm(q), v_n=np.asarray(v_n, float).copy(),
                               lat=float(lat), lon=float(lon), h=float(h))
        s.acc_bias = np.asarray(acc_bias, float).copy()
        s.gyro_bias = np.asarray(gyro_bias, float).copy()
        s.P = np.asarray(P, float).copy()
        s.phase = NAVIGATING
        s.heading_known = True
        self.s = s
        return "ok"

    # --- time update ----------------------------------------------------------------------
    def predict(self, omega_ib_b, f_ib_b, dt):
        p = self.p
        dt = float(dt)
        if not (math.isfinite(dt) and 0 < dt <= p.max_dt):
            return "invalid_dt"
        w_m = np.asarray(omega_ib_b, float)
        f_m = np.asarray(f_ib_b, float)
        if not (np.all(np.isfinite(w_m)) and np.all(np.isfinite(f_m))):
            return "non_finite"
        s = self.s.copy()
        w = w_m - s.gyro_bias
        f = f_m - s.acc_bias
        if s.phase == ALIGNING:
            s.align_sum = s.align_sum + f_m * dt
            s.align_time += dt
            if s.align_time >= p.align_time:
                fm = s.align_sum / s.align_time
                if not np.linalg.norm(fm) > 1.0:
                    s.align_sum = np.zeros(3)
                    s.align_time = 0.0
                    s.t += dt
                    self.s = s
                    return "ok"
                roll = math.atan2(-fm[1], -fm[2])
                pitch = math.atan2(fm[0], math.sqrt(fm[1] ** 2 + fm[2] ** 2))
                s.nav.q_nb = _from_euler(roll, pitch, 0.0)
                s.phase = LEVELLED
        elif s.phase == LEVELLED:
            q = Q.mul(s.nav.q_nb, Q.from_rotvec(w * dt))
            s.nav.q_nb = q / np.linalg.norm(q)
        else:
            F = gpsins_F(s.nav, f, p)
            st = strapdown_step(s.nav, w, f, dt, earth_rotation=p.earth_rotation)
            if st != "ok":
                return st
            Fdt = F * dt
            Phi = np.eye(15) + Fdt + 0.5 * Fdt @ Fdt
            qc = _qc_diag(p)
            Qd = 0.5 * dt * (Phi * qc) @ Phi.T + np.diag(0.5 * dt * qc)
            P = Phi @ s.P @ Phi.T + Qd
            P = 0.5 * (P + P.T)
            if p.acc_bias_tau > 0:
                s.acc_bias = s.acc_bias * math.exp(-dt / p.acc_bias_tau)
            if p.gyro_bias_tau > 0:
                s.gyro_bias = s.gyro_bias * math.exp(-dt / p.gyro_bias_tau)
            s.P = P
        s.omega_b = w
        s.f_b = f
        s.t += dt
        self.s = s
        return "ok"

    # --- measurement updates --------------------------------------------------------------
    def _count(self, kind, res):
        key = {"ok": "accepted", "rejected": "rejected"}.get(res.status, "skipped")
        self.s.counters[kind][key] += 1
        return res

    def _correct(self, kind, H, R, y, gate):
        status, dx, P, S, nis = kalman_correct(self.s.P, H, R, y, gate)
        res = Result(status, np.array(y, float), S, nis)
        if status == "ok":
            s = self.s.copy()
            s.P = P
            self._inject(s, dx)
            self.s = s
        return self._count(kind, res)

    @staticmethod
    def _inject(s, dx):
        """Feedback of paper Fig. 2: the error estimate goes into the nominal state and biases."""
        s.nav.lat, s.nav.lon, s.nav.h = geodetic_add(s.nav.lat, s.nav.lon, s.nav.h, -dx[0:3])
        s.nav.v_n = s.nav.v_n - dx[3:6]
        q = Q.mul(Q.from_rotvec(-dx[6:9]), s.nav.q_nb)
        s.nav.q_nb = q / np.linalg.norm(q)
        s.acc_bias = s.acc_bias - dx[9:12]
        s.gyro_bias = s.gyro_bias - dx[12:15]

    def _pos_sigma(self, sigma):
        s = np.asarray(sigma, float)
        d = np.array([self.p.gps_pos_sigma_h, self.p.gps_pos_sigma_h, self.p.gps_pos_sigma_v])
        return np.where(np.isnan(s), d, s)

    def _vel_sigma(self, sigma):
        s = np.asarray(sigma, float)
        return np.where(np.isnan(s), self.p.gps_vel_sigma, s)

    def _track_baro_offset(self, h_imu_gps):
        """Running mean of (GPS height of the IMU - latest altimeter) over baro_offset_fixes."""
        s = self.s
        if not (self.p.baro_offset_fixes > 0) or not s.baro_last_valid:
            return
        d = h_imu_gps - s.baro_last
        if not s.baro_offset_valid:
            s.baro_offset, s.baro_offset_valid, s.baro_offset_n = d, True, 1.0
            return
        if s.baro_offset_n < self.p.baro_offset_fixes:
            s.baro_offset_n += 1.0
        s.baro_offset += (d - s.baro_offset) / s.baro_offset_n

    def _set_yaw(self, yaw):
        e = Q.to_euler(self.s.nav.q_nb)
        self.s.nav.q_nb = _from_euler(e[0], e[1], yaw)
        self.s.heading_known = True

    def _start(self, lat, lon, h, sig, v0_n):
        s = self.s.copy()
        l_n = Q.rotate(s.nav.q_nb, self.p.lever_arm_b)
        lat, lon, h = geodetic_add(lat, lon, h, -l_n)
        v0 = np.asarray(v0_n, float)
        s.nav = StrapdownState(q_nb=s.nav.q_nb.copy(),
                               v_n=v0.copy() if np.all(np.isfinite(v0)) else np.zeros(3),
                               lat=lat, lon=lon, h=h)
        s.P = self.initial_covariance(sig, self.p.init_vel_sigma)
        s.phase = NAVIGATING
        if s.baro_last_valid:
            s.baro_offset = h - s.baro_last
            s.baro_offset_valid = True
            s.baro_offset_n = 1.0
        self.s = s
        return "ok"

    def update_gps_position(self, lat, lon, h, sigma, v0_n=(np.nan, np.nan, np.nan)):
        if not (math.isfinite(lat) and math.isfinite(lon) and math.isfinite(h)) or abs(lat) > math.pi / 2:
            return self._count("gps_pos", _result("non_finite", 3))
        sig = self._pos_sigma(sigma)
        if not (np.all(np.isfinite(sig)) and sig.min() > 0):
            return self._count("gps_pos", _result("invalid_argument", 3))
        if self.s.phase == ALIGNING:
            return _result("not_initialized", 3)
        if self.s.phase == LEVELLED:
            if not self.s.heading_known:
                return _result("not_initialized", 3)
            return _result(self._start(lat, lon, h, sig, v0_n), 3)
        C = Q.to_rotmat(self.s.nav.q_nb)
        l_n = C @ self.p.lever_arm_b
        self._track_baro_offset(h + l_n[2])
        la, lo, hh = geodetic_add(self.s.nav.lat, self.s.nav.lon, self.s.nav.h, l_n)
        y = geodetic_diff(la, lo, hh, lat, lon, h)
        H = np.zeros((3, 15))
        H[:, 0:3] = np.eye(3)
        H[:, 6:9] = -Q.skew(l_n)
        R = np.diag(sig ** 2)
        res = self._correct("gps_pos", H, R, y, self.p.gate_gps_pos)
        if self._lockout(res.status, "gps_pos_reject_run"):
            # Gate lockout: the IMU position from the fix, its covariance block from the fix's.
            s = self.s
            s.nav.lat, s.nav.lon, s.nav.h = geodetic_add(lat, lon, h, -l_n)
            self._reset_block(0, R)
            s.counters["gps_pos"]["resets"] += 1
        return res

    def _lockout(self, status, run):
        """Count consecutive gate rejections (state field ``run``); True when a reset is due."""
        if status == "ok":
            setattr(self.s, run, 0)
            return False
        if status != "rejected" or not self.p.gps_reset_after > 0:
            return False
        setattr(self.s, run, getattr(self.s, run) + 1)
        if getattr(self.s, run) < self.p.gps_reset_after + 1:
            return False
        setattr(self.s, run, 0)
        return True

    def _reset_block(self, i, R):
        P = self.s.P.copy()
        P[i:i + 3, :] = 0.0
        P[:, i:i + 3] = 0.0
        P[i:i + 3, i:i + 3] = R
        self.s.P = P

    def update_gps_velocity(self, v_n, sigma):
        v_n = np.asarray(v_n, float)
        if not np.all(np.isfinite(v_n)):
            return self._count("gps_vel", _result("non_finite", 3))
        sig = self._vel_sigma(sigma)
        if not (np.all(np.isfinite(sig)) and sig.min() > 0):
            return self._count("gps_vel", _result("invalid_argument", 3))
        if self.s.phase != NAVIGATING:
            if self.s.phase == LEVELLED and not self.s.heading_known and self.p.heading_from_gps:
                if math.hypot(v_n[0], v_n[1]) >= self.p.min_speed_for_heading:
                    self._set_yaw(math.atan2(v_n[1], v_n[0]))
            return _result("not_initialized", 3)
        C = Q.to_rotmat(self.s.nav.q_nb)
        wl = np.cross(self.s.omega_b, self.p.lever_arm_b)
        y = self.s.nav.v_n + C @ wl - v_n
        H = np.zeros((3, 15))
        H[:, 3:6] = np.eye(3)
        H[:, 6:9] = -Q.skew(C @ wl)
        H[:, 12:15] = C @ Q.skew(self.p.lever_arm_b)
        R = np.diag(sig ** 2)
        res = self._correct("gps_vel", H, R, y, self.p.gate_gps_vel)
        if self._lockout(res.status, "gps_vel_reject_run"):
            self.s.nav.v_n = v_n - C @ wl  # gate lockout: the IMU velocity from the fix
            self._reset_block(3, R)
            self.s.counters["gps_vel"]["resets"] += 1
        return res

    def update_gps(self, lat, lon, h, v_n, pos_sigma, vel_sigma):
        """Returns ``(pos_result, vel_result)`` (see the C++ ``update_gps``)."""
        v = np.asarray(v_n, float)
        have_vel = not np.all(np.isnan(v))
        vel = _result("not_initialized", 3)
        if self.s.phase != NAVIGATING:
            if have_vel:
                vel = self.update_gps_velocity(v, vel_sigma)
            pos = self.update_gps_position(lat, lon, h, pos_sigma, v)
            return pos, vel
        pos = self.update_gps_position(lat, lon, h, pos_sigma)
        if have_vel:
            vel = self.update_gps_velocity(v, vel_sigma)
        return pos, vel

    def update_baro(self, h_baro):
        """Returns ``(height_result, vd_result)``."""
        p = self.p
        vd = _result("not_initialized", 1)
        if not math.isfinite(h_baro):
            return self._count("baro", _result("non_finite", 1)), vd
        s = self.s
        s.baro_last = float(h_baro)
        s.baro_last_valid = True
        if s.phase != NAVIGATING:
            return _result("not_initialized", 1), vd
        if not s.baro_offset_valid:
            s.baro_offset = s.nav.h - h_baro
            s.baro_offset_valid = True
            s.baro_offset_n = 1.0
        H = np.zeros((1, 15))
        H[0, 2] = -1.0
        y = np.array([self.s.nav.h - (h_baro + self.s.baro_offset)])
        R = p.baro_sigma ** 2 + p.gps_pos_sigma_v ** 2 / max(s.baro_offset_n, 1.0)
        height = self._correct("baro", H, np.array([[R]]), y, p.gate_baro)
        s = self.s
        if p.baro_rate_baseline > 0:
            if not s.baro_ref_valid:
                s.baro_ref_valid = True
                s.baro_ref_h = float(h_baro)
                s.baro_ref_t = s.t
            elif s.t - s.baro_ref_t >= p.baro_rate_baseline:
                T = s.t - s.baro_ref_t
                vd_baro = -(h_baro - s.baro_ref_h) / T
                H = np.zeros((1, 15))
                H[0, 5] = 1.0
                R = np.array([[2 * p.baro_sigma ** 2 / T ** 2 + p.baro_vd_sigma ** 2]])
                vd = self._correct("baro_vd", H, R, np.array([s.nav.v_n[2] - vd_baro]), p.gate_baro)
                self.s.baro_ref_h = float(h_baro)
                self.s.baro_ref_t = self.s.t
        return height, vd

    def update_compass(self, heading):
        p = self.p
        if not math.isfinite(heading):
            return self._count("compass", _result("non_finite", 1))
        if self.s.phase == ALIGNING:
            return _result("not_initialized", 1)
        yaw_meas = float(Q.wrap_pi(heading + p.declination))
        if self.s.phase == LEVELLED:
            self._set_yaw(yaw_meas)
            return _result("not_initialized", 1)
        e = Q.to_euler(self.s.nav.q_nb)
        y = np.array([float(Q.wrap_pi(e[2] - yaw_meas))])
        H = np.zeros((1, 15))
        tp = math.tan(e[1])
        H[0, 6:9] = [tp * math.cos(e[2]), tp * math.sin(e[2]), 1.0]
        return self._correct("compass", H, np.array([[p.compass_sigma ** 2]]), y, p.gate_compass)

    # --- batch ----------------------------------------------------------------------------
    def run(self, t, gyro, accel, gps_t=(), gps_llh=None, gps_vel=None, gps_pos_sigma=None,
            gps_vel_sigma=None, baro_t=(), baro_h=None, compass_t=(), compass_yaw=None):
        """The loop of ``quatnav::gpsins_batch`` in Python; returns a dict of the same arrays."""
        t = np.asarray(t, float)
        n = len(t)
        gps_t = np.asarray(gps_t, float)
        baro_t = np.asarray(baro_t, float)
        compass_t = np.asarray(compass_t, float)
        ng, nb, nc = len(gps_t), len(baro_t), len(compass_t)
        nan3 = np.full((ng, 3), np.nan)
        gps_vel = nan3 if gps_vel is None else np.asarray(gps_vel, float)
        gps_pos_sigma = nan3 if gps_pos_sigma is None else np.asarray(gps_pos_sigma, float)
        gps_vel_sigma = nan3 if gps_vel_sigma is None else np.asarray(gps_vel_sigma, float)
        out = {"llh": np.full((n, 3), np.nan), "v_n": np.full((n, 3), np.nan),
               "q_nb": np.full((n, 4), np.nan), "acc_bias": np.zeros((n, 3)),
               "gyro_bias": np.zeros((n, 3)), "sigma": np.full((n, 15), np.nan),
               "flags": np.zeros(n, np.uint32),
               "gps_innov": np.full((ng, 6), np.nan), "gps_nis": np.full((ng, 2), np.nan),
               "gps_status": np.full((ng, 2), "not_initialized", dtype=object),
               "baro_innov": np.full((nb, 2), np.nan), "baro_nis": np.full((nb, 2), np.nan),
               "baro_status": np.full((nb, 2), "not_initialized", dtype=object),
               "compass_innov": np.full(nc, np.nan), "compass_nis": np.full(nc, np.nan),
               "compass_status": np.full(nc, "not_initialized", dtype=object)}
        if n == 0:
            return out
        ig = int(np.sum(gps_t <= t[0]))
        ib = int(np.sum(baro_t <= t[0]))
        ic = int(np.sum(compass_t <= t[0]))
        done = ("ok", "rejected")
        for k in range(n):
            was_nav = self.navigating
            if k > 0:
                self.predict(gyro[k], accel[k], t[k] - t[k - 1])
                while ic < nc and compass_t[ic] <= t[k]:
                    r = self.update_compass(float(compass_yaw[ic]))
                    if r.status != "not_initialized":
                        out["compass_innov"][ic] = r.innovation[0]
                    if r.status in done:
                        out["compass_nis"][ic] = r.nis
                    out["compass_status"][ic] = r.status
                    ic += 1
                while ib < nb and baro_t[ib] <= t[k]:
                    rs = self.update_baro(float(baro_h[ib]))
                    for c, r in enumerate(rs):
                        if r.status in done:
                            out["baro_innov"][ib, c] = r.innovation[0]
                            out["baro_nis"][ib, c] = r.nis
                        out["baro_status"][ib, c] = r.status
                    ib += 1
                while ig < ng and gps_t[ig] <= t[k]:
                    llh = gps_llh[ig]
                    if np.all(np.isnan(llh)):
                        rs = (_result("non_finite", 3), _result("not_initialized", 3))
                    else:
                        rs = self.update_gps(float(llh[0]), float(llh[1]), float(llh[2]), gps_vel[ig],
                                             gps_pos_sigma[ig], gps_vel_sigma[ig])
                    for c, r in enumerate(rs):
                        if r.status in done:
                            out["gps_innov"][ig, 3 * c:3 * c + 3] = r.innovation
                            out["gps_nis"][ig, c] = r.nis
                        out["gps_status"][ig, c] = r.status
                    ig += 1
            if self.navigating:
                out["llh"][k] = self.llh
                out["v_n"][k] = self.v_n
                out["sigma"][k] = np.sqrt(np.maximum(np.diag(self.s.P), 0.0))
            if self.s.phase != ALIGNING:
                out["q_nb"][k] = self.q_nb
            out["acc_bias"][k] = self.s.acc_bias
            out["gyro_bias"][k] = self.s.gyro_bias
            out["flags"][k] = (FLAGS[("aligning", "levelled", "navigating")[self.s.phase]]
                               | (FLAGS["initialized"] if (not was_nav and self.navigating) else 0))
        return out
