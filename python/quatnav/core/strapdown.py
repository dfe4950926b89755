"""Strapdown mechanization in the local NED frame (numpy twin of ``cpp/include/quatnav/strapdown.hpp``).

Integration scheme (one step from t[k-1] to t[k], dt = t[k] - t[k-1])
-------------------------------------------------------------------
Inputs are the *mean* body rate and specific force over the interval, ``omega_ib_b`` and
``f_ib_b`` (an IMU's increments divided by dt), so ``dtheta = omega_ib_b dt`` and
``dv = f_ib_b dt``. The previous increments are kept in the state for the two-sample
corrections (Savage, *Strapdown Analytics*, 2000, ch. 7; Titterton & Weston 2004, ch. 11):

1. rotation vector with coning:  ``phi = dtheta + 1/12 dtheta_prev x dtheta``
2. velocity increment in the body frame of t[k-1], rotation and sculling:
   ``dv_rot = dv + 1/2 dtheta x dv + 1/6 dtheta x (dtheta x dv)
   + 1/12 (dtheta_prev x dv + dv_prev x dtheta)``
   (the two-sample terms are skipped on the first step, when nothing precedes it)
3. Earth terms (``omega_ie_n``, ``omega_en_n``, ``g_n``) evaluated at the interval midpoint,
   predicted from a first pass with the values at t[k-1] (predictor-corrector, 2nd order):
   ``zeta = (omega_ie_n + omega_en_n) dt`` (rotation of the NED frame over the step),
   ``v_n += (I - 1/2 [zeta x]) C_nb dv_rot + (g_n - (2 omega_ie_n + omega_en_n) x v_mid) dt``
4. position by the trapezoidal rule in velocity with the radii at the midpoint:
   ``lat += v_N dt / (R_M + h)``, ``lon += v_E dt / ((R_N + h) cos lat)``, ``h -= v_D dt``
5. attitude: ``q_nb <- exp(-zeta) * q_nb * exp(phi)``, renormalized.

With ``earth_rotation=False`` ``omega_ie_n`` and ``omega_en_n`` are zero (a flat, non-rotating
Earth; position is still geodetic and gravity is normal gravity), which matches
``quatnav.sim.make_trajectory(..., earth_rate=False)``.

A step with non-finite input, non-finite state or ``dt <= 0`` returns a status and leaves the
state untouched.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace

import numpy as np

from . import earth

__all__ = ["StrapdownState", "STATUS_OK", "STATUS_NON_FINITE", "STATUS_INVALID_DT",
           "STATUS_NUMERICAL_FAILURE", "strapdown_step", "strapdown_run"]

# The same names as quatnav::Status in cpp/include/quatnav/core/types.hpp.
STATUS_OK = "ok"
STATUS_NON_FINITE = "non_finite"
STATUS_INVALID_DT = "invalid_dt"
STATUS_NUMERICAL_FAILURE = "numerical_failure"


@dataclass
class StrapdownState:
    """Navigation state.

    Attributes
    ----------
    q_nb : ndarray, shape (4,)
        Attitude [w, x, y, z], body to NED.
    v_n : ndarray, shape (3,)
        Velocity with respect to the Earth in NED (m/s).
    lat, lon : float
        Geodetic latitude and longitude (rad).
    h : float
        Height above the ellipsoid (m).
    dtheta_prev, dv_prev : ndarray, shape (3,)
        Increments of the previous step (rad, m/s), for the two-sample corrections.
    has_prev : bool
        Whether ``dtheta_prev``/``dv_prev`` hold a previous step.
    """

    q_nb: np.ndarray
    v_n: np.ndarray
    lat: float
    lon: float
    h: float
    dtheta_prev: np.ndarray = field(default_factory=lambda: np.zeros(3))
    dv_prev: np.ndarray = field(default_factory=lambda: np.zeros(3))
    has_prev: bool = False

    def copy(self):
        return replace(self, q_nb=np.array(self.q_nb, float), v_n=np.array(self.v_n, float),
                       dtheta_prev=np.array(self.dtheta_prev, float),
                       dv_prev=np.array(self.dv_prev, float))


def _qmul(p, q):
    pw, px, py, pz = p
    qw, qx, qy, qz = q
    return (pw * qw - px * qx - py * qy - pz * qz,
            pw * qx + px * qw + py * qz - pz * qy,
            pw * qy - px * qz + py * qw + pz * qx,
            pw * qz + px * qy - py * qx + pz * qw)


def _qexp(r):
    a = math.sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2])
    k = 0.5 - a * a / 48.0 if a < 1e-8 else math.sin(0.5 * a) / a
    return (math.cos(0.5 * a), k * r[0], k * r[1], k * r[2])


def _cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def _rotate(q, v):
    """C_nb v for a unit quaternion q_nb."""
    w, x, y, z = q
    return ((w*w + x*x - y*y - z*z) * v[0] + 2 * (x*y - w*z) * v[1] + 2 * (x*z + w*y) * v[2],
            2 * (x*y + w*z) * v[0] + (w*w - x*x + y*y - z*z) * v[1] + 2 * (y*z - w*x) * v[2],
            2 * (x*z - w*y) * v[0] + 2 * (y*z + w*x) * v[1] + (w*w - x*x - y*y + z*z) * v[2])


def _radii(lat):
    s2 = math.sin(lat) ** 2
    w = 1.0 - earth.E2 * s2
    return earth.A * (1.0 - earth.E2) / (w * math.sqrt(w)), earth.A / math.sqrt(w)


def _earth_terms(lat, h, v_n, earth_rotation):
    """(g, omega_ie_n, omega_en_n) at (lat, h, v_n), as plain floats."""
    s2 = math.sin(lat) ** 2
    g = earth.G0 + earth.G1 * s2 + (earth.G2 + earth.G3 * s2) * h
    if not earth_rotation:
        return g, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)
    R_M, R_N = _radii(lat)
    w_ie = (earth.OMEGA_IE * math.cos(lat), 0.0, -earth.OMEGA_IE * math.sin(lat))
    w_en = (v_n[1] / (R_N + h), -v_n[0] / (R_M + h), -v_n[1] * math.tan(lat) / (R_N + h))
    return g, w_ie, w_en


def _finite(*xs):
    return all(np.all(np.isfinite(np.asarray(x, float))) for x in xs)


def strapdown_step(state: StrapdownState, omega_ib_b, f_ib_b, dt, earth_rotation=True):
    """Advance ``state`` by one IMU interval (in place).

    Parameters
    ----------
    state : StrapdownState
        Updated in place when the status is ``"ok"``; untouched otherwise.
    omega_ib_b : array_like, shape (3,)
        Mean body rate with respect to inertial space over the interval (rad/s).
    f_ib_b : array_like, shape (3,)
        Mean specific force over the interval (m/s^2).
    dt : float
        Interval (s), > 0.
    earth_rotation : bool
        Include Earth rate, Coriolis and transport-rate terms.

    Returns
    -------
    str
        ``"ok"``, ``"non_finite"``, ``"invalid_dt"`` or ``"numerical_failure"``.
    """
    w = [float(x) for x in np.asarray(omega_ib_b, float).reshape(3)]
    f = [float(x) for x in np.asarray(f_ib_b, float).reshape(3)]
    dt = float(dt)
    if not (math.isfinite(dt) and dt > 0):
        return STATUS_INVALID_DT
    q = [float(x) for x in np.asarray(state.q_nb, float).reshape(4)]
    v = [float(x) for x in np.asarray(state.v_n, float).reshape(3)]
    lat, lon, h = float(state.lat), float(state.lon), float(state.h)
    dth_p = [float(x) for x in np.asarray(state.dtheta_prev, float).reshape(3)]
    dv_p = [float(x) for x in np.asarray(state.dv_prev, float).reshape(3)]
    if not all(math.isfinite(x) for x in (*w, *f, *q, *v, lat, lon, h, *dth_p, *dv_p)):
        return STATUS_NON_FINITE

    dth = (w[0] * dt, w[1] * dt, w[2] * dt)
    dvb = (f[0] * dt, f[1] * dt, f[2] * dt)
    c = _cross(dth, dvb)
    cc = _cross(dth, c)
    phi = list(dth)
    dv_rot = [dvb[i] + 0.5 * c[i] + cc[i] / 6.0 for i in range(3)]
    if state.has_prev:
        cn = _cross(dth_p, dth)
        s1 = _cross(dth_p, dvb)
        s2 = _cross(dv_p, dth)
        for i in range(3):
            phi[i] += cn[i] / 12.0
            dv_rot[i] += (s1[i] + s2[i]) / 12.0
    dv_n = _rotate(q, dv_rot)

    def velocity(lat_m, h_m, v_m):
        g, w_ie, w_en = _earth_terms(lat_m, h_m, v_m, earth_rotation)
        zeta = tuple((w_ie[i] + w_en[i]) * dt for i in range(3))
        zc = _cross(zeta, dv_n)
        cor = _cross(tuple(2 * w_ie[i] + w_en[i] for i in range(3)), v_m)
        g_n = (0.0, 0.0, g)
        return [v[i] + dv_n[i] - 0.5 * zc[i] + (g_n[i] - cor[i]) * dt for i in range(3)], zeta

    # predictor: Earth terms at t[k-1]
    v_pred, _ = velocity(lat, h, v)
    R_M, _ = _radii(lat)
    v_mid = [0.5 * (v[i] + v_pred[i]) for i in range(3)]
    h_mid = h - 0.5 * dt * v_mid[2]
    lat_mid = lat + 0.5 * dt * v_mid[0] / (R_M + h)
    # corrector: Earth terms at the midpoint
    v_new, zeta = velocity(lat_mid, h_mid, v_mid)
    v_avg = [0.5 * (v[i] + v_new[i]) for i in range(3)]
    h_mid = h - 0.5 * dt * v_avg[2]
    lat_mid = lat + 0.5 * dt * v_avg[0] / (R_M + h)
    R_Mm, R_Nm = _radii(lat_mid)
    lat_new = lat + dt * v_avg[0] / (R_Mm + h_mid)
    lon_new = lon + dt * v_avg[1] / ((R_Nm + h_mid) * math.cos(lat_mid))
    h_new = h - dt * v_avg[2]

    qn = _qmul(_qexp((-zeta[0], -zeta[1], -zeta[2])), _qmul(q, _qexp(phi)))
    nrm = math.sqrt(sum(x * x for x in qn))
    q_new = [x / nrm for x in qn]
    if not all(math.isfinite(x) for x in (*q_new, *v_new, lat_new, lon_new, h_new)):
        return STATUS_NUMERICAL_FAILURE
    state.q_nb = np.array(q_new)
    state.v_n = np.array(v_new)
    state.lat, state.lon, state.h = lat_new, lon_new, h_new
    state.dtheta_prev = np.array(dth)
    state.dv_prev = np.array(dvb)
    state.has_prev = True
    return STATUS_OK


def strapdown_run(state: StrapdownState, omega_ib_b, f_ib_b, dt, earth_rotation=True):
    """Integrate a sequence of IMU samples from ``state`` (which is copied, not modified).

    Parameters
    ----------
    state : StrapdownState
        State at the time just before the first sample's interval.
    omega_ib_b, f_ib_b : array_like, shape (N, 3)
        Mean body rate (rad/s) and specific force (m/s^2) over each interval.
    dt : float or array_like, shape (N,)
        Interval lengths (s).
    earth_rotation : bool
        Include Earth rate, Coriolis and transport-rate terms.

    Returns
    -------
    dict
        ``q_nb`` (N, 4), ``v_n`` (N, 3), ``lat``, ``lon``, ``h`` (N,), and ``status`` (N,) of str,
        the state after each sample.
    """
    w = np.asarray(omega_ib_b, float)
    f = np.asarray(f_ib_b, float)
    if w.ndim != 2 or w.shape[1] != 3 or f.shape != w.shape:
        raise ValueError(f"omega_ib_b and f_ib_b must both have shape (N, 3), got {w.shape} "
                         f"and {f.shape}")
    n = w.shape[0]
    dts = np.broadcast_to(np.asarray(dt, float), (n,))
    s = state.copy()
    out = {"q_nb": np.empty((n, 4)), "v_n": np.empty((n, 3)), "lat": np.empty(n),
           "lon": np.empty(n), "h": np.empty(n), "status": np.empty(n, dtype=object)}
    for k in range(n):
        out["status"][k] = strapdown_step(s, w[k], f[k], dts[k], earth_rotation)
        out["q_nb"][k] = s.q_nb
        out["v_n"][k] = s.v_n
        out["lat"][k], out["lon"][k], out["h"][k] = s.lat, s.lon, s.h
    return out
