"""The one API of the five filters, tested once for all: run(gyr, acc, mag=None, *, t, dt, <aids>,
on_invalid), keyword-only constructors from one parameter table, one result base class with
flag decoding, per-aid diagnostics, to_dataframe and a short repr, and run continuing from the
filter's state."""
import inspect
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import quatnav
from quatnav import Aid, reference
from quatnav.filters._base import core
from quatnav.filters.tables import FLAG_TABLES, PARAM_TABLES, STATUS_NAMES
from quatnav.sim.scenarios import make_scenario

NAMES = ("QuaternionEKF", "EulerEKF", "MargFilter", "NavFilter13", "GpsInsFilter")
REPO = Path(__file__).resolve().parents[2]
# the folder holding the quatnav this test session imported (installed, or the source tree with
# its compiled module): subprocesses must see the same package
PACKAGE_DIR = str(Path(quatnav.__file__).resolve().parents[1])


@pytest.fixture(scope="module")
def scn():
    return make_scenario("paper004_static", seed=0, duration=12.0)


def _log(name, s):
    """(new filter, gyr, acc, t, aid keywords, expected aid diagnostics) for one filter."""
    imu, g = s.imu, s.gps
    llh = np.column_stack([g.lat, g.lon, g.h])
    if name == "NavFilter13":
        tr = s.truth

        def make(**kw):
            f = quatnav.NavFilter13(**kw)
            f.reset(tr.v_n[0], tr.q_nb[0], lat=tr.lat[0], lon=tr.lon[0], h=tr.h[0])
            return f
        aids = dict(gps_vel=Aid(g.t_valid, g.v_n), yaw=Aid(s.compass.t, s.compass.yaw))
        return make, imu.gyro[1:], imu.accel[1:], imu.t[1:], aids, {"gps_vel", "yaw"}
    cls = getattr(quatnav, name)
    if name == "GpsInsFilter":
        aids = dict(gps_pos=Aid(g.t_valid, llh), gps_vel=Aid(g.t_valid, g.v_n), baro=Aid(s.baro.t, s.baro.h),
                    compass=Aid(s.compass.t, s.compass.yaw))
        # at rest: the zero-velocity and zero-rate updates too
        return cls, imu.gyro, imu.accel, imu.t, aids, {"gps_pos", "gps_vel", "baro", "baro_vd", "compass", "zupt", "zaru"}
    if name == "MargFilter":
        return cls, imu.gyro, imu.accel, imu.t, dict(gps_vel=Aid(g.t_valid, g.v_n)), set()
    return cls, imu.gyro, imu.accel, imu.t, {}, set()


def _cls(name):
    return getattr(quatnav, name)


@pytest.mark.parametrize("name", NAMES)
def test_run_signature_has_one_shape(name):
    sig = inspect.signature(_cls(name).run)
    ps = list(sig.parameters.values())[1:]
    assert [p.name for p in ps[:2]] == ["gyr", "acc"]
    assert all(p.kind == p.POSITIONAL_OR_KEYWORD for p in ps[:2])
    rest = [p for p in ps[2:] if p.kind != p.KEYWORD_ONLY]
    assert [p.name for p in rest] == ["mag"] and rest[0].default is None  # None where there is none
    kw = {p.name: p for p in ps if p.kind == p.KEYWORD_ONLY}
    assert {"t", "dt", "on_invalid"} <= set(kw)
    assert kw["t"].default is None and kw["dt"].default is None and kw["on_invalid"].default == "raise"


@pytest.mark.parametrize("name", NAMES)
def test_t_and_dt_are_exclusive(name, scn):
    make, gyr, acc, t, _, _ = _log(name, scn)
    with pytest.raises(ValueError, match="dt, t"):
        make().run(gyr[:50], acc[:50], t=t[:50], dt=0.02)
    with pytest.raises(ValueError, match="dt, t"):
        make().run(gyr[:50], acc[:50])


@pytest.mark.parametrize("name", NAMES)
def test_old_argument_orders_are_refused(name, scn):
    make, gyr, acc, t, _, _ = _log(name, scn)
    with pytest.raises(TypeError, match="gyr"):  # GpsInsFilter's old order: times first
        make().run(t, gyr, acc)
    with pytest.raises(TypeError, match="gyr"):  # NavFilter13's old order: specific force first
        make().run(acc, gyr, t=t)
    with pytest.raises(TypeError):  # times are keywords only
        make().run(gyr, acc, None, t)
    with pytest.raises(TypeError, match="gps_t"):  # old aid keywords are not accepted
        make().run(gyr, acc, t=t, gps_t=t[::10])


