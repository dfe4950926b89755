"""The model of the numpy GpsInsFilter (``quatnav.reference.gpsins``), the twin of
``cpp/include/quatnav/nav/gps_ins/`` params.hpp, model.hpp and aids.hpp: the parameters, the error
state's layout, the continuous error dynamics F and the process noise, the geodetic helpers, the
state record, the injection of a correction, and the aids, each one function giving ``(y, H, R)``
at a state.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from types import SimpleNamespace

import numpy as np

from .._validate import did_you_mean
from ..core import earth
from ..core import quaternion as Q
from ..core.strapdown import StrapdownState
from ..filters.tables import GPSINS_PARAMS
from .lowpass import lowpass
ALIGNING, LEVELLED, NAVIGATING = 0, 1, 2
KINDS = ("gps_pos", "gps_vel", "baro", "baro_vd", "compass", "mag", "zupt", "zaru", "nhc", "odometer")
#: ``quatnav::GpsInsDecision`` names by code.
DECISIONS = ("none", "accepted", "rejected", "inflated", "reset", "skipped", "aligned", "weighted")
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
    p.nhc_lever_b = np.asarray(p.nhc_lever_b, float).reshape(3)
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


def _qc_rate(p, q_scale, q_nb, w_b, scale_factors=False):
    """The attitude's rate-proportional process noise (3 x 3, NED): k^2 |w|^2 I, k =
    gyro_rate_noise, w the corrected rate w - b; with the scale factors k^2 C_nb diag(|w|^2 -
    w_i^2) C_nb^T, the misalignment that remains once the scale factors are states. None when
    zero. The derivation is at gpsins_Qc_rate (model.hpp)."""
    w_b = np.asarray(w_b, float)
    w2 = float(w_b @ w_b)
    if not (p.gyro_rate_noise > 0 and w2 > 0):
        return None
    k2 = q_scale * p.gyro_rate_noise ** 2
    if scale_factors:
        C = Q.to_rotmat(q_nb)
        return C @ np.diag(k2 * (w2 - w_b ** 2)) @ C.T
    return k2 * w2 * np.eye(3)


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
    rest_v: np.ndarray = field(default_factory=lambda: np.zeros(3))
    gnss_speed: float = -1.0
    gnss_speed_t: float = 0.0
    pseudo_t: float = -1e9
    gnss_t: float = -1e9
    gps_pos_t: float = -1e9
    nhc_ms: float = -1.0
    nhc_ky: float = 0.0
    nhc_kz: float = 0.0
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
                                                        "resets": 0, "weighted": 0} for k in KINDS})

    def copy(self):
        return replace(self, nav=self.nav.copy(), acc_bias=self.acc_bias.copy(), gyro_bias=self.gyro_bias.copy(),
                       P=self.P.copy(), acc_scale=self.acc_scale.copy(), gyro_scale=self.gyro_scale.copy(),
                       omega_b=self.omega_b.copy(), f_b=self.f_b.copy(),
                       align_sum=self.align_sum.copy(), reject_run=dict(self.reject_run),
                       rest_gyr_lp=self.rest_gyr_lp.copy(), rest_acc_lp=self.rest_acc_lp.copy(),
                       rest_v=self.rest_v.copy(),
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


def gnss_sigma_floor(p, kind):
    """Floor of a fix's NED one-sigma for the solution kind (a GNSS_SOLUTIONS code; detail::gnss_sigma_floor):
    the kind's floor north and east, gps_vertical_floor_ratio times it down."""
    f = {2: p.gps_float_sigma_min, 3: p.gps_dgnss_sigma_min, 4: p.gps_single_sigma_min}.get(int(kind),
                                                                                         p.gps_pos_sigma_min)
    return np.array([f, f, p.gps_vertical_floor_ratio * f])


