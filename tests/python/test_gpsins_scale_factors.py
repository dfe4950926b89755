"""GpsInsFilter's optional scale-factor states in the numpy twin (``GpsInsFilter(scale_factors=True)``,
22 error states: the 16 and ds_a, ds_g).

* The transition of one time update against finite differences of the twin's own step (the
  continuous F against the mechanization's derivatives is in test_gpsins_jacobian.py).
* With the scale factors pinned at zero (zero sigma, zero noise) the 22-state filter gives the
  16-state numbers (the 16-state twin itself is checked against the C++ filter in test_gpsins.py
  and, through it, against the committed regression outputs).
* The interface: parameters, initial covariance, reset, set_initial, injection, run's outputs.
* Estimation on a simulated drive with turns whose IMU has a 1 % gyro-z scale-factor error and
  accelerometer scale errors of a few 1e-3 (the sensors otherwise as the filter models them): the
  scale factors converge to the injected ones within 3 sigma, their NEES stays inside a chi-square
  band (on one drive: a gross check, see below), the heading and the drift in a GNSS outage are
  better than without the states, the smoother carries them.

The scale factors' consistency with power (a filter 1.5x over- or under-confident fails) is the
Monte Carlo of ``test_gpsins_consistency.py::test_scale_factor_nees_within_chi2_bounds`` on this
same drive (64 independent runs, C++ filter; the twin agrees with it step by step,
``test_gpsins_scale.py``).
"""
import math

import numpy as np
import pytest

import quatnav
from quatnav import reference as R
from quatnav.core import earth
from quatnav.core import quaternion as Q
from quatnav.reference.gpsins import BA, BG, N, N_SF, SA, SG, GpsInsRtsModel
from quatnav.sim import sensors as SS
from quatnav.sim.scenarios import make_scenario
from quatnav.sim.trajectory import Accelerate, Cruise, Turn, make_trajectory

LEVER = (0.1, 0.0, -0.1)


# --- one time update against the twin's own mechanization ------------------------------------------
_Q0 = Q.from_euler(np.array([0.3, -0.4, 2.0]))
_NAV0 = (np.array([150.0, -90.0, 12.0]), math.radians(50.0), math.radians(8.0), 800.0)
_BA, _BG = np.array([0.05, -0.03, 0.08]), np.array([2e-3, -1e-3, 3e-3])
_SA, _SG = np.array([0.01, -0.02, 0.015]), np.array([-0.01, 0.02, 0.01])
_F_TRUE, _W_TRUE = np.array([1.5, -0.8, -9.6]), np.array([0.1, -0.2, 0.3])


def _one_step(dt, **delta):
    """The twin reset to the state above (the given fields displaced by ``delta``) after one
    predict with the IMU of the true specific force and rate through the true scale factors and
    biases: ``(snapshot, filter)``."""
    x = dict(acc_bias=_BA, gyro_bias=_BG, acc_scale=_SA, gyro_scale=_SG)
    x = {k: v + delta.get(k, 0.0) for k, v in x.items()}
    f = R.GpsInsFilter(scale_factors=True)
    f.reset(_Q0, *_NAV0, x["acc_bias"], x["gyro_bias"], 1e-6 * np.eye(N_SF), x["acc_scale"], x["gyro_scale"])
    assert f.predict((1.0 + _SG) * _W_TRUE + _BG, (1.0 + _SA) * _F_TRUE + _BA, dt) == "ok"
    return GpsInsRtsModel(f).snapshot(f), f


