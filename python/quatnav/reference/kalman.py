"""The Kalman correction shared by the reference filters (Cholesky, Joseph form)."""
from __future__ import annotations

import numpy as np


def kalman_correct(P, H, R, y, gate: float = 0.0):
    """One Kalman correction.

    Returns ``(status, dx, P_new, S, nis)``. ``status`` is "ok", "rejected" (NIS above a
    positive ``gate``) or "solve_failed" (S not positive definite); on anything but "ok",
    ``dx`` is None and ``P_new`` is ``P``.
    """
    PHt = P @ H.T
    S = H @ PHt + R
    S = 0.5 * (S + S.T)
    try:
        L = np.linalg.cholesky(S)
    except np.linalg.LinAlgError:
        return "solve_failed", None, P, S, np.nan
    w = np.linalg.solve(L, y)
    nis = float(w @ w)
    if gate > 0 and not nis <= gate:
        return "rejected", None, P, S, nis
    K = np.linalg.solve(S, PHt.T).T
    dx = K @ y
    IKH = np.eye(P.shape[0]) - K @ H
    P_new = IKH @ P @ IKH.T + K @ R @ K.T
    P_new = 0.5 * (P_new + P_new.T)
    return "ok", dx, P_new, S, nis