@pytest.mark.parametrize("name", NAMES)
def test_swapped_imu_is_refused_on_a_long_log(name, scn):
    """The swap test reads a sample of the rows on a long log: a gyro in the accelerometer's place
    is refused all the same, and a log whose gyro reads gravity-sized on a few rows only runs."""
    make, gyr, acc, t, _, _ = _log(name, scn)
    reps = -(-60_000 // len(t))
    g, a = np.tile(gyr, (reps, 1)), np.tile(acc, (reps, 1))
    assert len(g) > 4096 * 10
    with pytest.raises(TypeError, match=r"gyr: median norm .* looks like specific force"):
        make().run(a, g, dt=0.01)
    from quatnav.filters._base import check_swapped
    spikes = g.copy()
    spikes[::7] = [9.8, 0.0, 0.0]  # one row in seven: the median stays that of a rate
    check_swapped(spikes, a)


@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_zero_norm_rows_are_found_as_by_the_norms(dtype):
    """The compiled zero-norm test of the batch inputs equals the norms' test on rows of zeros,
    tiny and huge values, NaN and infinity; non-contiguous arrays take the numpy path."""
    from quatnav import _validate as V
    rng = np.random.default_rng(7)
    tiny = np.finfo(dtype).tiny
    specials = np.array([[0, 0, 0], [tiny, 0, 0], [0, -tiny, 0], [np.nan, np.nan, np.nan], [np.nan, 0, 0],
                         [np.inf, 0, 0], [0, 0, 1e-30], [np.finfo(dtype).max, 0, 0], [1, 0, 0]], dtype=dtype)
    for trial in range(200):
        a = rng.normal(size=(rng.integers(1, 40), 3)).astype(dtype)
        k = rng.integers(0, 4)
        rows = rng.integers(0, len(a), k)
        a[rows] = specials[rng.integers(0, len(specials), k)]
        with np.errstate(invalid="ignore", over="ignore", under="ignore"):
            n = np.sqrt(np.einsum("ij,ij->i", a, a))
        bad = np.flatnonzero(n <= tiny ** 0.5)
        want = int(bad[0]) if bad.size else -1
        assert core().first_zero_norm_row(a) == want, (trial, a)
        for arr in (a, np.asfortranarray(a)):
            if want < 0:
                V.nonzero_rows(arr, "acc")
            else:
                with pytest.raises(ValueError, match=rf"^acc: zero-norm vector in row {want}$"):
                    V.nonzero_rows(arr, "acc")


@pytest.mark.parametrize("name", NAMES)
def test_result_fields_flags_aids_dataframe_and_repr(name, scn):
    make, gyr, acc, t, aids, expected_aids = _log(name, scn)
    r = make().run(gyr, acc, t=t, **aids)
    n = len(t)
    assert isinstance(r, quatnav.FilterResult) and r.filter == name and len(r) == n
    np.testing.assert_array_equal(r.t, t)
    assert r.quat.shape == (n, 4) and r.bias.shape == (n, 3) and r.euler.shape == (n, 3)
    assert r.flags.shape == (n,) and r.flags.dtype == np.uint32
    if name == "MargFilter":
        assert r.sigma is None
    else:
        assert r.sigma.shape == (n, len(r.sigma_names)) and len(r.sigma_names) >= 6
    if name in ("NavFilter13", "GpsInsFilter"):
        assert isinstance(r, quatnav.NavResult)
        assert r.velocity.shape == (n, 3) and r.acc_bias.shape == (n, 3)
    if name == "GpsInsFilter":
        assert r.position.shape == (n, 3) and r.lat.shape == (n,) and r.h.shape == (n,)
    assert set(r.aids) == expected_aids
    for key, a in r.aids.items():
        k = len(a.t)
        assert k > 0 and a.innovation.shape[0] == k and a.innovation.ndim == 2
        assert a.nis.shape == (k,) and a.status.shape == (k,) and a.status.dtype == np.uint8
        assert set(a.status_names) <= set(STATUS_NAMES) and a.accepted.any(), (key, a.counts())
        assert np.isfinite(a.nis[a.accepted]).all()
        assert len(a.to_dataframe()) == k
    # Flags: every name of the filter's table decodes; an unknown one lists the known ones.
    table = FLAG_TABLES[name]
    assert r.FLAGS is table
    for flag, bit in table.items():
        np.testing.assert_array_equal(r.flag(flag), (r.flags & bit) != 0)
    assert set(r.flags_seen()) <= set(table) and r.flags_seen()
    with pytest.raises(KeyError, match="known: " + ", ".join(list(table)[:2])):
        r.flag("no_such_flag")
    df = r.to_dataframe()
    assert len(df) == n and df.index.name == "t"
    assert {"q_w", "q_x", "q_y", "q_z", "roll", "pitch", "yaw", "bias_x", "flags"} <= set(df.columns)
    if name in ("NavFilter13", "GpsInsFilter"):
        assert {"v_n", "v_e", "v_d", "acc_bias_z"} <= set(df.columns)
    np.testing.assert_array_equal(df["q_w"].to_numpy(), r.quat[:, 0])
    text = repr(r)
    assert len(text) < 400 and name in text and f"{n} samples" in text and "\n" not in text
    for key in expected_aids:
        assert key in text


def test_to_dataframe_without_pandas_names_the_extra(scn, monkeypatch):
    r = quatnav.QuaternionEKF().run(scn.imu.gyro[:20], scn.imu.accel[:20], t=scn.imu.t[:20])
    monkeypatch.setitem(sys.modules, "pandas", None)
    with pytest.raises(ImportError, match=r"pip install 'quatnav\[io\]'"):
        r.to_dataframe()


def _split_aids(aids, t_end, before):
    out = {}
    for k, a in aids.items():
        m = a.t <= t_end if before else a.t > t_end
        out[k] = Aid(a.t[m], np.asarray(a.value)[m])
    return out


@pytest.mark.parametrize("name", NAMES)
def test_run_continues_from_the_state(name, scn):
    """run() continues where the filter stands: two calls on one object give the one-call result
    (GpsInsFilter: the second log starts with the last sample of the first, which only fixes the
    clock); a new object starts afresh."""
    make, gyr, acc, t, aids, _ = _log(name, scn)
    t = t[0] + np.arange(len(t)) / 128.0  # exact steps: each part derives the same step lengths
    whole = make().run(gyr, acc, t=t, **aids)
    f = make()
    h = len(t) // 2
    a = f.run(gyr[:h], acc[:h], t=t[:h], **_split_aids(aids, t[h - 1], True))
    k0 = h - 1 if name == "GpsInsFilter" else h
    b = f.run(gyr[k0:], acc[k0:], t=t[k0:], **_split_aids(aids, t[h - 1], False))
    both = np.vstack([a.quat, b.quat[h - k0:]])
    np.testing.assert_array_equal(both, whole.quat)
    again = f.run(gyr[:h], acc[:h], t=t[-1] + np.arange(1, h + 1) / 128.0)
    fresh = make().run(gyr[:h], acc[:h], t=t[-1] + np.arange(1, h + 1) / 128.0)
    assert not np.array_equal(again.quat, fresh.quat, equal_nan=True)  # the same object carries its state on


@pytest.mark.parametrize("name", NAMES)
def test_constructor_signature_repr_and_unknown_names(name):
    cls = _cls(name)
    table = PARAM_TABLES[name]
    assert cls.PARAMS is table
    sig = inspect.signature(cls)
    names = [p.name for p in table] + ["dtype"]
    assert list(sig.parameters) == names
    assert all(p.kind == p.KEYWORD_ONLY for p in sig.parameters.values())
    for p in table:
        d = sig.parameters[p.name].default
        assert d == p.default or np.array_equal(d, p.default), p.name
        assert p.name in cls.__doc__, p.name  # the docstring's Parameters section
    assert repr(cls()) == f"{name}()"
    assert repr(cls(max_dt=0.5)) == f"{name}(max_dt=0.5)"
    assert repr(cls(max_dt=1.0, dtype=np.float32)) == f"{name}(dtype=np.float32)"  # 1.0 is the default
    with pytest.raises(TypeError, match=r"unknown parameter 'gyro_bias_rw'( \(did you mean [^)]*\))?; known: " + table[0].name):
        cls(gyro_bias_rw=1e-5)
    with pytest.raises(TypeError, match="keyword-only"):
        cls(0.01)
    # a misspelt name: the closest known ones are suggested, in the class and in its numpy twin
    typo = {"MargFilter": "gian", "GpsInsFilter": "lever_arm"}.get(name, "gyro_nosie")
    hint = {"MargFilter": "'gain'", "GpsInsFilter": "'lever_arm_b' or 'lever_arm_sigma'"}.get(name, "'gyro_noise'")
    for make in (cls, getattr(reference, name)):
        with pytest.raises(TypeError, match=rf"unknown parameter '{typo}' \(did you mean {hint}\?\); known: "):
            make(**{typo: 1.0})
    r = cls().run(np.zeros((2, 3)), np.tile([0.0, 0.0, -9.81], (2, 1)), dt=0.01) if name != "NavFilter13" else None
    if r is not None:
        with pytest.raises(KeyError, match=r"'at_rset': not a flag of .* \(did you mean 'at_rest'\?\); known: "):
            r.flag("at_rset")


@pytest.mark.parametrize("name", NAMES)
def test_table_defaults_equal_the_cpp_defaults(name):
    f = _cls(name)()
    for p in PARAM_TABLES[name]:
        v = f.params[p.name]
        if p.kind in ("vec3", "mat3"):
            np.testing.assert_array_equal(v, p.default)
        elif isinstance(p.default, float):
            assert v == pytest.approx(p.default, rel=1e-7), p.name
        else:
            assert v == p.default, p.name


#: Filter -> its C++ parameter struct and (one of) its C++ classes, as bound in quatnav._core.
_CORE_CLASSES = {"NavFilter13": ("NavFilter13Params", "NavFilter13Ekf"),
                 "QuaternionEKF": ("QuaternionEKFParams", "QuaternionEKF"),
                 "QuaternionEKF paper": ("QuaternionEKFParams", "QuaternionEKF"),
                 "EulerEKF": ("EulerEKFParams", "EulerEKF"),
                 "MargFilter": ("MargFilterParams", "MargFilter"),
                 "GpsInsFilter": ("GpsInsParams", "GpsInsFilter")}


@pytest.mark.parametrize("name", sorted(_CORE_CLASSES))
@pytest.mark.parametrize("suffix", ["_f64", "_f32"])
def test_parameters_are_declared_once_and_the_python_table_equals_it(name, suffix):
    """The C++ Params struct declares each field once (core/fields.hpp); the Python table holds
    the same name, default, unit and meaning for every field, and nothing under another name."""
    params, _ = _CORE_CLASSES[name]
    cpp = {n: (d, u, doc) for n, d, u, doc in getattr(core(), params + suffix).fields()}
    py = {p.name: p for p in PARAM_TABLES[name.split()[0]] if p.core_name is not None}
    assert all(p.core_name == p.name for p in py.values()), "one vocabulary: the C++ field has the Python name"
    assert sorted(py) == sorted(cpp)
    tol = 1e-7 if suffix == "_f32" else 0
    for n, (d, u, doc) in cpp.items():
        p = py[n]
        assert (u, doc) == (p.unit, p.doc), n
        if isinstance(p.default, tuple):
            np.testing.assert_array_equal(np.asarray(d), np.asarray(p.default))
        elif isinstance(p.default, float):
            assert d == pytest.approx(p.default, rel=tol, abs=0), n
        else:
            assert d == p.default, n


@pytest.mark.parametrize("name", sorted(_CORE_CLASSES))
def test_state_dict_round_trip_refuses_unknown_and_missing_keys(name):
    """get_state/set_state come from the State declaration: every field, exactly, and no other."""
    cls = getattr(core(), _CORE_CLASSES[name][1] + "_f64")
    f = cls(getattr(core(), _CORE_CLASSES[name][0] + "_f64")())
    s = f.get_state()
    assert [row[0] for row in cls.state_fields()] == list(s)
    assert f.set_state(s) == "ok"
    with pytest.raises(ValueError, match="unknown key 'bogus'"):
        f.set_state({**s, "bogus": 1.0})
    missing = next(iter(s))
    with pytest.raises(ValueError, match=f"missing key '{missing}'"):
        f.set_state({k: v for k, v in s.items() if k != missing})
    key = "P" if "P" in s else "q_nb"  # MargFilter has no covariance
    with pytest.raises(TypeError, match=f"{key}: expected an array of shape"):
        f.set_state({**s, key: np.zeros(2)})


def test_one_vocabulary_of_shared_parameter_names():
    """A parameter name means one thing with one unit in every filter that has it."""
    seen = {}
    for name, table in PARAM_TABLES.items():
        for p in table:
            if p.name in seen:
                assert p.unit == seen[p.name].unit, (name, p.name)
            seen[p.name] = p
    for old in ("gyro_bias_rw", "accel_noise", "accel_bias_rw", "accel_bias_noise", "init_bias_sigma", "vel_noise"):
        assert old not in seen
    from quatnav.reference import nav13 as ref_nav13
    assert set(ref_nav13.DEFAULTS) == {p.name for p in PARAM_TABLES["NavFilter13"] if p.core_name}
    from quatnav import reference
    for name, twin in (("QuaternionEKF", reference.QuaternionEKF), ("EulerEKF", reference.EulerEKF),
                       ("MargFilter", reference.MargFilter)):
        assert twin.defaults == {p.name: p.default for p in PARAM_TABLES[name] if p.core_name}, name
        with pytest.raises(TypeError, match="unknown parameter 'acc_noise'; known: "):
            twin(acc_noise=0.1)
    from quatnav.reference import gpsins as ref_gpsins
    assert set(ref_gpsins.DEFAULTS) == {p.name for p in PARAM_TABLES["GpsInsFilter"] if p.core_name}
    with pytest.raises(TypeError, match="unknown parameter 'accel_noise'"):
        ref_gpsins.GpsInsFilter(accel_noise=1e-3)


@pytest.mark.parametrize("name", ["QuaternionEKF", "EulerEKF", "MargFilter"])
def test_twins_run_like_the_public_classes(name):
    """The numpy twins' run has the public signature (IMU first, times and aids as keywords) and,
    given the same times, follows the C++ filter."""
    from quatnav import reference
    public, twin = getattr(quatnav, name), getattr(reference, name)

    def shape(f):
        return [(p.name, p.kind, p.default) for p in inspect.signature(f).parameters.values()
                if p.name not in ("self", "on_invalid", "observer")]  # observer: the twin smoother's hook

    assert shape(twin.run) == shape(public.run)
    from quatnav.demo import rotation_scenario
    d = rotation_scenario(n=300, seed=4)
    t = 10.0 + np.cumsum(np.full(300, d.dt))
    a = public().run(d.gyr, d.acc, d.mag, t=t)
    b = twin().run(d.gyr, d.acc, d.mag, t=t)
    np.testing.assert_allclose(b.t, a.t)
    np.testing.assert_allclose(b.quat, a.quat, atol=1e-9)
    with pytest.raises(ValueError, match="give exactly one"):
        twin().run(d.gyr, d.acc, t=t, dt=0.01)
    if "smooth" in inspect.signature(public.run).parameters:
        a = public().run(d.gyr, d.acc, d.mag, t=t, smooth=True)
        b = twin().run(d.gyr, d.acc, d.mag, t=t, smooth=True)
        np.testing.assert_allclose(b.forward.quat, a.forward.quat, atol=1e-9)
        assert np.abs(b.quat - b.forward.quat).max() > 1e-6  # the backward pass moved the estimates
        np.testing.assert_allclose(b.quat, a.quat, atol=1e-7)


def test_gpsins_twin_runs_like_the_public_class():
    """The GpsInsFilter twin's run and run_smoothed have the public run's signature (IMU first,
    times and aids as keywords, the aids as Aid); given the same times and aids it follows the
    C++ filter, and its smooth=True is run_smoothed."""
    from quatnav import reference
    from quatnav.reference.gpsins import run_smoothed

    def shape(f, drop=()):
        return [(p.name, p.kind, p.default) for p in inspect.signature(f).parameters.values()
                if p.name not in ("self", "f", "on_invalid", "observer") + drop]

    assert shape(reference.GpsInsFilter.run) == shape(quatnav.GpsInsFilter.run)
    assert shape(run_smoothed) == shape(quatnav.GpsInsFilter.run, drop=("smooth",))
    s, n = make_scenario("paper004_walk", seed=0), 1200
    lever = np.asarray(s.params["gps"]["lever_arm_b_m"], float)
    aids = dict(gps_pos=quatnav.Aid(s.gps.t_valid, np.column_stack([s.gps.lat, s.gps.lon, s.gps.h])),
                gps_vel=quatnav.Aid(s.gps.t_valid, s.gps.v_n), baro=quatnav.Aid(s.baro.t, s.baro.h),
                compass=quatnav.Aid(s.compass.t, s.compass.yaw), outages=[(15.0, 18.0)])
    a = quatnav.GpsInsFilter(lever_arm_b=lever).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **aids)
    b = reference.GpsInsFilter(lever_arm_b=lever).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], **aids)
    nav = a.navigating
    assert nav.sum() > 500
    np.testing.assert_allclose(b["t"], a.t)
    np.testing.assert_allclose(b["llh"][nav, :2], a.position[nav, :2], rtol=0, atol=1e-12)
    np.testing.assert_allclose(b["q_nb"][nav], a.quat[nav], rtol=0, atol=1e-9)
    np.testing.assert_array_equal(b["gps"]["decision"][:, 0], a.aids["gps_pos"].decision_names)
    assert (a.aids["gps_pos"].decision_names == "skipped").sum() > 0  # the outage
    with pytest.raises(ValueError, match="give exactly one"):
        reference.GpsInsFilter().run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], dt=0.01)
    with pytest.raises(ValueError, match="gps_vel: needs gps_pos"):
        reference.GpsInsFilter().run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], gps_vel=aids["gps_vel"])
    sm = reference.GpsInsFilter(lever_arm_b=lever).run(s.imu.gyro[:n], s.imu.accel[:n], t=s.imu.t[:n], smooth=True,
                                                       **aids)
    fwd, ref = run_smoothed(reference.GpsInsFilter(lever_arm_b=lever), s.imu.gyro[:n], s.imu.accel[:n],
                            t=s.imu.t[:n], **aids)
    np.testing.assert_array_equal(sm["llh"], ref["llh"])
    np.testing.assert_array_equal(sm["forward"]["llh"], fwd["llh"])
    np.testing.assert_array_equal(fwd["llh"], b["llh"])