def test_transition_of_a_step_matches_the_twins_mechanization():
    """Columns ba, bg, sa, sg of Phi - I against the twin's own predict (strapdown step and
    (m - b) / (1 + s) inputs) from states displaced by +-eps in one bias or scale factor, the
    errors after the step in the filter's chart: the directly driven blocks (velocity by ba, sa;
    attitude by bg, sg) agree to the O(w dt) of a single step, well inside the 1-2 % that a
    missing 1 / (1 + s) would make. Without bias decay the scale-factor columns of Phi - I are its
    bias columns (which hold Da = diag(1 / (1 + s_a))) times diag(f) (diag(w)), f and w corrected:
    the spec's "bias columns times diag(f / (1 + s_a))" with the bias columns of 16 states (-C)."""
    dt = 1e-3
    base, f0 = _one_step(dt)
    Phi = f0.last_transition
    assert Phi.shape == (N_SF, N_SF)
    C = Q.to_rotmat(_Q0)
    cases = {"acc_bias": (BA, 1e-4, slice(3, 6)), "gyro_bias": (BG, 1e-6, slice(6, 9)),
             "acc_scale": (SA, 1e-4, slice(3, 6)), "gyro_scale": (SG, 1e-4, slice(6, 9))}
    for name, (c0, eps, rows) in cases.items():
        fd = np.zeros((N_SF, 3))
        for j in range(3):
            d = eps * np.eye(3)[j]
            fd[:, j] = (GpsInsRtsModel.local(_one_step(dt, **{name: d})[0], base)
                        - GpsInsRtsModel.local(_one_step(dt, **{name: -d})[0], base)) / (2 * eps)
        a, b = (Phi[rows, c0:c0 + 3]) / dt, fd[rows] / dt
        scale = np.abs(b).max()
        assert np.abs(a - b).max() <= 1e-3 * scale, (name, a, b)
        if name in ("acc_bias", "gyro_bias"):  # -C (no 1 / (1 + s)) is off by 1-2 %: seen
            assert np.abs(-C - b).max() > 5e-3 * scale, name
    # the spec's statement on Phi (bias random walks here: no decay term)
    f_b, w_b = f0.s.f_b, f0.s.omega_b
    np.testing.assert_allclose(f_b, _F_TRUE, rtol=1e-12)  # (m - b) / (1 + s) undoes the sensor model
    np.testing.assert_allclose(w_b, _W_TRUE, rtol=1e-12)
    D = Phi - np.eye(N_SF)  # the identity of each column aside
    np.testing.assert_allclose(D[:, SA:SA + 3], D[:, BA:BA + 3] * f_b, rtol=1e-12, atol=1e-18)
    np.testing.assert_allclose(D[:, SG:SG + 3], D[:, BG:BG + 3] * w_b, rtol=1e-12, atol=1e-18)
    # (the 22-state bias columns times f / (1 + s_a) would hold 1 / (1 + s_a) twice: 1-2 % off)
    twice = D[3:6, BA:BA + 3] * (f_b / (1 + _SA))
    assert np.abs(D[3:6, SA:SA + 3] - twice).max() > 5e-3 * np.abs(D[3:6, SA:SA + 3]).max()


# --- without scale factors, and pinned at zero ------------------------------------------------------
@pytest.fixture(scope="module")
def walk():
    """``(run, out)``: ``run(f, n)`` runs a twin on the first n samples of the paper-004 walk with
    every aid, ``out`` is the default twin's run on 1500 (alignment and ~25 s of navigation)."""
    s = make_scenario("paper004_walk", seed=0)
    aids = dict(gps_pos=quatnav.Aid(s.gps.t_valid, np.column_stack([s.gps.lat, s.gps.lon, s.gps.h])),
                gps_vel=quatnav.Aid(s.gps.t_valid, s.gps.v_n), baro=quatnav.Aid(s.baro.t, s.baro.h),
                compass=quatnav.Aid(s.compass.t, s.compass.yaw))

    def run(f, n=1500):
        return f.run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **aids)
    return run, run(R.GpsInsFilter(lever_arm_b=LEVER))


