"""Reference (numpy) Rauch-Tung-Striebel smoothers of the attitude twins, the twin of
``cpp/include/quatnav/attitude/smoother.hpp``: :class:`QuaternionEKF` (error state
``[dtheta (body), db]``, the smoothed attitude ``q * exp(d_theta)``) and :class:`EulerEKF`
(additive errors, roll and yaw wrapped). :func:`run_smoothed` runs a twin over a log and smooths it.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..core import quaternion as Q
from .smoother import Recorder


class _Model:
    def __init__(self, f, gyr, dt):
        self.f, self.gyr, self.dt = f, np.asarray(gyr, float), np.broadcast_to(np.asarray(dt, float), (len(gyr),))

    @staticmethod
    def same(a, b):
        return all(np.array_equal(x, y) for x, y in zip(a, b))

    @staticmethod
    def error_covariance(s):
        return s[2]


class ESKFModel(_Model):
    """Snapshot ``(q, b, P)``; ``x [-] base = [log(q_b^-1 q), b - b_b]``."""

    def snapshot(self, f):
        return (f.q.copy(), f.bias.copy(), f.P.copy()) if f.initialized else None

    def transition(self, post, k):
        return type(self.f).propagate(post[0], post[1], self.gyr[k], self.dt[k])[1]

    @staticmethod
    def local(base, x):
        return np.concatenate([Q.to_rotvec(Q.mul(Q.conj(base[0]), x[0])), x[1] - base[1]])

    @staticmethod
    def retract(base, d, Ps):
        q = Q.mul(base[0], Q.from_rotvec(d[:3]))
        return q / np.linalg.norm(q), base[1] + d[3:], Ps

    @staticmethod
    def quat(s):
        return s[0]

    @staticmethod
    def att_variance(s, Ps):
        return np.diag(Ps)[:3]


class EulerModel(_Model):
    """Snapshot ``(euler, b, P)``; additive errors with roll and yaw wrapped."""

    def snapshot(self, f):
        return (f.euler.copy(), f.bias.copy(), f.P.copy()) if f.initialized else None

    def transition(self, post, k):
        return self.f.propagate(post[0], post[1], self.gyr[k], self.dt[k], exact=False)[1]  # F only

    @staticmethod
    def local(base, x):
        d = x[0] - base[0]
        d[0], d[2] = Q.wrap_pi(d[0]), Q.wrap_pi(d[2])
        return np.concatenate([d, x[1] - base[1]])

    @staticmethod
    def retract(base, d, Ps):
        e = base[0] + d[:3]
        e[0], e[2] = Q.wrap_pi(e[0]), Q.wrap_pi(e[2])
        return e, base[1] + d[3:], Ps

    @staticmethod
    def quat(s):
        return Q.from_euler(s[0])

    @staticmethod
    def att_variance(s, Ps):
        cr, sr, cp, sp = np.cos(s[0][0]), np.sin(s[0][0]), np.cos(s[0][1]), np.sin(s[0][1])
        W = np.array([[1.0, 0.0, -sp], [0.0, cr, sr * cp], [0.0, -sr, cr * cp]])
        return np.diag(W @ Ps[:3, :3] @ W.T)


def run_smoothed(f, gyr, acc, mag=None, dt=None):
    """Run the twin ``f`` (QuaternionEKF or EulerEKF) over a log and smooth it: the forward
    result of ``f.run`` with ``smoothed`` (quat, bias, sigma, att_sigma and the error
    covariances P; the forward values, and NaN covariances, before the filter's first estimate)."""
    name = getattr(f, "rts_model", None)  # the twin names its model (no import of the twins here)
    if name is None:
        raise ValueError(f"smooth: {type(f).__name__} has no smoother (QuaternionEKF and EulerEKF have)")
    model = {"ESKFModel": ESKFModel, "EulerModel": EulerModel}[name](f, gyr, dt)
    rec = Recorder(model)
    out = f.run(gyr, acc, mag, dt=dt, observer=rec)
    sm = SimpleNamespace(quat=out.quat.copy(), bias=out.bias.copy(), sigma=out.sigma.copy(),
                         att_sigma=np.full((len(out.quat), 3), np.nan), P=np.full((len(out.quat), 6, 6), np.nan))
    if rec.first is not None:
        k0, xs, Ps = rec.smooth()
        for j, (s, P) in enumerate(zip(xs, Ps)):
            k = k0 + j
            sm.quat[k], sm.bias[k], sm.P[k] = model.quat(s), s[1], P
            sm.sigma[k] = np.sqrt(np.maximum(np.diag(P), 0))
            sm.att_sigma[k] = np.sqrt(np.maximum(model.att_variance(s, P), 0))
    out.smoothed = sm
    return out
