"""NavFilter13 (paper 002): C++ against the numpy reference for every time update, derivatives
against finite differences, float32 against float64, state round trips, input validation."""
from __future__ import annotations

from types import SimpleNamespace
import warnings

import numpy as np
import pytest

import quatnav
from quatnav.core import quaternion as Q
from quatnav.filters.nav13 import initial_covariance, euler_rate_matrix
from quatnav.reference import nav13 as R

LAT, LON, H = np.radians(36.37), np.radians(127.36), 50.0
POLICIES = ("ekf", "second_order", "ukf")


def _start(rng):
    q0 = Q.from_euler(np.radians([8.0, -6.0, 50.0]))
    P = initial_covariance(q0, 0.3, np.radians([10.0, 10.0, 20.0]), 0.02, np.radians(2.0) / 3600)
    v0 = np.array([1.7, 1.0, 0.05])
    return v0, q0, np.zeros(3), np.zeros(3), P


def _imu(rng, n):
    """A turning, accelerating vehicle: specific force near -g with manoeuvres, rates up to 0.3 rad/s."""
    t = np.arange(1, n + 1) * 0.01
    f = np.column_stack([0.3 * np.sin(0.7 * t), 0.2 * np.cos(0.5 * t), -9.80 + 0.1 * np.sin(t)])
    w = np.column_stack([0.05 * np.sin(0.3 * t), 0.04 * np.cos(0.2 * t), 0.3 * np.ones(n)])
    return t, f + 1e-3 * rng.standard_normal((n, 3)), w + 1e-4 * rng.standard_normal((n, 3))


@pytest.mark.parametrize("tu", POLICIES)
def test_cpp_matches_reference_step_by_step(tu):
    rng = np.random.default_rng(1)
    start = _start(rng)
    cpp = quatnav.NavFilter13(time_update=tu)
    ref = R.NavFilter13(tu)
    cpp.reset(*start, lat=LAT, lon=LON, h=H)
    ref.reset(*start, LAT, LON, H)
    t, f, w = _imu(rng, 40)
    for k in range(len(t)):
        assert cpp.predict(w[k], f[k], 0.01) == "ok"
        ref.predict(w[k], f[k], 0.01)
        if k % 5 == 4:
            v_meas = np.array([1.8, 0.9, 0.0]) + 0.03 * rng.standard_normal(3)
            yaw = np.radians(45.0) + 0.03 * rng.standard_normal()
            if k % 10 == 4:
                rc, rr = cpp.update_velocity(v_meas), ref.update_velocity(v_meas)
                assert rc.nis == pytest.approx(rr.nis, rel=1e-9)
                rc, rr = cpp.update_yaw(yaw), ref.update_yaw(yaw)
            else:
                rc, rr = cpp.update_velocity_yaw(v_meas, yaw), ref.update_velocity_yaw(v_meas, yaw)
            assert rc.status == rr.status == "ok"
            assert rc.nis == pytest.approx(rr.nis, rel=1e-9)
            np.testing.assert_allclose(rc.innovation, rr.innovation, atol=1e-10)
        np.testing.assert_allclose(cpp.x, ref.x, atol=1e-9, rtol=0)
        np.testing.assert_allclose(cpp.covariance, ref.P, atol=1e-9 * np.abs(ref.P).max(), rtol=0)
        s = cpp.get_state()
        assert s["lat"] == pytest.approx(ref.lat, abs=1e-12)
        assert s["h"] == pytest.approx(ref.h, abs=1e-9)


def test_policies_differ_where_they_should():
    rng = np.random.default_rng(2)
    start = _start(rng)
    t, f, w = _imu(rng, 20)
    xs = {}
    for tu in POLICIES:
        flt = quatnav.NavFilter13(time_update=tu)
        flt.reset(*start, lat=LAT, lon=LON, h=H)
        for k in range(len(t)):
            flt.predict(w[k], f[k], 0.01)
        xs[tu] = flt.x
    # With a 10-20 deg attitude uncertainty the mean corrections are visible in the velocity.
    assert np.linalg.norm(xs["ekf"][:3] - xs["second_order"][:3]) > 1e-4
    assert np.linalg.norm(xs["ekf"][:3] - xs["ukf"][:3]) > 1e-4


