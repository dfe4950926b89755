"""GpsInsFilter on third-party and real data: NaveGo's synthetic run (ADIS16405 + 5 Hz GNSS, with
truth) and a real pedestrian walk with RTK GNSS. Loaders (fields, units, monotonic time), the
IMU mounting found from the walk, and short runs with bounds from the measured figures
(docs/GPSINS_DATA.md) with margin. Skip when the shared data folder is absent."""
import numpy as np
import pytest

pytestmark = pytest.mark.data


@pytest.fixture(scope="module")
def navego(data_dir):
    from quatnav.datasets import navego
    d = data_dir / "navego_synthetic"
    if not d.is_dir():
        pytest.skip(f"{d} not found")
    return navego.load(d)


@pytest.fixture(scope="module")
def walk(data_dir):
    from quatnav.datasets import gnss_imu_walk
    d = data_dir / "gnss_imu_walk"
    if not d.is_dir():
        pytest.skip(f"{d} not found")
    return gnss_imu_walk.load(d)


# --- NaveGo -------------------------------------------------------------------------------------
def test_navego_loader_fields_units_and_time(navego):
    d = navego
    n, k = len(d.imu_t), len(d.gnss_t)
    assert n == 87450 and d.gyro.shape == d.accel.shape == (n, 3)
    assert np.all(np.diff(d.imu_t) > 0) and np.all(np.diff(d.gnss_t) > 0) and np.all(np.diff(d.ref_t) > 0)
    assert np.median(np.diff(d.imu_t)) == pytest.approx(0.005) and np.median(np.diff(d.gnss_t)) == pytest.approx(0.2)
    np.testing.assert_array_equal(d.ref_t, d.imu_t)
    # specific force at the start: about -g on body z (FRD, level), m/s^2 not g
    assert -10.5 < d.accel[0, 2] < -9.0
    # radians: the run is near 32.8 S, 68.8 W (NaveGo's example), heights in metres
    assert np.all(np.abs(d.gnss_llh[:, :2]) < np.pi) and np.degrees(d.ref_llh[0, 0]) == pytest.approx(-32.83, abs=0.05)
    assert d.gnss_llh.shape == (k, 3) and d.gnss_vel.shape == (k, 3)
    np.testing.assert_allclose(d.gnss_pos_sigma, [5, 5, 10])
    # ADIS16405 profile in SI: 2 deg/sqrt(h) and 0.2 m/s/sqrt(h)
    np.testing.assert_allclose(d.imu_profile["arw"], np.radians(2.0) / 60.0, rtol=1e-6)
    np.testing.assert_allclose(d.imu_profile["vrw"], 0.2 / 60.0, rtol=1e-6)
    # the reference DCM is body-to-NED, row-major, and agrees with the Euler angles
    from quatnav.core import quaternion as Q
    for i in (0, 20000, 60000):
        np.testing.assert_allclose(Q.to_rotmat(Q.from_euler(d.ref_rpy[i])), d.ref_C_nb[i], atol=1e-9)


def test_navego_gps_ins_rmse(navego):
    from quatnav.experiments.navego import run_navego
    out, _ = run_navego(navego.path)
    a, g = out["ins_gnss"], out["gnss_only"]
    # GNSS alone: its stated noise (5/5/10 m, 0.05 m/s)
    assert 4.5 < g["position_rmse_m"]["n"] < 5.5 and 9.0 < g["position_rmse_m"]["d"] < 11.0
    # INS/GNSS: measured 0.34/0.44/0.55 m, 0.02 m/s, roll/pitch 0.27/0.20 deg, yaw 1.2 deg
    for c in "ned":
        assert a["position_rmse_m"][c] < 1.5
        assert a["position_rmse_m"][c] < 0.3 * g["position_rmse_m"][c]
        assert a["velocity_rmse_mps"][c] < 0.05
    assert a["attitude_rmse_deg"]["roll"] < 0.6 and a["attitude_rmse_deg"]["pitch"] < 0.6
    assert a["attitude_rmse_deg"]["yaw"] < 2.5
    # the filter's sigma covers the error
    assert min(out["within_3sigma_fraction"].values()) > 0.95
    # the gyro bias in the data (about 3 deg/s per axis) is found to 0.05 deg/s
    np.testing.assert_allclose(out["final_bias"]["gyro_dps"], out["final_bias"]["gyro_in_data_dps"], atol=0.05)
    assert sum(out["rejections"].values()) == 0


