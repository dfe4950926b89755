"""The Rauch-Tung-Striebel smoother (core/smoother.hpp, docs/SMOOTHING.md): the numpy twin's
backward pass against batch least squares on a linear-Gaussian model (the C++ one:
tests/cpp/test_smoother.cpp)."""
from __future__ import annotations

import numpy as np
import pytest

from quatnav.reference import kalman_correct
from quatnav.reference.smoother import rts


# ---- a linear-Gaussian model: the smoother equals batch least squares -----------------------------
def _cv(dt, q):
    F = np.eye(4)
    F[0, 2] = F[1, 3] = dt
    Qd = np.zeros((4, 4))
    for i in range(2):
        Qd[i, i] = q * dt**3 / 3
        Qd[i, i + 2] = Qd[i + 2, i] = q * dt**2 / 2
        Qd[i + 2, i + 2] = q * dt
    return F, Qd


def test_linear_model_equals_batch_least_squares():
    """A 2-D constant-velocity filter (position measured every 10th sample): the twin's RTS pass
    gives the minimizer of the batch least-squares cost and its covariance to 1e-9."""
    rng = np.random.default_rng(3)
    n, q, r = 120, 0.5, 0.3
    dts = rng.uniform(0.05, 0.2, n)
    x0, P0 = np.array([0.0, 0.0, 1.0, -0.5]), np.diag([4.0, 4.0, 1.0, 1.0])
    xt = np.array([0.5, -0.3, 1.2, -0.4])
    z = {}
    for k in range(n):
        if k:
            xt = _cv(dts[k], q)[0] @ xt + rng.normal(0, [0.1, 0.1, 0.3, 0.3])
        if k % 10 == 0 or k == 7:
            z[k] = xt[:2] + r * rng.standard_normal(2)
    Hm = np.eye(2, 4)
    x, P = x0.copy(), P0.copy()
    posts, links = [], []
    for k in range(n):
        if k:
            F, Qd = _cv(dts[k], q)
            x, P = F @ x, F @ P @ F.T + Qd
            links.append(((x, P), F))
        if k in z:
            status, dx, P, _, _ = kalman_correct(P, Hm, r * r * np.eye(2), z[k] - x[:2])
            assert status == "ok"
            x = x + dx
        posts.append((x, P))
    xs, Ps = rts(posts, links, lambda s: s[1], lambda b, s: s[0] - b[0], lambda b, d, Pe: (b[0] + d, Pe))
    # Batch least squares: the normal equations of every prior, process and measurement residual.
    A = np.zeros((4 * n, 4 * n))
    b = np.zeros(4 * n)
    A[:4, :4] += np.linalg.inv(P0)
    b[:4] += np.linalg.solve(P0, x0)
    for k in range(1, n):
        F, Qd = _cv(dts[k], q)
        J = np.zeros((4, 4 * n))
        J[:, 4 * (k - 1):4 * k] = -F
        J[:, 4 * k:4 * k + 4] = np.eye(4)
        A += J.T @ np.linalg.solve(Qd, J)
    for k, zk in z.items():
        A[4 * k:4 * k + 2, 4 * k:4 * k + 2] += np.eye(2) / r**2
        b[4 * k:4 * k + 2] += zk / r**2
    X = np.linalg.solve(A, b)
    C = np.linalg.inv(A)
    for k in range(n):
        np.testing.assert_allclose(xs[k][0], X[4 * k:4 * k + 4], atol=1e-9, rtol=0)
        np.testing.assert_allclose(Ps[k], C[4 * k:4 * k + 4, 4 * k:4 * k + 4], atol=1e-9, rtol=0)