def _rand_input(rng, dt=0.1):
    return SimpleNamespace(f_ib_b=np.array([0.3, -0.2, -9.7]) + 0.3 * rng.standard_normal(3),
                             omega_ib_b=0.2 * rng.standard_normal(3), dt=dt,
                             omega_ie_n=0.05 * rng.standard_normal(3), omega_en_n=0.05 * rng.standard_normal(3),
                             g_n=np.array([0.0, 0.0, 9.8]))


def test_reference_jacobian_and_second_derivatives_by_finite_differences():
    rng = np.random.default_rng(3)
    for _ in range(5):
        x = rng.standard_normal(13)
        u = _rand_input(rng)
        F = R.jacobian(x, u)
        h = 1e-6
        Fn = np.column_stack([(R.f_d(x + h * e, u) - R.f_d(x - h * e, u)) / (2 * h) for e in np.eye(13)])
        np.testing.assert_allclose(F, Fn, atol=1e-8)
        # d2 f_c / dx_i dx_j from differences of the analytic Jacobian, contracted with P.
        Hs = np.stack([(R.jacobian(x + h * e, u) - R.jacobian(x - h * e, u)) / (2 * h) for e in np.eye(13)], axis=2)
        A = rng.standard_normal((13, 13))
        P = A @ A.T
        dense = 0.5 * np.einsum("cij,ij->c", Hs, P)
        np.testing.assert_allclose(R.second_order_term(x, P, u), dense, atol=1e-7 * (1 + np.abs(dense).max()))


def test_initial_covariance_matches_euler_perturbation():
    q = Q.from_euler(np.radians([5.0, -3.0, 40.0]))
    rpy = Q.to_euler(q)
    J = 0.5 * Q.xi(q) @ euler_rate_matrix(rpy)
    h = 1e-6
    Jn = np.column_stack([(Q.from_euler(rpy + h * e) - Q.from_euler(rpy - h * e)) / (2 * h) for e in np.eye(3)])
    np.testing.assert_allclose(J, Jn, atol=1e-9)
    P = initial_covariance(q, 0.3, [0.1, 0.2, 0.3], 0.01, 1e-5)
    assert np.allclose(P, P.T) and np.all(np.linalg.eigvalsh(P) > -1e-15)


@pytest.mark.parametrize("tu", POLICIES)
def test_batch_run_matches_steps_and_split_state(tu):
    rng = np.random.default_rng(4)
    start = _start(rng)
    t, f, w = _imu(rng, 120)
    vel_t = t[9::10]
    vel = np.tile([1.8, 0.9, 0.0], (len(vel_t), 1)) + 0.03 * rng.standard_normal((len(vel_t), 3))
    yaw_t = t[4::10]
    yaw = np.radians(45.0) + 0.03 * rng.standard_normal(len(yaw_t))
    a = quatnav.NavFilter13(time_update=tu)
    a.reset(*start, lat=LAT, lon=LON, h=H)
    s0 = a.get_state()
    res = a.run(w, f, t=t, gps_vel=quatnav.Aid(vel_t, vel), yaw=quatnav.Aid(yaw_t, yaw), return_covariance=True)
    assert res.x.shape == (120, 13) and res.P.shape == (120, 13, 13)
    assert np.all(res.aids["gps_vel"].status == 0) and np.all(res.aids["yaw"].status == 0)
    assert res.flag("gps_vel_used").sum() == len(vel_t)
    # The same by steps.
    b = quatnav.NavFilter13(time_update=tu)
    b.set_state(s0)
    d = np.diff(t)
    steps = np.concatenate([d[:1], d])  # the step lengths run() derives from t
    iv = iy = 0
    for k in range(len(t)):
        b.predict(w[k], f[k], steps[k])
        while iv < len(vel_t) and vel_t[iv] <= t[k] + 1e-6:
            assert b.update_velocity(vel[iv]).nis == res.aids["gps_vel"].nis[iv]
            iv += 1
        while iy < len(yaw_t) and yaw_t[iy] <= t[k] + 1e-6:
            assert b.update_yaw(yaw[iy]).nis == res.aids["yaw"].nis[iy]
            iy += 1
        np.testing.assert_array_equal(b.x, res.x[k])
    # Split run: first half, save, restore into a new filter, second half.
    c = quatnav.NavFilter13(time_update=tu)
    c.set_state(s0)
    m = 60
    v1, y1 = vel_t <= t[m - 1], yaw_t <= t[m - 1]
    r1 = c.run(w[:m], f[:m], t=t[:m], gps_vel=quatnav.Aid(vel_t[v1], vel[v1]), yaw=quatnav.Aid(yaw_t[y1], yaw[y1]))
    d = quatnav.NavFilter13(time_update=tu)
    d.set_state(c.get_state())
    r2 = d.run(w[m:], f[m:], t=t[m:], gps_vel=quatnav.Aid(vel_t[~v1], vel[~v1]),
               yaw=quatnav.Aid(yaw_t[~y1], yaw[~y1]))
    np.testing.assert_array_equal(np.vstack([r1.x, r2.x]), res.x)


