"""Sensor models: Allan read-outs match the specification, error terms, validation."""
import numpy as np
import pytest

from quatnav.core import earth
from quatnav.core import quaternion as quat
from quatnav.sim import (AccelSpec, BaroSpec, CompassSpec, GpsSpec, GyroSpec, ImuSpec,
                         MagDisturbance, MagSpec, Rest, Cruise, Turn, allan_deviation, allan_readout,
                         make_trajectory, simulate_baro, simulate_compass, simulate_gps,
                         simulate_imu, simulate_mag)
from quatnav.sim import units
from quatnav.sim.sensors import _triad


@pytest.fixture(scope="module")
def allan_runs():
    """4 h of a static IMU at 10 Hz (noise only)."""
    rate = 10.0
    n = int(4 * 3600 * rate)
    gyro = GyroSpec(arw_deg_per_sqrt_h=0.15, bias_instability_deg_per_h=10.0, bias_corr_time_s=20.0)
    accel = AccelSpec(vrw_m_per_s_per_sqrt_h=0.02, bias_instability_ug=100.0, bias_corr_time_s=20.0)
    rng = np.random.default_rng(2024)
    g, _, _ = _triad(np.zeros((n, 3)), gyro.si(), 1 / rate, rng)
    a, _, _ = _triad(np.zeros((n, 3)), accel.si(), 1 / rate, rng)
    return rate, g, a


def test_allan_gyro_matches_spec(allan_runs):
    rate, g, _ = allan_runs
    taus, ad = allan_deviation(g, rate)
    for ax in range(3):
        r = allan_readout(taus, ad[:, ax])
        assert units.to_arw_deg_per_sqrt_h(r.random_walk) == pytest.approx(0.15, rel=0.10)
        assert units.to_deg_per_h(r.bias_instability) == pytest.approx(10.0, rel=0.10)


def test_allan_accel_matches_spec(allan_runs):
    rate, _, a = allan_runs
    taus, ad = allan_deviation(a, rate)
    for ax in range(3):
        r = allan_readout(taus, ad[:, ax])
        assert units.to_vrw_m_per_s_per_sqrt_h(r.random_walk) == pytest.approx(0.02, rel=0.10)
        assert units.to_ug(r.bias_instability) == pytest.approx(100.0, rel=0.10)


def test_allan_white_noise_slope():
    rng = np.random.default_rng(1)
    x = rng.standard_normal(100000)
    taus, ad = allan_deviation(x, 100.0)
    # white noise of density sigma/sqrt(rate): adev = density / sqrt(tau)
    short = taus <= 1.0
    assert np.allclose(ad[short] * np.sqrt(taus[short]), 0.1, rtol=0.05)
    r = allan_readout(taus, ad)
    assert r.random_walk == pytest.approx(0.1, rel=0.05)


@pytest.fixture(scope="module")
def drive():
    return make_trajectory([Rest(10.0), Turn(20.0, rate=0.5, ramp=1.0)], 100.0)


def test_imu_error_terms(drive):
    spec = ImuSpec(gyro=GyroSpec(bias_deg_per_h=(100.0, -50.0, 20.0), scale_factor_ppm=1e4,
                                 misalignment_mrad=(1.0, 0, 0, 0, 0, 0)),
                   accel=AccelSpec(bias_ug=(1000.0, 0.0, -1000.0)))
    imu = simulate_imu(drive, spec, np.random.default_rng(0))
    w = drive.omega_mean_b
    M = np.eye(3)
    M[0, 1] = 1e-3
    expect = (w @ M.T) * 1.01 + units.deg_per_h(np.array([100.0, -50.0, 20.0]))
    assert np.allclose(imu.gyro, expect, atol=1e-12)
    assert np.allclose(imu.accel - drive.f_mean_b, units.ug(np.array([1000.0, 0, -1000.0])))
    assert not imu.saturated.any()


def test_imu_saturation_quantization_decimation(drive):
    spec = ImuSpec(gyro=GyroSpec(range_deg_per_s=10.0, quantization_deg_per_s=0.1),
                   accel=AccelSpec(range_g=0.5, quantization_mg=1.0), rate_hz=50.0)
    imu = simulate_imu(drive, spec, np.random.default_rng(0))
    assert imu.rate_hz == 50.0 and len(imu.t) == 1501
    assert np.all(np.abs(imu.gyro) <= np.radians(10.0) + 1e-12)
    assert imu.saturated.all()  # gravity exceeds 0.5 g
    q = imu.gyro / np.radians(0.1)
    assert np.allclose(q, np.round(q), atol=1e-6)
    # decimated output is the mean over the 2-sample interval
    k = 700
    expect = (drive.dtheta_b[2 * k - 1] + drive.dtheta_b[2 * k]) / 0.02
    assert np.allclose(imu.gyro[k], np.clip(expect, -np.radians(10), np.radians(10)),
                       atol=np.radians(0.05) + 1e-12)


def test_imu_noise_level(drive):
    spec = ImuSpec(gyro=GyroSpec(arw_deg_per_sqrt_h=0.6), accel=AccelSpec(noise_density_ug_per_sqrt_hz=100.0))
    imu = simulate_imu(drive, spec, np.random.default_rng(3))
    e = imu.gyro - drive.omega_mean_b
    assert np.std(e) == pytest.approx(units.arw_deg_per_sqrt_h(0.6) * 10.0, rel=0.05)
    e = imu.accel - drive.f_mean_b
    assert np.std(e) == pytest.approx(units.ug(100.0) * 10.0, rel=0.05)


