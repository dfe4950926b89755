"""GpsInsFilter (paper 004): the NEES of its error state on simulated walks, and the static alignment.

The paper-004 scenarios of ``quatnav.sim`` give the IMU scale-factor and misalignment errors, a
1 deg compass bias, altimeter drift and GPS latency, none of which is in the filter's 15-state
model (the accelerometer-z "bias" estimate then absorbs the scale factor times g, and the yaw
settles on the compass bias): against them the state is, by design, not consistent. The NEES test
therefore simulates the same walk with sensors that match the filter's model (white noise of the
filter's densities, constant biases drawn from the filter's prior, unbiased compass, the altimeter
offset drifting as the filter's random walk, no GPS latency), once with GPS and compass (15
states) and once with the altimeter too (16, its offset included), and checks blocks of the error
state against the two-sided 99 % chi-square interval of ``_consistency.check_mean_nees``, sized to
reject a filter 1.5x over- or under-confident with probability >= 99 %.

The statistic of a block: the mean over the first ``runs`` runs (sensor seeds) and the samples of
each (every 4 s from 20 s, once the alignment's prior is forgotten) of NEES / dof. The samples of
a run are correlated (a bias error persists over the whole run), so a run counts as M_EFF
independent samples, 80 % of the measured (``python -c "import test_gpsins_consistency as T;
T.measure_meff()"`` in tests/python: the per-run means of 200 runs vary as m independent samples
of the block's dof would). Measured (2026-12-05, 200 runs; GPS + compass / with altimeter):

    block        dof      m measured    M_EFF     runs     truth       x 1/1.5     x 1.5
    navigation   9        3.1 / 3.1     2.5       17       1.06 / 1.06  1.54 / 1.55  0.74 / 0.75
    biases       6 / 7    0.87 / 0.91   0.7       82 / 71  1.11 / 1.14  1.57 / 1.62  0.74 / 0.76
    all          15 / 16  1.35 / 1.50   1.1 / 1.2 21 / 19  1.07 / 1.06  1.53 / 1.53  0.73 / 0.73
    vertical     4        3.2           2.5       35       0.99         1.45         0.67

(the last three columns: the mean NEES / dof of the checked runs, at truth and with the filter told
Q, R and P0 times 1/1.5 and 1.5 by QUATNAV_TEST_VARIANCE_SCALE, which fails every check; over all
200 runs the means at truth are 1.04, 1.10, 1.08 and 0.95: the filter is a few per cent
over-confident, far from 1.5x). The biases' heavy tail (a few runs with a per-run mean of 3 to 5
per dof, in the direction of the accelerometer-z bias, whose own normalized error has an RMS of
0.99) is why they count as fewer independent samples than a chi-square would. 153 runs, about 8 s
CPU.

(When the altimeter offset was a running mean of GPS heights kept outside the filter, whose error
entered R as white noise, the vertical channel was over-confident: mean NEES about 24 for dp_D, 4
for dv_D, 5 for b_az; the offset as a state fixed it.)
"""
import numpy as np
import pytest

import quatnav
from _consistency import check_mean_nees, scaled
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


def _samples(seed, use_baro, traj):
    """(error state, covariance) of one run (the filter built through ``scaled``: the truth, or Q,
    R and P0 times QUATNAV_TEST_VARIANCE_SCALE)."""
    imu, gps, baro, cmp_ = _matched(traj, seed)
    f = quatnav.GpsInsFilter(**scaled("GpsInsFilter", **_filter_params()))
    aids = dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
                gps_vel=quatnav.Aid(gps.t_valid, gps.v_n), compass=quatnav.Aid(cmp_.t, cmp_.yaw))
    if use_baro:
        aids.update(baro=quatnav.Aid(baro.t, baro.h))
    # Run in pieces (overlapping by one sample: a piece's first sample only fixes its start time,
    # so the pieces give exactly the one-run result) and read the full covariance at each piece's
    # end, every 4 s once the prior has been forgotten (20 s).
    ends = np.searchsorted(imu.t, np.arange(20.0, imu.t[-1], 4.0))
    k0, out = 0, []
    for k1 in ends:
        f.run(imu.gyro[k0:k1 + 1], imu.accel[k0:k1 + 1], t=imu.t[k0:k1 + 1], **aids)
        k0 = k1
        assert f.navigating
        out.append((_error_state(f, traj, imu.index[k1], imu, k1, baro), f.covariance))
    return out