@pytest.mark.parametrize("tu", POLICIES)
def test_float32_tracks_float64(tu):
    rng = np.random.default_rng(5)
    start = _start(rng)
    t, f, w = _imu(rng, 1000)
    vel_t = t[9::10]
    vel = np.tile([1.8, 0.9, 0.0], (len(vel_t), 1))
    out = {}
    for dt in (np.float64, np.float32):
        flt = quatnav.NavFilter13(time_update=tu, dtype=dt)
        flt.reset(*start, lat=LAT, lon=LON, h=H)
        out[dt] = flt.run(w, f, t=t, gps_vel=quatnav.Aid(vel_t, vel), yaw=quatnav.Aid(vel_t, np.full(len(vel_t), 0.8)))
    assert out[np.float32].x.dtype == np.float32
    assert np.abs(out[np.float32].x[:, :3] - out[np.float64].x[:, :3]).max() < 1e-3
    ang = Q.angle_between(out[np.float32].quat.astype(float), out[np.float64].quat)
    assert np.max(ang) < 1e-3


def _paper002_float32(tu, **params):
    from quatnav.sim.scenarios import make_scenario
    s = make_scenario("paper002_straight_then_circle", seed=1)
    tr = s.truth
    f = quatnav.NavFilter13(time_update=tu, dtype=np.float32, **params)
    f.reset(tr.v_n[0], tr.q_nb[0], lat=tr.lat[0], lon=tr.lon[0], h=tr.h[0])
    r = f.run(s.imu.gyro[1:], s.imu.accel[1:], t=s.imu.t[1:], gps_vel=quatnav.Aid(s.gps.t_valid, s.gps.v_n),
              yaw=quatnav.Aid(s.compass.t, s.compass.yaw))
    i = np.searchsorted(tr.t, r.t)
    return r.aids["gps_vel"].counts(), np.sqrt(np.mean(np.sum((r.velocity - tr.v_n[i]) ** 2, axis=1)))


@pytest.mark.parametrize("tu", POLICIES)
def test_float32_over_the_whole_paper002_scenario(tu):
    """200 s of paper 002's scenario in float32. With the default cov_floor = 0 (the paper's
    filter) the bias variances, which have no process noise, shrink into float's rounding: with
    the ekf and second-order time updates the covariance stops being positive definite at about
    90-100 s and most velocity updates are refused after it (docs/PORTING.md). cov_floor = 1e-12
    holds the whole run: every update applied, the velocity within 0.05 m/s RMS of the truth."""
    counts, rms = _paper002_float32(tu)
    if tu == "ukf":
        assert counts == {"ok": 2001} and rms < 0.05
    else:  # the documented limit: if this starts to pass, update docs/PORTING.md. A correction
        # that would make a variance negative is refused (numerical_failure: 1445 / 1474 of the
        # 2001, ekf / second order, 2026-12-06) and the filter coasts between the ones it takes
        # (0.085 / 0.093 m/s RMS). Bound: 1 m/s, 20x the run with the floor; before those were
        # refused the velocity ran off (52 m/s RMS with the ekf, 1.3e4 with second order).
        assert counts.get("numerical_failure", 0) > 500 and rms < 1.0
    counts, rms = _paper002_float32(tu, cov_floor=1e-12)
    assert counts == {"ok": 2001} and rms < 0.05