def test_scale_factors_pinned_at_zero_give_the_16_state_run(walk):
    """22 states with the scale factors' sigma and noise zero: the same numbers as 16 (the new
    states are decoupled and the extended code path changes nothing else; measured: the same
    bits), the scale factors stay zero."""
    run, a = walk
    f = R.GpsInsFilter(scale_factors=True, lever_arm_b=LEVER, init_acc_scale_sigma=0.0, init_gyro_scale_sigma=0.0,
                       acc_scale_noise=0.0, gyro_scale_noise=0.0)
    b = run(f)
    assert b["sigma"].shape == (1500, N_SF) and f.covariance.shape == (N_SF, N_SF)
    for key in ("llh", "v_n", "q_nb", "acc_bias", "gyro_bias", "baro_offset", "q_scale"):
        np.testing.assert_allclose(b[key], a[key], rtol=1e-12, atol=1e-15, err_msg=key)
    np.testing.assert_allclose(b["sigma"][:, :N], a["sigma"], rtol=1e-12, atol=1e-15)
    nav = np.isfinite(b["llh"][:, 0])
    assert not b["sigma"][nav, N:].any() and not b["acc_scale"].any() and not b["gyro_scale"].any()
    for key in ("gps", "baro", "compass"):
        np.testing.assert_array_equal(b[key]["decision"], a[key]["decision"])
        np.testing.assert_allclose(b[key]["nis"], a[key]["nis"], rtol=1e-12, atol=1e-15)


# --- the interface ----------------------------------------------------------------------------------
def test_scale_factor_interface():
    p = R.GpsInsFilter().p  # the spec's defaults
    assert (p.acc_scale_noise, p.gyro_scale_noise, p.init_acc_scale_sigma, p.init_gyro_scale_sigma) == \
        (1e-5, 1e-5, 3e-3, 5e-3)
    assert R.GpsInsFilter(gyro_scale_noise=2e-5).p.gyro_scale_noise == 2e-5
    with pytest.raises(TypeError, match="unknown parameter 'scale_noise'"):
        R.GpsInsFilter(scale_factors=True, scale_noise=1e-5)
    f16, f = R.GpsInsFilter(), R.GpsInsFilter(scale_factors=True)
    assert (f16.n_states, f.n_states) == (16, 22) and f.covariance.shape == (22, 22)
    P16, P = f16.initial_covariance([1.0, 2.0, 3.0], 0.5), f.initial_covariance([1.0, 2.0, 3.0], 0.5)
    np.testing.assert_array_equal(P[:16, :16], P16)
    np.testing.assert_array_equal(np.diag(P)[16:], [3e-3 ** 2] * 3 + [5e-3 ** 2] * 3)
    assert not P[:16, 16:].any()
    # reset: a 22 x 22 covariance and the scale factors; the wrong size is refused
    with pytest.raises(ValueError, match=r"P: expected shape \(22, 22\)"):
        f.reset([1, 0, 0, 0], np.zeros(3), 0.6, 2.2, 50.0, np.zeros(3), np.zeros(3), P16)
    with pytest.raises(ValueError, match=r"P: expected shape \(16, 16\)"):
        f16.reset([1, 0, 0, 0], np.zeros(3), 0.6, 2.2, 50.0, np.zeros(3), np.zeros(3), P)
    with pytest.raises(ValueError, match="no scale-factor states"):
        f16.reset([1, 0, 0, 0], np.zeros(3), 0.6, 2.2, 50.0, np.zeros(3), np.zeros(3), P16, acc_scale=[1e-3, 0, 0])
    with pytest.raises(ValueError, match="no scale-factor states"):
        f16.set_initial([1, 0, 0, 0], gyro_scale=[0, 0, 1e-3])
    sa, sg = np.array([2e-3, -1e-3, 3e-3]), np.array([-4e-3, 5e-3, 1e-2])
    P = P.copy()
    P[3, SA], P[SA, 3] = 0.5 * 0.5 * 3e-3, 0.5 * 0.5 * 3e-3  # dv_N and ds_ax correlated
    assert f.reset([1, 0, 0, 0], np.zeros(3), 0.6, 2.2, 50.0, np.zeros(3), np.zeros(3), P, sa, sg) == "ok"
    np.testing.assert_array_equal(f.acc_scale, sa)
    np.testing.assert_array_equal(f.gyro_scale, sg)
    # a correction reaches the scale factors: s -= dx[16:22] with dx = K y
    v_meas = np.array([-0.2, 0.0, 0.0])
    res = f.update_gps_velocity(v_meas, [0.1, 0.1, 0.1])
    assert res.accepted
    H = np.zeros((3, 22))
    H[:, 3:6] = np.eye(3)
    dx = P @ H.T @ np.linalg.solve(res.innovation_cov, res.innovation)
    np.testing.assert_allclose(res.innovation, -v_meas, atol=1e-12)
    np.testing.assert_allclose(f.acc_scale, sa - dx[SA:SA + 3], rtol=1e-12, atol=1e-18)
    assert f.acc_scale[0] < sa[0]  # the INS ahead by 0.2 m/s, positively correlated: the scale factor down
    np.testing.assert_array_equal(f.gyro_scale, sg)
    # the scale factors are random walks of their densities (Qc), without decay
    f = R.GpsInsFilter(scale_factors=True, acc_scale_noise=2e-5, gyro_scale_noise=3e-5, acc_bias_tau=100.0)
    f.reset([1, 0, 0, 0], np.zeros(3), 0.6, 2.2, 50.0, np.zeros(3), np.zeros(3), np.zeros((22, 22)), sa, sg)
    assert f.predict(np.zeros(3), np.array([0.0, 0.0, -9.8]), 0.01) == "ok"
    np.testing.assert_allclose(np.diag(f.covariance)[SA:], [4e-10 * 0.01] * 3 + [9e-10 * 0.01] * 3, rtol=1e-12)
    np.testing.assert_array_equal(f.acc_scale, sa)
    # before navigation the inputs are corrected as (m - b) / (1 + s) too
    f = R.GpsInsFilter(scale_factors=True)
    ba, bg = np.array([0.1, -0.2, 0.05]), np.array([1e-3, 2e-3, -1e-3])
    assert f.set_initial([1, 0, 0, 0], acc_bias=ba, gyro_bias=bg, acc_scale=sa, gyro_scale=sg) == "ok"
    w_m, f_m = np.array([0.01, 0.02, 0.3]), np.array([0.3, -0.2, -9.7])
    assert f.predict(w_m, f_m, 0.01) == "ok" and f.phase == R.gpsins.LEVELLED
    np.testing.assert_allclose(f.s.omega_b, (w_m - bg) / (1 + sg), rtol=1e-15)
    np.testing.assert_allclose(f.s.f_b, (f_m - ba) / (1 + sa), rtol=1e-15)
    np.testing.assert_allclose(f.q_nb, Q.from_rotvec((w_m - bg) / (1 + sg) * 0.01), rtol=0, atol=1e-15)
    f.clear()
    assert f.covariance.shape == (22, 22) and not f.gyro_scale.any()


