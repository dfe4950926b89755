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
    """Continuous derivatives of the mechanization state x = dict(lat, lon, h, v, C, ba, bg)."""
    lat, h, v, C = x["lat"], x["h"], x["v"], x["C"]
    R_M, R_N = (float(r) for r in _radii(lat, lat_frozen))
    f_b = f_m - x["ba"]
    w_b = w_m - x["bg"]
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
    else:
        x["bg"][i - 12] += eps
    return x


def _error_rate(xe, xt, f_m, w_m, p, lat_frozen):
    """d/dt of the error (estimate minus truth) with both states moving by the mechanization."""
    de, dt_ = _xdot(xe, f_m, w_m, p, lat_frozen), _xdot(xt, f_m, w_m, p, lat_frozen)
    L, h = xt["lat"], xt["h"]
    R_M, R_N = (float(r) for r in _radii(L, lat_frozen))
    dRM, dRN = _dradii(L, lat_frozen)
    dlat, dlon = xe["lat"] - xt["lat"], xe["lon"] - xt["lon"]
    out = np.zeros(15)
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
    return out


# Steps per error component (m, m/s, rad, m/s^2, rad/s): central differences cancel the
# second-order terms, so large steps keep the round-off of the geodetic position small.
EPS = np.array([100.0] * 3 + [1e-2] * 3 + [1e-5] * 3 + [1e-4] * 3 + [1e-6] * 3)
#: Round-off of the differenced error rates (about 2e-14 in the rates over each step).
ATOL = 2e-14 / EPS


def _fd_F(xt, f_m, w_m, p, lat_frozen):
    F = np.zeros((15, 15))
    for i in range(15):
        e = EPS[i]
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
