"""The GPS/INS error-state matrix F (paper 004 eq. 8-10) against finite differences of the
continuous-time mechanization (eq. 1-2).

The error is "estimate minus truth" as in ``quatnav/gps_ins.hpp``:
dp = NED metres of (lat, lon, h)_est - (lat, lon, h)_true about the truth, dv = v_est - v_true,
psi with C_nb_est = exp([psi x]) C_nb_true, db = b_est - b_true (the estimated IMU is the
measurement less b_est, so a bias error enters the estimated mechanization as -db).

For each error component i the estimate is built from the truth displaced by +-eps along i, both
are advanced by the exact continuous derivatives of the mechanization

    lat' = v_N / (R_M + h),  lon' = v_E / ((R_N + h) cos lat),  h' = -v_D
    v'   = C_nb f_b + [0, 0, g(lat, h)] - (2 w_ie + w_en) x v
    C'   = C_nb [w_b x] - [w_in x] C_nb
    b'   = -b / tau   (0 for a random walk)

and the time derivative of the error, differenced over +-eps, is column i of F. The filter's F
takes the radii of curvature as constant in latitude; the strict check freezes them likewise, a
second check lets them vary and bounds the neglected terms (order e^2 ~ 0.7 % of their row).

With the scale-factor states (``GpsInsFilter(scale_factors=True)``) the state also holds the
scale factors sa, sg (constant: s' = 0), the IMU is corrected as (m - b) / (1 + s) and their
errors ds = s_est - s_true are six more components; the 22-state F is checked the same way at
scale factors of a few per cent, so that the factors 1 / (1 + s) of the bias and scale-factor
columns are seen.
"""
import math

import numpy as np
import pytest

from quatnav.core import earth
from quatnav.core import quaternion as Q
from quatnav.reference.gpsins import GpsInsParams, gpsins_F
from quatnav.core.strapdown import StrapdownState


def _radii(lat, lat_frozen):
    return earth.radii(lat_frozen if lat_frozen is not None else lat)


def _dradii(lat, lat_frozen):
    """d R_M / d lat, d R_N / d lat (zero when the radii are frozen)."""
    if lat_frozen is not None:
        return 0.0, 0.0
    s, c = math.sin(lat), math.cos(lat)
    w = 1.0 - earth.E2 * s * s
    return (3.0 * earth.A * (1 - earth.E2) * earth.E2 * s * c / w ** 2.5, earth.A * earth.E2 * s * c / w ** 1.5)


def _xdot(x, f_m, w_m, p, lat_frozen):
    """Continuous derivatives of the mechanization state x = dict(lat, lon, h, v, C, ba, bg) (and
    sa, sg: the scale factors)."""
    lat, h, v, C = x["lat"], x["h"], x["v"], x["C"]
    R_M, R_N = (float(r) for r in _radii(lat, lat_frozen))
    f_b = f_m - x["ba"]
    w_b = w_m - x["bg"]
    if "sa" in x:  # the sensor model m = (1 + s) x + b, per axis
        f_b, w_b = f_b / (1.0 + x["sa"]), w_b / (1.0 + x["sg"])
    if p.earth_rotation:
        w_ie = np.array([earth.OMEGA_IE * math.cos(lat), 0.0, -earth.OMEGA_IE * math.sin(lat)])
        w_en = np.array([v[1] / (R_N + h), -v[0] / (R_M + h), -v[1] * math.tan(lat) / (R_N + h)])
    else:
        w_ie = w_en = np.zeros(3)
    g = float(earth.gravity(lat, h))
    d = dict(lat=v[0] / (R_M + h), lon=v[1] / ((R_N + h) * math.cos(lat)), h=-v[2],
             v=C @ f_b + np.array([0.0, 0.0, g]) - np.cross(2.0 * w_ie + w_en, v),
             C=C @ Q.skew(w_b) - Q.skew(w_ie + w_en) @ C,
             ba=-x["ba"] / p.acc_bias_tau if p.acc_bias_tau > 0 else np.zeros(3),
             bg=-x["bg"] / p.gyro_bias_tau if p.gyro_bias_tau > 0 else np.zeros(3))
    if "sa" in x:
        d["sa"], d["sg"] = np.zeros(3), np.zeros(3)
    return d


