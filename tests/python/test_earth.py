"""WGS-84 Earth model against published values."""
import numpy as np
import pytest

from quatnav.core import earth


def test_constants():
    assert earth.A == 6378137.0
    assert earth.B == pytest.approx(6356752.3142, abs=1e-4)
    assert earth.E2 == pytest.approx(6.69437999014e-3, rel=1e-11)
    assert earth.M == pytest.approx(0.00344978650684, rel=1e-10)


def test_gravity_equator_pole():
    # TR8350.2 table 3.4: normal gravity at the equator and at the poles
    assert earth.gravity(0.0, 0.0) == pytest.approx(9.7803253359, abs=1e-10)
    assert earth.gravity(np.pi / 2, 0.0) == pytest.approx(9.8321849378, abs=1e-10)
    assert earth.gravity_somigliana(0.0) == pytest.approx(9.7803253359, abs=1e-10)
    assert earth.gravity_somigliana(np.pi / 2) == pytest.approx(9.8321849378, abs=1e-9)


def test_gravity_against_somigliana():
    lat = np.radians(np.linspace(-90, 90, 181))
    for h in (0.0, 1000.0, 5000.0):
        d = earth.gravity(lat, h) - earth.gravity_somigliana(lat, h)
        assert np.max(np.abs(d)) < 6e-5
    # free-air gradient about -3.086e-6 /s^2
    assert earth.G2 == pytest.approx(-3.0877e-6, rel=1e-3)
    # 45 deg, sea level: 9.806198 m/s^2 (GRS80, whose gamma_e is 1.4e-6 larger, gives 9.806199)
    assert earth.gravity_somigliana(np.radians(45.0)) == pytest.approx(9.806198, abs=1e-6)


def test_radii():
    R_M, R_N = earth.radii(0.0)
    assert R_N == pytest.approx(6378137.0, abs=1e-6)
    assert R_M == pytest.approx(6335439.327, abs=1e-3)
    R_M, R_N = earth.radii(np.pi / 2)
    assert R_M == pytest.approx(R_N, rel=1e-14)
    assert R_N == pytest.approx(6399593.626, abs=1e-3)  # a^2 / b


def test_rates():
    lat = np.radians(36.0)
    w = earth.earth_rate_n(lat)
    assert np.linalg.norm(w) == pytest.approx(7.292115e-5)
    assert w[2] < 0 and w[1] == 0
    v = np.array([10.0, 5.0, -1.0])
    wen = earth.transport_rate_n(lat, 100.0, v)
    R_M, R_N = earth.radii(lat)
    assert wen[0] == pytest.approx(5.0 / (R_N + 100))
    assert wen[1] == pytest.approx(-10.0 / (R_M + 100))
    assert wen[2] == pytest.approx(-5.0 * np.tan(lat) / (R_N + 100))


def test_ned_geodetic_round_trip_and_ecef():
    lat0, lon0, h0 = np.radians(36.37), np.radians(127.36), 50.0
    p = np.array([[1000.0, -2000.0, -30.0], [0.0, 0.0, 0.0]])
    lat, lon, h = earth.ned_to_geodetic(p, lat0, lon0, h0)
    assert np.allclose(earth.geodetic_to_ned(lat, lon, h, lat0, lon0, h0), p, atol=1e-9)
    # the small conversion against exact ECEF differences (local level at the origin)
    e0 = earth.geodetic_to_ecef(lat0, lon0, h0)
    e1 = earth.geodetic_to_ecef(lat[0], lon[0], h[0])
    sl, cl, so, co = np.sin(lat0), np.cos(lat0), np.sin(lon0), np.cos(lon0)
    C_ne = np.array([[-sl * co, -sl * so, cl], [-so, co, 0.0], [-cl * co, -cl * so, -sl]])
    exact = C_ne @ (e1 - e0)
    assert np.allclose(exact[:2], p[0, :2], atol=1.0)  # curvature: sub-metre at 2 km
    assert np.linalg.norm(earth.geodetic_to_ecef(0.0, 0.0, 0.0) - [earth.A, 0, 0]) < 1e-6
