"""The C++ NED strapdown mechanization (``quatnav._core.strapdown``) over a whole record; its
numpy twin is :func:`quatnav.core.strapdown.strapdown_run`."""
from __future__ import annotations

import numpy as np

from ..core.strapdown import (STATUS_INVALID_DT, STATUS_NON_FINITE, STATUS_NUMERICAL_FAILURE, STATUS_OK,
                              StrapdownState)

__all__ = ["strapdown_run_cpp"]


def strapdown_run_cpp(state: StrapdownState, omega_ib_b, f_ib_b, dt, earth_rotation=True,
                      dtype=np.float64):
    """:func:`strapdown_run` in C++ (``quatnav._core.strapdown``), GIL released during the loop.

    Parameters
    ----------
    state : StrapdownState
        Initial state (not modified).
    omega_ib_b, f_ib_b : array_like, shape (N, 3)
        Mean body rate (rad/s) and specific force (m/s^2) over each interval.
    dt : float or array_like, shape (N,)
        Interval lengths (s).
    earth_rotation : bool
        Include Earth rate, Coriolis and transport-rate terms.
    dtype : numpy.float64 or numpy.float32
        Scalar type of the C++ mechanization (the geodetic position is double in both).

    Returns
    -------
    dict
        Same keys as :func:`strapdown_run`, plus ``state``: the final :class:`StrapdownState`.
    """
    from ._base import core
    dtype = np.dtype(dtype)
    if dtype not in (np.dtype(np.float64), np.dtype(np.float32)):
        raise ValueError(f"dtype must be float64 or float32, got {dtype}")
    w = np.asarray(omega_ib_b, dtype=dtype)
    f = np.asarray(f_ib_b, dtype=dtype)
    if w.ndim != 2 or w.shape[1] != 3 or f.shape != w.shape:
        raise ValueError(f"omega_ib_b and f_ib_b must both have shape (N, 3), got {w.shape} "
                         f"and {f.shape}")
    dts = np.ascontiguousarray(np.broadcast_to(np.asarray(dt, dtype=dtype), (w.shape[0],)))
    mod = core().strapdown
    cls = mod.StrapdownState_f64 if dtype == np.float64 else mod.StrapdownState_f32
    s = cls(np.asarray(state.q_nb, dtype), np.asarray(state.v_n, dtype), float(state.lat),
            float(state.lon), float(state.h))
    s.dtheta_prev = np.asarray(state.dtheta_prev, dtype)
    s.dv_prev = np.asarray(state.dv_prev, dtype)
    s.has_prev = bool(state.has_prev)
    q, v, llh, status = mod.strapdown_batch(s, w, f, dts, bool(earth_rotation))
    names = {0: STATUS_OK, 2: STATUS_NON_FINITE, 4: STATUS_INVALID_DT, 8: STATUS_NUMERICAL_FAILURE}
    final = StrapdownState(np.array(s.q_nb, float), np.array(s.v_n, float), s.lat, s.lon, s.h,
                           np.array(s.dtheta_prev, float), np.array(s.dv_prev, float), s.has_prev)
    return {"q_nb": q, "v_n": v, "lat": llh[:, 0], "lon": llh[:, 1], "h": llh[:, 2],
            "status": np.array([names.get(int(c), str(int(c))) for c in status], dtype=object),
            "state": final}