# --- estimation on a simulated drive ----------------------------------------------------------------
RATE = 50.0  # Hz, trajectory and IMU
_r = np.radians
#: A test-track drive of 79 s: accelerations and turns of 90 to 360 deg, mostly to the right.
SEGMENTS = [Accelerate(4.0, to_speed=10.0), Cruise(3.0), Turn(6.0, angle=_r(90), ramp=1.5),
            Accelerate(3.0, to_speed=14.0), Turn(8.0, angle=_r(180), ramp=2.0), Accelerate(3.0, to_speed=8.0),
            Turn(8.0, angle=_r(270), ramp=2.0), Accelerate(3.0, to_speed=12.0), Cruise(4.0),
            Turn(6.0, angle=_r(-90), ramp=1.5), Accelerate(3.0, to_speed=8.0), Turn(10.0, angle=_r(360), ramp=2.0),
            Cruise(4.0), Turn(8.0, angle=_r(180), ramp=2.0), Cruise(6.0)]
SA_TRUE = np.array([5e-3, -4e-3, 3e-3])   # accelerometer scale factors
SG_TRUE = np.array([4e-3, -3e-3, 1e-2])   # gyro: 1 % on z
GYRO_DENSITY, ACC_DENSITY = 0.005, 100.0  # deg/s/sqrt(Hz), ug/sqrt(Hz)
G_BIAS_SIGMA, A_BIAS_SIGMA = np.radians(0.05), 0.02
OUTAGE_S = 22.0                           # GNSS lost for the last 22 s (from 57 s: in the 360 deg turn)
PARAMS = dict(gyro_noise=np.radians(GYRO_DENSITY), acc_noise=ACC_DENSITY * 9.80665e-6,
              init_gyro_bias_sigma=G_BIAS_SIGMA, init_acc_bias_sigma=A_BIAS_SIGMA, gyro_bias_noise=1e-7,
              acc_bias_noise=1e-6, gps_pos_sigma_h=0.5, gps_pos_sigma_v=1.0, gps_vel_sigma=0.05,
              init_level_sigma=0.01, init_yaw_sigma=0.02, init_gyro_scale_sigma=0.01, zupt=False)