def _perturb(xt, i, eps, lat_frozen):
    """The estimate: the truth displaced by eps along error component i."""
    x = {k: (v.copy() if isinstance(v, np.ndarray) else v) for k, v in xt.items()}
    R_M, R_N = (float(r) for r in _radii(xt["lat"], lat_frozen))
    if i == 0:
        x["lat"] += eps / (R_M + xt["h"])
    elif i == 1:
        x["lon"] += eps / ((R_N + xt["h"]) * math.cos(xt["lat"]))
    elif i == 2:
        x["h"] -= eps
    elif i < 6:
        x["v"][i - 3] += eps
    elif i < 9:
        x["C"] = Q.to_rotmat(Q.from_rotvec(eps * np.eye(3)[i - 6])) @ xt["C"]
    elif i < 12:
        x["ba"][i - 9] += eps
    elif i < 15:
        x["bg"][i - 12] += eps
    elif i < 18:
        x["sa"][i - 15] += eps
    else:
        x["sg"][i - 18] += eps
    return x


def _error_rate(xe, xt, f_m, w_m, p, lat_frozen):
    """d/dt of the error (estimate minus truth) with both states moving by the mechanization."""
    de, dt_ = _xdot(xe, f_m, w_m, p, lat_frozen), _xdot(xt, f_m, w_m, p, lat_frozen)
    L, h = xt["lat"], xt["h"]
    R_M, R_N = (float(r) for r in _radii(L, lat_frozen))
    dRM, dRN = _dradii(L, lat_frozen)
    dlat, dlon = xe["lat"] - xt["lat"], xe["lon"] - xt["lon"]
    out = np.zeros(21 if "sa" in xt else 15)
    out[0] = (de["lat"] - dt_["lat"]) * (R_M + h) + dlat * (dRM * dt_["lat"] + dt_["h"])
    out[1] = ((de["lon"] - dt_["lon"]) * (R_N + h) * math.cos(L)
              + dlon * ((dRN * dt_["lat"] + dt_["h"]) * math.cos(L) - (R_N + h) * math.sin(L) * dt_["lat"]))
    out[2] = -(de["h"] - dt_["h"])
    out[3:6] = de["v"] - dt_["v"]
    # [psi x] = C_e C_t^T - I to first order; its rate, the skew part of the derivative (the
    # second-order remainder is even in eps and cancels in the central difference).
    Ed = de["C"] @ xt["C"].T + xe["C"] @ dt_["C"].T
    S = 0.5 * (Ed - Ed.T)
    out[6:9] = [S[2, 1], S[0, 2], S[1, 0]]
    out[9:12] = de["ba"] - dt_["ba"]
    out[12:15] = de["bg"] - dt_["bg"]
    if "sa" in xt:
        out[15:18] = de["sa"] - dt_["sa"]
        out[18:21] = de["sg"] - dt_["sg"]
    return out


# Steps per error component (m, m/s, rad, m/s^2, rad/s): central differences cancel the
# second-order terms, so large steps keep the round-off of the geodetic position small.
EPS = np.array([100.0] * 3 + [1e-2] * 3 + [1e-5] * 3 + [1e-4] * 3 + [1e-6] * 3)
#: Round-off of the differenced error rates (about 2e-14 in the rates over each step).
ATOL = 2e-14 / EPS
#: With the scale factors (1).
EPS_SF = np.concatenate([EPS, [1e-4] * 6])
ATOL_SF = 2e-14 / EPS_SF


def _fd_F(xt, f_m, w_m, p, lat_frozen):
    eps = EPS_SF if "sa" in xt else EPS
    n = len(eps)
    F = np.zeros((n, n))
    for i in range(n):
        e = eps[i]
        rp = _error_rate(_perturb(xt, i, e, lat_frozen), xt, f_m, w_m, p, lat_frozen)
        rm = _error_rate(_perturb(xt, i, -e, lat_frozen), xt, f_m, w_m, p, lat_frozen)
        F[:, i] = (rp - rm) / (2 * e)
    return F


def _case(earth_rotation, tau):
    p = GpsInsParams(earth_rotation=earth_rotation, acc_bias_tau=tau, gyro_bias_tau=2 * tau)
    q = Q.from_euler(np.array([0.3, -0.4, 2.0]))
    # A fast, climbing vehicle at 50 deg N so that the small transport-rate and Coriolis terms
    # are far above the differencing noise.
    xt = dict(lat=math.radians(50.0), lon=math.radians(8.0), h=800.0, v=np.array([150.0, -90.0, 12.0]),
              C=Q.to_rotmat(q), ba=np.array([0.05, -0.03, 0.08]), bg=np.array([2e-3, -1e-3, 3e-3]))
    f_m = np.array([1.5, -0.8, -9.6]) + xt["ba"]
    w_m = np.array([0.1, -0.2, 0.3]) + xt["bg"]
    nav = StrapdownState(q_nb=q, v_n=xt["v"].copy(), lat=xt["lat"], lon=xt["lon"], h=xt["h"])
    F = gpsins_F(nav, f_m - xt["ba"], p)
    return p, xt, f_m, w_m, F