@pytest.mark.parametrize("tu, n", [("ekf", 1000), ("second_order", 400), ("ukf", 150)])
def test_nav13_twin_runs_like_the_public_class(tu, n):
    """The NavFilter13 twin's run has the public run's signature (without on_invalid) and, on the
    first n samples of the paper-002 scenario from a perturbed start, with NIS gates that reject
    some yaw fixes and a saturated sample, follows the C++ batch run: the same state, covariance,
    flags and per-measurement results (every velocity and yaw fix lands on its IMU sample within
    the 1e-4 dt tolerance, the one at the start before the first predict), forward and smoothed.
    Measured differences: 3e-14 in x, 3e-12 of max |P| smoothed (double rounding of 150-1000
    steps); the bounds are 1e-10."""
    from quatnav import reference
    from quatnav.experiments import nav13 as X

    def shape(f):
        return [(p.name, p.kind, p.default) for p in inspect.signature(f).parameters.values()
                if p.name not in ("self", "on_invalid")]

    assert shape(reference.NavFilter13.run) == shape(quatnav.NavFilter13.run)
    s = make_scenario(X.SCENARIO, seed=3)
    start = X.initial_state(s, "gaussian", np.random.default_rng(1))
    kw = dict(acc_noise=X._density(s, "accel"), gyro_noise=X._density(s, "gyro"),
              gps_vel_sigma=s.params["gps"]["vel_sigma_m_s"], yaw_sigma=np.radians(s.params["compass"]["noise_deg"]),
              gate_gps_vel=16.0, gate_yaw=1.0, gyro_range=2.0)
    gyr, acc, t = s.imu.gyro[1:n + 1].copy(), s.imu.accel[1:n + 1], s.imu.t[1:n + 1]
    gyr[n // 2] = [0.0, 0.0, 3.0]  # saturated: the predict is skipped (the smoother's "same" link)
    aids = dict(gps_vel=Aid(s.gps.t_valid, s.gps.v_n), yaw=Aid(s.compass.t, s.compass.yaw))
    due = {k: int(np.sum(a.t <= t[-1] + 1e-4 * (t[1] - t[0]))) for k, a in aids.items()}  # later ones: never applied

    def both(**opts):
        a = quatnav.NavFilter13(time_update=tu, **kw)
        a.reset(*start, lat=s.truth.lat[0], lon=s.truth.lon[0], h=s.truth.h[0])
        b = reference.NavFilter13(tu, **kw)
        b.reset(*start, s.truth.lat[0], s.truth.lon[0], s.truth.h[0])
        return (a.run(gyr, acc, return_covariance=True, **aids, **opts),
                b.run(gyr, acc, return_covariance=True, **aids, **opts))

    for smooth in (False, True):
        a, b = both(t=t, smooth=smooth)
        np.testing.assert_allclose(b.t, a.t, rtol=0, atol=0)
        np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-10)
        np.testing.assert_allclose(b.P, a.P, rtol=0, atol=1e-10 * np.abs(a.P).max())
        np.testing.assert_allclose(b.sigma, a.sigma, rtol=1e-8, atol=1e-14)
        np.testing.assert_allclose(b.att_sigma, a.att_sigma, rtol=1e-8, atol=1e-14)
        np.testing.assert_array_equal(b.flags, a.flags)
        for name, m in due.items():
            ra, rb = a.aids[name], b.aids[name]
            np.testing.assert_array_equal(rb.status[:m], [STATUS_NAMES[c] for c in ra.status[:m]])
            np.testing.assert_allclose(rb.innovation[:m], ra.innovation[:m], rtol=0, atol=1e-10)
            np.testing.assert_allclose(rb.nis[:m], ra.nis[:m], rtol=1e-8, atol=1e-10)
            # Fixes after the last sample are never applied: NaN, status not_initialized, in both.
            assert len(ra.status) > m
            np.testing.assert_array_equal(ra.status_names[m:], rb.status[m:])
            assert (ra.status_names[m:] == "not_initialized").all()
            assert np.isnan(ra.innovation[m:]).all() and np.isnan(ra.nis[m:]).all()
        assert a.flag("saturated")[n // 2] and (b.aids["yaw"].status == "rejected").sum() > 0
        assert b.aids["gps_vel"].status[0] == "ok" and b.flags[0] & quatnav.NavFilter13.FLAGS["gps_vel_used"]
        if smooth:
            assert np.abs(b.x - b.forward.x)[: n // 2].max() > 1e-6  # the backward pass moved the estimates
            np.testing.assert_allclose(b.forward.x, a.forward.x, rtol=0, atol=1e-10)
    # Times as dt (t = cumsum(dt), as the public run reads them).
    a, b = both(dt=0.01)
    np.testing.assert_allclose(b.t, a.t, rtol=0, atol=1e-12)
    np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-10)
    f = reference.NavFilter13()
    with pytest.raises(ValueError, match="not initialized"):
        f.run(gyr, acc, t=t)
    f.reset(*start, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="give exactly one"):
        f.run(gyr, acc, t=t, dt=0.01)


@pytest.mark.parametrize("name", ["QuaternionEKF", "EulerEKF", "MargFilter"])
def test_twin_paper_values_equal_the_cpp_paper_parameters(name):
    """paper=True: the numpy twin's values are those of the C++ Params::paper()."""
    from quatnav import reference
    cpp = getattr(core(), _CORE_CLASSES[name][0] + "_f64").paper().to_dict()
    twin = vars(getattr(reference, name)(paper=True).p)
    assert set(cpp) == set(twin)
    for k, v in cpp.items():
        assert np.asarray(twin[k]) == pytest.approx(np.asarray(v), rel=1e-15), k
    public = getattr(quatnav, name)(paper=True).params
    for k, v in cpp.items():
        assert np.asarray(public[k]) == pytest.approx(np.asarray(v), rel=1e-7), k


def test_parameters_page_lists_every_parameter():
    text = (REPO / "docs" / "PARAMETERS.md").read_text()
    for name, table in PARAM_TABLES.items():
        assert f"`{name}`" in text
        for p in table:
            assert f"`{p.name}`" in text, (name, p.name)
    from quatnav.filters.tables import parameters_table_markdown
    assert parameters_table_markdown() in text  # regenerate the table from the tables when they change
    assert "PARAMETERS" in (REPO / "docs" / "index.md").read_text()


def test_aid_is_refused_in_other_forms(scn):
    make, gyr, acc, t, aids, _ = _log("GpsInsFilter", scn)
    with pytest.raises(TypeError, match=r"gps_pos: expected quatnav.Aid"):
        make().run(gyr, acc, t=t, gps_pos=(aids["gps_pos"].t, aids["gps_pos"].value))
    with pytest.raises(ValueError, match=r"baro.sigma: this filter takes no per-sample sigma"):
        make().run(gyr, acc, t=t, baro=Aid(scn.baro.t, scn.baro.h, np.ones(len(scn.baro.t))))


@pytest.mark.parametrize("name, options", [(n, {}) for n in NAMES] + [
    ("QuaternionEKF", {"paper": True}), ("NavFilter13", {"time_update": "ukf"}), ("GpsInsFilter", {"scale_factors": True})])
def test_n_states_is_the_size_of_the_covariance_and_of_sigma(name, options, scn):
    make, gyr, acc, t, aids, _ = _log(name, scn)
    f = make(**options)
    r = f.run(gyr, acc, t=t, **aids)
    if name == "MargFilter":  # no covariance: q and the gyro bias
        assert f.n_states == 7 and r.sigma is None
        return
    assert f.covariance.shape == (f.n_states, f.n_states)
    assert r.sigma.shape[1] == len(r.sigma_names) == f.n_states


@pytest.mark.parametrize("name", NAMES)
def test_initialized_says_whether_the_filter_has_a_state(name, scn):
    make, gyr, acc, t, aids, _ = _log(name, scn)
    f = make()
    assert f.initialized == (name == "NavFilter13")  # NavFilter13 starts from reset()
    r = f.run(gyr, acc, t=t, **aids)
    assert f.initialized
    if name != "NavFilter13":  # the sample where it happened
        assert r.flag("initialized").sum() == 1


@pytest.mark.parametrize("dtype", [np.float64, np.float32])
@pytest.mark.parametrize("name", NAMES)
def test_copy_deepcopy_and_pickle_give_an_independent_filter(name, dtype, scn):
    """A copy (copy.copy, copy.deepcopy, pickle) has the parameters and the state of the original
    and its own compiled filter: both continue alike, and running one leaves the other as it was."""
    import copy
    import pickle
    make, gyr, acc, t, _, _ = _log(name, scn)
    f = make(max_dt=0.5, dtype=dtype)
    h = len(t) // 2
    f.run(gyr[:h], acc[:h], t=t[:h])
    copies = [copy.copy(f), copy.deepcopy(f), pickle.loads(pickle.dumps(f))]
    for g in copies:
        assert type(g) is type(f) and repr(g) == repr(f) and g.dtype == f.dtype
    rest = f.run(gyr[h - 1:], acc[h - 1:], t=t[h - 1:])
    for g in copies:
        np.testing.assert_array_equal(g.run(gyr[h - 1:], acc[h - 1:], t=t[h - 1:]).quat, rest.quat)


@pytest.mark.parametrize("source, target, key", [
    (dict(paper=True), dict(), "P"), (dict(), dict(paper=True), "P"),
    (dict(scale_factors=True), dict(), "P"), (dict(), dict(scale_factors=True), "P")])
def test_set_state_of_another_configuration_is_named_as_such(source, target, key):
    cls = quatnav.GpsInsFilter if "scale_factors" in {**source, **target} else quatnav.QuaternionEKF
    dst = cls(**target)
    state = cls(**source).get_state()
    with pytest.raises(ValueError, match=rf"state: {key} has shape \(\d+, \d+\), {re.escape(repr(dst))} has "
                                         r"\(\d+, \d+\): a state of another filter or configuration"):
        dst.set_state(state)
    with pytest.raises(ValueError, match=r"state: missing keys \['euler'\] for EulerEKF\(\): a state of another"):
        quatnav.EulerEKF().set_state(quatnav.QuaternionEKF().get_state())


def test_euler_angles_and_latitudes_in_degrees_are_refused_with_a_hint():
    """EulerEKF.reset and GpsInsFilter.set_initial took euler=[0, 0, 90] as 90 rad (EulerEKF kept
    yaw = 90); GpsInsFilter.reset with llh in degrees and NavFilter13.set_position said only
    'rejected by the filter (invalid_argument)'."""
    hint = r"\(degrees\? use np\.radians"
    with pytest.raises(ValueError, match=rf"euler: yaw 90 is not an angle in rad {hint}\(\[0\.0, 0\.0, 90\.0\]\)\)"):
        quatnav.EulerEKF().reset([0.0, 0.0, 90.0])
    with pytest.raises(ValueError, match=rf"euler: roll -170 is not an angle in rad {hint}"):
        quatnav.GpsInsFilter().set_initial(euler=[-170.0, 0.0, 0.0])
    with pytest.raises(ValueError,
                       match=rf"llh: latitude: expected a finite angle in \[-1.571, 1.571\] rad, got 36.4 {hint}"):
        quatnav.GpsInsFilter().reset([1, 0, 0, 0], [0, 0, 0], [36.4, 127.3, 50.0])
    for call in (lambda f: f.reset([0, 0, 0], [1, 0, 0, 0], lat=36.4), lambda f: f.set_position(36.4, 127.3, 50.0)):
        with pytest.raises(ValueError, match=rf"lat: expected a finite angle in \[-1.5, 1.5\] rad, got 36.4 {hint}"):
            call(quatnav.NavFilter13())
    # radians, up to a full turn either way, are taken as they are
    f = quatnav.EulerEKF()
    f.reset([0.1, -0.2, 6.0])
    np.testing.assert_allclose(f.euler, [0.1, -0.2, 6.0])
    quatnav.GpsInsFilter().set_initial(euler=[0.0, 0.0, -3.5])


@pytest.mark.parametrize("name", NAMES)
def test_datetime_and_timedelta_times_are_refused_with_the_conversion(name, scn):
    """numpy counts timedelta64 as a number: a pandas TimedeltaIndex was taken as seconds in
    nanosecond ticks; datetime64 was refused without saying what to give."""
    make, gyr, acc, t, aids, _ = _log(name, scn)
    td = (t * 1e9).astype("timedelta64[ns]")
    for kw in ({"t": td}, {"t": np.datetime64("2025-08-28T17:30:00", "ns") + td},
               {"dt": np.timedelta64(20, "ms")}, {"dt": np.diff(td, prepend=td[0] - (td[1] - td[0]))}):
        key = next(iter(kw))
        with pytest.raises(TypeError, match=rf"{key}: values of dtype (timedelta|datetime)64\[.*\] are not accepted: "
                                            r"give seconds as floats, e\.g\. .*np\.timedelta64\(1, 's'\)"):
            make().run(gyr, acc, **kw)
    key, a = next(iter(aids.items()), (None, None))
    if key:
        with pytest.raises(TypeError, match=rf"{key}.t: values of dtype timedelta64"):
            make().run(gyr, acc, t=t, **{key: Aid((np.asarray(a.t) * 1e9).astype("timedelta64[ns]"), a.value)})


@pytest.mark.parametrize("name", ["NavFilter13", "GpsInsFilter"])
def test_one_column_aids_take_k_or_k_by_1_values(name, scn):
    """Aid(t, value) with value (K,) or (K, m): a one-column aid given as (K, 1) (a DataFrame's
    df[["h"]]) runs as the (K,) one."""
    make, gyr, acc, t, aids, _ = _log(name, scn)
    cols = {"NavFilter13": ("yaw",), "GpsInsFilter": ("baro", "compass")}[name]
    col = {k: (Aid(a.t, np.asarray(a.value)[:, None]) if k in cols else a) for k, a in aids.items()}
    a, b = make().run(gyr, acc, t=t, **aids), make().run(gyr, acc, t=t, **col)
    np.testing.assert_array_equal(a.quat, b.quat)
    for k in cols:
        np.testing.assert_array_equal(a.aids[k].nis, b.aids[k].nis)


@pytest.mark.parametrize("name", ["MargFilter", "NavFilter13", "GpsInsFilter"])
def test_a_length_mismatch_names_what_the_rows_should_match(name, scn):
    """An aid's values are counted against its own times, the IMU's against gyr (or t)."""
    make, gyr, acc, t, aids, _ = _log(name, scn)
    a = aids["gps_vel"] if name != "GpsInsFilter" else aids["gps_pos"]
    key = "gps_vel" if name != "GpsInsFilter" else "gps_pos"
    with pytest.raises(ValueError, match=rf"{key}.value: expected {len(a.t)} rows \(as many as {key}.t\), "
                                         rf"got {len(a.t) - 1}"):
        make().run(gyr, acc, t=t, **{**aids, key: Aid(a.t, np.asarray(a.value)[:-1])})
    with pytest.raises(ValueError, match=rf"acc: expected {len(t)} rows \(as many as (gyr|t)\)"):
        make().run(gyr, acc[:-1], t=t, **aids)
    if name == "GpsInsFilter":
        with pytest.raises(ValueError, match=rf"gyr: expected {len(t)} rows \(as many as t\), got {len(t) - 1}"):
            make().run(gyr[:-1], acc, t=t)


def test_compiled_module_loads_on_first_use():
    code = ("import sys, quatnav; assert 'quatnav._core' not in sys.modules, 'eager'; "
            "f = quatnav.QuaternionEKF(); assert 'quatnav._core' in sys.modules; print(quatnav.__version__)")
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env={"PYTHONPATH": PACKAGE_DIR, "PATH": ""})
    assert p.returncode == 0, p.stderr