NEES_TIMES = np.arange(10.0, 57.0, 5.0)


class _ScaleBlock:
    """Observer of a run: the scale factors and their 6 x 6 covariance at the given times."""

    def __init__(self, t, times):
        self.k = set(np.searchsorted(t, times).tolist())
        self.rows = {}

    def after_predict(self, k, f):
        pass

    def after_sample(self, k, f):
        if k in self.k:
            self.rows[k] = (np.concatenate([f.acc_scale, f.gyro_scale]), f.covariance[SA:, SA:])


@pytest.fixture(scope="module")
def drive():
    """The drive with the IMU (white noise of the filter's densities, constant biases from its
    prior, the scale factors above) and GNSS (5 Hz, 0.5 m / 1 m, 0.05 m/s, no lever arm or
    latency); the filter without and with the scale factors (with: forward and smoothed), both
    given the true initial attitude and velocity."""
    traj = make_trajectory(SEGMENTS, RATE, rpy0=(0.0, 0.0, _r(30.0)), speed0=2.0)
    rng = np.random.default_rng(0)
    bg, ba = rng.normal(0.0, G_BIAS_SIGMA, 3), rng.normal(0.0, A_BIAS_SIGMA, 3)
    spec = SS.ImuSpec(gyro=SS.GyroSpec(bias_deg_per_h=tuple(np.degrees(bg) * 3600.0),
                                       noise_density_dps_per_sqrt_hz=GYRO_DENSITY,
                                       scale_factor_ppm=tuple(SG_TRUE * 1e6)),
                      accel=SS.AccelSpec(bias_ug=tuple(ba / 9.80665e-6), noise_density_ug_per_sqrt_hz=ACC_DENSITY,
                                         scale_factor_ppm=tuple(SA_TRUE * 1e6)))
    imu = SS.simulate_imu(traj, spec, rng)
    t_out = float(traj.t[-1]) - OUTAGE_S
    gps = SS.simulate_gps(traj, SS.GpsSpec(rate_hz=5.0, pos_sigma_h_m=0.5, pos_sigma_v_m=1.0, vel_sigma_m_s=0.05,
                                           outages=((t_out, np.inf),)), rng)
    aids = dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
                gps_vel=quatnav.Aid(gps.t_valid, gps.v_n))
    runs = {}
    for sf in (False, True):
        f = R.GpsInsFilter(scale_factors=sf, **PARAMS)
        f.set_initial(traj.q_nb[0], v_n=traj.v_n[0])
        obs = _ScaleBlock(imu.t, NEES_TIMES) if sf else None
        runs[sf] = f.run(imu.gyro, imu.accel, t=imu.t, smooth=sf, observer=obs, **aids)
        if sf:
            runs["block"] = obs.rows
    return traj, imu, t_out, runs


def _errors(traj, imu, out):
    """Yaw error (deg) and horizontal position error (m) at the IMU samples."""
    k = imu.index
    yaw = np.degrees(Q.wrap_pi(Q.to_euler(out["q_nb"])[:, 2] - Q.to_euler(traj.q_nb[k])[:, 2]))
    lat = traj.lat[k]
    R_M, R_N = earth.radii(lat)
    dn = (out["llh"][:, 0] - lat) * (R_M + traj.h[k])
    de = (out["llh"][:, 1] - traj.lon[k]) * (R_N + traj.h[k]) * np.cos(lat)
    return yaw, np.hypot(dn, de)


