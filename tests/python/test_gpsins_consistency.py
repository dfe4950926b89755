"""GpsInsFilter (paper 004): full 16-state NEES on simulated walks, and the static alignment.

The paper-004 scenarios of ``quatnav.sim`` give the IMU scale-factor and misalignment errors, a
1 deg compass bias, altimeter drift and GPS latency, none of which is in the filter's 15-state
model (the accelerometer-z "bias" estimate then absorbs the scale factor times g, and the yaw
settles on the compass bias): against them the state is, by design, not consistent. The NEES test
therefore simulates the same walk with sensors that match the filter's model (white noise of the
filter's densities, constant biases drawn from the filter's prior, unbiased compass, driftless
altimeter offset drifting as the filter's random walk, no GPS latency) and checks the whole error
state, block by block and together.

With GPS and compass the 15 navigation and bias states are consistent; with the altimeter too all
16, its offset included. (When the offset was a running mean of GPS heights kept outside the
filter, whose error entered R as white noise, the vertical channel was over-confident: mean NEES
about 24 for dp_D, 4 for dv_D, 5 for b_az; the offset as a state fixed it.)
"""
import numpy as np
import pytest

import quatnav
from quatnav.core import earth
from quatnav.core import quaternion as Q
from quatnav.sim import sensors as SS
from quatnav.sim.scenarios import make_scenario

LEVER = (0.1, 0.0, -0.1)
RAD_PER_DEG_H = np.radians(1.0) / 3600.0
G_BIAS_SIGMA = 300.0 * RAD_PER_DEG_H   # rad/s, prior one-sigma of the gyro bias
A_BIAS_SIGMA = 0.05                    # m/s^2, prior one-sigma of the accelerometer bias
BARO_OFFSET_NOISE = 0.02               # m/sqrt(s), the altimeter offset's random walk


def _matched(traj, seed, compass_bias_deg=0.0):
    rng = np.random.default_rng(1000 + seed)
    bg = rng.normal(0.0, G_BIAS_SIGMA, 3)
    ba = rng.normal(0.0, A_BIAS_SIGMA, 3)
    spec = SS.ImuSpec(
        gyro=SS.GyroSpec(bias_deg_per_h=tuple(bg / RAD_PER_DEG_H), noise_density_dps_per_sqrt_hz=0.05),
        accel=SS.AccelSpec(bias_ug=tuple(ba / (9.80665e-6)), noise_density_ug_per_sqrt_hz=200.0),
        rate_hz=50.0)
    r_imu, r_gps, r_baro, r_cmp = rng.spawn(4)
    imu = SS.simulate_imu(traj, spec, r_imu)
    gps = SS.simulate_gps(traj, SS.GpsSpec(rate_hz=5.0, pos_sigma_h_m=2.5, pos_sigma_v_m=5.0, vel_sigma_m_s=0.1,
                                           lever_arm_b_m=LEVER), r_gps)
    baro = SS.simulate_baro(traj, SS.BaroSpec(rate_hz=10.0, noise_m=0.5, bias_m=3.0,
                                              drift_m_per_sqrt_h=BARO_OFFSET_NOISE * 60.0), r_baro)
    cmp_ = SS.simulate_compass(traj, SS.CompassSpec(rate_hz=10.0, noise_deg=2.0, bias_deg=compass_bias_deg), r_cmp)
    return imu, gps, baro, cmp_


def _filter_params():
    # noise densities of the simulated sensors; constant biases: a tiny random walk
    return dict(lever_arm_b=LEVER, gyro_noise=np.radians(0.05), acc_noise=200.0 * 9.80665e-6,
                init_gyro_bias_sigma=G_BIAS_SIGMA, init_acc_bias_sigma=A_BIAS_SIGMA,
                gyro_bias_noise=1e-7, acc_bias_noise=1e-6, compass_sigma=np.radians(2.0), baro_sigma=0.5,
                baro_offset_noise=BARO_OFFSET_NOISE)


def _error_state(f, traj, k_traj, imu, k_imu, baro):
    """Estimate minus truth in the filter's error coordinates (dp m, dv m/s, psi rad, db, offset m;
    the offset's error 0 while the filter has none)."""
    lat, lon, h = f.llh
    lt, ht = traj.lat[k_traj], traj.h[k_traj]
    R_M, R_N = (float(x) for x in earth.radii(lt))
    dp = [(lat - lt) * (R_M + ht), (lon - traj.lon[k_traj]) * (R_N + ht) * np.cos(lt), -(h - ht)]
    dv = f.v_n - traj.v_n[k_traj]
    E = Q.to_rotmat(f.quat) @ Q.to_rotmat(traj.q_nb[k_traj]).T  # exp([psi x])
    psi = Q.to_rotvec(Q.from_rotmat(E))
    j = np.searchsorted(baro.t, traj.t[k_traj], side="right") - 1  # the offset of the last altimeter sample
    offset = f.baro_offset - baro.drift[j] if f.covariance[15, 15] > 0 else 0.0
    return np.concatenate([dp, dv, psi, f.acc_bias - imu.accel_bias[k_imu], f.gyro_bias - imu.gyro_bias[k_imu],
                           [offset]])