def test_navego_short_run_has_no_attitude_after_60s(navego, tmp_path, capsys):
    """--seconds 60: the ins run runs navigate less than 60 s, so there is no attitude RMSE from
    60 s on: None in the JSON and one line saying why, not numpy's empty-mean warning and NaN."""
    import json
    import warnings

    from quatnav import cli
    js = tmp_path / "n.json"
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        assert cli.main(["experiment", "navego", "--data", str(navego.path), "--seconds", "60",
                         "--json", str(js)]) == 0
    text = capsys.readouterr().out
    assert "nan" not in text and "none after 60 s (it navigated 58.6 s)" in text
    got = json.loads(js.read_text())
    for name in ("cli_in_motion", "cli_position_only"):
        assert got[name]["attitude_rmse_after_60s_deg"] is None and got[name]["navigation_s"] < 60.0


def test_navego_run_too_short_to_align(navego, capsys):
    """--seconds 1: the ins run runs never start navigating; the report says so, no traceback."""
    from quatnav import cli
    assert cli.main(["experiment", "navego", "--data", str(navego.path), "--seconds", "1"]) == 0
    out = capsys.readouterr().out
    assert out.count("navigation never started in the 1 s run") == 2, out


# --- the walk ------------------------------------------------------------------------------------
def test_walk_loader_fields_units_and_time(walk):
    w = walk
    assert np.all(np.diff(w.imu_t) > 0) and np.all(np.diff(w.gnss_t) > 0)
    assert 160 < 1 / np.median(np.diff(w.imu_t)) < 175
    assert np.median(np.diff(w.gnss_t)) == pytest.approx(0.25, abs=1e-6)
    # both clocks on the same GPS-time scale: the records overlap over the whole walk
    assert abs(w.imu_t[0] - w.gnss_t[0]) < 2.0 and abs(w.imu_t[-1] - w.gnss_t[-1]) < 3.0
    # accelerometer converted from g: |f| ~ 9.8 m/s^2 at rest
    rest = w.imu_t - w.imu_t[0] < 8
    assert 9.7 < np.linalg.norm(w.accel_s[rest].mean(axis=0)) < 10.0
    # Boulder, CO in radians; ellipsoidal height ~1600 m; Q flags 1 and 2
    assert np.degrees(w.gnss_llh[0, 0]) == pytest.approx(40.0967, abs=1e-3)
    assert np.degrees(w.gnss_llh[0, 1]) == pytest.approx(-105.1472, abs=1e-3)
    assert 1590 < w.gnss_llh[0, 2] < 1610
    assert set(np.unique(w.q)) == {1, 2} and w.fixed.sum() > 300
    # RTKLIB gives north, east, UP velocity: the loader's down velocity agrees with -dh/dt
    dh = np.diff(w.gnss_llh[:, 2]) / np.diff(w.gnss_t)
    vd = 0.5 * (w.vel_n[1:, 2] + w.vel_n[:-1, 2])
    assert np.sqrt(np.mean((dh + vd) ** 2)) < np.sqrt(np.mean((dh - vd) ** 2))