def test_validation_names_argument_and_row():
    with pytest.raises(ValueError, match="time_update"):
        quatnav.NavFilter13(time_update="particle")
    with pytest.raises(TypeError, match="keyword-only"):
        quatnav.NavFilter13("ekf")
    with pytest.raises(TypeError, match="dtype"):
        quatnav.NavFilter13(dtype=np.int32)
    with pytest.raises(TypeError, match="unknown parameter"):
        quatnav.NavFilter13(gyro_nois=1.0)
    with pytest.raises(ValueError, match="gps_vel_sigma"):
        quatnav.NavFilter13(gps_vel_sigma=-1.0)
    with pytest.raises(ValueError, match="ukf_alpha"):
        quatnav.NavFilter13(time_update="ukf", ukf_alpha=1.0, ukf_kappa=-12.0)
    flt = quatnav.NavFilter13()
    with pytest.raises(ValueError, match="not initialized"):
        flt.predict([0, 0, 0], [0, 0, -9.8], 0.01)
    rng = np.random.default_rng(6)
    flt.reset(*_start(rng), lat=LAT, lon=LON, h=H)
    before = flt.get_state()
    t, f, w = _imu(rng, 10)
    f[3, 1] = np.nan
    with pytest.raises(ValueError, match=r"acc: non-finite value in row 3"):
        flt.run(w, f, t=t)
    with pytest.raises(ValueError, match=r"acc: expected 10 rows"):
        flt.run(w, w[:5], t=t)
    with pytest.raises(ValueError, match=r"gps_vel.value: non-finite value in row 1"):
        flt.run(w, w, t=t, gps_vel=quatnav.Aid(t[:2], [[1, 2, 3], [np.inf, 0, 0]]))
    with pytest.raises(ValueError, match=r"gps_vel.t: times must be non-decreasing"):
        flt.run(w, w, t=t, gps_vel=quatnav.Aid(t[[3, 1]], [[1, 2, 3], [1, 2, 3]]))
    with pytest.raises(ValueError, match=r"yaw.value: expected 2 rows"):
        flt.run(w, w, t=t, yaw=quatnav.Aid(t[:2], [0.1]))
    with pytest.raises(TypeError, match=r"gps_vel: expected quatnav.Aid"):
        flt.run(w, w, t=t, gps_vel=(t[:2], [[1, 2, 3], [1, 2, 3]]))
    with pytest.raises(ValueError, match="dt"):
        flt.predict([0, 0, 0], [0, 0, -9.8], 0.0)
    with pytest.raises(ValueError, match="yaw"):
        flt.update_yaw(np.nan)
    with pytest.raises(ValueError, match="state"):
        flt.set_state({"v_n": [0, 0, 0]})
    after = flt.get_state()
    for k in before:
        np.testing.assert_array_equal(before[k], after[k])


def test_yaw_innovation_wraps():
    flt = quatnav.NavFilter13()
    q = Q.from_euler([0.0, 0.0, np.radians(179.0)])
    flt.reset([0, 0, 0], q, lat=LAT, lon=LON, h=H)
    r = flt.update_yaw(np.radians(-179.0))
    assert r.innovation[0] == pytest.approx(np.radians(2.0), abs=1e-9)


def test_time_update_cost_helper_reports_all_policies():
    d = quatnav._core.nav13_time_update_cost_ns(repeats=3, iterations=50)
    assert set(POLICIES) <= set(d) and all(d[k] > 0 for k in POLICIES)


