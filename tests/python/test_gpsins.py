"""GpsInsFilter (paper 004): C++ against the numpy reference, simulated paper-004 runs, GPS
outage, input validation."""
import numpy as np
import pytest

import quatnav
from quatnav import reference as R
from quatnav.sim.scenarios import make_scenario

from _aids import as_aids

LEVER = (0.1, 0.0, -0.1)


def _aids(s):
    return dict(gps_t=s.gps.t_valid, gps_llh=np.column_stack([s.gps.lat, s.gps.lon, s.gps.h]),
                gps_vel=s.gps.v_n, baro_t=s.baro.t, baro_h=s.baro.h, compass_t=s.compass.t,
                compass_yaw=s.compass.yaw)


def _horizontal_error(s, r):
    nav = r.navigating
    i = np.searchsorted(s.truth.t, r.t[nav])
    assert np.allclose(s.truth.t[i], r.t[nav])
    a, e2 = 6378137.0, 6.69437999014e-3
    sl2 = np.sin(s.truth.lat[i]) ** 2
    rm = a * (1 - e2) / (1 - e2 * sl2) ** 1.5
    rn = a / np.sqrt(1 - e2 * sl2)
    dn = (r.lat[nav] - s.truth.lat[i]) * (rm + s.truth.h[i])
    de = (r.lon[nav] - s.truth.lon[i]) * (rn + s.truth.h[i]) * np.cos(s.truth.lat[i])
    return nav, i, np.hypot(dn, de)


@pytest.fixture(scope="module")
def walk():
    return make_scenario("paper004_walk", seed=0)