#: block: (state indices, runs, M_EFF) with GPS and compass, and with the altimeter too
BLOCKS = {"navigation": (list(range(9)), 17, 2.5), "biases": (list(range(9, 15)), 82, 0.7),
          "all": (list(range(15)), 21, 1.1)}
WITH_BARO = {"navigation": (list(range(9)), 17, 2.5), "biases": (list(range(9, 16)), 71, 0.7),
             "all": (list(range(16)), 19, 1.2), "vertical": ([2, 5, 11, 15], 35, 2.5)}


def nees_per_block(blocks, use_baro, runs=None):
    """{block: NEES (runs x samples)} over the first ``runs`` seeds (default: as many as the
    largest block needs)."""
    traj = make_scenario("paper004_walk", seed=0).truth
    runs = max(r for _, r, _ in blocks.values()) if runs is None else runs
    out = {name: [] for name in blocks}
    for seed in range(runs):
        samples = _samples(seed, use_baro, traj)
        for name, (idx, _, _) in blocks.items():
            ix = np.ix_(idx, idx)
            out[name].append([e[idx] @ np.linalg.solve(P[ix], e[idx]) for e, P in samples])
    return {name: np.array(v) for name, v in out.items()}


def measure_meff(runs=200):
    """The measured m of each block: the per-run means of NEES / dof vary as 2 / (dof m)."""
    for label, blocks, baro in (("GPS + compass", BLOCKS, False), ("with altimeter", WITH_BARO, True)):
        nees = nees_per_block(blocks, baro, runs)
        for name, (idx, _, _) in blocks.items():
            per_run = nees[name].mean(axis=1) / len(idx)
            print(f"{label:15s} {name:10s} dof {len(idx):2d}: mean {per_run.mean():.3f}, "
                  f"m = {2.0 / (len(idx) * per_run.var(ddof=1)):.2f}")


@pytest.fixture(scope="module")
def nees_gps_compass():
    return nees_per_block(BLOCKS, use_baro=False)


@pytest.fixture(scope="module")
def nees_all_aids():
    return nees_per_block(WITH_BARO, use_baro=True)


@pytest.mark.parametrize("block", list(BLOCKS))
def test_nees_gps_and_compass_within_chi2_bounds(nees_gps_compass, block):
    idx, runs, m_eff = BLOCKS[block]
    check_mean_nees(nees_gps_compass[block][:runs], len(idx), m_eff=m_eff, what=f"GPS + compass, {block} NEES")


@pytest.mark.parametrize("block", list(WITH_BARO))
def test_nees_with_altimeter_within_chi2_bounds(nees_all_aids, block):
    idx, runs, m_eff = WITH_BARO[block]
    check_mean_nees(nees_all_aids[block][:runs], len(idx), m_eff=m_eff, what=f"with altimeter, {block} NEES")


# --- the scale-factor states (scale_factors=True, 22 error states) ---------------------------------
#: The drive of test_gpsins_scale_factors.py (79 s of accelerations and turns of 90 to 360 deg, which
#: make the gyro-z and the horizontal accelerometer scale factors observable), with the IMU's bias
#: and scale factors drawn from the filter's prior and the filter started from an attitude error
#: drawn from its own.
SF_GYRO_DENSITY, SF_ACC_DENSITY = 0.005, 100.0  # deg/s/sqrt(Hz), ug/sqrt(Hz)
SF_PARAMS = dict(gyro_noise=np.radians(SF_GYRO_DENSITY), acc_noise=SF_ACC_DENSITY * 9.80665e-6,
                 init_gyro_bias_sigma=np.radians(0.05), init_acc_bias_sigma=0.02, gyro_bias_noise=1e-7,
                 acc_bias_noise=1e-6, gps_pos_sigma_h=0.5, gps_pos_sigma_v=1.0, gps_vel_sigma=0.05,
                 init_level_sigma=0.01, init_yaw_sigma=0.02, init_gyro_scale_sigma=0.005,
                 init_acc_scale_sigma=0.003, gyro_scale_noise=1e-7, acc_scale_noise=1e-7)
