"""Plain numpy twin of ``cpp/include/quatnav/nav/gps_ins.hpp``: the 16-state feedback GPS/INS
filter of paper 004 with altimeter (and its offset as a state) and compass, optionally with the
accelerometer and gyro scale factors as six more states (``GpsInsFilter(scale_factors=True)``, 22
states; C++ ``GpsInsFilter<S, true>``).

Same method names and the same algorithm step by step as the C++ class (see the header comment
there for the equations, the error definitions and the paper's slips). Written to be read and
compared with the C++, not to be fast: per-sample Python.

Error state ``dx = [dp_n (m), dv_n (m/s), psi (rad), db_a (m/s^2), db_g (rad/s), d_baro_offset (m)]``,
estimate minus truth, attitude error the phi-angle ``C_nb_est = (I + [psi x]) C_nb``. Each aid is
one function giving ``(y, H, R)`` (``_gps_position``, ...), sent through the one gated path
:meth:`GpsInsFilter._apply`, as the C++ pieces of ``nav/gps_ins/aids.hpp``.

Scale factors (the model shared with the C++ ``GpsInsFilter<S, true>``): ``dx`` continues with
``[ds_a (1), ds_g (1)]`` (indices SA, SG) for the sensor model, per axis in the body axes,
``f_m = (1 + s_a) f + b_a + noise``, ``w_m = (1 + s_g) w + b_g + noise``. The IMU is corrected as
``(m - b) / (1 + s)`` in every phase (:func:`_corrected`), F gains the terms of :func:`gpsins_F`,
the scale factors are random walks (``acc_scale_noise``, ``gyro_scale_noise``) without decay, no aid
sees them directly (their H columns are zero), a correction is injected as ``s -= ds``. Without
them everything is as with 16 states, bit for bit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from types import SimpleNamespace

import numpy as np

from .._validate import did_you_mean
from ..core import earth
from ..core import quaternion as Q
from ..core.strapdown import StrapdownState, strapdown_step
from ..filters.tables import FLAGS, GPSINS_PARAMS
from .attitude import sample_times
from .kalman import kalman_correct
from .lowpass import lowpass, lowpass_weight
from .smoother import Recorder

__all__ = ["DEFAULTS", "GpsInsParams", "GpsInsFilter", "gpsins_F", "ALIGNING", "LEVELLED", "NAVIGATING",
           "GpsInsRtsModel", "run_smoothed"]

ALIGNING, LEVELLED, NAVIGATING = 0, 1, 2
KINDS = ("gps_pos", "gps_vel", "baro", "baro_vd", "compass", "mag", "zupt", "zaru", "nhc", "odometer")
#: ``quatnav::GpsInsDecision`` names by code.
DECISIONS = ("none", "accepted", "rejected", "inflated", "reset", "skipped", "aligned")
N = 16
POS, VEL, ATT, BA, BG, BO = 0, 3, 6, 9, 12, 15
#: With the scale factors: 22 states, the accelerometer's (SA) and the gyro's (SG) after the 16.
N_SF = 22
SA, SG = 16, 19


#: The parameters of the C++ filter with its defaults (the one table, quatnav.filters.tables).
DEFAULTS = {p.name: p.default for p in GPSINS_PARAMS if p.core_name is not None}


def GpsInsParams(**params) -> SimpleNamespace:
    """The parameters: the names, units and defaults of ``quatnav::GpsInsParams`` (the table
    :data:`quatnav.filters.tables.GPSINS_PARAMS`); an unknown name is a TypeError."""
    unknown = sorted(set(params) - set(DEFAULTS))
    if unknown:
        raise TypeError(f"GpsInsFilter: unknown parameter {unknown[0]!r}{did_you_mean(unknown[0], DEFAULTS)}; "
                        f"known: {', '.join(DEFAULTS)}")
    p = SimpleNamespace(**{**DEFAULTS, **params})
    p.lever_arm_b = np.asarray(p.lever_arm_b, float).reshape(3)
    p.imu_rotation = np.asarray(p.imu_rotation, float).reshape(3, 3)
    return p


def _radii(lat):
    r = earth.radii(lat)
    return float(np.asarray(r[0])), float(np.asarray(r[1]))


def gpsins_F(nav: StrapdownState, f_b, p, w_b=None, acc_scale=None, gyro_scale=None) -> np.ndarray:
    """Continuous error dynamics F (16 x 16) at ``nav`` for the bias-corrected specific force
    (the altimeter offset is a random walk: its row is zero). With the scale factors
    (``acc_scale`` and ``gyro_scale`` given) 22 x 22, ``f_b`` and ``w_b`` the corrected specific
    force and body rate ``(m - b) / (1 + s)``."""
    sf = acc_scale is not None
    n = N_SF if sf else N
    F = np.zeros((n, n))
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
    F[6:9, 0:3] = Fpsi_p
    F[6:9, 3:6] = Fpsi_v
    F[6:9, 6:9] = -Q.skew(w_in)
    if not sf:
        F[3:6, 9:12] = -C
        F[6:9, 12:15] = -C
    else:
        # Scale factors: the corrected input f = (f_m - b_a) / (1 + s_a) is off by (exactly, from
        # (1 + s_est) f_est - (1 + s_true) f_true = -db_a) df = -(db_a + ds_a * f_true) / (1 + s_a)
        # ~= -Da (db_a + diag(f) ds_a), Da = diag(1 / (1 + s_a)); the rate likewise with Dg. They
        # enter as dv' = ... + C_nb df (eq. 8) and psi' = ... + C_nb dw (eq. 10), where the biases
        # alone gave -C_nb db: the bias columns gain Da (Dg), the scale-factor columns are them
        # times diag(f) (diag(w)). The scale-factor rows are zero (random walks, no decay).
        da, dg = 1.0 / (1.0 + np.asarray(acc_scale, float)), 1.0 / (1.0 + np.asarray(gyro_scale, float))
        F[3:6, 9:12] = -C * da                                              # -C Da
        F[3:6, SA:SA + 3] = -C * (np.asarray(f_b, float) * da)              # -C diag(f / (1 + s_a))
        F[6:9, 12:15] = -C * dg                                             # -C Dg
        F[6:9, SG:SG + 3] = -C * (np.asarray(w_b, float) * dg)              # -C diag(w / (1 + s_g))
    if p.acc_bias_tau > 0:
        F[9:12, 9:12] = -np.eye(3) / p.acc_bias_tau
    if p.gyro_bias_tau > 0:
        F[12:15, 12:15] = -np.eye(3) / p.gyro_bias_tau
    return F


def _qc_diag(p, q_scale, n=N):
    """Qc: the IMU and bias densities scaled by the adaptation's q_scale, the offset's random walk;
    with the scale factors (n = 22) their random walks, scaled like the biases."""
    qc = np.concatenate([np.zeros(3), q_scale * np.full(3, p.acc_noise ** 2), q_scale * np.full(3, p.gyro_noise ** 2),
                         q_scale * np.full(3, p.acc_bias_noise ** 2), q_scale * np.full(3, p.gyro_bias_noise ** 2),
                         [p.baro_offset_noise ** 2]])
    if n == N_SF:
        qc = np.concatenate([qc, q_scale * np.full(3, p.acc_scale_noise ** 2),
                             q_scale * np.full(3, p.gyro_scale_noise ** 2)])
    return qc


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
    acc_scale: np.ndarray = field(default_factory=lambda: np.zeros(3))   # zero and unused without the
    gyro_scale: np.ndarray = field(default_factory=lambda: np.zeros(3))  # scale-factor states
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
    q_scale: float = 1.0
    dt_last: float = 0.0
    align_method: str = "none"
    heading_source: str = "none"
    level_t: float = -1.0
    nav_start_t: float = -1.0
    rest_init: bool = False
    rest_gyr_lp: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rest_acc_lp: np.ndarray = field(default_factory=lambda: np.zeros(3))
    rest_t: float = 0.0
    gnss_speed: float = -1.0
    gnss_speed_t: float = 0.0
    pseudo_t: float = -1e9
    gnss_t: float = -1e9
    nhc_ms: float = -1.0
    nhc_t: float = 0.0
    mot_valid: bool = False
    mot_llh: tuple = (0.0, 0.0, 0.0)
    mot_has_v: bool = False
    mot_v0: np.ndarray = field(default_factory=lambda: np.zeros(3))
    mot_q: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))
    mot_dv: np.ndarray = field(default_factory=lambda: np.zeros(3))
    mot_T: float = 0.0
    init_v: np.ndarray | None = None
    mag_ref_norm: float = 0.0
    mag_ref_dip: float = 0.0
    mag_ref_n: int = 0
    reject_run: dict = field(default_factory=lambda: {k: 0 for k in KINDS})
    counters: dict = field(default_factory=lambda: {k: {"accepted": 0, "rejected": 0, "skipped": 0, "inflated": 0,
                                                        "resets": 0} for k in KINDS})

    def copy(self):
        return replace(self, nav=self.nav.copy(), acc_bias=self.acc_bias.copy(), gyro_bias=self.gyro_bias.copy(),
                       P=self.P.copy(), acc_scale=self.acc_scale.copy(), gyro_scale=self.gyro_scale.copy(),
                       omega_b=self.omega_b.copy(), f_b=self.f_b.copy(),
                       align_sum=self.align_sum.copy(), reject_run=dict(self.reject_run),
                       rest_gyr_lp=self.rest_gyr_lp.copy(), rest_acc_lp=self.rest_acc_lp.copy(),
                       mot_v0=self.mot_v0.copy(), mot_q=self.mot_q.copy(), mot_dv=self.mot_dv.copy(),
                       init_v=None if self.init_v is None else self.init_v.copy(),
                       counters={k: dict(v) for k, v in self.counters.items()})


def _new_state(n=N):
    return _State(nav=StrapdownState(q_nb=np.array([1.0, 0, 0, 0]), v_n=np.zeros(3), lat=0.0,
                                     lon=0.0, h=0.0),
                  acc_bias=np.zeros(3), gyro_bias=np.zeros(3), P=np.zeros((n, n)))


def _corrected(s, w_m, f_m, scale_factors):
    """The IMU corrected by the estimates: ``w = w_m - b_g``, ``f = f_m - b_a``; with the scale
    factors ``(m - b) / (1 + s)`` elementwise (the sensor model ``m = (1 + s) x + b``)."""
    w, f = w_m - s.gyro_bias, f_m - s.acc_bias
    if scale_factors:
        w, f = w / (1.0 + s.gyro_scale), f / (1.0 + s.acc_scale)
    return w, f


@dataclass
class Result:
    status: str
    innovation: np.ndarray
    innovation_cov: np.ndarray
    nis: float
    decision: str = "none"
    inflation: float = 1.0

    @property
    def accepted(self):
        return self.status == "ok"


def _result(status, m, decision="none"):
    return Result(status, np.zeros(m), np.zeros((m, m)), 0.0, decision)


# --- the aids: each gives (y, H, R) at the state (``nav/gps_ins/aids.hpp``) ----------------------
# H has the state's columns (len(s.P)): the scale factors' six are zero, no aid sees them directly.
def _antenna_velocity(s, p, C):
    return s.nav.v_n + C @ np.cross(s.omega_b, p.lever_arm_b)


def _nav_acceleration(s, C):
    return C @ s.f_b + np.array([0.0, 0.0, float(earth.gravity(s.nav.lat, s.nav.h))])


def _gps_position(s, p, lat, lon, h, sigma, age):
    """INS antenna position, taken back by ``age`` with the antenna velocity, minus the fix."""
    C = Q.to_rotmat(s.nav.q_nb)
    l_n = C @ p.lever_arm_b
    v_ant = _antenna_velocity(s, p, C)
    la, lo, hh = geodetic_add(s.nav.lat, s.nav.lon, s.nav.h, l_n - v_ant * age)
    y = geodetic_diff(la, lo, hh, lat, lon, h)
    H = np.zeros((3, len(s.P)))
    H[:, POS:POS + 3] = np.eye(3)
    H[:, VEL:VEL + 3] = -age * np.eye(3)
    H[:, ATT:ATT + 3] = -Q.skew(l_n) + age * Q.skew(v_ant - s.nav.v_n)
    H[:, BG:BG + 3] = -age * C @ Q.skew(p.lever_arm_b)
    R = np.diag(np.maximum(sigma, p.gps_pos_sigma_min) ** 2)
    R = R + p.gps_time_sigma ** 2 * np.outer(v_ant, v_ant) + p.lever_arm_sigma ** 2 * np.eye(3)
    return y, H, R


def _gps_velocity(s, p, v_n, sigma, age):
    """INS antenna velocity, taken back by ``age`` with the acceleration, minus the fix."""
    C = Q.to_rotmat(s.nav.q_nb)
    CW = C @ Q.skew(s.omega_b)
    wl = C @ np.cross(s.omega_b, p.lever_arm_b)
    a_n = _nav_acceleration(s, C)
    y = s.nav.v_n + wl - a_n * age - v_n
    H = np.zeros((3, len(s.P)))
    H[:, VEL:VEL + 3] = np.eye(3)
    H[:, ATT:ATT + 3] = -Q.skew(wl) + age * Q.skew(C @ s.f_b)
    H[:, BA:BA + 3] = age * C
    H[:, BG:BG + 3] = C @ Q.skew(p.lever_arm_b)
    R = np.diag(np.maximum(sigma, p.gps_vel_sigma_min) ** 2)
    R = R + p.gps_time_sigma ** 2 * np.outer(a_n, a_n) + p.lever_arm_sigma ** 2 * CW @ CW.T
    return y, H, R


def _baro_height(s, p, h_baro):
    """The altimeter reads the ellipsoidal height plus its offset (the 16th state)."""
    H = np.zeros((1, len(s.P)))
    H[0, POS + 2] = -1.0
    H[0, BO] = 1.0
    return np.array([s.nav.h + s.baro_offset - h_baro]), H, np.array([[p.baro_sigma ** 2]])


def _baro_vd(s, p, h_baro, h_ref, T):
    H = np.zeros((1, len(s.P)))
    H[0, VEL + 2] = 1.0
    R = np.array([[2 * p.baro_sigma ** 2 / T ** 2 + p.baro_vd_sigma ** 2]])
    return np.array([s.nav.v_n[2] + (h_baro - h_ref) / T]), H, R


def _compass(s, p, yaw):
    e = Q.to_euler(s.nav.q_nb)
    H = np.zeros((1, len(s.P)))
    tp = math.tan(e[1])
    H[0, ATT:ATT + 3] = [tp * math.cos(e[2]), tp * math.sin(e[2]), 1.0]
    return np.array([float(Q.wrap_pi(e[2] - yaw))]), H, np.array([[p.compass_sigma ** 2]])


def _mag_heading(s, p, m_b):
    """Angle of the field in NED as the filter sees it minus the declination."""
    m_n = Q.rotate(s.nav.q_nb, m_b)
    mh2 = m_n[0] ** 2 + m_n[1] ** 2
    H = np.zeros((1, len(s.P)))
    h = np.array([-m_n[0] * m_n[2] / mh2, -m_n[1] * m_n[2] / mh2, 1.0])
    y = float(Q.wrap_pi(math.atan2(m_n[1], m_n[0]) - p.declination))
    R = p.mag_heading_sigma ** 2
    if p.mag_heading_only:  # the tilt terms into R: the magnetometer corrects the heading only
        R += float(h[:2] @ s.P[ATT:ATT + 2, ATT:ATT + 2] @ h[:2])
        H[0, ATT + 2] = 1.0
    else:
        H[0, ATT:ATT + 3] = h
    return np.array([y]), H, np.array([[R]])


def _body_velocity_rows(s, rows):
    Ct = Q.to_rotmat(s.nav.q_nb).T
    H = np.zeros((len(rows), len(s.P)))
    H[:, VEL:VEL + 3] = Ct[rows]
    H[:, ATT:ATT + 3] = (Ct @ Q.skew(s.nav.v_n))[rows]
    return (Ct @ s.nav.v_n)[rows], H


def _zupt(s, p):
    H = np.zeros((3, len(s.P)))
    H[:, VEL:VEL + 3] = np.eye(3)
    return s.nav.v_n.copy(), H, p.zupt_sigma ** 2 * np.eye(3)


def _zaru(s, p):
    w_ie = earth.earth_rate_n(s.nav.lat) if p.earth_rotation else np.zeros(3)
    Ct = Q.to_rotmat(s.nav.q_nb).T
    H = np.zeros((3, len(s.P)))
    H[:, ATT:ATT + 3] = -Ct @ Q.skew(w_ie)  # the Earth rate seen in the body turns with the attitude
    H[:, BG:BG + 3] = -np.eye(3)
    dt = s.dt_last if s.dt_last > 0 else 1.0
    return s.omega_b - Ct @ w_ie, H, (p.gyro_noise ** 2 / dt + p.zaru_sigma ** 2) * np.eye(3)


def _nhc(s, p, var=0.0):
    y, H = _body_velocity_rows(s, [1, 2])
    return y, H, (var if var > 0 else p.nhc_sigma ** 2) * np.eye(2)


def _nhc_evidence(s, p, dt):
    """The evidence of a wheeled vehicle (as detail::gpsins_nhc_evidence): while GNSS-aided and
    faster than nhc_auto_speed, the low-passed mean square lateral and vertical body velocity and the
    time it has stayed within nhc_auto_limit^2 (lost above twice the limit, held in between)."""
    if not p.nhc_auto or not s.t - s.gnss_t < 2.5:
        return
    v_b = Q.rotate_inv(s.nav.q_nb, s.nav.v_n)
    if not v_b @ v_b > p.nhc_auto_speed ** 2:
        return
    e = v_b[1] ** 2 + v_b[2] ** 2
    tau = p.nhc_auto_time / 4
    s.nhc_ms = e if s.nhc_ms < 0 else lowpass(s.nhc_ms, e, dt, tau)
    if s.nhc_ms <= p.nhc_auto_limit ** 2:
        s.nhc_t += dt
    elif not s.nhc_ms <= 4 * p.nhc_auto_limit ** 2:  # above twice the limit: lost; between: held
        s.nhc_t = 0.0


def _odometer(s, p, speed):
    y, H = _body_velocity_rows(s, [0])
    return y - speed, H, np.array([[p.odometer_sigma ** 2]])


def _triad(a_b, b_b, a_n, b_n):
    """C_nb with C_nb a_b along a_n and C_nb b_b in the plane of a_n, b_n (or None)."""
    cb, cn = np.cross(a_b, b_b), np.cross(a_n, b_n)
    tiny = 1e-6
    if not (np.linalg.norm(a_b) > tiny and np.linalg.norm(a_n) > tiny
            and np.linalg.norm(cb) > tiny * np.linalg.norm(a_b) * np.linalg.norm(b_b)
            and np.linalg.norm(cn) > tiny * np.linalg.norm(a_n) * np.linalg.norm(b_n)):
        return None

    def frame(a, c):
        t1, t2 = a / np.linalg.norm(a), c / np.linalg.norm(c)
        return np.column_stack([t1, t2, np.cross(t1, t2)])
    return frame(a_n, cn) @ frame(a_b, cb).T


def _reset_block(P, i, R):
    P = P.copy()
    P[i:i + 3, :] = 0.0
    P[:, i:i + 3] = 0.0
    P[i:i + 3, i:i + 3] = R
    return P


def _reset_position(s, p, fix, R):
    lat, lon, h = fix
    l_n = Q.to_rotmat(s.nav.q_nb) @ p.lever_arm_b
    s.nav.lat, s.nav.lon, s.nav.h = geodetic_add(lat, lon, h, -l_n)
    s.P = _reset_block(s.P, POS, R)


def _reset_velocity(s, p, v_n, R):
    s.nav.v_n = v_n - Q.to_rotmat(s.nav.q_nb) @ np.cross(s.omega_b, p.lever_arm_b)
    s.P = _reset_block(s.P, VEL, R)


class GpsInsFilter:
    """Numpy twin of ``quatnav::GpsInsFilter`` (see the C++ header for the model);
    ``scale_factors=True``: with the accelerometer and gyro scale-factor states (22 states)."""

    n_states = N

    def __init__(self, scale_factors=False, **params):
        self.p = GpsInsParams(**params)
        self.scale_factors = bool(scale_factors)
        self.n_states = N_SF if self.scale_factors else N
        self.s = _new_state(self.n_states)

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
    def acc_scale(self):
        return self.s.acc_scale.copy()

    @property
    def gyro_scale(self):
        return self.s.gyro_scale.copy()

    @property
    def baro_offset(self):
        return self.s.baro_offset

    @property
    def q_scale(self):
        return self.s.q_scale

    @property
    def covariance(self):
        return self.s.P.copy()

    @property
    def counters(self):
        return {k: dict(v) for k, v in self.s.counters.items()}

    def clear(self):
        self.s = _new_state(self.n_states)

    def initial_covariance(self, pos_sigma, vel_sigma):
        p = self.p
        return self._initial_P(pos_sigma, vel_sigma, p.init_level_sigma, p.init_yaw_sigma)

    def _initial_P(self, pos_sigma, vel_sigma, level_sigma, yaw_sigma):
        """The covariance at the start of navigation (the offset's 0 until the altimeter gives it)."""
        p = self.p
        d = np.concatenate([np.asarray(pos_sigma, float), np.full(3, vel_sigma),
                            [level_sigma, level_sigma, yaw_sigma],
                            np.full(3, p.init_acc_bias_sigma), np.full(3, p.init_gyro_bias_sigma), [0.0]])
        if self.scale_factors:
            d = np.concatenate([d, np.full(3, p.init_acc_scale_sigma), np.full(3, p.init_gyro_scale_sigma)])
        return np.diag(d ** 2)

    def _scales(self, acc_scale, gyro_scale):
        """Given scale factors as arrays (only zeros without the scale-factor states)."""
        a, g = np.array(acc_scale, float).reshape(3), np.array(gyro_scale, float).reshape(3)
        if not self.scale_factors and (a.any() or g.any()):
            raise ValueError("acc_scale, gyro_scale: the filter has no scale-factor states (scale_factors=False)")
        return a, g

    def reset(self, q_nb, v_n, lat, lon, h, acc_bias, gyro_bias, P, acc_scale=(0.0, 0.0, 0.0),
              gyro_scale=(0.0, 0.0, 0.0)):
        P = np.asarray(P, float)
        if P.shape != (self.n_states, self.n_states):
            raise ValueError(f"P: expected shape ({self.n_states}, {self.n_states}), got {P.shape}")
        s = self.s.copy()
        q = np.asarray(q_nb, float)
        s.nav = StrapdownState(q_nb=q / np.linalg.norm(q), v_n=np.asarray(v_n, float).copy(),
                               lat=float(lat), lon=float(lon), h=float(h))
        s.acc_bias = np.asarray(acc_bias, float).copy()
        s.gyro_bias = np.asarray(gyro_bias, float).copy()
        s.acc_scale, s.gyro_scale = self._scales(acc_scale, gyro_scale)
        s.P = P.copy()
        s.phase = NAVIGATING
        s.heading_known = True
        s.baro_offset_valid = False
        s.align_method = s.heading_source = "given"
        s.level_t = s.nav_start_t = s.t
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
        if not np.array_equal(p.imu_rotation, np.eye(3)):
            w_m, f_m = p.imu_rotation @ w_m, p.imu_rotation @ f_m
        w, f = _corrected(s, w_m, f_m, self.scale_factors)
        g = float(earth.gravity(s.nav.lat, s.nav.h)) if s.phase == NAVIGATING else 9.80665
        if s.phase == NAVIGATING:
            sv = math.sqrt(np.trace(s.P[VEL:VEL + 3, VEL:VEL + 3]))
            slow = np.linalg.norm(s.nav.v_n) < p.rest_speed + min(3 * sv, p.rest_speed)
        else:
            slow = not (s.gnss_speed >= 0 and s.t - s.gnss_speed_t < 2.0 and s.gnss_speed > p.rest_speed)
        still = self._rest_step(s, w, f, dt, g, slow)
        if s.phase != NAVIGATING:
            self._window_step(s, w, f, dt)
        if s.phase == ALIGNING:
            if not still:
                s.align_sum = np.zeros(3)
                s.align_time = 0.0
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
                s.align_method = "static"
                s.level_t = s.t + dt
        elif s.phase == LEVELLED:
            q = Q.mul(s.nav.q_nb, Q.from_rotvec(w * dt))
            s.nav.q_nb = q / np.linalg.norm(q)
        else:
            sf = dict(w_b=w, acc_scale=s.acc_scale, gyro_scale=s.gyro_scale) if self.scale_factors else {}
            F = gpsins_F(s.nav, f, p, **sf)
            st = strapdown_step(s.nav, w, f, dt, earth_rotation=p.earth_rotation)
            if st != "ok":
                return st
            Fdt = F * dt
            Phi = np.eye(len(F)) + Fdt + 0.5 * Fdt @ Fdt
            self.last_transition = Phi  # the smoother's (GpsInsRtsModel)
            qc = _qc_diag(p, s.q_scale, len(F))
            Qd = 0.5 * dt * (Phi * qc) @ Phi.T + np.diag(0.5 * dt * qc)
            P = Phi @ s.P @ Phi.T + Qd
            P = 0.5 * (P + P.T)
            if p.acc_bias_tau > 0:
                s.acc_bias = s.acc_bias * math.exp(-dt / p.acc_bias_tau)
            if p.gyro_bias_tau > 0:
                s.gyro_bias = s.gyro_bias * math.exp(-dt / p.gyro_bias_tau)
            s.P = P
        if s.phase == NAVIGATING:
            _nhc_evidence(s, p, dt)
        s.omega_b = w
        s.f_b = f
        s.dt_last = dt
        s.t += dt
        self.s = s
        return "ok"

    def _rest_step(self, s, w, f, dt, g, slow):
        p = self.p
        if not s.rest_init:
            s.rest_gyr_lp, s.rest_acc_lp, s.rest_init = w.copy(), f.copy(), True
        else:
            a = lowpass_weight(dt, p.rest_tau)
            s.rest_gyr_lp = s.rest_gyr_lp + a * (w - s.rest_gyr_lp)
            s.rest_acc_lp = s.rest_acc_lp + a * (f - s.rest_acc_lp)
        still = (slow and np.linalg.norm(w - s.rest_gyr_lp) < p.rest_gyr_th
                 and np.linalg.norm(f - s.rest_acc_lp) < p.rest_acc_th and abs(np.linalg.norm(s.rest_acc_lp) - g) < p.rest_acc_th)
        s.rest_t = s.rest_t + dt if still else 0.0
        return still

    @staticmethod
    def _window_start(s, llh, v, has_v):
        s.mot_valid, s.mot_llh, s.mot_has_v = True, tuple(llh), has_v
        s.mot_v0 = np.asarray(v, float).copy() if has_v else np.zeros(3)
        s.mot_q, s.mot_dv, s.mot_T = np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(3), 0.0

    @staticmethod
    def _window_step(s, w, f, dt):
        half = Q.mul(s.mot_q, Q.from_rotvec(w * (0.5 * dt)))
        s.mot_dv = s.mot_dv + Q.rotate(half, f) * dt
        q = Q.mul(s.mot_q, Q.from_rotvec(w * dt))
        s.mot_q = q / np.linalg.norm(q)
        s.mot_T += dt

    @property
    def at_rest(self):
        return self.p.rest_time > 0 and self.s.rest_t >= self.p.rest_time

    def set_initial(self, q_nb, v_n=None, acc_bias=(0.0, 0.0, 0.0), gyro_bias=(0.0, 0.0, 0.0),
                    acc_scale=(0.0, 0.0, 0.0), gyro_scale=(0.0, 0.0, 0.0)):
        if self.s.phase == NAVIGATING:
            return "not_initialized"
        s = self.s.copy()
        q = np.asarray(q_nb, float)
        s.nav.q_nb = q / np.linalg.norm(q)
        s.acc_bias, s.gyro_bias = np.asarray(acc_bias, float).copy(), np.asarray(gyro_bias, float).copy()
        s.acc_scale, s.gyro_scale = self._scales(acc_scale, gyro_scale)
        s.init_v = None if v_n is None else np.asarray(v_n, float).copy()
        s.phase, s.heading_known = LEVELLED, True
        s.align_method = s.heading_source = "given"
        s.level_t = s.t
        self.s = s
        return "ok"

    @property
    def nhc_active(self):
        """The non-holonomic constraint applies while moving: forced (nhc) or by evidence (nhc_auto)."""
        return bool(self.p.nhc or (self.p.nhc_auto and self.s.nhc_t >= self.p.nhc_auto_time))

    def update_constraints(self):
        """ZUPT and ZARU at rest, NHC while moving, at most every pseudo_interval."""
        p, s = self.p, self.s
        none = (_result("not_initialized", 3), _result("not_initialized", 3), _result("not_initialized", 2))
        if s.phase != NAVIGATING or s.t - s.pseudo_t < p.pseudo_interval * (1 - 1e-9):
            return none
        zupt, zaru, nhc = none
        if self.at_rest and p.zupt:
            zupt = self._apply("zupt", *_zupt(self.s, p), p.gate_zupt)
            zaru = self._apply("zaru", *_zaru(self.s, p), p.gate_zupt)
            self.s.pseudo_t = self.s.t
        elif not self.at_rest and self.nhc_active:
            var = p.nhc_sigma ** 2 if p.nhc else max(p.nhc_sigma ** 2, self.s.nhc_ms)
            nhc = self._apply("nhc", *_nhc(self.s, p, var), p.gate_nhc)
            self.s.pseudo_t = self.s.t
        return zupt, zaru, nhc

    def update_odometer(self, speed):
        if not math.isfinite(speed):
            return self._count("odometer", _result("non_finite", 1))
        if self.s.phase != NAVIGATING:
            return _result("not_initialized", 1)
        return self._apply("odometer", *_odometer(self.s, self.p, float(speed)), self.p.gate_odometer)

    def update_mag(self, m_imu):
        p = self.p
        m = np.asarray(m_imu, float)
        if not np.all(np.isfinite(m)):
            return self._count("mag", _result("non_finite", 1))
        m_b = p.imu_rotation @ m if not np.array_equal(p.imu_rotation, np.eye(3)) else m
        norm = float(np.linalg.norm(m_b))
        if not norm > 0:
            return self._count("mag", _result("zero_norm", 1))
        if self.s.phase == ALIGNING:
            return _result("not_initialized", 1)
        s = self.s
        m_n = Q.rotate(s.nav.q_nb, m_b)
        dip = math.atan2(m_n[2], math.hypot(m_n[0], m_n[1]))
        if s.mag_ref_n < max(p.mag_ref_samples, 0):
            n1 = s.mag_ref_n + 1
            s.mag_ref_norm += (norm - s.mag_ref_norm) / n1
            s.mag_ref_dip += (dip - s.mag_ref_dip) / n1
            s.mag_ref_n += 1
        elif ((p.mag_norm_tol > 0 and abs(norm / s.mag_ref_norm - 1) > p.mag_norm_tol)
              or (p.mag_dip_tol > 0 and abs(dip - s.mag_ref_dip) > p.mag_dip_tol)):
            res = _result("rejected", 1)
            res.innovation[0] = float(Q.wrap_pi(math.atan2(m_n[1], m_n[0]) - p.declination))
            res.nis = math.nan
            return self._count("mag", res)
        if s.phase == LEVELLED:
            res = _result("not_initialized", 1)
            if not s.heading_known:
                e = Q.to_euler(s.nav.q_nb)
                self._set_yaw(float(Q.wrap_pi(e[2] - (math.atan2(m_n[1], m_n[0]) - p.declination))))
                self.s.heading_source = "magnetometer"
                res.decision = "aligned"
            return res
        return self._apply("mag", *_mag_heading(s, p, m_b), p.gate_mag)

    # --- the one gated correction path ----------------------------------------------------
    def _count(self, kind, res):
        c = self.s.counters[kind]
        if res.status == "ok":
            c["accepted"] += 1
            if kind in ("gps_pos", "gps_vel"):
                self.s.gnss_t = self.s.t
            res.decision = "accepted" if res.decision == "none" else res.decision
        elif res.status == "rejected":
            c["rejected"] += 1
            res.decision = "rejected" if res.decision == "none" else res.decision
        else:
            c["skipped"] += 1
            res.decision = "skipped"
        if res.decision == "inflated":
            c["inflated"] += 1
        if res.decision == "reset":
            c["resets"] += 1
        return res

    def _correct_commit(self, P, H, R, y, gate):
        status, dx, P_new, S, nis = kalman_correct(P, H, R, y, gate)
        if status == "ok":
            s = self.s.copy()
            s.P = P_new
            self._inject(s, dx)
            self.s = s
        return status, S, nis

    def _apply(self, kind, y, H, R, gate, adaptive=False, reset=None):
        """Gate; for a GNSS aid outlier isolation, inflation or reset, adaptation; correction."""
        p, m = self.p, len(y)
        y = np.asarray(y, float)
        status, S, nis = self._correct_commit(self.s.P, H, R, y, gate)
        res = Result(status, y, S, nis)
        if status == "ok":
            self.s.reject_run[kind] = 0
            if adaptive:
                self._adapt(nis / m)
            return self._count(kind, res)
        if status != "rejected":
            return self._count(kind, res)
        if adaptive and p.inflate_after > 0 and self.s.reject_run[kind] >= p.inflate_after:
            a = self._inflation(H, S, y)
            if a <= p.inflate_max:
                P = self.s.P.copy()
                P[:9, :9] *= a
                if self._correct_commit(P, H, R, y, 0.0)[0] == "ok":
                    res.status, res.decision, res.inflation = "ok", "inflated", a
                    self.s.reject_run[kind] = 0
                    self._adapt(nis / m)
                    return self._count(kind, res)
            else:
                s = self.s.copy()
                reset(s, R)
                self.s = s
                res.decision = "reset"
                self.s.reject_run[kind] = 0
                return self._count(kind, res)
        self.s.reject_run[kind] += 1
        return self._count(kind, res)

    def _inflation(self, H, S, y):
        """Smallest a in [1, inflate_max] with y^T (S + (a - 1) H_n P_nn H_n^T)^-1 y <= rows."""
        Hn = H[:, :9]
        B = Hn @ self.s.P[:9, :9] @ Hn.T
        m = len(y)

        def nis(a):
            try:
                L = np.linalg.cholesky(S + (a - 1.0) * B)
            except np.linalg.LinAlgError:
                return np.inf
            w = np.linalg.solve(L, y)
            return float(w @ w)
        amax = max(self.p.inflate_max, 1.0)
        if not nis(amax) <= m:
            return 2.0 * amax
        lo, hi = 0.0, math.log(amax)
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            if nis(math.exp(mid)) <= m:
                hi = mid
            else:
                lo = mid
        return math.exp(hi)

    def _adapt(self, r):
        """ln q_scale moves by adapt_gain (ln r -+ ln 3) outside [1/3, 3], within [1, adapt_q_max]."""
        p = self.p
        if not p.adapt_q_max > 1 or not r > 0 or not math.isfinite(r):
            return
        l3, lr = math.log(3.0), math.log(min(r, 1e3))
        step = p.adapt_gain * (lr - l3) if lr > l3 else (p.adapt_gain * (lr + l3) if lr < -l3 else 0.0)
        if step == 0.0:
            return
        l = min(max(math.log(self.s.q_scale) + step, 0.0), math.log(p.adapt_q_max))
        self.s.q_scale = math.exp(l)

    @staticmethod
    def _inject(s, dx):
        """Feedback of paper Fig. 2: the error estimate goes into the nominal state and biases
        (and the scale factors, when dx has their six rows)."""
        s.nav.lat, s.nav.lon, s.nav.h = geodetic_add(s.nav.lat, s.nav.lon, s.nav.h, -dx[0:3])
        s.nav.v_n = s.nav.v_n - dx[3:6]
        q = Q.mul(Q.from_rotvec(-dx[6:9]), s.nav.q_nb)
        s.nav.q_nb = q / np.linalg.norm(q)
        s.acc_bias = s.acc_bias - dx[9:12]
        s.gyro_bias = s.gyro_bias - dx[12:15]
        s.baro_offset = s.baro_offset - dx[BO]
        if len(dx) > N:
            s.acc_scale = s.acc_scale - dx[SA:SA + 3]
            s.gyro_scale = s.gyro_scale - dx[SG:SG + 3]

    # --- measurement updates --------------------------------------------------------------
    def _pos_sigma(self, sigma):
        s = np.asarray(sigma, float)
        d = np.array([self.p.gps_pos_sigma_h, self.p.gps_pos_sigma_h, self.p.gps_pos_sigma_v])
        return np.where(np.isnan(s), d, s)

    def _vel_sigma(self, sigma):
        s = np.asarray(sigma, float)
        return np.where(np.isnan(s), self.p.gps_vel_sigma, s)

    def _set_yaw(self, yaw):
        e = Q.to_euler(self.s.nav.q_nb)
        self.s.nav.q_nb = _from_euler(e[0], e[1], yaw)
        self.s.heading_known = True

    def _init_baro_offset(self, s, h_baro):
        """The offset state from one altimeter sample: its error is dp_D plus the sample's noise."""
        s.baro_offset = h_baro - s.nav.h
        P = s.P.copy()
        P[BO, :] = P[POS + 2, :]
        P[:, BO] = P[:, POS + 2]
        P[BO, BO] = P[POS + 2, POS + 2] + self.p.baro_sigma ** 2
        s.P = P
        s.baro_offset_valid = True

    def _start(self, lat, lon, h, sig, q, v0, vel_sigma, level_sigma, yaw_sigma, method, heading):
        s = self.s.copy()
        q = np.asarray(q, float) / np.linalg.norm(q)
        lat, lon, h = geodetic_add(lat, lon, h, -Q.rotate(q, self.p.lever_arm_b))
        s.nav = StrapdownState(q_nb=q, v_n=np.asarray(v0, float).copy(), lat=lat, lon=lon, h=h)
        s.P = self._initial_P(sig, vel_sigma, level_sigma, yaw_sigma)
        s.phase, s.heading_known = NAVIGATING, True
        s.align_method, s.heading_source, s.nav_start_t = method, heading, s.t
        s.mot_valid = False
        s.baro_offset_valid = False
        if s.baro_last_valid:
            self._init_baro_offset(s, s.baro_last)
        self.s = s
        return "ok"

    def _align_in_motion(self, lat, lon, h, psig, v2, vsig):
        """Alignment in motion at a fix: TRIAD with GNSS velocity, else the course between fixes."""
        p, s = self.p, self.s
        have_v = bool(np.all(np.isfinite(v2)))
        if not s.mot_valid:
            self._window_start(s, (lat, lon, h), v2, have_v)
            return "not_initialized"
        T = s.mot_T
        if T >= p.align_motion_time:
            g = float(earth.gravity(lat, h))
            dv_b = Q.rotate_inv(s.mot_q, s.mot_dv)
            if have_v and s.mot_has_v:
                speed = math.hypot(v2[0], v2[1])
                C = _triad(dv_b, np.array([1.0, 0, 0]), v2 - s.mot_v0 - np.array([0, 0, g * T]),
                           np.array([v2[0], v2[1], 0.0])) if speed >= p.min_speed_for_heading else None
                if C is not None:
                    e = math.sqrt(2) * float(np.max(vsig)) / (g * T)
                    b = p.init_gyro_bias_sigma * T
                    st = self._start(lat, lon, h, psig, Q.from_rotmat(C), v2, p.init_vel_sigma,
                                     math.sqrt(p.init_level_sigma ** 2 + e ** 2 + b ** 2), p.init_yaw_sigma,
                                     "gnss_velocity", "gnss_velocity")
                    self.s.level_t = self.s.t
                    return st
            elif not have_v:
                c = self._window_course(lat, lon, h, psig, True)
                if c is not None:
                    q, v, vs, ys, ls = c
                    st = self._start(lat, lon, h, psig, q, v, vs, ls, ys, "gnss_course", "gnss_course")
                    self.s.level_t = self.s.t
                    return st
        if T > p.align_motion_max:
            self._window_start(self.s, (lat, lon, h), v2, have_v)
        return "not_initialized"

    def _window_course(self, lat, lon, h, psig, level):
        p, s = self.p, self.s
        if not s.mot_valid:
            self._window_start(s, (lat, lon, h), np.zeros(3), False)
            return None
        d = geodetic_diff(lat, lon, h, *s.mot_llh)
        dist = math.hypot(d[0], d[1])
        sh = math.hypot(psig[0], psig[1])
        T = s.mot_T
        if T > 0 and 2 * sh / T < 0.5 * p.rest_speed:  # the window tells rest from motion
            s.gnss_speed, s.gnss_speed_t = dist / T, s.t
        if not (dist >= max(p.align_course_distance, 4 * sh)) or not T > 0:
            if T > p.align_motion_max:
                self._window_start(s, (lat, lon, h), np.zeros(3), False)
            return None
        course = math.atan2(d[1], d[0])
        a, ls = 0.0, p.init_level_sigma
        if level:
            dv_b = Q.rotate_inv(s.mot_q, s.mot_dv)
            g = float(earth.gravity(lat, h))
            dev = abs(np.linalg.norm(dv_b) / T - g)
            if not dev < p.rest_acc_th:  # accelerating: wait
                if T > p.align_motion_max:
                    self._window_start(s, (lat, lon, h), np.zeros(3), False)
                return None
            C = _triad(dv_b, np.array([1.0, 0, 0]), np.array([0, 0, -1.0]),
                       np.array([math.cos(course), math.sin(course), 0.0]))
            if C is None:
                return None
            q = Q.from_rotmat(C)
            a = math.sqrt(2 * g * dev)
            l0 = max(p.align_level_sigma, p.init_level_sigma)
            ls = math.sqrt(l0 ** 2 + (a / g) ** 2 + (p.init_gyro_bias_sigma * T) ** 2)
        else:
            e = Q.to_euler(s.nav.q_nb)
            q = _from_euler(e[0], e[1], course)
        v = np.array([d[0] / T, d[1] / T, 0.0])
        return q, v, max(2 * sh / T + a * T / 2, p.init_vel_sigma), max(2 * sh / dist, p.init_yaw_sigma), ls

    def update_gps_position(self, lat, lon, h, sigma, age=0.0, v0_n=(np.nan, np.nan, np.nan),
                            vel_sigma=(np.nan, np.nan, np.nan)):
        if not (math.isfinite(lat) and math.isfinite(lon) and math.isfinite(h) and math.isfinite(age)) \
                or abs(lat) > math.pi / 2:
            return self._count("gps_pos", _result("non_finite", 3))
        sig = self._pos_sigma(sigma)
        if not (np.all(np.isfinite(sig)) and sig.min() > 0):
            return self._count("gps_pos", _result("invalid_argument", 3))
        p = self.p
        psig = np.maximum(sig, p.gps_pos_sigma_min)
        v0_n = np.asarray(v0_n, float)
        if self.s.phase == ALIGNING:
            st = self._align_in_motion(lat, lon, h, psig, v0_n, self._vel_sigma(vel_sigma))
            return _result(st, 3, "aligned" if st == "ok" else "none")
        if self.s.phase == LEVELLED:
            s = self.s
            if not s.heading_known:
                c = self._window_course(lat, lon, h, psig, False)
                if c is None:
                    return _result("not_initialized", 3)
                q, v, vs, ys, _ = c
                st = self._start(lat, lon, h, psig, q, v, vs, p.init_level_sigma, ys, s.align_method, "gnss_course")
            else:
                v0 = s.init_v if s.init_v is not None else (v0_n if np.all(np.isfinite(v0_n)) else np.zeros(3))
                st = self._start(lat, lon, h, psig, s.nav.q_nb, v0, p.init_vel_sigma, p.init_level_sigma,
                                 p.init_yaw_sigma, s.align_method, s.heading_source)
            return _result(st, 3, "aligned")
        y, H, R = _gps_position(self.s, self.p, lat, lon, h, sig, age)
        return self._apply("gps_pos", y, H, R, self.p.gate_gps_pos, True,
                           lambda s, R: _reset_position(s, self.p, (lat, lon, h), R))

    def update_gps_velocity(self, v_n, sigma, age=0.0):
        v_n = np.asarray(v_n, float)
        if not (np.all(np.isfinite(v_n)) and math.isfinite(age)):
            return self._count("gps_vel", _result("non_finite", 3))
        sig = self._vel_sigma(sigma)
        if not (np.all(np.isfinite(sig)) and sig.min() > 0):
            return self._count("gps_vel", _result("invalid_argument", 3))
        if self.s.phase != NAVIGATING:
            res = _result("not_initialized", 3)
            speed = math.hypot(v_n[0], v_n[1])
            self.s.gnss_speed = max(speed - 3 * math.hypot(sig[0], sig[1]), 0.0)  # less three sigmas
            self.s.gnss_speed_t = self.s.t
            if self.s.phase == LEVELLED and not self.s.heading_known and self.p.heading_from_gps:
                if math.hypot(v_n[0], v_n[1]) >= self.p.min_speed_for_heading:
                    self._set_yaw(math.atan2(v_n[1], v_n[0]))
                    self.s.heading_source = "gnss_velocity"
                    res.decision = "aligned"
            return res
        y, H, R = _gps_velocity(self.s, self.p, v_n, sig, age)
        return self._apply("gps_vel", y, H, R, self.p.gate_gps_vel, True,
                           lambda s, R: _reset_velocity(s, self.p, v_n, R))

    def update_gps(self, lat, lon, h, v_n, pos_sigma, vel_sigma, age=0.0):
        """Returns ``(pos_result, vel_result)`` (see the C++ ``update_gps``)."""
        v = np.asarray(v_n, float)
        have_vel = not np.all(np.isnan(v))
        vel = _result("not_initialized", 3)
        if self.s.phase != NAVIGATING:
            if have_vel:
                vel = self.update_gps_velocity(v, vel_sigma, age)
            pos = self.update_gps_position(lat, lon, h, pos_sigma, age, v, vel_sigma)
            return pos, vel
        pos = self.update_gps_position(lat, lon, h, pos_sigma, age, v, vel_sigma)
        if have_vel:
            vel = self.update_gps_velocity(v, vel_sigma, age)
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
            self._init_baro_offset(s, float(h_baro))
            height = _result("ok", 1, "aligned")
        else:
            height = self._apply("baro", *_baro_height(s, p, float(h_baro)), p.gate_baro)
        s = self.s
        if p.baro_rate_baseline > 0:
            if not s.baro_ref_valid:
                s.baro_ref_valid = True
                s.baro_ref_h = float(h_baro)
                s.baro_ref_t = s.t
            elif s.t - s.baro_ref_t >= p.baro_rate_baseline:
                T = s.t - s.baro_ref_t
                vd = self._apply("baro_vd", *_baro_vd(s, p, float(h_baro), s.baro_ref_h, T), p.gate_baro)
                if vd.status in ("ok", "rejected"):
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
            if self.s.heading_source == "given":
                return _result("not_initialized", 1)
            self._set_yaw(yaw_meas)
            self.s.heading_source = "compass"
            return _result("not_initialized", 1, "aligned")
        return self._apply("compass", *_compass(self.s, p, yaw_meas), p.gate_compass)

    # --- batch ----------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
            odometer=None, outages=(), imu_input="rate", smooth=False, observer=None):
        """The loop of ``quatnav::gpsins_batch`` in Python with the public ``run``'s signature
        (:meth:`quatnav.GpsInsFilter.run`): IMU first, times as ``t`` or ``dt``, the aids as
        ``Aid(t, value[, sigma])`` (anything with ``.t``, ``.value`` and optionally ``.sigma``),
        ``outages`` as ``(t_start, t_end)`` pairs that drop the fixes inside them, ``imu_input``
        "rate" or "increment". Returns a dict of the C++ batch's arrays (``llh``, ``v_n``,
        ``q_nb``, ``acc_bias``, ``gyro_bias``, ``sigma``, ``baro_offset``, ``q_scale``,
        ``flags``, ``t`` and one report per aid, statuses and decisions as names; with the
        scale factors also ``acc_scale`` and ``gyro_scale``, and ``sigma`` has 22 columns).
        ``smooth=True``: the smoothed values over the navigating samples
        (:func:`run_smoothed`), the forward dict in ``forward``. ``observer``:
        ``after_predict(k, f)`` after the time update of sample k (``f.sample_transition``: the
        product of its steps' transitions) and ``after_sample(k, f)`` after all its steps (the
        smoother's record)."""
        aids = dict(gps_pos=gps_pos, gps_vel=gps_vel, baro=baro, compass=compass, odometer=odometer,
                    outages=outages, imu_input=imu_input)
        if smooth:
            out, sm = run_smoothed(self, gyr, acc, mag, t=t, dt=dt, observer=observer, **aids)
            return {**out, **sm, "forward": out}
        if imu_input not in ("rate", "increment"):
            raise ValueError(f"imu_input: expected 'rate' or 'increment', got {imu_input!r}")
        gyr, acc = np.asarray(gyr, float), np.asarray(acc, float)
        t, _ = sample_times(len(gyr), t, dt)
        if gps_vel is not None and gps_pos is None:
            raise ValueError("gps_vel: needs gps_pos (the filter takes a velocity with a position fix)")
        kw = {}
        if gps_pos is not None:
            kw["gps_t"] = np.asarray(gps_pos.t, float)
            kw["gps_llh"] = np.array(gps_pos.value, float)
            kw["gps_pos_sigma"] = getattr(gps_pos, "sigma", None)
            for o in outages:
                kw["gps_llh"][(kw["gps_t"] >= o[0]) & (kw["gps_t"] < o[1])] = np.nan
        if gps_vel is not None:
            if not np.array_equal(np.asarray(gps_vel.t, float), np.asarray(gps_pos.t, float)):
                raise ValueError("gps_vel.t: expected the times of gps_pos (give NaN rows where a fix has no velocity)")
            kw["gps_vel"], kw["gps_vel_sigma"] = gps_vel.value, getattr(gps_vel, "sigma", None)
        if baro is not None:
            kw["baro_t"], kw["baro_h"] = baro.t, baro.value
        if compass is not None:
            kw["compass_t"], kw["compass_yaw"] = compass.t, compass.value
        if odometer is not None:
            kw["odo_t"], kw["odo_speed"] = odometer.t, odometer.value
        out = self._loop(t, gyr, acc, mag=None if mag is None else np.asarray(mag, float),
                         increments=imu_input == "increment", observer=observer, **kw)
        out["t"] = t
        return out

    def _loop(self, t, gyro, accel, gps_t=(), gps_llh=None, gps_vel=None, gps_pos_sigma=None,
              gps_vel_sigma=None, baro_t=(), baro_h=None, compass_t=(), compass_yaw=None, mag=None,
              odo_t=(), odo_speed=None, increments=False, observer=None):
        """The batch loop over arrays (:meth:`run` unpacks its aids into them)."""
        p = self.p
        t = np.asarray(t, float)
        n = len(t)
        gps_t = np.asarray(gps_t, float) + p.gps_time_offset
        baro_t = np.asarray(baro_t, float)
        compass_t = np.asarray(compass_t, float)
        odo_t = np.asarray(odo_t, float)
        ng, nb, nc, no = len(gps_t), len(baro_t), len(compass_t), len(odo_t)
        nan3 = np.full((ng, 3), np.nan)
        gps_vel = nan3 if gps_vel is None else np.asarray(gps_vel, float)
        gps_pos_sigma = nan3 if gps_pos_sigma is None else np.asarray(gps_pos_sigma, float)
        gps_vel_sigma = nan3 if gps_vel_sigma is None else np.asarray(gps_vel_sigma, float)

        def report(rows, cols, m):
            return {"innovation": np.full((rows, cols * m), np.nan), "nis": np.full((rows, cols), np.nan),
                    "status": np.full((rows, cols), "not_initialized", dtype=object),
                    "decision": np.full((rows, cols), "none", dtype=object), "inflation": np.ones((rows, cols))}

        def write(rep, i, c, r):
            m = len(r.innovation)
            if r.status in ("ok", "rejected"):
                rep["innovation"][i, c * m:(c + 1) * m] = r.innovation
                rep["nis"][i, c] = r.nis
            rep["status"][i, c], rep["decision"][i, c], rep["inflation"][i, c] = r.status, r.decision, r.inflation

        out = {"llh": np.full((n, 3), np.nan), "v_n": np.full((n, 3), np.nan),
               "q_nb": np.full((n, 4), np.nan), "acc_bias": np.zeros((n, 3)),
               "gyro_bias": np.zeros((n, 3)), "sigma": np.full((n, self.n_states), np.nan),
               "baro_offset": np.full(n, np.nan), "q_scale": np.ones(n), "flags": np.zeros(n, np.uint32),
               "gps": report(ng, 2, 3), "baro": report(nb, 2, 1), "compass": report(nc, 1, 1),
               "odometer": report(no, 1, 1), "mag": report(n if mag is not None else 0, 1, 1),
               "zupt": report(n, 1, 3), "zaru": report(n, 1, 3), "nhc": report(n, 1, 2)}
        if self.scale_factors:
            out["acc_scale"], out["gyro_scale"] = np.zeros((n, 3)), np.zeros((n, 3))
        if n == 0:
            return out
        ig = int(np.sum(gps_t <= t[0]))
        ib = int(np.sum(baro_t <= t[0]))
        ic = int(np.sum(compass_t <= t[0]))
        io = int(np.sum(odo_t <= t[0]))
        for k in range(n):
            was_nav = self.navigating
            if k > 0:
                step = t[k] - t[k - 1]
                w, a = np.asarray(gyro[k], float), np.asarray(accel[k], float)
                if increments:
                    w, a = w / step, a / step
                m = 1
                if p.max_dt < step <= p.max_coast and p.max_dt > 0:
                    m = int(math.ceil(step / (p.max_dt * (1 - 1e-9))))
                st = "ok"
                self.sample_transition = np.eye(self.n_states)
                for _ in range(m):
                    if st == "ok":
                        st = self.predict(w, a, step / m)
                        if st == "ok" and self.navigating:
                            self.sample_transition = self.last_transition @ self.sample_transition
                if observer is not None:
                    observer.after_predict(k, self)
                for name, r in zip(("zupt", "zaru", "nhc"), self.update_constraints()):
                    write(out[name], k, 0, r)
                if mag is not None and not np.all(np.isnan(mag[k])):
                    write(out["mag"], k, 0, self.update_mag(mag[k]))
                while ic < nc and compass_t[ic] <= t[k]:
                    write(out["compass"], ic, 0, self.update_compass(float(compass_yaw[ic])))
                    ic += 1
                while io < no and odo_t[io] <= t[k]:
                    write(out["odometer"], io, 0, self.update_odometer(float(odo_speed[io])))
                    io += 1
                while ib < nb and baro_t[ib] <= t[k]:
                    for c, r in enumerate(self.update_baro(float(baro_h[ib]))):
                        write(out["baro"], ib, c, r)
                    ib += 1
                while ig < ng and gps_t[ig] <= t[k]:
                    llh = gps_llh[ig]
                    if np.all(np.isnan(llh)):
                        write(out["gps"], ig, 0, _result("non_finite", 3, "skipped"))
                    else:
                        rs = self.update_gps(float(llh[0]), float(llh[1]), float(llh[2]), gps_vel[ig],
                                             gps_pos_sigma[ig], gps_vel_sigma[ig], t[k] - gps_t[ig])
                        for c, r in enumerate(rs):
                            write(out["gps"], ig, c, r)
                    ig += 1
            if self.navigating:
                out["llh"][k] = self.llh
                out["v_n"][k] = self.v_n
                out["sigma"][k] = np.sqrt(np.maximum(np.diag(self.s.P), 0.0))
                if self.s.baro_offset_valid:
                    out["baro_offset"][k] = self.s.baro_offset
            if self.s.phase != ALIGNING:
                out["q_nb"][k] = self.q_nb
            out["acc_bias"][k] = self.s.acc_bias
            out["gyro_bias"][k] = self.s.gyro_bias
            if self.scale_factors:
                out["acc_scale"][k], out["gyro_scale"][k] = self.s.acc_scale, self.s.gyro_scale
            out["q_scale"][k] = self.s.q_scale
            out["flags"][k] = (FLAGS[("aligning", "levelled", "navigating")[self.s.phase]]
                               | (FLAGS["initialized"] if (not was_nav and self.navigating) else 0)
                               | (FLAGS["at_rest"] if self.at_rest else 0))
            if observer is not None:
                observer.after_sample(k, self)
        out["align_method"], out["heading_source"] = self.s.align_method, self.s.heading_source
        return out


