"""WGS-84 Earth model shared by the simulator, the strapdown mechanization and the filters.

Everything is in SI units and radians; the navigation frame is the local NED frame.
The same formulas live in C++ in ``cpp/include/quatnav/earth.hpp`` and the two are tested
against each other.

Constants
---------
WGS-84 defining and derived parameters, from NIMA TR8350.2, *Department of Defense World
Geodetic System 1984*, 3rd edition (2000), tables 3.1 to 3.3:
semi-major axis ``A``, flattening ``F``, Earth rotation rate ``OMEGA_IE``, normal gravity at
the equator ``GAMMA_E`` and at the poles ``GAMMA_P`` and the ratio ``M = omega^2 a^2 b / GM``.

Normal gravity
--------------
:func:`gravity` uses the four-coefficient form of paper 004 eq. (2),

    g(L, h) = g0 + g1 sin^2 L + g2 h + g3 h sin^2 L,

with coefficients obtained from the WGS-84 constants above:

* ``g0 = GAMMA_E`` and ``g1 = GAMMA_P - GAMMA_E``, so the surface value is exact at the equator
  and at the poles (it is the Somigliana closed form, TR8350.2 eq. 4-1, truncated after the
  sin^2 L term; the difference from Somigliana is below 6e-5 m/s^2 (6 ug), largest at 45 deg);
* ``g2`` and ``g3`` are the linear free-air terms of TR8350.2 eq. 4-3,
  ``-2 gamma(L) / a * (1 + f + m - 2 f sin^2 L) h``, expanded to first order in sin^2 L.

Numerically ``g = 9.7803253 + 0.0518596 sin^2 L - 3.0877e-6 h + 4.19e-9 h sin^2 L``; compare the
free-air gradient -3.0877e-6 /s^2 and the 0.0053024 sin^2 L latitude term of the normal-gravity
formula quoted by Titterton & Weston, *Strapdown Inertial Navigation Technology* (2nd ed.,
2004, ch. 3) and Savage, *Strapdown Analytics* (2000).
:func:`gravity_somigliana` gives the closed form for comparison.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "A", "F", "B", "E2", "OMEGA_IE", "GM", "GAMMA_E", "GAMMA_P", "M", "G0", "G1", "G2", "G3",
    "STANDARD_GRAVITY",
    "radii", "meridian_radius", "transverse_radius", "gravity", "gravity_somigliana",
    "gravity_n", "earth_rate_n", "transport_rate_n", "geodetic_rates", "ned_to_geodetic",
    "geodetic_to_ned", "geodetic_to_ecef",
]

A = 6378137.0  #: semi-major axis (m)
F = 1.0 / 298.257223563  #: flattening
B = A * (1.0 - F)  #: semi-minor axis (m)
E2 = F * (2.0 - F)  #: first eccentricity squared
OMEGA_IE = 7.292115e-5  #: Earth rotation rate (rad/s)
GM = 3.986004418e14  #: gravitational constant (m^3/s^2)
GAMMA_E = 9.7803253359  #: normal gravity at the equator (m/s^2)
GAMMA_P = 9.8321849378  #: normal gravity at the poles (m/s^2)
M = OMEGA_IE**2 * A**2 * B / GM  #: omega^2 a^2 b / GM (TR8350.2: 0.00344978650684)
STANDARD_GRAVITY = 9.80665  #: conventional g used only for unit conversions (ug, mg, g)

# Coefficients of g = G0 + G1 sin^2 L + G2 h + G3 h sin^2 L (paper 004 eq. 2), see the module doc.
G0 = GAMMA_E  #: m/s^2
G1 = GAMMA_P - GAMMA_E  #: m/s^2
G2 = -2.0 * GAMMA_E * (1.0 + F + M) / A  #: 1/s^2
G3 = -2.0 * ((GAMMA_P - GAMMA_E) * (1.0 + F + M) - 2.0 * F * GAMMA_E) / A  #: 1/s^2


def radii(lat):
    """Meridian and transverse radii of curvature.

    Parameters
    ----------
    lat : float or array_like
        Geodetic latitude (rad).

    Returns
    -------
    R_M, R_N : float or ndarray
        Meridian (north-south) and transverse (east-west, prime vertical) radii (m).
    """
    s2 = np.sin(lat) ** 2
    w = 1.0 - E2 * s2
    R_N = A / np.sqrt(w)
    R_M = A * (1.0 - E2) / (w * np.sqrt(w))
    return R_M, R_N


def meridian_radius(lat):
    """Meridian radius of curvature R_M (m) at geodetic latitude ``lat`` (rad)."""
    return radii(lat)[0]


def transverse_radius(lat):
    """Transverse (prime-vertical) radius of curvature R_N (m) at latitude ``lat`` (rad)."""
    return radii(lat)[1]


def gravity(lat, h):
    """Magnitude of WGS-84 normal gravity (paper 004 eq. 2 form, see the module doc).

    Parameters
    ----------
    lat : float or array_like
        Geodetic latitude (rad).
    h : float or array_like
        Height above the ellipsoid (m).

    Returns
    -------
    float or ndarray
        Normal gravity (m/s^2), positive, pointing down along the ellipsoid normal.
    """
    s2 = np.sin(lat) ** 2
    return G0 + G1 * s2 + G2 * h + G3 * h * s2


def gravity_somigliana(lat, h=0.0):
    """Closed-form WGS-84 normal gravity (TR8350.2 eq. 4-1 and the 2nd-order height series 4-3).

    Parameters
    ----------
    lat : float or array_like
        Geodetic latitude (rad).
    h : float or array_like
        Height above the ellipsoid (m).

    Returns
    -------
    float or ndarray
        Normal gravity (m/s^2).
    """
    s2 = np.sin(lat) ** 2
    k = (B * GAMMA_P) / (A * GAMMA_E) - 1.0
    g = GAMMA_E * (1.0 + k * s2) / np.sqrt(1.0 - E2 * s2)
    return g * (1.0 - 2.0 / A * (1.0 + F + M - 2.0 * F * s2) * h + 3.0 * h**2 / A**2)


def gravity_n(lat, h):
    """Normal gravity vector in NED, ``[0, 0, g]`` (m/s^2); shape (..., 3)."""
    g = np.asarray(gravity(lat, h), dtype=float)
    out = np.zeros(g.shape + (3,))
    out[..., 2] = g
    return out


def earth_rate_n(lat):
    """Earth rotation rate expressed in NED, ``Omega [cos L, 0, -sin L]`` (rad/s); shape (..., 3).

    (Paper 004 prints the first component without the cos L factor; this is the correct form.)
    """
    lat = np.asarray(lat, dtype=float)
    out = np.zeros(lat.shape + (3,))
    out[..., 0] = OMEGA_IE * np.cos(lat)
    out[..., 2] = -OMEGA_IE * np.sin(lat)
    return out


def transport_rate_n(lat, h, v_n):
    """Transport rate omega_en_n: rotation of NED with respect to the Earth (rad/s).

    Parameters
    ----------
    lat : float or array_like, shape (...)
        Geodetic latitude (rad).
    h : float or array_like, shape (...)
        Height (m).
    v_n : array_like, shape (..., 3)
        Velocity with respect to the Earth in NED (m/s).

    Returns
    -------
    ndarray, shape (..., 3)
        ``[v_E/(R_N+h), -v_N/(R_M+h), -v_E tan L/(R_N+h)]``.
    """
    v_n = np.asarray(v_n, dtype=float)
    R_M, R_N = radii(lat)
    out = np.empty(np.broadcast_shapes(np.shape(R_M), v_n.shape[:-1]) + (3,))
    out[..., 0] = v_n[..., 1] / (R_N + h)
    out[..., 1] = -v_n[..., 0] / (R_M + h)
    out[..., 2] = -v_n[..., 1] * np.tan(lat) / (R_N + h)
    return out


def geodetic_rates(lat, h, v_n):
    """Time derivatives of latitude, longitude (rad/s) and height (m/s) for a NED velocity.

    Returns
    -------
    lat_dot, lon_dot, h_dot : float or ndarray
    """
    v_n = np.asarray(v_n, dtype=float)
    R_M, R_N = radii(lat)
    return (v_n[..., 0] / (R_M + h), v_n[..., 1] / ((R_N + h) * np.cos(lat)), -v_n[..., 2])


def ned_to_geodetic(p_n, lat0, lon0, h0):
    """Small-displacement conversion from local NED position to geodetic coordinates.

    Uses the radii at the reference point, so the error grows as (distance / R)^2 relative;
    below 1 mm at 10 km.

    Parameters
    ----------
    p_n : array_like, shape (..., 3)
        Position in NED with respect to the reference point (m).
    lat0, lon0 : float
        Reference geodetic latitude and longitude (rad).
    h0 : float
        Reference height (m).

    Returns
    -------
    lat, lon, h : float or ndarray
        Geodetic latitude, longitude (rad) and height (m).
    """
    p_n = np.asarray(p_n, dtype=float)
    R_M, R_N = radii(lat0)
    lat = lat0 + p_n[..., 0] / (R_M + h0)
    lon = lon0 + p_n[..., 1] / ((R_N + h0) * np.cos(lat0))
    h = h0 - p_n[..., 2]
    return lat, lon, h


def geodetic_to_ned(lat, lon, h, lat0, lon0, h0):
    """Inverse of :func:`ned_to_geodetic`: local NED position (m), shape (..., 3)."""
    R_M, R_N = radii(lat0)
    lat, lon, h = np.broadcast_arrays(np.asarray(lat, float), np.asarray(lon, float),
                                      np.asarray(h, float))
    out = np.empty(lat.shape + (3,))
    out[..., 0] = (lat - lat0) * (R_M + h0)
    out[..., 1] = (lon - lon0) * (R_N + h0) * np.cos(lat0)
    out[..., 2] = h0 - h
    return out


def geodetic_to_ecef(lat, lon, h):
    """Earth-centred Earth-fixed position (m), shape (..., 3), of geodetic coordinates."""
    _, R_N = radii(lat)
    lat, lon, h = np.broadcast_arrays(np.asarray(lat, float), np.asarray(lon, float),
                                      np.asarray(h, float))
    R_N = np.broadcast_to(R_N, lat.shape)
    out = np.empty(lat.shape + (3,))
    out[..., 0] = (R_N + h) * np.cos(lat) * np.cos(lon)
    out[..., 1] = (R_N + h) * np.cos(lat) * np.sin(lon)
    out[..., 2] = (R_N * (1.0 - E2) + h) * np.sin(lat)
    return out