def test_experiment_cli_writes_table_and_claims(tmp_path):
    """``quatnav experiment nav13`` on one run: the JSON holds every policy's RMSE per window, the
    cost of each time update and the evaluated claims; the figure is written."""
    pytest.importorskip("quatnav.sim")
    pytest.importorskip("matplotlib")
    from quatnav import cli
    out, png = tmp_path / "nav13.json", tmp_path / "nav13.png"
    assert cli.main(["experiment", "nav13", "--runs", "1", "--cost-repeats", "3", "--json", str(out),
                     "--plot", str(png)]) == 0
    import json
    d = json.loads(out.read_text())
    assert d["runs"] == 1 and png.stat().st_size > 10_000
    for tu in POLICIES:
        s = d["policies"][tu]
        assert s["time_update_ns"] > 0
        for w in ("0-100s", "100-200s", "0-5s"):
            assert set(s[w]) >= {"roll_deg", "pitch_deg", "yaw_deg", "gyro_bias_x_deg_h", "gyro_bias_y_deg_h",
                                 "gyro_bias_z_deg_h"}
        # The filter converges: the attitude error after the turn is far below the initial 10-20 deg.
        assert s["100-200s"]["attitude_deg"] < 1.0 < s["0-5s"]["attitude_deg"]
    assert set(d["claims"]) == {"before_100s_attitude_ukf_lt_second_order_lt_ekf", "after_100s_second_order_best_yaw",
                                "after_100s_second_order_best_gyro_bias_z", "second_order_cheaper_than_ukf"}


@pytest.mark.parametrize("tu", POLICIES)
def test_chunks_with_the_whole_aid_record_equal_one_run(tu):
    """A stream run in chunks, every chunk given the whole aid record (as a reader that does not
    slice the aids would): each measurement is applied once, in the chunk whose samples reach its
    time, and the chunks give the single run bit for bit. The chunks start on measurement times
    (where a measurement could be applied twice); one fix lies before the start (never applied)
    and one at it (applied by the first run, which starts from reset). Times on a 1/128 s grid,
    so that every chunk's first step equals the single run's."""
    rng = np.random.default_rng(8)
    n = 400
    t, f, w = _imu(rng, n)
    t = np.arange(1, n + 1) / 128.0
    vel_t = np.concatenate([[-1.0, 0.0], t[9::10]])  # before and at the start, then every 10th sample
    aids = dict(gps_vel=quatnav.Aid(vel_t, rng.normal(size=(len(vel_t), 3)) * 0.05 + [1.7, 1.0, 0.05]),
                yaw=quatnav.Aid(t[4::10], np.full(len(t[4::10]), np.radians(50.0))))
    start = _start(rng)

    def fresh():
        flt = quatnav.NavFilter13(time_update=tu)
        flt.reset(*start, lat=LAT, lon=LON, h=H)
        return flt

    whole = fresh().run(w, f, t=t, **aids)
    chunked, parts = fresh(), []
    with warnings.catch_warnings():
        warnings.simplefilter("error", quatnav.AidWarning)  # the record overlaps every chunk: quiet
        for a, b in ((0, 100), (100, 250), (250, n)):
            parts.append(chunked.run(w[a:b], f[a:b], t=t[a:b], **aids))
    np.testing.assert_array_equal(np.concatenate([p.x for p in parts]), whole.x)
    status = whole.aids["gps_vel"].status_names
    assert status[0] == "not_initialized" and (status[1:] == "ok").all()
    for name in ("gps_vel", "yaw"):
        # Every measurement applied in exactly one chunk, with the single run's innovation.
        applied = np.array([p.aids[name].status_names != "not_initialized" for p in parts])
        np.testing.assert_array_equal(applied.sum(axis=0), whole.aids[name].status_names != "not_initialized")
        innov = np.where(applied[..., None], np.stack([np.asarray(p.aids[name].innovation).reshape(
            len(applied[0]), -1) for p in parts]), 0.0).sum(axis=0)
        ref = np.nan_to_num(np.asarray(whole.aids[name].innovation).reshape(len(applied[0]), -1))
        np.testing.assert_array_equal(innov, ref)
    # The numpy twin follows the same rule, chunk by chunk.
    twin, tparts = R.NavFilter13(tu), []
    twin.reset(*start, LAT, LON, H)
    for a, b in ((0, 100), (100, 250), (250, n)):
        tparts.append(twin.run(w[a:b], f[a:b], t=t[a:b], **aids))
    np.testing.assert_allclose(np.concatenate([p.x for p in tparts]), whole.x, rtol=0, atol=1e-10)
    for p, q in zip(parts, tparts):
        for name in ("gps_vel", "yaw"):
            np.testing.assert_array_equal(q.aids[name].status, p.aids[name].status_names)