def test_scale_factors_converge_to_the_injected_ones(drive):
    """At the last fix every scale factor is within 3 sigma of the injected one; the observable
    ones converged: the gyro z (turns seen by the GNSS velocity) to a tenth of its prior sigma and
    within 1e-3 of 0.01, the horizontal accelerometers (accelerations, turns) below their prior.
    The NEES of the six (full 6 x 6 block) every 5 s is within the two-sided 99.9 % chi-square
    bounds of 6 dof (measured: 3.9 to 6.9; at the end 5.3). On one drive that band is a gross
    check only: measured on this drive (the C++ filter run in pieces ending at these times: 3.3
    to 10.7 at c = 1; 2026-12-06) with Q, R and P0 times c (``_consistency.scaled``), the NEES
    stays inside it for c = 1/1.5 (4.9 to 15.5), 1.5 and 3, and leaves it only for c = 1/3 (up
    to 26.7, bound 24.1). A covariance off by 1.5x is
    caught by the Monte Carlo of test_gpsins_consistency.py."""
    from scipy.stats import chi2
    traj, imu, t_out, runs = drive
    out = runs[True]["forward"]
    truth = np.concatenate([SA_TRUE, SG_TRUE])
    k = np.searchsorted(imu.t, t_out) - 1
    est = np.concatenate([out["acc_scale"][k], out["gyro_scale"][k]])
    sig = out["sigma"][k, SA:]
    assert np.all(np.abs(est - truth) < 3 * sig), ((est - truth) / sig)
    assert sig[5] < 0.1 * PARAMS["init_gyro_scale_sigma"] and abs(est[5] - SG_TRUE[2]) < 1e-3
    assert np.all(sig[:2] < 0.7 * R.GpsInsFilter().p.init_acc_scale_sigma)
    lo, hi = chi2.ppf([0.0005, 0.9995], 6)
    rows = runs["block"]
    assert len(rows) == len(NEES_TIMES)
    for _, (x, P) in sorted(rows.items()):
        e = x - truth
        assert lo < e @ np.linalg.solve(P, e) < hi


def test_scale_factors_improve_heading_and_the_outage_drift(drive):
    """Without the states the 1 % gyro-z scale error turns into heading error in every turn (the
    bias estimate follows it around); in the outage, through a 180 deg turn, the heading error of
    the 16-state filter exceeds 1 deg and the position drifts (measured: 2.0 deg, 7.4 m after
    22 s); with the states a fraction of that (0.13 deg, 3.1 m)."""
    traj, imu, t_out, runs = drive
    yaw0, pos0 = _errors(traj, imu, runs[False])
    yaw1, pos1 = _errors(traj, imu, runs[True]["forward"])
    nav = np.isfinite(runs[False]["llh"][:, 0]) & (imu.t >= 5.0)
    gnss, out = nav & (imu.t < t_out), imu.t >= t_out
    assert np.sqrt(np.mean(yaw1[gnss] ** 2)) < 0.6 * np.sqrt(np.mean(yaw0[gnss] ** 2))
    assert np.abs(yaw0[out]).max() > 1.0
    assert np.abs(yaw1[out]).max() < 0.3 * np.abs(yaw0[out]).max()
    assert pos1[-1] < 0.6 * pos0[-1]


def test_smoother_carries_the_scale_factors_back(drive):
    """The smoother runs on the 22 states: the smoothed scale factors early in the drive are those
    learnt from the turns after (the gyro z at 10 s: sigma a tenth of the forward one, within 3
    sigma of the truth), no smoothed sigma above the forward one."""
    traj, imu, t_out, runs = drive
    sm, fwd = runs[True], runs[True]["forward"]
    assert sm["sigma"].shape[1] == N_SF and sm["gyro_scale"].shape == (len(imu.t), 3)
    nav = np.isfinite(fwd["llh"][:, 0])
    assert np.all(sm["sigma"][nav] <= fwd["sigma"][nav] * (1 + 1e-9) + 1e-15)
    k = np.searchsorted(imu.t, 10.0)
    assert sm["sigma"][k, SG + 2] < 0.1 * fwd["sigma"][k, SG + 2]
    assert abs(sm["gyro_scale"][k, 2] - SG_TRUE[2]) < 3 * sm["sigma"][k, SG + 2]
    assert "acc_scale" not in runs[False]