SF_RUNS, SF_MEFF = 64, 0.9


def _scale_factor_run(seed, traj):
    """The scale-factor errors and their 6 x 6 covariance every 4 s from 20 s of one run."""
    import warnings
    p = SF_PARAMS
    rng = np.random.default_rng(5000 + seed)
    bg, ba = rng.normal(0.0, p["init_gyro_bias_sigma"], 3), rng.normal(0.0, p["init_acc_bias_sigma"], 3)
    sg, sa = rng.normal(0.0, p["init_gyro_scale_sigma"], 3), rng.normal(0.0, p["init_acc_scale_sigma"], 3)
    dtheta = rng.normal(0.0, [p["init_level_sigma"], p["init_level_sigma"], p["init_yaw_sigma"]])
    spec = SS.ImuSpec(gyro=SS.GyroSpec(bias_deg_per_h=tuple(bg / RAD_PER_DEG_H),
                                       noise_density_dps_per_sqrt_hz=SF_GYRO_DENSITY, scale_factor_ppm=tuple(sg * 1e6)),
                      accel=SS.AccelSpec(bias_ug=tuple(ba / 9.80665e-6), noise_density_ug_per_sqrt_hz=SF_ACC_DENSITY,
                                         scale_factor_ppm=tuple(sa * 1e6)))
    r_imu, r_gps = rng.spawn(2)
    imu = SS.simulate_imu(traj, spec, r_imu)
    gps = SS.simulate_gps(traj, SS.GpsSpec(rate_hz=5.0, pos_sigma_h_m=0.5, pos_sigma_v_m=1.0, vel_sigma_m_s=0.05), r_gps)
    f = quatnav.GpsInsFilter(scale_factors=True, **scaled("GpsInsFilter", **p))
    f.set_initial(Q.mul(Q.from_rotvec(dtheta), traj.q_nb[0]), v_n=traj.v_n[0])
    aids = dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([gps.lat, gps.lon, gps.h])),
                gps_vel=quatnav.Aid(gps.t_valid, gps.v_n))
    out, k0 = [], 0
    for k1 in np.searchsorted(imu.t, np.arange(20.0, imu.t[-1], 4.0)):
        with warnings.catch_warnings():
            # a piece that starts in a steady turn looks to the units check like a still IMU
            # turning about a horizontal axis (the specific force tilted by the centripetal term)
            warnings.simplefilter("ignore", quatnav.UnitWarning)
            f.run(imu.gyro[k0:k1 + 1], imu.accel[k0:k1 + 1], t=imu.t[k0:k1 + 1], **aids)
        k0 = k1
        assert f.navigating
        out.append((np.concatenate([f.acc_scale - sa, f.gyro_scale - sg]), f.covariance[16:, 16:]))
    return out


def test_scale_factor_nees_within_chi2_bounds():
    """The six scale-factor states' NEES on SF_RUNS runs of the drive (every 4 s from 20 s), against
    the interval of check_mean_nees: a run counts as SF_MEFF = 0.9 independent 6-dof samples, 80 %
    of the measured 1.16 (the states change slowly; 200 runs, per-run means' variance). Measured
    (2026-12-05, 200 runs): mean NEES / dof 0.98 at truth, 1.56 and 0.69 with the filter told Q,
    R and P0 times 1/1.5 and 1.5. The navigation states of the same runs are about 14 %
    under-confident (0.86, every normalized error's RMS 0.87 to 0.97); they are checked on the
    walk above."""
    from quatnav.sim.trajectory import make_trajectory
    from test_gpsins_scale_factors import RATE, SEGMENTS
    traj = make_trajectory(SEGMENTS, RATE, rpy0=(0.0, 0.0, np.radians(30.0)), speed0=2.0)
    nees = [[e @ np.linalg.solve(P, e) for e, P in _scale_factor_run(seed, traj)] for seed in range(SF_RUNS)]
    check_mean_nees(nees, 6, m_eff=SF_MEFF, what="scale-factor NEES")


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