def test_cpp_matches_reference_step_by_step(walk):
    s, n = walk, 1500  # alignment, levelling and ~25 s of navigation with every aid
    kw = _aids(s)
    r = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    ref = R.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    assert r.navigating.sum() > 1000
    np.testing.assert_array_equal(np.isnan(r.position), np.isnan(ref["llh"]))
    nav = r.navigating
    np.testing.assert_allclose(r.position[nav, :2], ref["llh"][nav, :2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(r.h[nav], ref["llh"][nav, 2], rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.velocity[nav], ref["v_n"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.quat[nav], ref["q_nb"][nav], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.bias, ref["gyro_bias"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.acc_bias, ref["acc_bias"], rtol=0, atol=1e-9)
    np.testing.assert_allclose(r.sigma[nav], ref["sigma"][nav], rtol=1e-7, atol=1e-12)
    np.testing.assert_allclose(r.baro_offset, ref["baro_offset"], rtol=0, atol=1e-7)
    np.testing.assert_allclose(r.q_scale, ref["q_scale"], rtol=1e-12)
    np.testing.assert_array_equal(r.flags & 0xF, ref["flags"] & 0xF)  # phase bits; the reference keeps no aid bits
    for key, names, m in (("gps", ("gps_pos", "gps_vel"), 3), ("baro", ("baro", "baro_vd"), 1),
                          ("compass", ("compass",), 1)):
        for c, name in enumerate(names):
            a = r.aids[name]
            np.testing.assert_array_equal(a.status_names, ref[key]["status"][:, c], err_msg=name)
            np.testing.assert_array_equal(a.decision_names, ref[key]["decision"][:, c], err_msg=name)
            np.testing.assert_allclose(a.nis, ref[key]["nis"][:, c], rtol=1e-6, atol=1e-12, err_msg=name)
            np.testing.assert_allclose(a.innovation, ref[key]["innovation"][:, c * m:(c + 1) * m], rtol=1e-6,
                                       atol=1e-9, err_msg=name)
    assert r.counters == R_filter_counters(kw, n, s)


def R_filter_counters(kw, n, s):
    f = R.GpsInsFilter(lever_arm_b=LEVER)
    f.run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    return f.counters


def test_decision_names_are_the_compiled_ones():
    from quatnav.filters._base import core
    from quatnav.filters.tables import GPSINS_DECISIONS
    from quatnav.reference.gpsins import DECISIONS
    assert tuple(core().gpsins_decision_names()) == GPSINS_DECISIONS == DECISIONS


def test_gnss_solution_names_are_the_compiled_ones():
    from quatnav.filters._base import core
    from quatnav.filters.tables import GNSS_SOLUTIONS
    assert tuple(core().gnss_solution_names()) == GNSS_SOLUTIONS


def test_receiver_quality_codes_map_to_solution_kinds():
    from quatnav.filters.gpsins import gnss_solution
    names = quatnav.filters.gpsins.GNSS_SOLUTIONS
    kinds = lambda q, fmt: [names[c] for c in gnss_solution(q, fmt)]  # noqa: E731
    assert kinds([1, 2, 4, 5, 7], "rtklib") == ["rtk_fixed", "rtk_float", "dgnss", "single", "unknown"]
    assert kinds([4, 5, 2, 1, 0], "nmea-gga") == ["rtk_fixed", "rtk_float", "dgnss", "single", "unknown"]
    assert kinds([6, 5, 3], "px4-fix_type") == ["rtk_fixed", "rtk_float", "single"]
    assert kinds([1, 2], "some-other-format") == ["unknown", "unknown"]


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_solution_kind_sets_the_position_sigma_floor(dtype):
    """A fix reported at 5 mm: its variance in the innovation covariance is the floor of its
    solution kind squared, the kind's own parameter (each set apart here) north and east and
    gps_vertical_floor_ratio times it down, in C++ and in the numpy twin; a kind that is not one
    is refused and leaves the filter untouched."""
    floors = dict(unknown=0.011, rtk_fixed=0.011, rtk_float=0.2, dgnss=0.7, single=2.5)
    params = dict(gps_pos_sigma_min=0.011, gps_float_sigma_min=0.2, gps_dgnss_sigma_min=0.7,
                  gps_single_sigma_min=2.5, gps_vertical_floor_ratio=1.5, gps_time_sigma=0.0, gps_error_tau=0.0,
                  dtype=dtype)  # the correlation time's raise: test_a_wandering_solution_weighs_by_its_correlation_time
    ned = np.array([1.0, 1.0, 1.5])
    lat, lon, h = 0.7, 0.2, 100.0

    def innovation_cov(kind, cls=quatnav.GpsInsFilter):
        f = cls(**params) if cls is quatnav.GpsInsFilter else cls(**{k: v for k, v in params.items() if k != "dtype"})
        if cls is quatnav.GpsInsFilter:
            f.set_initial(euler=[0.0, 0.0, 0.3], v_n=[0.0, 0.0, 0.0])
        else:
            f.set_initial(quatnav.core.quaternion.from_euler([0.0, 0.0, 0.3]), v_n=[0.0, 0.0, 0.0])
        sig = np.full(3, 0.005)
        f.update_gps(lat, lon, h, [0.0, 0.0, 0.0], sig, [0.05] * 3)  # starts navigation
        for _ in range(10):
            f.predict([0.0, 0.0, 0.0], [0.0, 0.0, -9.81], 0.01)
        if cls is quatnav.GpsInsFilter:
            return f, f.update_gps(lat, lon, h, None, sig, None, solution=kind)[0].innovation_cov
        return f, f.update_gps(lat, lon, h, [np.nan] * 3, sig, [np.nan] * 3,
                               solution=quatnav.filters.gpsins.GNSS_SOLUTIONS.index(kind))[0].innovation_cov

    _, s0 = innovation_cov("unknown")
    rtol = 1e-5 if dtype == np.float32 else 1e-9
    for kind, floor in floors.items():
        f, s = innovation_cov(kind)
        np.testing.assert_allclose(np.diag(s - s0), (ned * floor) ** 2 - (ned * floors["unknown"]) ** 2, rtol=rtol,
                                   atol=1e-9)
        _, s_ref = innovation_cov(kind, R.GpsInsFilter)
        np.testing.assert_allclose(s, s_ref, rtol=1e-4 if dtype == np.float32 else 1e-9, atol=1e-9)
    before = f.covariance.copy(), f.llh.copy(), f.counters
    with pytest.raises(ValueError, match="gps_solution"):
        f.update_gps(lat, lon, h, None, np.full(3, 0.005), None, solution="rtk")
    with pytest.raises(ValueError, match="gps_solution"):
        f.update_gps(lat, lon, h, None, np.full(3, 0.005), None, solution=7)
    np.testing.assert_array_equal(f.covariance, before[0])
    np.testing.assert_array_equal(f.llh, before[1])
    assert f.counters == before[2]


def _navigating(cls=quatnav.GpsInsFilter, dtype=np.float64, **params):
    """A filter navigating at rest at (0.7, 0.2, 100) after a 5 mm fix and 0.5 s of time updates
    (C++ or, with cls=R.GpsInsFilter, the numpy twin)."""
    params = dict(gps_time_sigma=0.0, **params)
    if cls is quatnav.GpsInsFilter:
        f = cls(dtype=dtype, **params)
        f.set_initial(euler=[0.0, 0.0, 0.3], v_n=[0.0, 0.0, 0.0])
    else:
        f = cls(**params)
        f.set_initial(quatnav.core.quaternion.from_euler([0.0, 0.0, 0.3]), v_n=[0.0, 0.0, 0.0])
    f.update_gps(0.7, 0.2, 100.0, [0.0, 0.0, 0.0], [0.005] * 3, [0.05] * 3)
    for _ in range(50):
        f.predict([0.0, 0.0, 0.0], [0.0, 0.0, -9.81], 0.01)
    return f


def _fix(f, north_m, sigma):
    """A position fix ``north_m`` north of (0.7, 0.2, 100) with one-sigma ``sigma`` (3,): the
    update's result and its decision's name, for the C++ filter or the twin."""
    lat = 0.7 + north_m / 6.37e6
    if isinstance(f, quatnav.GpsInsFilter):
        r = f.update_gps(lat, 0.2, 100.0, None, sigma, None)[0]
        return r, quatnav.filters.gpsins.GPSINS_DECISIONS[r.decision]
    r = f.update_gps(lat, 0.2, 100.0, [np.nan] * 3, sigma, [np.nan] * 3)[0]
    return r, r.decision


def _llh_cov(f):
    if isinstance(f, quatnav.GpsInsFilter):
        return np.asarray(f.llh), f.covariance
    return np.array([f.s.nav.lat, f.s.nav.lon, f.s.nav.h]), f.s.P


@pytest.mark.parametrize("cls", [quatnav.GpsInsFilter, R.GpsInsFilter])
def test_robust_weighting_raises_the_variance_of_far_components(cls):
    """A fix 4 sigma off north (sigma: the innovation's, from P and the fix's): the gate passes it, and it is applied as a fix whose north variance is raised by |z| / k (Huber;
    the same correction as a plain update with that sigma), reported ``weighted``. One within k
    is applied as it came; a gross outlier is still gated out, the state untouched."""
    k = 2.5
    f = _navigating(cls, gps_robust_k=k, gps_pos_sigma_min=0.001)
    sig = float(np.sqrt(_llh_cov(f)[1][0, 0]))  # the fix as good as the INS: a gain of about 1/2
    s_n = float(np.sqrt(_llh_cov(f)[1][0, 0] + sig ** 2))
    r, decision = _fix(f, 4 * s_n, [sig] * 3)
    z = np.abs(r.innovation) / np.sqrt(np.diag(r.innovation_cov))
    assert z[0] > 1.5 * k and np.all(z[1:] < 1.0), z  # north far, east and down not
    assert decision == "weighted"
    if cls is quatnav.GpsInsFilter:
        assert f.counters["gps_pos"]["weighted"] == 1 and f.counters["gps_pos"]["accepted"] == 1
    else:
        assert f.s.counters["gps_pos"]["weighted"] == 1 and f.s.counters["gps_pos"]["accepted"] == 1
    plain = _navigating(cls, gps_robust_k=0.0, gps_pos_sigma_min=0.001)
    _fix(plain, 4 * s_n, [sig * np.sqrt(z[0] / k), sig, sig])
    np.testing.assert_allclose(_llh_cov(f)[0], _llh_cov(plain)[0], rtol=0, atol=1e-14)
    np.testing.assert_allclose(_llh_cov(f)[1], _llh_cov(plain)[1], rtol=1e-9, atol=1e-18)
    unweighted = _navigating(cls, gps_robust_k=0.0, gps_pos_sigma_min=0.001)
    _fix(unweighted, 4 * s_n, [sig] * 3)
    moved = lambda g: (_llh_cov(g)[0][0] - 0.7) * 6.37e6  # noqa: E731
    assert 0.2 * moved(unweighted) < moved(f) < 0.9 * moved(unweighted)  # pulled less far north
    # within k: applied as it came
    g1, g0 = _navigating(cls, gps_robust_k=k), _navigating(cls, gps_robust_k=0.0)
    assert _fix(g1, 0.5 * s_n, [sig] * 3)[1] == "accepted"
    _fix(g0, 0.5 * s_n, [sig] * 3)
    np.testing.assert_array_equal(_llh_cov(g1)[0], _llh_cov(g0)[0])
    # a gross outlier: gated, nothing changes
    before = [x.copy() for x in _llh_cov(g1)]
    assert _fix(g1, 100 * s_n, [sig] * 3)[1] == "rejected"
    np.testing.assert_array_equal(_llh_cov(g1)[0], before[0])
    np.testing.assert_array_equal(_llh_cov(g1)[1], before[1])


@pytest.mark.parametrize("cls", [quatnav.GpsInsFilter, R.GpsInsFilter])
def test_robust_weighting_rejects_only_gross_outliers(cls):
    """With gps_robust_k, the gate judges the fix down-weighted: a fix 5 sigma off north (NIS 25,
    above the 3-dof gate of 21.1, refused without the weighting) is applied as a fix whose north
    variance is raised by |z| / k = 2 (k = 2.5; the fix as good as the INS, so the weighted NIS is
    25 * 2 / 3 = 16.7); one at 10 sigma (weighted NIS 100 * 2 / 5 = 40) is a gross outlier,
    refused with the state untouched."""
    k, gate = 2.5, 21.108
    f = _navigating(cls, gps_robust_k=k, gps_pos_sigma_min=0.001)
    sig = float(np.sqrt(_llh_cov(f)[1][0, 0]))
    s_n = float(np.sqrt(_llh_cov(f)[1][0, 0] + sig ** 2))
    plain = _navigating(cls, gps_robust_k=0.0, gps_pos_sigma_min=0.001)
    r0, d0 = _fix(plain, 5 * s_n, [sig] * 3)
    assert d0 == "rejected" and r0.nis > gate, r0.nis  # refused without the weighting
    r, decision = _fix(f, 5 * s_n, [sig] * 3)
    z = abs(r.innovation[0]) / np.sqrt(r.innovation_cov[0, 0])
    assert decision == "weighted" and 4.5 < z < 5.5 and r.nis > gate, (decision, z, r.nis)  # the NIS as it came
    same = _navigating(cls, gps_robust_k=0.0, gps_pos_sigma_min=0.001)
    _fix(same, 5 * s_n, [sig * np.sqrt(z / k), sig, sig])  # the plain update with the raised sigma
    np.testing.assert_allclose(_llh_cov(f)[0], _llh_cov(same)[0], rtol=0, atol=1e-14)
    np.testing.assert_allclose(_llh_cov(f)[1], _llh_cov(same)[1], rtol=1e-9, atol=1e-18)
    g = _navigating(cls, gps_robust_k=k, gps_pos_sigma_min=0.001)
    before = [x.copy() for x in _llh_cov(g)]
    assert _fix(g, 10 * s_n, [sig] * 3)[1] == "rejected"
    np.testing.assert_array_equal(_llh_cov(g)[0], before[0])
    np.testing.assert_array_equal(_llh_cov(g)[1], before[1])


def test_gnss_time_offset_and_age():
    """A GNSS latency: fixes stamped 0.2 s after their time of validity. Given gps_time_offset =
    -0.2 the result equals the run with the true times; a fix between IMU samples is applied with
    its age (the INS taken back to the fix's time)."""
    s = make_scenario("paper004_walk", seed=1)
    n = 2500
    kw = _aids(s)
    late = dict(kw, gps_t=kw["gps_t"] + 0.2)
    r0 = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(kw))
    r1 = quatnav.GpsInsFilter(lever_arm_b=LEVER, gps_time_offset=-0.2).run(s.imu.gyro[:n], s.imu.accel[:n],
                                                                            t=s.imu.t[:n], **as_aids(late))
    np.testing.assert_allclose(r1.position, r0.position, rtol=0, atol=1e-9)
    r2 = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **as_aids(late))
    nav, i, e0 = _horizontal_error(s, r0)
    _, _, e2 = _horizontal_error(s, r2)
    assert np.sqrt(np.mean(e2 ** 2)) > np.sqrt(np.mean(e0 ** 2))  # the latency, not given, costs accuracy


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
def test_walk_position_error_bounded(walk, dtype):
    s = walk
    r = quatnav.GpsInsFilter(dtype=dtype, lever_arm_b=LEVER).run(s.imu.gyro, s.imu.accel, t=s.imu.t, **as_aids(_aids(s)))
    nav, i, err = _horizontal_error(s, r)
    assert nav.mean() > 0.9
    assert np.sqrt(np.mean(err ** 2)) < 2.0  # GPS sigma 2.5 m; paper's bound is 30 m
    assert err.max() < 6.0
    yaw_err = np.angle(np.exp(1j * (r.euler[nav, 2] - s.truth.rpy[i, 2])))
    level_err = r.euler[nav, :2] - s.truth.rpy[i, :2]
    assert np.degrees(np.abs(level_err)).max() < 2.0
    assert np.degrees(np.abs(yaw_err[len(yaw_err) // 5:])).max() < 5.0


def test_gps_outage_sigma_grows_and_error_stays_consistent(walk):
    s = walk
    t0, t1 = 30.0, 40.0
    r = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro, s.imu.accel, t=s.imu.t,
                                                     outages=[(t0, t1)], **as_aids(_aids(s)))
    nav, i, err = _horizontal_error(s, r)
    t = r.t
    sig_h = np.hypot(r.sigma[:, 0], r.sigma[:, 1])
    k0, k1 = np.searchsorted(t, t0), np.searchsorted(t, t1) - 1
    inside = sig_h[k0:k1]
    assert np.all(np.diff(inside) >= -1e-9)  # no position aid: the horizontal sigma cannot shrink
    assert inside[-1] > 1.5 * inside[0]
    after = sig_h[k1 + 50]
    assert after < inside[-1]  # GPS back: the sigma drops again
    err_full = np.full(len(t), np.nan)
    err_full[nav] = err
    assert np.nanmax(err_full[k0:k1]) < 4.0 * inside.max() + 1.0


def test_position_nees_within_chi2_bounds():
    from scipy.stats import chi2
    nees = []
    for seed in range(4):
        s = make_scenario("paper004_walk", seed=seed)
        r = quatnav.GpsInsFilter(lever_arm_b=LEVER).run(s.imu.gyro, s.imu.accel, t=s.imu.t, **as_aids(_aids(s)))
        nav, i, _ = _horizontal_error(s, r)
        a, e2 = 6378137.0, 6.69437999014e-3
        sl2 = np.sin(s.truth.lat[i]) ** 2
        rm = a * (1 - e2) / (1 - e2 * sl2) ** 1.5
        rn = a / np.sqrt(1 - e2 * sl2)
        dn = (r.lat[nav] - s.truth.lat[i]) * (rm + s.truth.h[i])
        de = (r.lon[nav] - s.truth.lon[i]) * (rn + s.truth.h[i]) * np.cos(s.truth.lat[i])
        # horizontal position, 2 dof (diagonal sigmas), one sample every 5 s to limit correlation
        k = np.arange(0, len(dn), 250)
        nees.append((dn[k] / r.sigma[nav, 0][k]) ** 2 + (de[k] / r.sigma[nav, 1][k]) ** 2)
    nees = np.concatenate(nees)
    m = len(nees)
    lo, hi = chi2.ppf([0.001, 0.999], 2 * m) / m
    assert lo < nees.mean() < hi, (lo, nees.mean(), hi)


def test_bad_input_raises_naming_argument(walk):
    s = walk
    f = quatnav.GpsInsFilter()
    gyro = s.imu.gyro[:100].copy()
    gyro[10, 1] = np.nan
    with pytest.raises(ValueError, match="gyr: non-finite value in row 10"):
        f.run(gyro, s.imu.accel[:100], t=s.imu.t[:100])
    with pytest.raises(ValueError, match="acc"):
        f.run(s.imu.gyro[:100], s.imu.accel[:100, :2], t=s.imu.t[:100])
    t = s.imu.t[:100].copy()
    t[50] = t[49]
    with pytest.raises(ValueError, match="t: times must be strictly increasing"):
        f.run(s.imu.gyro[:100], s.imu.accel[:100], t=t)
    with pytest.raises(ValueError, match="gps_pos.value"):
        f.run(s.imu.gyro[:100], s.imu.accel[:100], t=s.imu.t[:100], gps_pos=quatnav.Aid([0.5, 1.0], np.zeros((3, 3))))
    with pytest.raises(ValueError, match="gps_pos.t"):
        f.run(s.imu.gyro[:100], s.imu.accel[:100], t=s.imu.t[:100], gps_pos=quatnav.Aid([1.0, 0.5], np.zeros((2, 3))))
    with pytest.raises(ValueError, match="gps_vel.t: expected the times of gps_pos"):
        f.run(s.imu.gyro[:100], s.imu.accel[:100], t=s.imu.t[:100], gps_pos=quatnav.Aid([0.5, 1.0], np.zeros((2, 3))),
              gps_vel=quatnav.Aid([0.5, 1.1], np.zeros((2, 3))))
    with pytest.raises(ValueError, match="gps_vel: needs gps_pos"):
        f.run(s.imu.gyro[:100], s.imu.accel[:100], t=s.imu.t[:100], gps_vel=quatnav.Aid([0.5, 1.0], np.zeros((2, 3))))


def test_outages_take_pairs_or_none_and_name_a_single_pair(walk):
    """outages=(20, 30) failed with "object of type 'float' has no len()", outages=None (the
    docstring says optional) with "'NoneType' has no len()"."""
    s = walk
    g = s.gps
    kw = dict(t=s.imu.t, gps_pos=quatnav.Aid(g.t_valid, np.column_stack([g.lat, g.lon, g.h])),
              gps_vel=quatnav.Aid(g.t_valid, g.v_n), compass=quatnav.Aid(s.compass.t, s.compass.yaw))
    base = quatnav.GpsInsFilter().run(s.imu.gyro, s.imu.accel, outages=None, **kw)
    np.testing.assert_array_equal(base.position, quatnav.GpsInsFilter().run(s.imu.gyro, s.imu.accel, **kw).position)
    cut = [quatnav.GpsInsFilter().run(s.imu.gyro, s.imu.accel, outages=o, **kw) for o in ([(20.0, 30.0)], np.array([[20.0, 30.0]]))]
    np.testing.assert_array_equal(cut[0].position, cut[1].position)
    assert cut[0].counters["gps_pos"]["accepted"] == base.counters["gps_pos"]["accepted"] - 50
    with pytest.raises(ValueError, match=r"outages: expected a sequence of \(t_start, t_end\) pairs, got one pair "
                                         r"\(20.0, 30.0\): give \[\(20.0, 30.0\)\]"):
        quatnav.GpsInsFilter().run(s.imu.gyro, s.imu.accel, outages=(20.0, 30.0), **kw)
    with pytest.raises(ValueError, match=r"outages: .* t_end > t_start; row 1 is \(40.0, 35.0\)"):
        quatnav.GpsInsFilter().run(s.imu.gyro, s.imu.accel, outages=[(20.0, 30.0), (40.0, 35.0)], **kw)


def test_experiment_cli_writes_json(tmp_path):
    import json

    from quatnav import cli
    out = tmp_path / "gpsins.json"
    assert cli.main(["experiment", "gpsins", "--scenario", "walk", "--json", str(out)]) == 0
    res = json.loads(out.read_text())
    assert res["horizontal_m"]["rms"] < 2.0 and res["horizontal_m"]["max"] < 6.0  # paper bound 30 m
    o = res["outage"]
    assert o["horizontal_error_at_end_m"] > o["horizontal_error_at_start_m"]


@pytest.mark.parametrize("name, value", [("declination", 8.5), ("declination", -12.0), ("compass_sigma", 2.0),
                                         ("init_level_sigma", 5.0), ("init_yaw_sigma", 10.0)])
def test_angle_parameters_in_degrees_are_refused(name, value):
    """Angles are radians: a value outside the parameter's range (most likely degrees) raises a
    ValueError naming the parameter and the np.radians conversion; the range itself is accepted."""
    with pytest.raises(ValueError, match=rf"^{name}: .* is outside .* rad; angles are in radians: .*np\.radians"):
        quatnav.GpsInsFilter(**{name: value})
    ok = float(np.radians(value)) if name == "declination" else 0.5 * abs(float(np.radians(value)))
    assert quatnav.GpsInsFilter(**{name: ok}).params[name] == pytest.approx(ok)
    for bad in (float("nan"), float("inf")):
        with pytest.raises(ValueError, match=name):
            quatnav.GpsInsFilter(**{name: bad})
    with pytest.raises(ValueError, match=rf"{name}: .* is outside"):
        quatnav.GpsInsFilter(**{name: -1e6})


def test_messages_print_numbers_plainly():
    t = np.array([0.0, 4000.0, 8000.0])
    with pytest.raises(ValueError) as e:
        quatnav.GpsInsFilter().run(np.zeros((3, 3)), np.tile([0.0, 0.0, -9.8], (3, 1)), t=t)
    assert str(e.value) == "t: step 4000.0 s in row 1 exceeds max_coast=10.0 s (gaps up to it are coasted)"
    with pytest.raises(ValueError) as e:
        quatnav.GpsInsFilter().run(np.zeros((3, 3)), np.zeros((3, 3)), t=np.array([0.0, 0.2, 0.1]))
    assert "row 2 (0.1) does not follow row 1 (0.2)" in str(e.value) and "np." not in str(e.value)
    with pytest.raises(ValueError) as e:
        quatnav.GpsInsFilter(max_dt=np.float64(-1.0))
    assert str(e.value) == "max_dt: expected a positive finite number, got -1.0"


@pytest.mark.parametrize("kind", ["unknown", "rtk_fixed", "rtk_float", "dgnss", "single"])
def test_a_wandering_solution_weighs_by_its_correlation_time(kind):
    """A fix dt after the last one, of a kind whose error wanders (RTK float, DGNSS, single), has
    its variance in the innovation covariance raised by (1 + rho) / (1 - rho), rho = exp(-dt /
    gps_error_tau), against the same filter with gps_error_tau = 0; an RTK-fixed fix or one of
    unknown kind is taken as white. C++ and the numpy twin agree, and both keep the time of
    validity of the last position they used (the start fix included)."""
    tau, floor = 10.0, 0.2
    params = dict(gps_float_sigma_min=floor, gps_dgnss_sigma_min=floor, gps_single_sigma_min=floor,
                  gps_pos_sigma_min=floor, gps_vertical_floor_ratio=1.0)
    code = quatnav.filters.gpsins.GNSS_SOLUTIONS.index(kind)

    def innovation_cov(cls, tau_):
        f = _navigating(cls, gps_error_tau=tau_, **params)  # started by a fix at t = 0, now t = 0.5
        if cls is quatnav.GpsInsFilter:
            r = f.update_gps(0.7, 0.2, 100.0, None, [0.005] * 3, None, age=0.1, solution=kind)[0]
            return r.innovation_cov, f.get_state()["gps_pos_t"]
        r = f.update_gps(0.7, 0.2, 100.0, [np.nan] * 3, [0.005] * 3, [np.nan] * 3, age=0.1, solution=code)[0]
        return r.innovation_cov, f.s.gps_pos_t

    s0, _ = innovation_cov(quatnav.GpsInsFilter, 0.0)
    s1, t_used = innovation_cov(quatnav.GpsInsFilter, tau)
    rho = np.exp(-0.4 / tau)  # the fix valid at 0.4 s, 0.4 s after the start fix
    factor = (1 + rho) / (1 - rho) if kind in ("rtk_float", "dgnss", "single") else 1.0
    np.testing.assert_allclose(np.diag(s1 - s0), floor ** 2 * (factor - 1.0), rtol=1e-9, atol=1e-15)
    assert t_used == pytest.approx(0.4, abs=1e-9)
    s_ref, t_ref = innovation_cov(R.GpsInsFilter, tau)
    np.testing.assert_allclose(s1, s_ref, rtol=1e-9, atol=1e-15)
    assert t_ref == pytest.approx(0.4, abs=1e-9)