BLOCKS = {"pos": slice(0, 3), "vel": slice(3, 6), "att": slice(6, 9), "ba": slice(9, 12), "bg": slice(12, 15)}


@pytest.mark.parametrize("earth_rotation,tau", [(True, 0.0), (True, 300.0), (False, 0.0)])
def test_F_matches_finite_differences_with_frozen_radii(earth_rotation, tau):
    p, xt, f_m, w_m, F = _case(earth_rotation, tau)
    Ffd = _fd_F(xt, f_m, w_m, p, lat_frozen=xt["lat"])
    # Each 3x3 block on its own scale: the blocks span 1e-12 (Earth-rate position terms) to 10.
    for rn, rs in BLOCKS.items():
        for cn, cs in BLOCKS.items():
            a, b = F[rs, cs], Ffd[rs, cs]
            tol = 1e-5 * np.abs(b).max() + ATOL[cs]
            assert np.all(np.abs(a - b) <= tol), (rn, cn, a, b)
    # The altimeter offset (16th state) is a random walk: no dynamics, no coupling.
    assert F.shape == (16, 16) and not F[15, :].any() and not F[:, 15].any()
    # The tiny terms are really exercised (non-zero) when the Earth turns.
    if earth_rotation:
        assert np.abs(Ffd[6:9, 0:3]).max() > 1e-12 and np.abs(Ffd[3:6, 0:3][:2]).max() > 1e-10


def test_F_radii_variation_is_negligible():
    """With the radii varying in latitude, F misses only terms of relative size e^2 (documented)."""
    p, xt, f_m, w_m, F = _case(True, 0.0)
    Ffd = _fd_F(xt, f_m, w_m, p, lat_frozen=None)
    for rs in BLOCKS.values():
        for cs in BLOCKS.values():
            a, b = F[rs, cs], Ffd[rs, cs]
            assert np.all(np.abs(a - b) <= 2e-2 * np.abs(b).max() + ATOL[cs])
    # ... and it does see them (the check is not vacuous): R_N' in the east position row.
    assert abs(F[1, 0] - Ffd[1, 0]) > 1e-4 * abs(Ffd[1, 0])


def test_F_finite_difference_check_detects_an_error():
    """A sign slip in one Coriolis term must fail the strict comparison."""
    p, xt, f_m, w_m, F = _case(True, 0.0)
    Ffd = _fd_F(xt, f_m, w_m, p, lat_frozen=xt["lat"])
    bad = F.copy()
    bad[3:6, 3:6] += Q.skew(np.array([earth.OMEGA_IE * math.cos(xt["lat"]), 0, 0]))  # 2 w_ie -> w_ie (N)
    assert np.abs(bad[3:6, 3:6] - Ffd[3:6, 3:6]).max() > 1e-5 * np.abs(Ffd[3:6, 3:6]).max() + ATOL[3]
    bad = F.copy()
    bad[6, 2] *= 1.01  # 1 % off in an Earth-rate position term (1e-12 1/s/m)
    assert abs(bad[6, 2] - Ffd[6, 2]) > 1e-5 * np.abs(Ffd[6:9, 0:3]).max() + ATOL[2]


# --- the scale-factor states ----------------------------------------------------------------------
#: The 21 differenced components among the 22 states (the altimeter offset, 15, has no dynamics).
SF_IDX = np.r_[0:15, 16:22]
SF_BLOCKS = {**BLOCKS, "sa": slice(15, 18), "sg": slice(18, 21)}


def _case_sf(earth_rotation, tau, s=0.01):
    """The state of :func:`_case` with scale factors of a few ``s`` (the same true specific force
    and rate, measured through them) and the filter's 22-state F there."""
    p, xt, f_m, w_m, _ = _case(earth_rotation, tau)
    sa, sg = s * np.array([1.0, -2.0, 1.5]), s * np.array([-1.0, 2.0, 1.0])
    xt = dict(xt, sa=sa, sg=sg)
    f_m = (1.0 + sa) * (f_m - xt["ba"]) + xt["ba"]
    w_m = (1.0 + sg) * (w_m - xt["bg"]) + xt["bg"]
    f_b, w_b = (f_m - xt["ba"]) / (1.0 + sa), (w_m - xt["bg"]) / (1.0 + sg)  # as the filter corrects them
    return p, xt, f_m, w_m, f_b, w_b, gpsins_F(_nav(xt), f_b, p, w_b=w_b, acc_scale=sa, gyro_scale=sg)


