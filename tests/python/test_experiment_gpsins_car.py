"""The simulated-car experiment (``quatnav experiment gpsins-car``): its consistency figure is 1
for errors drawn from the filter's own sigmas, its outage drift is the error at the end of each
window, and one drive gives every figure the Monte Carlo sums up."""
from types import SimpleNamespace

import numpy as np

from quatnav.experiments import gpsins_car as X


def test_nees_is_one_for_errors_drawn_from_the_sigmas():
    rng = np.random.default_rng(0)
    n = 20000
    t = np.arange(n) * 0.01
    sigma = np.exp(rng.normal(0.0, 1.0, (n, 16)))
    e = rng.standard_normal((n, 9)) * sigma[:, :9]
    r = SimpleNamespace(t=t, navigating=np.ones(n, bool), sigma=sigma)
    errs = {"dp": e[:, 0:3], "dv": e[:, 3:6], "psi": e[:, 6:9]}
    v = X.nees_per_run(r, errs, t0=1.0, every=0.01)
    assert all(0.9 < x < 1.1 for x in v.values()), v
    errs2 = {k: 1.5 * x for k, x in errs.items()}  # 1.5x over-confident: 2.25
    assert X.nees_per_run(r, errs2, t0=1.0, every=0.01)["all"] > 2.0


def test_nees_per_axis_splits_the_samples_at_the_outage_windows():
    """Inside the windows the errors are 2x their sigmas (NEES 4), outside 1x (NEES 1): each part
    gets its own, per axis."""
    n = 10000
    t = np.arange(n) * 0.01  # 100 s
    sigma = np.full((n, 16), 0.1)
    out = (t >= 50.0) & (t < 70.0)
    e = np.where(out[:, None], 2.0, 1.0) * sigma[:, :9] * np.array([1, -1, 1, 1, 1, -1, 1, 1, 1])
    r = SimpleNamespace(t=t, navigating=np.ones(n, bool), sigma=sigma)
    errs = {"dp": e[:, 0:3], "dv": e[:, 3:6], "psi": e[:, 6:9]}
    inside = X.nees_per_axis(r, errs, [(50.0, 70.0)], t0=40.0)
    aided = X.nees_per_axis(r, errs, [(50.0, 70.0)], inside=False, t0=40.0)
    for b in ("position", "velocity", "attitude"):
        np.testing.assert_allclose(inside[b], [4.0] * 3, rtol=1e-12)
        np.testing.assert_allclose(aided[b], [1.0] * 3, rtol=1e-12)


def test_outage_drift_is_the_error_before_the_first_fix_after():
    t = np.arange(0.0, 100.0, 0.01)
    dp = np.zeros((len(t), 3))
    dp[:, 0] = np.where((t >= 20) & (t < 50), (t - 20) * 0.5, 0.0)  # grows 0.5 m/s in the outage
    r = SimpleNamespace(t=t)
    d = X.outage_drift(None, r, {"dp": dp}, [(20.0, 50.0)])
    np.testing.assert_allclose(d, [14.995], atol=1e-9)


def test_one_drive_gives_every_figure():
    res = X.run_seed(0)["defaults"]
    assert len(res["30"]["drift_m"]) == 4 and len(res["60"]["drift_m"]) == 3
    assert all(np.isfinite(res["30"]["drift_m"])) and all(np.isfinite(res["60"]["drift_m"]))
    rej = res["all"]["rejected"]
    from quatnav.sim.car import car_rtk
    q = car_rtk(seed=0).gps.quality
    assert [rej[k]["fixes"] for k in ("fixed", "float", "single")] == [int((q == c).sum()) for c in (1, 2, 5)]
    assert 0.0 < res["all"]["horizontal_rms_m"] < 2.0 and res["all"]["navigating_from_s"] < 60.0
    summary = X.summarize([{"defaults": res}], ("defaults",))["defaults"]
    assert summary["30"]["drift_worst_m"] == max(res["30"]["drift_m"])
    for kind in ("30", "60"):
        for part in ("nees_outage", "nees_aided"):
            assert all(len(v) == 3 and np.all(np.isfinite(v)) for v in summary[kind][part].values())


def test_the_truth_is_taken_at_the_output_stamps_on_the_gnss_clock():
    """The IMU stamps its samples late; an output stamped t is compared with the vehicle at GNSS
    time t (on the trajectory's grid exactly, between its samples interpolated), not at the
    sample's true time t less the delay (v times the delay, decimetres at speed)."""
    from quatnav.core import quaternion as Q
    from quatnav.sim.car import car_rtk
    s = car_rtk(seed=0)
    tr = s.truth
    assert s.params["sensor_model"]["imu_delay_s"] > 0.002
    idx = np.arange(4000, 90000, 997)
    lat, lon, h, v, q = X.truth_at(s, SimpleNamespace(t=tr.t[idx]))
    np.testing.assert_allclose(np.column_stack([lat, lon]), np.column_stack([tr.lat[idx], tr.lon[idx]]), rtol=0,
                               atol=1e-13)
    np.testing.assert_allclose(v, tr.v_n[idx], atol=1e-9)
    q_b_imu = np.asarray(s.params["sensor_model"]["q_b_imu"])
    np.testing.assert_allclose(Q.canonical(q), Q.canonical(Q.mul(tr.q_nb[idx], q_b_imu)), atol=1e-12)
    # half way between two samples: the mean of the neighbours
    _, _, _, v2, q2 = X.truth_at(s, SimpleNamespace(t=tr.t[idx] + 0.5 / tr.rate_hz))
    np.testing.assert_allclose(v2, 0.5 * (tr.v_n[idx] + tr.v_n[idx + 1]), atol=1e-9)
    ang = Q.angle_between(q2, Q.mul(tr.q_nb[idx], q_b_imu))
    step = Q.angle_between(tr.q_nb[idx + 1], tr.q_nb[idx])
    np.testing.assert_allclose(ang, 0.5 * step, atol=1e-9)