def test_mag(drive):
    spec = MagSpec(intensity_uT=50.0, inclination_deg=60.0, declination_deg=-8.0, noise_uT=0.0,
                   hard_iron_uT=(1.0, 2.0, 3.0),
                   disturbances=(MagDisturbance(12.0, 15.0, (30.0, 0.0, 0.0), ramp_s=0.5),))
    m = simulate_mag(drive, spec, np.random.default_rng(0))
    clean = ~m.disturbed
    body = quat.rotate_inv(drive.q_nb, m.field_n)
    assert np.allclose(m.mag[clean], body[clean] + 1e-6 * np.array([1.0, 2.0, 3.0]), atol=1e-15)
    assert np.linalg.norm(m.field_n) == pytest.approx(50e-6)
    assert np.degrees(np.arctan2(m.field_n[2], np.hypot(*m.field_n[:2]))) == pytest.approx(60.0)
    assert np.degrees(np.arctan2(m.field_n[1], m.field_n[0])) == pytest.approx(-8.0)
    assert m.disturbed[(m.t > 12.1) & (m.t < 14.9)].all() and not m.disturbed[m.t < 11.9].any()
    k = np.searchsorted(m.t, 13.5)
    assert m.mag[k, 0] - body[k, 0] == pytest.approx(31e-6)


def test_gps_lever_arm_latency_outage():
    tr = make_trajectory([Cruise(10.0), Turn(30.0, rate=0.2, ramp=1.0)], 100.0, speed0=10.0)
    spec = GpsSpec(rate_hz=10.0, pos_sigma_h_m=0.0, pos_sigma_v_m=0.0, vel_sigma_m_s=0.0,
                   lever_arm_b_m=(1.0, 0.5, -1.0), latency_s=0.2, outages=((20.0, 25.0),))
    g = simulate_gps(tr, spec, np.random.default_rng(0))
    assert np.allclose(g.t - g.t_valid, 0.2)
    assert not np.any((g.t_valid >= 20.0) & (g.t_valid < 25.0))
    i = g.index_valid
    lever_n = quat.rotate(tr.q_nb[i], np.array([1.0, 0.5, -1.0]))
    assert np.allclose(g.pos_n, tr.pos_n[i] + lever_n, atol=1e-6)
    # antenna velocity by differentiating the antenna position
    ant = tr.pos_n + quat.rotate(tr.q_nb, np.array([1.0, 0.5, -1.0]))
    v_num = np.gradient(ant, tr.dt, axis=0)[i]
    assert np.allclose(g.v_n[2:-2], v_num[2:-2], atol=1e-3)


def test_baro_compass(drive):
    b = simulate_baro(drive, BaroSpec(rate_hz=10.0, noise_m=0.0, bias_m=2.0, drift_m_per_sqrt_h=0.0),
                      np.random.default_rng(0))
    assert np.allclose(b.h - drive.h[b.index], 2.0)
    c = simulate_compass(drive, CompassSpec(rate_hz=10.0, noise_deg=0.0, bias_deg=1.0),
                         np.random.default_rng(0))
    d = np.angle(np.exp(1j * (c.yaw - drive.rpy[c.index, 2])))
    assert np.allclose(d, np.radians(1.0))


@pytest.mark.parametrize("make, name", [
    (lambda: GyroSpec(arw_deg_per_sqrt_h=-1.0), "arw_deg_per_sqrt_h"),
    (lambda: GyroSpec(arw_deg_per_sqrt_h=0.1, noise_density_dps_per_sqrt_hz=0.01), "not both"),
    (lambda: GyroSpec(bias_deg_per_h=(1.0, 2.0)), "bias_deg_per_h"),
    (lambda: GyroSpec(bias_corr_time_s=0.0), "bias_corr_time_s"),
    (lambda: GyroSpec(range_deg_per_s=np.nan), "range_deg_per_s"),
    (lambda: AccelSpec(misalignment_mrad=(1.0, 2.0, 3.0)), "misalignment_mrad"),
    (lambda: AccelSpec(bias_instability_ug=-5.0), "bias_instability_ug"),
    (lambda: MagSpec(inclination_deg=100.0), "inclination_deg"),
    (lambda: MagSpec(soft_iron=np.zeros((3, 3))), "soft_iron"),
    (lambda: MagDisturbance(5.0, 4.0), "t_end"),
    (lambda: GpsSpec(rate_hz=0.0), "rate_hz"),
    (lambda: GpsSpec(outages=((5.0, 1.0),)), "outages"),
    (lambda: BaroSpec(noise_m=-1.0), "noise_m"),
    (lambda: CompassSpec(noise_deg=np.inf), "noise_deg"),
])
def test_bad_sensor_parameters(make, name):
    with pytest.raises(ValueError, match=name):
        make()


def test_rate_must_divide(drive):
    with pytest.raises(ValueError, match="rate_hz"):
        simulate_imu(drive, ImuSpec(rate_hz=30.0), np.random.default_rng(0))