def _nav(xt):
    return StrapdownState(q_nb=Q.from_rotmat(xt["C"]), v_n=xt["v"].copy(), lat=xt["lat"], lon=xt["lon"], h=xt["h"])


def _blocks_match(F21, Ffd):
    """Every 3x3 block of the 21 components within 1e-5 of its own scale (as the strict check)."""
    for rn, rs in SF_BLOCKS.items():
        for cn, cs in SF_BLOCKS.items():
            a, b = F21[rs, cs], Ffd[rs, cs]
            if not np.all(np.abs(a - b) <= 1e-5 * np.abs(b).max() + ATOL_SF[cs]):
                return False, (rn, cn, a, b)
    return True, None


@pytest.mark.parametrize("earth_rotation,tau", [(True, 0.0), (True, 300.0), (False, 0.0)])
def test_F_with_scale_factors_matches_finite_differences(earth_rotation, tau):
    """The 22-state F at scale factors of 1-2 %: F_v,ba = -C Da, F_v,sa = -C diag(f / (1 + s_a)),
    F_psi,bg = -C Dg, F_psi,sg = -C diag(w / (1 + s_g)) (f, w corrected), the rest as with 16."""
    p, xt, f_m, w_m, f_b, w_b, F = _case_sf(earth_rotation, tau)
    assert F.shape == (22, 22)
    Ffd = _fd_F(xt, f_m, w_m, p, lat_frozen=xt["lat"])
    ok, where = _blocks_match(F[np.ix_(SF_IDX, SF_IDX)], Ffd)
    assert ok, where
    # the offset and the scale factors are random walks: no dynamics; the offset is not coupled
    assert not F[15, :].any() and not F[:, 15].any() and not F[16:22, :].any()
    # the factors 1 / (1 + s) are seen: -C alone is off by far more than the tolerance
    C = xt["C"]
    for rs, cs in ((SF_BLOCKS["vel"], SF_BLOCKS["ba"]), (SF_BLOCKS["att"], SF_BLOCKS["bg"])):
        assert np.abs(-C - Ffd[rs, cs]).max() > 100 * 1e-5 * np.abs(Ffd[rs, cs]).max()
    # at s = 0 the 22-state F holds the 16-state one, bit for bit
    p, xt, f_m, w_m, f_b, w_b, F0 = _case_sf(earth_rotation, tau, s=0.0)
    np.testing.assert_array_equal(F0[:16, :16], gpsins_F(_nav(xt), f_b, p))


def test_F_scale_factor_slips_fail_the_finite_differences():
    """A wrong sign, (1 + s) for 1 / (1 + s), the uncorrected input or a missing Da each fail the
    strict comparison (the check is not vacuous at s of 1-2 %)."""
    p, xt, f_m, w_m, f_b, w_b, F = _case_sf(True, 0.0)
    Ffd = _fd_F(xt, f_m, w_m, p, lat_frozen=xt["lat"])
    C, sa, sg = xt["C"], xt["sa"], xt["sg"]
    slips = {"F_v,ba = -C (no Da)": (slice(3, 6), slice(9, 12), -C),
             "F_v,sa with (1 + s_a)": (slice(3, 6), slice(16, 19), -C * (f_b * (1.0 + sa))),
             "F_v,sa with f_m - b_a": (slice(3, 6), slice(16, 19), -C * ((f_m - xt["ba"]) / (1.0 + sa))),
             "F_psi,bg = -C (no Dg)": (slice(6, 9), slice(12, 15), -C),
             "F_psi,sg with + sign": (slice(6, 9), slice(19, 22), C * (w_b / (1.0 + sg))),
             "F_psi,sg with w_m - b_g": (slice(6, 9), slice(19, 22), -C * ((w_m - xt["bg"]) / (1.0 + sg)))}
    for name, (rs, cs, block) in slips.items():
        bad = F.copy()
        bad[rs, cs] = block
        assert not _blocks_match(bad[np.ix_(SF_IDX, SF_IDX)], Ffd)[0], name