def gnss_correlation_scale(p, kind, dt):
    """One-sigma scale sqrt((1 + rho) / (1 - rho)), rho = exp(-dt / gps_error_tau), of a position
    fix whose error wanders (RTK float, DGNSS, single: codes 2, 3, 4), dt (s, at least 1 ms) after
    the last accepted one (detail::gnss_correlation_scale); 1 otherwise."""
    if int(kind) not in (2, 3, 4) or not p.gps_error_tau > 0:
        return 1.0
    rho = math.exp(-max(dt, 1e-3) / p.gps_error_tau)
    return math.sqrt((1.0 + rho) / (1.0 - rho))


def huber_scales(y, S, k):
    """Huber's weights as variance factors (detail::huber_scales): per component of y the factor
    sqrt(|z| / k) of its standard deviation where |z| = |y_i| / sqrt(S_ii) > k (else 1), or None
    when every component is within k."""
    z = np.abs(y) / np.sqrt(np.diag(S))
    if not np.any(z > k):
        return None
    return np.where(z > k, np.sqrt(z / k), 1.0)


def _gps_position(s, p, lat, lon, h, sigma, age, floor):
    """INS antenna position, taken back by ``age`` with the antenna velocity, minus the fix (its
    one-sigma at least ``floor``)."""
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
    R = np.diag(np.maximum(sigma, floor) ** 2)
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


def _nhc(s, p, var=0.0, lateral=True):
    """No lateral or vertical velocity of the vehicle: the body velocity's rows 1, 2 less the
    mounting's share of the forward speed (s.nhc_ky, s.nhc_kz; as gpsins_aid::NonHolonomic); the
    lateral row's variance gains (w_z nhc_arm)^2; without ``lateral`` the lateral row is zero (no
    information)."""
    v, Hb = _body_velocity_rows(s, [0, 1, 2])
    v = v + np.cross(s.omega_b, p.nhc_lever_b)  # at the non-slipping point (its bias term left out of H)
    k = np.array([s.nhc_ky, s.nhc_kz])
    y = v[1:] - k * v[0]
    H = Hb[1:] - k[:, None] * Hb[0]
    if not lateral:
        y[0] = 0.0
        H[0] = 0.0
    R = (var if var > 0 else p.nhc_sigma ** 2) * np.eye(2)
    if p.nhc_arm > 0:
        R[0, 0] += (s.omega_b[2] * p.nhc_arm) ** 2
    return y, H, R


def _gnss_aided(s):
    """A GNSS position or velocity accepted within the last 2.5 s (as detail::gpsins_gnss_aided)."""
    return s.t - s.gnss_t < 2.5


def _nhc_evidence(s, p, dt):
    """The evidence of a wheeled vehicle (as detail::gpsins_nhc_evidence): while GNSS-aided and
    faster than nhc_auto_speed forward, the mounting (lateral and vertical body velocity per forward
    speed, low-passed from 0 with nhc_mount_tau_yaw and _pitch while the yaw rate is within nhc_auto_rate), the low-passed mean square of the
    lateral and vertical body velocity about it and the time it has stayed within nhc_auto_limit^2
    (lost above twice the limit, held in between)."""
    if not p.nhc_auto or not _gnss_aided(s):
        return
    v_b = Q.rotate_inv(s.nav.q_nb, s.nav.v_n) + np.cross(s.omega_b, p.nhc_lever_b)  # at the axle
    if not abs(v_b[0]) > p.nhc_auto_speed:
        return
    if abs(s.omega_b[2]) <= p.nhc_auto_rate:
        if p.nhc_mount_tau_yaw > 0:
            s.nhc_ky = lowpass(s.nhc_ky, v_b[1] / v_b[0], dt, p.nhc_mount_tau_yaw)
        if p.nhc_mount_tau_pitch > 0:
            s.nhc_kz = lowpass(s.nhc_kz, v_b[2] / v_b[0], dt, p.nhc_mount_tau_pitch)
    e = (v_b[1] - s.nhc_ky * v_b[0]) ** 2 + (v_b[2] - s.nhc_kz * v_b[0]) ** 2
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


def inject(s, dx):
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
