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


def kalman_correct_rows(P, H, r, y, gate: float = 0.0, gain=None):
    """The rows of H (noise variances ``r``, uncorrelated) as scalar updates in turn, each with the
    Joseph form (core/kalman.hpp's ``kalman_correct_diagonal``): the same result as
    :func:`kalman_correct` for the optimal gain. ``gain(i, k)`` returns the gain of row ``i`` to use
    instead of the optimal ``k`` (a Schmidt-Kalman projection); the Joseph form keeps ``P_new``
    the covariance of the error for any gain.

    Returns ``(status, dx, P_new, S, nis)`` as :func:`kalman_correct`.
    """
    H = np.atleast_2d(np.asarray(H, float))
    r = np.asarray(r, float)
    y = np.asarray(y, float)
    M, N = H.shape
    Pw = np.array(P, float)
    dx = np.zeros(N)
    s = np.zeros(M)
    L = np.eye(M)
    nis = 0.0
    for i in range(M):
        h = H[i]
        a = Pw @ h
        si = float(h @ a + r[i])
        if not si > 0:
            return "solve_failed", None, P, None, np.nan
        s[i] = si
        L[i + 1:, i] = H[i + 1:] @ a / si
        e = y[i] - h @ dx
        nis += e * e / si
        k = a / si
        if gain is not None:
            k = gain(i, k)
        dx = dx + k * e
        Pw = Pw - np.outer(a, k) - np.outer(k, a) + si * np.outer(k, k)
    S = L @ np.diag(s) @ L.T
    S = 0.5 * (S + S.T)
    if gate > 0 and not nis <= gate:
        return "rejected", None, P, S, nis
    return "ok", dx, 0.5 * (Pw + Pw.T), S, nis