# --- the Rauch-Tung-Striebel smoother (the twin of nav/gps_ins/smoother.hpp) ----------------------
class GpsInsRtsModel:
    """The smoother's model of :class:`GpsInsFilter` (``quatnav.reference.smoother``): a snapshot
    is the posterior ``(lat, lon, h, baro_offset, q_nb, v_n, acc_bias, gyro_bias, P, breaks,
    baro_valid)`` while navigating (``breaks``: resets to a fix and covariance inflations so far),
    then ``(acc_scale, gyro_scale)`` with the scale factors; the error chart is the filter's
    (estimate minus truth):
    ``local(base, x)`` the error of ``base`` if ``x`` were the truth, ``retract(base, d)`` the
    injection of the error ``d`` into ``base``. ``f``: the filter whose run is recorded (its
    ``sample_transition``)."""

    def __init__(self, f):
        self.f = f

    def snapshot(self, f):
        if not f.navigating:
            return None
        s = f.s
        post = (s.nav.lat, s.nav.lon, s.nav.h, s.baro_offset, s.nav.q_nb.copy(), s.nav.v_n.copy(),
                s.acc_bias.copy(), s.gyro_bias.copy(), s.P.copy(),
                sum(c["resets"] + c["inflated"] for c in s.counters.values()),
                s.baro_offset_valid)
        return post + (s.acc_scale.copy(), s.gyro_scale.copy()) if f.scale_factors else post

    @staticmethod
    def same(a, b):
        return all(np.array_equal(x, y) for x, y in zip(a, b))

    @staticmethod
    def restart(prior, post):
        """A reset to a fix, a covariance inflation or the initialization of the altimeter offset:
        not crossed (nav/gps_ins/smoother.hpp says why)."""
        return prior[9] != post[9] or prior[10] != post[10]

    def transition(self, post, k):
        return self.f.sample_transition

    @staticmethod
    def error_covariance(x):
        return x[8]

    @staticmethod
    def local(base, x):
        d = np.concatenate([geodetic_diff(base[0], base[1], base[2], x[0], x[1], x[2]), base[5] - x[5],
                            Q.to_rotvec(Q.mul(base[4], Q.conj(x[4]))), base[6] - x[6], base[7] - x[7],
                            [base[3] - x[3]]])
        return np.concatenate([d, base[11] - x[11], base[12] - x[12]]) if len(base) > 11 else d

    @staticmethod
    def retract(base, d, Ps):
        s = _new_state()
        s.nav = StrapdownState(q_nb=base[4], v_n=base[5], lat=base[0], lon=base[1], h=base[2])
        s.acc_bias, s.gyro_bias, s.baro_offset = base[6], base[7], base[3]
        if len(base) > 11:
            s.acc_scale, s.gyro_scale = base[11], base[12]
        GpsInsFilter._inject(s, d)
        x = (s.nav.lat, s.nav.lon, s.nav.h, s.baro_offset, s.nav.q_nb, s.nav.v_n, s.acc_bias, s.gyro_bias, Ps,
             base[9], base[10])
        return x + (s.acc_scale, s.gyro_scale) if len(base) > 11 else x


