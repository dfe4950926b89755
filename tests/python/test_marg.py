"""Paper 001 MargFilter: C++ against the numpy reference step by step, the Gauss-Newton
Jacobian against finite differences, convergence on static data, the stationary error against
its prediction (chi-square), the GPS correction on the constant-turn scenario, bad input."""
import numpy as np
import pytest
from scipy import stats

import quatnav
from quatnav.core import quaternion as Q
from quatnav.reference import MargFilter as RefMarg
from quatnav.reference import marg as refm

G0 = 9.80665
MAG_N = np.array([0.6, 0.0, 0.8])


def _synthetic(n=600, seed=0, rate=100.0):
    """A rotating, accelerating body with exact sensors plus noise, and GPS velocity at 20 Hz."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    t = np.arange(n) * dt
    w = np.column_stack([0.3 * np.sin(0.7 * t), 0.2 * np.cos(0.5 * t), 0.25 + 0.0 * t])
    q = np.empty((n, 4))
    q[0] = Q.from_euler([0.05, -0.04, 0.3])
    for k in range(1, n):
        q[k] = Q.mul(q[k - 1], Q.from_rotvec(w[k] * dt))
    a_n = np.column_stack([1.5 * np.sin(0.4 * t), 1.0 * np.cos(0.3 * t), 0.0 * t])
    f_b = Q.rotate_inv(q, a_n - [0, 0, G0])
    acc = f_b + 0.05 * rng.standard_normal((n, 3))
    gyr = w + 0.002 * rng.standard_normal((n, 3)) + [0.01, -0.005, 0.003]
    mag = 50.0 * Q.rotate_inv(q, np.broadcast_to(MAG_N, (n, 3))) + 0.2 * rng.standard_normal((n, 3))
    mag[3::7] = np.nan  # magnetometer missing on some samples: 6D update there
    v_n = np.cumsum(a_n, axis=0) * dt
    gps_idx = np.arange(3, n, 5)
    return dict(t=t, dt=dt, gyr=gyr, acc=acc, mag=mag, q=q, gps_t=t[gps_idx] - 0.002,
                gps_vel_n=v_n[gps_idx] + 0.01 * rng.standard_normal((len(gps_idx), 3)))


PARAMS = dict(gain=2.0, bias_gain=0.05, lever_arm_b=(0.4, -0.2, -0.3), gps_acc_tau=0.1, declination=0.0)


def test_jacobian_matches_finite_differences():
    rng = np.random.default_rng(1)
    for _ in range(20):
        q, r = rng.standard_normal(4), rng.standard_normal(3)
        X = refm.jacobian(q, r)
        h = 1e-6
        fd = np.column_stack([(refm.h(q + h * e, r) - refm.h(q - h * e, r)) / (2 * h) for e in np.eye(4)])
        np.testing.assert_allclose(X, fd, atol=1e-8 * (1 + np.abs(fd).max()))
    # eq. (2) is R^{n->b}: for a unit quaternion, h is the inverse rotation.
    qn = Q.normalize(q)
    np.testing.assert_allclose(refm.h(qn, r), Q.rotate_inv(qn, r), atol=1e-14)


def test_gauss_newton_converges_on_static_data():
    q_true = Q.from_euler([0.4, -0.3, 2.0])
    refs = [MAG_N, np.array([0.0, 0.0, -1.0])]
    meas = [Q.rotate_inv(q_true, r) for r in refs]
    q0 = Q.mul(q_true, Q.from_rotvec([0.3, -0.25, 0.3]))
    status, q, iters, conv = refm.gauss_newton(q0, meas, refs, 20, 1e-12)
    assert status == "ok" and conv and iters <= 7
    assert Q.angle_between(Q.normalize(q), q_true) < 1e-10
    # Quadratic convergence: each error far below the previous one.
    errs = []
    for it in range(1, 5):
        _, qi, _, _ = refm.gauss_newton(q0, meas, refs, it, 1e-15)
        errs.append(Q.angle_between(Q.normalize(qi), q_true))
    assert errs[1] < 0.1 * errs[0] and errs[2] < 0.1 * errs[1]


@pytest.mark.parametrize("with_mag", [True, False])
def test_cpp_matches_reference_step_by_step(with_mag):
    d = _synthetic()
    params = dict(PARAMS, declination=0.15)  # exercises the true -> magnetic NED rotation
    cpp = quatnav.MargFilter(**params)
    ref = RefMarg(**params)
    cpp.initialize(d["acc"][0], d["mag"][0] if with_mag else None)
    ref.initialize(d["acc"][0], d["mag"][0] if with_mag else None)
    j = 0
    for k in range(1, len(d["t"])):
        while j < len(d["gps_t"]) and d["gps_t"][j] <= d["t"][k]:
            assert cpp.update_gps_velocity(d["gps_vel_n"][j], d["gps_t"][j]) == \
                ref.update_gps_velocity(d["gps_vel_n"][j], d["gps_t"][j])
            j += 1
        assert cpp.predict(d["gyr"][k], d["dt"]) == ref.predict(d["gyr"][k], d["dt"]) == "ok"
        m = d["mag"][k]
        if with_mag and np.all(np.isfinite(m)):
            rc, rr = cpp.update_acc_mag(d["acc"][k], m), ref.update_acc_mag(d["acc"][k], m)
        else:
            rc, rr = cpp.update_acc(d["acc"][k]), ref.update_acc(d["acc"][k])
        assert rc.status == rr.status == "ok"
        assert rc.iterations == rr.iterations and rc.converged == rr.converged
        assert rc.gps_corrected == rr.gps_corrected
        assert abs(rc.residual - rr.residual) < 1e-9
        np.testing.assert_allclose(rc.correction, rr.correction, atol=1e-9)
        np.testing.assert_allclose(cpp.quat, ref.quat, atol=1e-9)
        np.testing.assert_allclose(cpp.bias, ref.bias, atol=1e-9)
    assert j > 100 and rc.gps_corrected
    # The batch run is the same loop.
    out = quatnav.MargFilter(**params).run(d["gyr"], d["acc"], d["mag"] if with_mag else None, t=d["t"],
                                           gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"]))
    ref_out = RefMarg(**params).run(d["gyr"], d["acc"], d["mag"] if with_mag else None, t=d["t"],
                                    gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"]))
    np.testing.assert_allclose(out.quat, ref_out.quat, atol=1e-9)
    np.testing.assert_allclose(out.bias, ref_out.bias, atol=1e-9)
    assert out.flag("gps_corrected")[-1] and out.flag("initialized")[0]
    assert np.all(np.isnan(out.gps_acc_n[~out.flag("gps_corrected")]))


def test_tracks_attitude_with_correction_and_float32_close():
    d = _synthetic(n=3000, seed=2)
    kw = dict(t=d["t"], gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"]))
    with_gps = quatnav.MargFilter(**PARAMS).run(d["gyr"], d["acc"], d["mag"], **kw)
    without = quatnav.MargFilter(**PARAMS).run(d["gyr"], d["acc"], d["mag"], t=d["t"])
    f32 = quatnav.MargFilter(dtype=np.float32, **PARAMS).run(d["gyr"], d["acc"], d["mag"], **kw)
    err_with = Q.angle_between(with_gps.quat, d["q"])[1000:]
    err_without = Q.angle_between(without.quat, d["q"])[1000:]
    # The body accelerates by up to 1.8 m/s^2 (~10 deg of apparent tilt); with the GPS
    # acceleration removed the error is a fraction of that.
    assert np.sqrt(np.mean(err_with**2)) < 0.3 * np.sqrt(np.mean(err_without**2))
    assert np.max(Q.angle_between(f32.quat.astype(float), with_gps.quat)) < 1e-3


def test_split_run_and_state_round_trip():
    d = _synthetic(n=800, seed=3, rate=64.0)  # exact times: the split sees the same steps
    full = quatnav.MargFilter(**PARAMS).run(d["gyr"], d["acc"], d["mag"], t=d["t"],
                                            gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"]))
    h = 377
    gsplit = np.searchsorted(d["gps_t"], d["t"][h - 1], side="right")
    a = quatnav.MargFilter(**PARAMS)
    first = a.run(d["gyr"][:h], d["acc"][:h], d["mag"][:h], t=d["t"][:h],
                  gps_vel=quatnav.Aid(d["gps_t"][:gsplit], d["gps_vel_n"][:gsplit]))
    b = quatnav.MargFilter(**PARAMS)
    b.set_state(a.get_state())
    second = b.run(d["gyr"][h:], d["acc"][h:], d["mag"][h:], t=d["t"][h:],
                   gps_vel=quatnav.Aid(d["gps_t"][gsplit:], d["gps_vel_n"][gsplit:]))
    np.testing.assert_array_equal(np.vstack([first.quat, second.quat]), full.quat)
    s = a.get_state()
    assert set(s) >= {"q_nb", "gyro_bias", "gps_acc_n", "gps_fixes", "time_since_gps"}
    bad = dict(s, q_nb=2 * s["q_nb"])
    with pytest.raises(ValueError, match="state"):
        b.set_state(bad)


def test_stationary_error_matches_prediction():
    """Static, level, 6D: the blend of eq. (6) makes the tilt error a first-order low-pass of
    the Gauss-Newton tilt (white, var sigma_a^2/g^2) driven also by gyro noise. Its stationary
    variance is V = ((1-a)^2 s_g^2 T^2 + a^2 s_z^2) / (1 - (1-a)^2), a = 1 - exp(-k T).
    The sample variance over nearly independent samples must pass a chi-square test."""
    rate, k_gain, s_a, s_g = 100.0, 5.0, 0.3, 0.01
    T = 1 / rate
    n = 200_000
    rng = np.random.default_rng(11)
    acc = np.array([0.0, 0.0, -G0]) + s_a * rng.standard_normal((n, 3))
    gyr = s_g * rng.standard_normal((n, 3))
    res = quatnav.MargFilter(paper=True, gain=k_gain, gn_max_iter=5, gn_tol=1e-12).run(gyr, acc, dt=T)
    a = 1 - np.exp(-k_gain * T)
    s_z = s_a / G0
    V = ((1 - a) ** 2 * s_g**2 * T**2 + a**2 * s_z**2) / (1 - (1 - a) ** 2)
    # Truth is level (heading free in 6D mode): roll and pitch are the tilt errors.
    tilt = Q.to_euler(res.quat)[:, :2]
    step = int(5 * rate / k_gain)  # five time constants apart: correlation e^-5
    samples = tilt[1000::step]
    m = samples.shape[0]
    for axis in range(2):
        x = samples[:, axis]
        chi = (m - 1) * np.var(x, ddof=1) / V
        assert stats.chi2.ppf(0.0005, m - 1) < chi < stats.chi2.ppf(0.9995, m - 1), (axis, chi / (m - 1))
        assert abs(np.mean(x)) < 4 * np.sqrt(V / m)


def test_constant_turn_correction_gains():
    """paper001_constant_turn: the GPS correction reduces the roll/pitch error of the turn."""
    sim = pytest.importorskip("quatnav.sim")
    from quatnav.experiments import marg_turn
    s = sim.make_scenario("paper001_constant_turn", seed=5)
    out = marg_turn.run_seed(s)
    assert out["rmse_deg"]["corrected"]["turn"] < 0.3 * out["rmse_deg"]["uncorrected"]["turn"]
    assert out["rmse_deg"]["uncorrected"]["turn"] > 1.0
    # The filter's frame is magnetic NED: the GPS acceleration must be rotated by the
    # declination (-8.5 deg here), or the turn acceleration is misplaced along track.
    assert out["rmse_deg"]["corrected"]["pitch_turn"] < 0.7 * out["rmse_deg"]["corrected_no_declination"]["pitch_turn"]
    # With exact sensors the lever-arm terms of eq. (7') remove what is left of the error.
    dg = marg_turn.diagnose_lever_arm(s, gps_taus=(0.05,))
    assert dg["exact"]["with_lever"] < 0.2 * dg["exact"]["without_lever"]


def test_bad_input_names_argument_and_row():
    d = _synthetic(n=50)
    f = quatnav.MargFilter()
    kw = dict(t=d["t"], gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"]))
    acc = d["acc"].copy()
    acc[7] = np.nan
    with pytest.raises(ValueError, match=r"acc: non-finite value in row 7"):
        f.run(d["gyr"], acc, **kw)
    acc[7] = 0
    with pytest.raises(ValueError, match=r"acc: zero-norm vector in row 7"):
        f.run(d["gyr"], acc, **kw)
    with pytest.raises(ValueError, match=r"gps_vel.t: times must be strictly increasing \(duplicate\); row 3"):
        gt = d["gps_t"].copy()
        gt[3] = gt[2]
        f.run(d["gyr"], d["acc"], t=d["t"], gps_vel=quatnav.Aid(gt, d["gps_vel_n"]))
    with pytest.raises(ValueError, match=r"gps_vel.value: non-finite value in row 2"):
        gv = d["gps_vel_n"].copy()
        gv[2, 1] = np.inf
        f.run(d["gyr"], d["acc"], t=d["t"], gps_vel=quatnav.Aid(d["gps_t"], gv))
    with pytest.raises(ValueError, match=r"gps_vel.value: expected .* rows"):
        f.run(d["gyr"], d["acc"], t=d["t"], gps_vel=quatnav.Aid(d["gps_t"][:-1], d["gps_vel_n"]))
    with pytest.raises(TypeError, match=r"gps_vel: expected quatnav.Aid"):
        f.run(d["gyr"], d["acc"], t=d["t"], gps_vel=d["gps_vel_n"])
    with pytest.raises(ValueError, match=r"gps_vel.sigma: this filter takes no per-sample sigma"):
        f.run(d["gyr"], d["acc"], t=d["t"], gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"], np.ones_like(d["gps_vel_n"])))
    with pytest.raises(ValueError, match=r"gyr: expected shape \(N, 3\)"):
        f.run(d["gyr"][:, :2], d["acc"], **kw)
    with pytest.raises(ValueError, match="dt: expected positive finite steps; row 4"):
        dt = np.full(50, 0.01)
        dt[4] = -1
        f.run(d["gyr"], d["acc"], dt=dt)
    with pytest.raises(TypeError, match="unknown parameter 'gian'"):
        quatnav.MargFilter(gian=1.0)
    with pytest.raises(ValueError, match="gain"):
        quatnav.MargFilter(gain=-1.0)
    with pytest.raises(ValueError, match="gn_max_iter"):
        quatnav.MargFilter(gn_max_iter=0)
    with pytest.raises(ValueError, match="lever_arm_b"):
        quatnav.MargFilter(lever_arm_b=[0, np.nan, 0])
    with pytest.raises(ValueError, match="not initialized"):
        quatnav.MargFilter().predict([0, 0, 0], 0.01)
    g = quatnav.MargFilter()
    g.initialize([0, 0, -G0], [20, 0, 40])
    g.update_gps_velocity([1, 0, 0], 1.0)
    before = g.get_state()
    with pytest.raises(ValueError, match="t: .* does not follow"):
        g.update_gps_velocity([1, 0, 0], 0.5)
    with pytest.raises(ValueError, match="mag: zero-norm"):
        g.update_acc_mag([0, 0, -G0], [0, 0, 0])
    with pytest.raises(ValueError, match="acc: non-finite"):
        g.update_acc([np.nan, 0, -G0])
    after = g.get_state()
    for k, v in before.items():
        np.testing.assert_array_equal(after[k], v)
    # on_invalid="skip": the bad row is skipped and reported, the run continues.
    acc[7] = np.nan
    out = f.run(d["gyr"], acc, t=d["t"], on_invalid="skip")
    assert list(out.skipped_rows["acc_skipped"]) == [7]
    assert np.all(np.isfinite(out.quat))
