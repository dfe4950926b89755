"""GpsInsFilter's rate-proportional attitude noise (``gyro_rate_noise``): C++ against the numpy
twin, the term against the attitude error that a gyro scale-factor and misalignment error makes
in a turn, and the attitude's consistency in the simulated car's outages (the derivation is at
``detail::gpsins_Qc_diag``, cpp/include/quatnav/nav/gps_ins/model.hpp)."""
import numpy as np
import pytest

import quatnav
from quatnav import reference as R
from quatnav.core import quaternion as Q
from quatnav.sim.scenarios import make_scenario

from _aids import as_aids

LEVER = (0.1, 0.0, -0.1)


@pytest.fixture(scope="module")
def walk():
    return make_scenario("paper004_walk", seed=0)


@pytest.mark.parametrize("scale_factors", [False, True])
def test_cpp_matches_reference_step_by_step_with_the_rate_noise(walk, scale_factors):
    """C++ and the twin with the term on agree step by step (as test_gpsins.py's twin test), and
    the term moves the attitude sigma (so the comparison sees it)."""
    s, n = walk, 1500
    kw = as_aids(dict(gps_t=s.gps.t_valid, gps_llh=np.column_stack([s.gps.lat, s.gps.lon, s.gps.h]),
                      gps_vel=s.gps.v_n, compass_t=s.compass.t, compass_yaw=s.compass.yaw))
    p = dict(lever_arm_b=LEVER, gyro_rate_noise=0.1, scale_factors=scale_factors)
    r = quatnav.GpsInsFilter(**p).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **kw)
    ref = R.GpsInsFilter(**p).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **kw)
    off = quatnav.GpsInsFilter(**{**p, "gyro_rate_noise": 0.0}).run(s.imu.gyro[:n], s.imu.accel[:n],
                                                                     t=s.imu.t[:n], **kw)
    nav = r.navigating
    assert nav.sum() > 1000
    np.testing.assert_allclose(r.quat[nav], ref["q_nb"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.velocity[nav], ref["v_n"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.sigma[nav], ref["sigma"][nav], rtol=1e-7, atol=1e-12)
    ratio = r.sigma[nav, 6:9] / off.sigma[nav, 6:9]
    # The walk turns slowly (and its compass holds the heading): with k = 0.1 the sigma grows by
    # 1-3 %, 1e5 times the twin comparison's rtol.
    assert ratio.max() > 1.005 and ratio.min() >= 1.0 - 1e-9, (ratio.min(), ratio.max())


def _turn_attitude_variance(k, rate, T, dt=0.01, **params):
    """The twin's attitude covariance growth over a turn at the constant body rate ``rate`` for T
    s, every other noise and the gyro bias's prior zero, the rate-proportional density k: P_psi(T)
    - P_psi(0) (NED), and the rotation axis in NED at the end."""
    f = R.GpsInsFilter(gyro_noise=0.0, acc_noise=0.0, gyro_bias_noise=0.0, acc_bias_noise=0.0,
                       init_gyro_bias_sigma=0.0, gyro_rate_noise=k, earth_rotation=False, gps_time_sigma=0.0,
                       **params)
    f.set_initial(Q.from_euler([0.0, 0.0, 0.3]), v_n=[0.0, 0.0, 0.0])
    f.update_gps(0.7, 0.2, 100.0, [0.0, 0.0, 0.0], [0.005] * 3, [0.05] * 3)
    P0 = f.s.P[6:9, 6:9].copy()
    w = np.asarray(rate, float)
    for _ in range(int(round(T / dt))):
        f_b = Q.rotate(Q.conj(f.s.nav.q_nb), np.array([0.0, 0.0, -9.81]))  # at rest, turning
        assert f.predict(w, f_b, dt) == "ok"
    return f.s.P[6:9, 6:9] - P0, Q.rotate(f.s.nav.q_nb, w / np.linalg.norm(w))


def test_the_term_is_the_variance_of_a_scale_and_misalignment_error_over_a_turn():
    """The derivation (detail::gpsins_Qc_rate), checked against the errors it stands for: a gyro
    that reads (I + E) w, the nine entries of E independent with one-sigma sigma_E, turns the
    attitude (NED) by the rotation between exp((I + E) w T) and exp(w T). At the end of a turn by
    theta = |w| T about u its variance is sigma_E^2 theta^2 along u and 4 sigma_E^2 sin^2(theta / 2)
    across it (the body-fixed error turns with the body). The filter with k = sigma_E sqrt(T) adds
    k^2 |w|^2 T = sigma_E^2 theta^2 on every axis: exact along u, 1.23x across for a 90 deg turn,
    and an upper bound for longer ones. Monte Carlo of 4000 draws of E: a sample variance has a
    relative standard error of sqrt(2 / 4000) = 2.2 %, so the 10 % bounds are 4.5 of them; the
    filter's growth is checked to 1 % (its F turns the attitude error by the Earth rate only,
    switched off here)."""
    sigma_E = 1e-3  # 0.1 % and 1 mrad
    q0 = Q.from_euler([0.0, 0.0, 0.3])
    rng = np.random.default_rng(3)
    E = rng.normal(0.0, sigma_E, (4000, 3, 3))
    for w, T in (([0.0, 0.0, 0.248], 19.0), ([0.0, 0.0, -0.3], np.pi / 2 / 0.3)):  # the loop; a 90 deg turn
        w = np.asarray(w)
        theta = np.linalg.norm(w) * T
        q_true = Q.mul(q0, Q.from_rotvec(w * T))
        q_meas = Q.mul(q0, Q.from_rotvec(np.einsum("nij,j->ni", np.eye(3) + E, w) * T))
        psi = Q.to_rotvec(Q.mul(q_meas, Q.conj(np.broadcast_to(q_true, q_meas.shape))))  # NED
        cov = np.cov(psi.T)
        along, across = sigma_E ** 2 * theta ** 2, 4 * sigma_E ** 2 * np.sin(theta / 2) ** 2
        np.testing.assert_allclose(np.diag(cov), [across, across, along], rtol=0.10)
        block, u_n = _turn_attitude_variance(sigma_E * np.sqrt(T), w, T)
        np.testing.assert_allclose(np.abs(u_n), [0.0, 0.0, 1.0], atol=1e-12)
        np.testing.assert_allclose(block, along * np.eye(3), rtol=0, atol=0.01 * along)
        assert np.all(np.diag(block)[:2] >= np.diag(cov)[:2])  # across: an upper bound
    off, _ = _turn_attitude_variance(0.0, w, T)
    assert np.abs(off).max() < 1e-3 * along  # without the term nothing grows


def test_with_the_scale_factor_states_only_the_misalignment_remains():
    """With the scale factors as states the diagonal of E is theirs; what remains is E' w, E' off
    the diagonal: sigma_E^2 diag(|w|^2 - w_i^2) in the body, rotated into NED. A yaw turn (w on the
    body z) then adds k^2 |w|^2 T to the tilt and nothing to the heading; a turn about the body
    diagonal 2/3 of it on the rotation axis (the scale-factor states' prior and noise set to zero,
    so their own block adds nothing)."""
    k, T = 4.4e-3, 5.0
    sf = dict(scale_factors=True, init_gyro_scale_sigma=0.0, init_acc_scale_sigma=0.0, gyro_scale_noise=0.0,
              acc_scale_noise=0.0)
    yaw, _ = _turn_attitude_variance(k, [0.0, 0.0, 0.3], T, **sf)
    np.testing.assert_allclose(yaw, np.diag([1.0, 1.0, 0.0]) * k ** 2 * 0.09 * T, rtol=0, atol=0.01 * k ** 2 * 0.09 * T)
    w = np.full(3, 0.3 / np.sqrt(3.0))
    diag, u_n = _turn_attitude_variance(k, w, T, **sf)
    np.testing.assert_allclose(u_n @ diag @ u_n, 2.0 / 3.0 * k ** 2 * 0.09 * T, rtol=0.01)
    full, _ = _turn_attitude_variance(k, w, T)
    np.testing.assert_allclose(full, np.eye(3) * k ** 2 * 0.09 * T, rtol=0, atol=0.01 * k ** 2 * 0.09 * T)


# --- consistency in an outage through turns ------------------------------------------------------
#: A matched drive: the filter's model but for the gyro's E (1 % scale factors and 10 mrad
#: misalignments, a consumer MEMS gyro; sigma_E = 1e-2), ten turns of 90 deg in 6 s (1.5 s ramps)
#: in random directions, the GNSS lost for the last 45 s (five turns).
SIGMA_E, OUTAGE_S, TURNS = 1e-2, 45.0, 10
#: The turn's effective duration (int w)^2 / int w^2 (a trapezoid of 1.5 + 3 + 1.5 s: 4.5^2 / 4):
#: k = sigma_E sqrt(T_eff) makes the white term's variance over one turn sigma_E^2 theta^2.
T_EFF = 4.5 ** 2 / 4.0
K_DERIVED = SIGMA_E * np.sqrt(T_EFF)


def _drive(seed):
    from quatnav.sim.trajectory import Accelerate, Cruise, Turn, make_trajectory
    signs = np.random.default_rng(900 + seed).choice([-1.0, 1.0], TURNS)
    segments = [Accelerate(4.0, to_speed=10.0), Cruise(3.0)]
    for s in signs:
        segments += [Turn(6.0, angle=s * np.pi / 2, ramp=1.5), Cruise(3.0)]
    return make_trajectory(segments, 50.0, rpy0=(0.0, 0.0, np.radians(30.0)), speed0=2.0)


def _outage_attitude_nees(seed, k):
    """The attitude's squared error over the filter's variance per NED axis every 2 s inside the
    outage of one matched drive (samples x 3)."""
    from quatnav.sim import sensors as SS
    gyro_density, acc_density = 0.005, 100.0  # deg/s/sqrt(Hz), ug/sqrt(Hz)
    bias_g, bias_a = np.radians(0.05), 0.02
    traj = _drive(seed)
    rng = np.random.default_rng(7000 + seed)
    bg, ba = rng.normal(0.0, bias_g, 3), rng.normal(0.0, bias_a, 3)
    sg, mg = rng.normal(0.0, SIGMA_E, 3), rng.normal(0.0, SIGMA_E, 6)
    dtheta = rng.normal(0.0, [0.01, 0.01, 0.02])
    spec = SS.ImuSpec(gyro=SS.GyroSpec(bias_deg_per_h=tuple(np.degrees(bg) * 3600.0),
                                       noise_density_dps_per_sqrt_hz=gyro_density, scale_factor_ppm=tuple(sg * 1e6),
                                       misalignment_mrad=tuple(mg * 1e3)),
                      accel=SS.AccelSpec(bias_ug=tuple(ba / 9.80665e-6), noise_density_ug_per_sqrt_hz=acc_density))
    r_imu, r_gps = rng.spawn(2)
    imu = SS.simulate_imu(traj, spec, r_imu)
    t_out = float(traj.t[-1]) - OUTAGE_S
    gps = SS.simulate_gps(traj, SS.GpsSpec(rate_hz=5.0, pos_sigma_h_m=0.5, pos_sigma_v_m=1.0, vel_sigma_m_s=0.05,
                                           outages=((t_out, np.inf),)), r_gps)
    f = quatnav.GpsInsFilter(gyro_noise=np.radians(gyro_density), acc_noise=acc_density * 9.80665e-6,
                             init_gyro_bias_sigma=bias_g, init_acc_bias_sigma=bias_a, gyro_bias_noise=1e-7,
                             acc_bias_noise=1e-6, gps_pos_sigma_h=0.5, gps_pos_sigma_v=1.0, gps_vel_sigma=0.05,
                             init_level_sigma=0.01, init_yaw_sigma=0.02, zupt=False, gyro_rate_noise=k)
    f.set_initial(Q.mul(Q.from_rotvec(dtheta), traj.q_nb[0]), v_n=traj.v_n[0])
    llh = np.column_stack([gps.lat, gps.lon, gps.h])
    r = f.run(imu.gyro, imu.accel, t=imu.t, gps_pos=quatnav.Aid(gps.t_valid, llh), gps_vel=quatnav.Aid(gps.t_valid, gps.v_n))
    ks = np.searchsorted(imu.t, np.arange(t_out + 2.0, imu.t[-1], 2.0))
    psi = Q.to_rotvec(Q.mul(r.quat[ks], Q.conj(traj.q_nb[imu.index[ks]])))
    return (psi / r.sigma[ks, 6:9]) ** 2


def attitude_nees_in_outages(k, runs=30):
    """Mean attitude NEES per NED axis inside the outages of ``runs`` matched drives."""
    return np.mean([_outage_attitude_nees(seed, k).mean(axis=0) for seed in range(runs)], axis=0)


def test_attitude_nees_in_an_outage_through_turns():
    """The attitude in an outage through five turns, on matched drives whose gyro has the errors
    the term stands for (1 % scale, 10 mrad misalignment): the mean NEES per NED axis inside the
    outages of 30 drives, with k = sigma_E sqrt(T_eff) from the derivation.

    Bounds. Upper: the two-sided 99 % chi-square limit of 30 runs x 3 axes, a run counting as one
    sample per axis (E is drawn once per drive), 1.42. Lower: 1/4, not the chi-square's 0.65: the
    white form stands for a constant error and is conservative by design (across the rotation
    axis 1.23x per 90 deg turn, more in longer ones; the estimates made while aided are not
    modelled as correlated with E), and it must stay so by at most 4x. Measured (2026-12-06): tilt
    0.41 / 0.41, heading 0.76, mean 0.53; with k = 0 438 (the filter blind to E), k / 3 5.0, 3 k
    0.081 and 10 k 0.014: every one fails. 6 s."""
    from _consistency import chi2_interval
    hi = chi2_interval(30 * 3, 0.01)[1]
    nees = attitude_nees_in_outages(K_DERIVED)
    assert 0.25 < nees.mean() < hi, nees
    assert attitude_nees_in_outages(0.0).mean() > 100 * hi  # without the term, far over-confident
    assert attitude_nees_in_outages(10 * K_DERIVED).mean() < 0.25 / 10  # ten times too large