def test_numpy_parts_import_without_the_compiled_module():
    """quatnav.core, quatnav.reference, quatnav.sim and quatnav.datasets work where quatnav._core
    cannot be imported (a meta-path blocker); a filter then fails with the import error."""
    code = """
import sys
class Block:
    def find_spec(self, name, path=None, target=None):
        if name == "quatnav._core":
            raise ImportError("blocked: no compiled module")
sys.meta_path.insert(0, Block())
import numpy as np
import quatnav, quatnav.core, quatnav.reference, quatnav.sim, quatnav.datasets
from quatnav.core import quaternion as Q, earth, strapdown
q = Q.from_euler([0.1, 0.2, 0.3]); assert abs(Q.to_euler(q)[2] - 0.3) < 1e-12
assert earth.radii(0.5)[0] > 6.3e6
s = quatnav.sim.make_scenario("paper004_static", seed=0, duration=3.0)
r = quatnav.reference.QuaternionEKF().run(s.imu.gyro[:50], s.imu.accel[:50], None, dt=0.01)
assert np.isfinite(r.quat).all()
assert "quatnav._core" not in sys.modules
try:
    quatnav.QuaternionEKF()
except ImportError as e:
    assert "blocked" in str(e)
else:
    raise SystemExit("the filter ran without its compiled module")
print("ok")
"""
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env={"PYTHONPATH": PACKAGE_DIR, "PATH": ""})
    assert p.returncode == 0 and p.stdout.strip() == "ok", p.stderr


def test_one_flag_table_and_status_list_equal_the_cpp_declarations():
    from quatnav.filters.tables import FLAGS
    core = quatnav._core
    rows = core.flag_table()
    assert {name: bit for name, bit, _ in rows} == FLAGS
    bits = [bit for _, bit, _ in rows]
    assert len(set(bits)) == len(bits) and all(b & (b - 1) == 0 for b in bits)  # unique single bits
    assert tuple(core.status_names()) == STATUS_NAMES
    for name, table in FLAG_TABLES.items():  # each filter sets a subset, with the table's bits
        assert all(FLAGS[f] == bit for f, bit in table.items()), name
    assert quatnav.Flag.acc_rejected == FLAGS["acc_rejected"] and quatnav.Status.rejected == STATUS_NAMES.index("rejected")
    assert set(quatnav.Flag(FLAGS["gps_pos_used"] | FLAGS["navigating"])) == {quatnav.Flag.gps_pos_used,
                                                                                quatnav.Flag.navigating}