class _GpsInsRecorder(Recorder):
    """The record, with the filter's restarts (no link across them)."""

    def after_predict(self, k, f):
        super().after_predict(k, f)
        if self._pending is not None and not isinstance(self._pending[1], str):
            self._prior = self._pending[1][0]
        else:
            self._prior = None

    def after_sample(self, k, f):
        pending = self._pending
        prior = getattr(self, "_prior", None)
        super().after_sample(k, f)
        if pending is not None and prior is not None and self.links and self.posts:
            if pending[0] == k and self.model.restart(prior, self.posts[-1]):
                self.links[-1] = None
        self._prior = None


class _Both:
    """Two observers of one run, in order."""

    def __init__(self, a, b):
        self.a, self.b = a, b

    def after_predict(self, k, f):
        self.a.after_predict(k, f)
        self.b.after_predict(k, f)

    def after_sample(self, k, f):
        self.a.after_sample(k, f)
        self.b.after_sample(k, f)


def run_smoothed(f, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
                 odometer=None, outages=(), imu_input="rate", observer=None):
    """:meth:`GpsInsFilter.run` (the same arguments) followed by the backward pass. Returns
    ``(out, smoothed)``: the forward dict and ``{"llh", "v_n", "q_nb", "acc_bias", "gyro_bias",
    "sigma", "baro_offset"}`` (and ``"acc_scale", "gyro_scale"`` with the scale factors), the
    smoothed values at the navigating samples and the forward ones elsewhere. ``observer``: also
    told of every sample (after the smoother's record)."""
    rec = _GpsInsRecorder(GpsInsRtsModel(f))
    out = f.run(gyr, acc, mag, t=t, dt=dt, gps_pos=gps_pos, gps_vel=gps_vel, baro=baro, compass=compass,
                odometer=odometer, outages=outages, imu_input=imu_input,
                observer=rec if observer is None else _Both(rec, observer))
    keys = ("llh", "v_n", "q_nb", "acc_bias", "gyro_bias", "sigma", "baro_offset")
    sm = {k: np.array(out[k], dtype=float, copy=True)
          for k in keys + (("acc_scale", "gyro_scale") if f.scale_factors else ())}
    if rec.first is None:
        return out, sm
    first, xs, Ps = rec.smooth()
    for i, (x, P) in enumerate(zip(xs, Ps)):
        k = first + i
        sm["llh"][k] = x[0:3]
        sm["v_n"][k], sm["q_nb"][k], sm["acc_bias"][k], sm["gyro_bias"][k] = x[5], x[4], x[6], x[7]
        sm["sigma"][k] = np.sqrt(np.maximum(np.diag(P), 0.0))
        sm["baro_offset"][k] = x[3] if x[10] else np.nan
        if f.scale_factors:
            sm["acc_scale"][k], sm["gyro_scale"][k] = x[11], x[12]
    return out, sm