def test_walk_mounting_from_data(walk):
    from quatnav.datasets import gnss_imu_walk as W
    m = W.find_mounting(walk)
    assert m["up_axis"] == "+z" and m["rest_accel_norm_g"] == pytest.approx(1.012, abs=0.005)
    assert m["yaw_rate_sign"] == -1
    # the other sign leaves course minus yaw scattered (117 deg vs 22 deg measured)
    assert m["spread_other_sign_deg"] > 3 * m["forward_spread_deg"]
    assert abs(m["forward_yaw_deg"] - W.FORWARD_YAW_DEG) < 5
    assert np.ptp(m["forward_yaw_10s_deg"]) < 40  # steady over the walk
    C = W.C_BS
    np.testing.assert_allclose(C @ C.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(C) == pytest.approx(1.0)
    # at rest the body specific force is -g along body down
    f_b = W.to_body(walk.accel_s[walk.imu_t - walk.imu_t[0] < 8].mean(axis=0)[None])[0]
    assert f_b[2] < -9.7 and np.hypot(f_b[0], f_b[1]) < 0.3


def test_walk_rtk_outages_and_degraded(walk):
    from quatnav.experiments.walk_rtk import run_walk
    s, _ = run_walk(walk.path)
    # with every RTK epoch: measured 2.6 cm RMS against the fixed epochs
    assert s["rtk"]["all_fixed"]["horizontal_m"]["rms"] < 0.03
    assert s["rtk"]["rejections"]["gps_pos"] == 0  # every RTK position accepted
    assert s["rtk"]["navigating_from_s"] < 20
    # 10 s outages every 30 s: measured drifts 15.9 (first, 6 s after navigation starts), 1.8, 0.7 m;
    # a pedestrian walks ~13 m in 10 s
    outs = [o for o in s["rtk_outages"]["outages"] if o["fixed_epochs"]]
    assert len(outs) == 3
    assert all(o["horizontal_max_m"] < 30 for o in outs)
    assert all(o["horizontal_max_m"] < 5 for o in outs[1:])
    assert all(o["horizontal_at_start_m"] < 0.2 for o in outs)
    # degraded GNSS (2.5 m white noise per axis, input RMS ~3.5 m): measured 0.84 m
    d = s["degraded"]
    assert d["all_fixed"]["horizontal_m"]["rms"] < 0.5 * d["gnss_input_horizontal_rms_m"]
    assert d["all_fixed"]["horizontal_m"]["rms"] < 1.5


def test_walk_perturbation_table(walk):
    """The car's robustness table on the walk's RTK run with outages: every setting of
    ``gpsins_car.PERTURBATIONS``, each changing what it names (the defaults' noise as ``ins run``
    sets it: raised to the log's), and the mean drift within 1.5x of the defaults' (measured
    0.84-1.03, docs/GPSINS_DATA.md). About 2 s."""
    from quatnav.experiments.gpsins_car import PERTURBATIONS
    from quatnav.experiments.walk_rtk import perturbation_table
    t = perturbation_table(walk.path)
    assert list(t) == list(PERTURBATIONS)
    assert t["defaults"]["ratio"] == 1.0 and len(t["defaults"]["drift_m"]) == 3
    assert t["noise x10"]["noise"]["gyro_noise"] > t["defaults"]["noise"]["gyro_noise"]
    assert t["noise x10"]["drift_m"] != t["defaults"]["drift_m"]
    assert t["lever arm +5 cm"]["drift_m"] != t["defaults"]["drift_m"]
    assert all(1 / 1.5 < v["ratio"] < 1.5 for v in t.values()), {k: v["ratio"] for k, v in t.items()}


def test_walk_gate_lockout_recovery(walk):
    """The walk's noise densities given ten times too small: with the plain gate (no inflation,
    no adaptation) the filter locks out of its own cm-level fixes and drifts by tens of metres;
    with them it rejects no more than a few percent of the fixes and stays at the cm level."""
    from quatnav.experiments.walk_rtk import WALK_PARAMS, run_walk
    small = {k: WALK_PARAMS[k] / 10 for k in ("gyro_noise", "acc_noise", "gyro_bias_noise", "acc_bias_noise")}
    s0, _ = run_walk(walk.path, runs=("rtk",), params=dict(small, inflate_after=0, adapt_q_max=1.0))
    s1, _ = run_walk(walk.path, runs=("rtk",), params=small)
    assert s0["rtk"]["all_fixed"]["horizontal_m"]["max"] > 20
    fixes = s1["fixed_epochs"] + s1["float_epochs"]
    assert s1["rtk"]["all_fixed"]["horizontal_m"]["rms"] < 0.1
    assert s1["rtk"]["rejections"]["gps_pos"] < 0.03 * fixes and s1["rtk"]["rejections"]["gps_vel"] < 0.03 * fixes
    assert WALK_PARAMS.get("inflate_after") is None  # the experiment uses the default