def _nees_samples(use_baro):
    traj = make_scenario("paper004_walk", seed=0).truth
    out = []
    for seed in range(3):
        imu, gps, baro, cmp_ = _matched(traj, seed)
        f = quatnav.GpsInsFilter(**_filter_params())
        aids = dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
                    gps_vel=quatnav.Aid(gps.t_valid, gps.v_n), compass=quatnav.Aid(cmp_.t, cmp_.yaw))
        if use_baro:
            aids.update(baro=quatnav.Aid(baro.t, baro.h))
        # Run in pieces (overlapping by one sample: a piece's first sample only fixes its start
        # time, so the pieces give exactly the one-run result) and read the full covariance at
        # each piece's end, every 4 s once the prior has been forgotten (20 s).
        ends = np.searchsorted(imu.t, np.arange(20.0, imu.t[-1], 4.0))
        k0 = 0
        for k1 in ends:
            f.run(imu.gyro[k0:k1 + 1], imu.accel[k0:k1 + 1], t=imu.t[k0:k1 + 1], **aids)
            k0 = k1
            assert f.navigating
            e = _error_state(f, traj, imu.index[k1], imu, k1, baro)
            out.append((e, f.covariance))
    return out


@pytest.fixture(scope="module")
def nees_gps_compass():
    return _nees_samples(use_baro=False)


@pytest.fixture(scope="module")
def nees_all_aids():
    return _nees_samples(use_baro=True)


BLOCKS = {"position": [0, 1, 2], "velocity": [3, 4, 5], "attitude": [6, 7, 8],
          "accel_bias": [9, 10, 11], "gyro_bias": [12, 13, 14], "all": list(range(15))}
WITH_BARO = {**BLOCKS, "vertical": [2, 5, 11, 15], "baro_offset": [15], "all": list(range(16))}


def _check_nees(samples, idx, label):
    from scipy.stats import chi2
    idx = np.asarray(idx)
    d = len(idx)
    nees = np.array([e[idx] @ np.linalg.solve(P[np.ix_(idx, idx)], e[idx]) for e, P in samples])
    m = len(nees)
    lo, hi = chi2.ppf([0.0005, 0.9995], d * m) / m
    assert m >= 60
    assert lo < nees.mean() < hi, (label, d, lo, nees.mean(), hi)


@pytest.mark.parametrize("block", list(BLOCKS))
def test_nees_gps_and_compass_within_chi2_bounds(nees_gps_compass, block):
    _check_nees(nees_gps_compass, BLOCKS[block], block)


@pytest.mark.parametrize("block", list(WITH_BARO))
def test_nees_with_altimeter_within_chi2_bounds(nees_all_aids, block):
    _check_nees(nees_all_aids, WITH_BARO[block], block)


def test_static_alignment_level_and_heading():
    """Level from the averaged accelerometer at rest, heading from the compass.

    The paper-004 static run (tilted 2 deg / -1 deg, yaw 30 deg), with the model-matched IMU
    (constant biases, white noise) so that the expected error is known: the levelled attitude is
    the one of the mean specific force f + b_a, i.e. the truth tilted by the accelerometer bias
    seen through gravity (about b / g), to within the averaged white noise
    sigma_a / sqrt(T) / g (T = align_time)."""
    traj = make_scenario("paper004_static", seed=0, duration=20.0).truth
    imu, gps, _, cmp_ = _matched(traj, seed=5, compass_bias_deg=1.0)
    f = quatnav.GpsInsFilter(**_filter_params())
    r = f.run(imu.gyro, imu.accel, t=imu.t, gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
              gps_vel=quatnav.Aid(gps.t_valid, gps.v_n), compass=quatnav.Aid(cmp_.t, cmp_.yaw))
    k = int(np.argmax(~r.flag("aligning")))  # the sample where levelling happened
    assert k > 0 and r.flag("aligning")[k - 1] and np.isfinite(r.quat[k]).all()
    rpy = r.euler[k]
    truth = traj.rpy[imu.index[k]]
    g = 9.80  # about the normal gravity at 36 deg N, 50 m (only the direction matters)
    f_b = Q.rotate_inv(traj.q_nb[imu.index[k]], [0.0, 0.0, -g]) + imu.accel_bias[k]
    expected = np.array([np.arctan2(-f_b[1], -f_b[2]), np.arctan2(f_b[0], np.hypot(f_b[1], f_b[2]))])
    T = imu.t[k] - imu.t[0]
    noise = 200e-6 * 9.80665 / np.sqrt(T) / g  # rad, one sigma of the averaged accelerometer noise
    assert np.all(np.abs(rpy[:2] - expected) < 5 * noise), (np.degrees(rpy[:2] - expected), np.degrees(noise))
    # ... and the bias effect is far above that noise, so the comparison means something.
    assert np.abs(expected - truth[:2]).max() > 10 * noise
    assert np.all(np.abs(rpy[:2] - truth[:2]) < np.abs(imu.accel_bias[k, :2]).max() / g * 1.5 + 5 * noise)
    # Heading: the compass sets the yaw (1 deg bias, 2 deg noise per sample).
    nav0 = int(np.argmax(r.navigating))
    yaw0 = np.degrees(Q.wrap_pi(r.euler[nav0, 2] - traj.rpy[imu.index[nav0], 2]))
    assert abs(yaw0 - 1.0) < 4 * 2.0
    # Navigating at rest, 18 s of compass updates average the noise: the yaw error tends to the
    # compass bias (not observable), within 4 one-sigma of the filter.
    yaw_end = Q.wrap_pi(r.euler[-1, 2] - traj.rpy[imu.index[-1], 2])
    assert abs(yaw_end - np.radians(1.0)) < 4 * r.sigma[-1, 8], (np.degrees(yaw_end), np.degrees(r.sigma[-1, 8]))
    assert r.sigma[-1, 8] < np.radians(2.0) / 3