def _wandering_run(seed, traj, tau_filter, tau=20.0, sig=(2.5, 2.5, 5.0)):
    """Position NEES per component (samples every 4 s from 20 s) of one matched walk whose GNSS
    position errors wander (first-order Gauss-Markov, ``tau`` s, stationary one-sigma ``sig``),
    reported as single solutions with that sigma; the filter told ``gps_error_tau=tau_filter``."""
    from quatnav.sim.sensors import gauss_markov
    from _consistency import scaled_sigma
    imu, gps, baro, cmp_ = _matched(traj, seed)
    rng = np.random.default_rng(5000 + seed)
    iv = gps.index_valid
    n = len(iv)
    sig = np.asarray(sig, float)
    e = gauss_markov(n, 1.0, tau, float(np.median(np.diff(gps.t_valid))), rng) * sig
    ant = traj.pos_n[iv] + Q.rotate(traj.q_nb[iv], np.broadcast_to(np.asarray(LEVER), (n, 3)))
    lat, lon, h = earth.ned_to_geodetic(ant + e, traj.lat[0], traj.lon[0], traj.h[0])
    f = quatnav.GpsInsFilter(**scaled("GpsInsFilter", **_filter_params(), gps_error_tau=tau_filter))
    aids = dict(gps_pos=quatnav.Aid(gps.t_valid, np.column_stack([lat, lon, h]), np.tile(scaled_sigma(sig), (n, 1))),
                gps_vel=quatnav.Aid(gps.t_valid, gps.v_n), compass=quatnav.Aid(cmp_.t, cmp_.yaw),
                gps_solution=np.full(n, "single"))
    ends = np.searchsorted(imu.t, np.arange(20.0, imu.t[-1], 4.0))
    k0, out = 0, []
    for k1 in ends:
        f.run(imu.gyro[k0:k1 + 1], imu.accel[k0:k1 + 1], t=imu.t[k0:k1 + 1], **aids)
        k0 = k1
        d = _error_state(f, traj, imu.index[k1], imu, k1, baro)[:3]
        out.append(d ** 2 / np.diag(f.covariance)[:3])
    return np.array(out)


def test_wandering_gnss_errors_are_weighed_by_their_correlation_time():
    """GNSS position errors that wander (a 20 s Gauss-Markov of 2.5 / 5 m, as a single, DGNSS or
    RTK-float solution's do) taken as white make the position about fifty times over-confident:
    each fix at 5 Hz repeats most of the last one's error, and the filter averages them as if
    independent (gps_error_tau = 0: mean NEES per component 78 over these 20 runs). Weighed by
    their correlation time (gps_error_tau = 20 s, the default) it is 1.55 (north, east, down 1.5,
    1.2, 2.0; told 60 s 1.33, told 10 s 2.1): the weighting, the variance of the mean of a
    Gauss-Markov sequence, is an approximation that leaves the filter somewhat over-confident.

    Checked: the mean lies in [0.9, 2.5]. Not a 1.5x test (a run of 98 s holds few correlation
    times, so the per-run means scatter widely): measured over these runs (2026-12-06) with the
    variances the filter is told times 1/1.75, 1/1.5, 1.5, 2 (QUATNAV_TEST_VARIANCE_SCALE):
    2.70 (fails), 2.32, 1.03 (both pass), 0.78 (fails); the white treatment fails by far. 3 s."""
    traj = make_scenario("paper004_walk", seed=0).truth
    nees = np.array([_wandering_run(seed, traj, 20.0).mean() for seed in range(20)])
    assert 0.9 < nees.mean() < 2.5, (nees.mean(), nees)
