"""C++ strapdown against its numpy twin, and the C++ round trip on simulated IMU data."""
import numpy as np
import pytest

from quatnav import _core
from quatnav.core import earth
from quatnav.core import quaternion as quat
from quatnav.sim import Climb, CoordinatedTurn, Cruise, Rotate, Rest, Turn, make_trajectory
from quatnav.core.strapdown import StrapdownState, strapdown_run, strapdown_step
from quatnav.filters.strapdown import strapdown_run_cpp


def att_err_deg(a, b):
    return np.degrees(np.linalg.norm(quat.to_rotvec(quat.mul(quat.conj(a), b)), axis=-1))


def start(tr):
    return StrapdownState(tr.q_nb[0], tr.v_n[0], tr.lat[0], tr.lon[0], tr.h[0])


@pytest.fixture(scope="module")
def flight():
    return make_trajectory([Cruise(5), CoordinatedTurn(15, rate=0.2, ramp=2), Climb(10, 0.2),
                            Rotate("roll", 5, angle=1.0), Turn(10, angle=-1.0)], 100.0,
                           speed0=25.0, lat0=np.radians(60.0))


@pytest.mark.parametrize("earth_rotation", [True, False])
def test_cpp_matches_numpy_step_by_step(flight, earth_rotation):
    tr = flight
    py = strapdown_run(start(tr), tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt, earth_rotation)
    cp = strapdown_run_cpp(start(tr), tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt, earth_rotation)
    assert np.all(cp["status"] == "ok")
    assert np.max(np.abs(py["q_nb"] - cp["q_nb"])) < 1e-9
    assert np.max(np.abs(py["v_n"] - cp["v_n"])) < 1e-9
    R = earth.A
    assert np.max(np.abs(py["lat"] - cp["lat"])) * R < 1e-9
    assert np.max(np.abs(py["lon"] - cp["lon"])) * R < 1e-9
    assert np.max(np.abs(py["h"] - cp["h"])) < 1e-9


def test_cpp_single_step_matches_numpy():
    s_py = StrapdownState(quat.from_euler([0.1, -0.2, 2.0]), np.array([3.0, -1.0, 0.5]), 0.7, 2.1, 300.0)
    s_cp = _core.strapdown.StrapdownState_f64(s_py.q_nb, s_py.v_n, s_py.lat, s_py.lon, s_py.h)
    rng = np.random.default_rng(0)
    for _ in range(20):
        w = rng.normal(0, 0.5, 3)
        f = rng.normal(0, 2, 3) + [0, 0, -9.8]
        assert strapdown_step(s_py, w, f, 0.01) == "ok"
        assert _core.strapdown.strapdown_step(s_cp, w, f, 0.01) == "ok"
    assert np.allclose(s_py.q_nb, s_cp.q_nb, atol=1e-12)
    assert np.allclose(s_py.v_n, s_cp.v_n, atol=1e-12)
    assert np.allclose(s_py.dtheta_prev, s_cp.dtheta_prev, atol=0)


def test_cpp_round_trip_200s_100hz():
    tr = make_trajectory([Cruise(100.0), Turn(110.0, rate=0.1, ramp=1.0)], 100.0, speed0=2.0,
                         t_end=200.0)
    out = strapdown_run_cpp(start(tr), tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt)
    pos = earth.geodetic_to_ned(out["lat"], out["lon"], out["h"], tr.lat[0], tr.lon[0], tr.h[0])
    assert np.linalg.norm(pos - tr.pos_n[1:], axis=1).max() < 0.5
    assert att_err_deg(out["q_nb"], tr.q_nb[1:]).max() < 0.01


def test_float_against_double(flight):
    tr = flight
    d = strapdown_run_cpp(start(tr), tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt)
    f = strapdown_run_cpp(start(tr), tr.omega_mean_b[1:], tr.f_mean_b[1:], tr.dt, dtype=np.float32)
    assert f["q_nb"].dtype == np.float32
    assert att_err_deg(d["q_nb"], f["q_nb"].astype(float)).max() < 0.01
    assert np.max(np.abs(d["v_n"] - f["v_n"])) < 0.05
    pos = earth.geodetic_to_ned(f["lat"], f["lon"], f["h"], d["lat"], d["lon"], d["h"])
    assert np.max(np.abs(pos)) < 1.0


def test_cpp_bad_input_status_and_shapes():
    s = _core.strapdown.StrapdownState_f64(np.array([1.0, 0, 0, 0]), np.zeros(3), 0.6, 2.0, 10.0)
    assert _core.strapdown.strapdown_step(s, [np.nan, 0, 0], [0, 0, -9.8], 0.01) == "non_finite"
    assert _core.strapdown.strapdown_step(s, [0, 0, 0], [0, 0, -9.8], 0.0) == "invalid_dt"
    assert s.has_prev is False and s.lat == 0.6
    st = StrapdownState(quat.identity(), np.zeros(3), 0.6, 2.0, 10.0)
    w = np.zeros((4, 3))
    w[2, 0] = np.inf
    out = strapdown_run_cpp(st, w, np.tile([0, 0, -9.8], (4, 1)), 0.01)
    assert list(out["status"]) == ["ok", "ok", "non_finite", "ok"]
    with pytest.raises(ValueError, match="f_ib_b"):
        _core.strapdown.strapdown_batch(s, np.zeros((4, 3)), np.zeros((3, 3)), np.ones(4) * 0.01)
    with pytest.raises(ValueError, match="dtype"):
        strapdown_run_cpp(st, np.zeros((2, 3)), np.zeros((2, 3)), 0.01, dtype=np.int32)


def test_cpp_earth_matches_numpy():
    ce = _core.earth
    for lat in np.radians([-80.0, -10.0, 0.0, 36.4, 89.0]):
        assert ce.gravity(lat, 1234.0) == pytest.approx(earth.gravity(lat, 1234.0), abs=1e-12)
        assert ce.radii(lat) == pytest.approx(earth.radii(lat), rel=1e-15)
        v = np.array([3.0, -4.0, 0.5])
        assert np.allclose(ce.transport_rate_n(lat, 100.0, v), earth.transport_rate_n(lat, 100.0, v),
                           rtol=1e-14, atol=0)
        assert np.allclose(ce.earth_rate_n(lat), earth.earth_rate_n(lat), rtol=1e-15, atol=1e-20)
        assert np.allclose(ce.geodetic_to_ecef(lat, 1.0, 50.0), earth.geodetic_to_ecef(lat, 1.0, 50.0))
    assert (ce.G0, ce.G1, ce.G2, ce.G3) == pytest.approx((earth.G0, earth.G1, earth.G2, earth.G3), rel=1e-15)


def test_split_run_is_identical(flight):
    tr = flight
    w, f = tr.omega_mean_b[1:], tr.f_mean_b[1:]
    full = strapdown_run_cpp(start(tr), w, f, tr.dt)
    first = strapdown_run_cpp(start(tr), w[:1234], f[:1234], tr.dt)
    rest = strapdown_run_cpp(first["state"], w[1234:], f[1234:], tr.dt)
    assert np.array_equal(full["q_nb"][1234:], rest["q_nb"])
    assert np.array_equal(full["lat"][1234:], rest["lat"])
    a = strapdown_run(start(tr), w[:300], f[:300], tr.dt)
    s = start(tr)
    for k in range(300):
        strapdown_step(s, w[k], f[k], tr.dt)
    assert np.array_equal(a["q_nb"][-1], s.q_nb)
