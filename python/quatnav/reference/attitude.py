"""Reference (numpy) QuaternionEKF and EulerEKF of paper 000; see quatnav.attitude."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from .. import quaternion as Q
from .kalman import kalman_correct

GRAVITY_REF = (0.0, -1.0)  # [r_x, r_z] of the normalized specific force at rest, NED


def _unit(v):
    v = np.asarray(v, dtype=float)
    if not np.all(np.isfinite(v)):
        return "non_finite", None
    n = np.linalg.norm(v)
    if not n > np.sqrt(np.finfo(float).tiny):
        return "zero_norm", None
    return "ok", v / n


def attitude_from_acc_mag(acc, mag=None):
    """Tilt from gravity, heading from the field. Returns (q_nb, mag_ref [m_x, 0, m_z]) or None."""
    a = np.asarray(acc, dtype=float)
    a = a / np.linalg.norm(a)
    roll = np.arctan2(-a[1], -a[2])
    pitch = np.arctan2(a[0], np.hypot(a[1], a[2]))
    yaw = 0.0
    mag_ref = None
    if mag is not None:
        m = np.asarray(mag, dtype=float)
        m = m / np.linalg.norm(m)
        mh = Q.rotate(Q.from_euler([roll, pitch, 0.0]), m)
        horiz = np.hypot(mh[0], mh[1])
        if not horiz > 1e-3:
            return None
        yaw = np.arctan2(-mh[1], mh[0])
        mag_ref = np.array([horiz, 0.0, mh[2]])
        mag_ref /= np.linalg.norm(mag_ref)
    return Q.from_euler([roll, pitch, yaw]), mag_ref


class _Base:
    defaults: dict = {}

    def __init__(self, **params):
        p = dict(self.defaults)
        for k, v in params.items():
            if k not in p:
                raise TypeError(f"unknown parameter {k!r}")
            p[k] = float(v)
        self.p = SimpleNamespace(**p)
        self.mag_ref = np.array([1.0, 0.0, 0.0])
        self.mag_sin_dip_sum = 0.0
        self.mag_ref_count = 0
        self.mag_ref_fixed = False
        self.initialized = False

    def set_mag_dip(self, dip):
        self.mag_ref = np.array([np.cos(dip), 0.0, np.sin(dip)])
        self.mag_ref_fixed = True

    def _learn_mag_ref(self, m_n_unit):
        """Average sin(dip) over the first mag_ref_samples samples (unless fixed)."""
        if self.mag_ref_fixed or self.mag_ref_count >= self.p.mag_ref_samples:
            return
        self.mag_sin_dip_sum += m_n_unit[2]
        self.mag_ref_count += 1
        sd = np.clip(self.mag_sin_dip_sum / self.mag_ref_count, -1.0, 1.0)
        self.mag_ref = np.array([np.sqrt(1 - sd * sd), 0.0, sd])

    def update_mag(self, mag, gate=0.0):
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, m = _unit(mag)
        if status != "ok":
            return SimpleNamespace(status=status)
        self._learn_mag_ref(Q.rotate(self.quat, m))
        return self._update3(mag, self.mag_ref[0], self.mag_ref[2], self.p.mag_noise, gate)

    def _init_mag_ref(self, mref):
        if mref is not None:
            if not self.mag_ref_fixed:
                self.mag_sin_dip_sum, self.mag_ref_count = 0.0, 0
            self._learn_mag_ref(mref)

    def update_acc(self, acc, gate=0.0):
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        return self._update3(acc, *GRAVITY_REF, self.p.acc_noise, gate)

    def run(self, gyr, acc, mag=None, dt=None):
        """Same loop as quatnav.batch.hpp: initialize, then predict + update_acc + update_mag."""
        gyr = np.asarray(gyr, float)
        n = len(gyr)
        dt = np.broadcast_to(np.asarray(dt, float), (n,))
        quat = np.empty((n, 4))
        bias = np.empty((n, 3))
        sigma = np.empty((n, self.n_states))
        for k in range(n):
            m = None if mag is None or np.all(np.isnan(mag[k])) else mag[k]
            if not self.initialized:
                self.initialize(acc[k], m)
            else:
                self.predict(gyr[k], dt[k])
                self.update_acc(acc[k])
                if m is not None:
                    self.update_mag(m)
            quat[k] = self.quat
            bias[k] = self.bias
            sigma[k] = np.sqrt(np.maximum(np.diag(self.P), 0))
        return SimpleNamespace(quat=quat, bias=bias, sigma=sigma)


class QuaternionEKF(_Base):
    """Quaternion EKF of paper 000 in numpy. State x = [q0 q1 q2 q3 bx by bz]."""

    defaults = dict(gyro_noise=0.005, gyro_bias_noise=1e-5, acc_noise=0.05, mag_noise=0.1,
                    init_att_sigma=0.05, init_bias_sigma=0.01, mag_ref_samples=100, max_dt=1.0)
    n_states = 7

    def __init__(self, **params):
        super().__init__(**params)
        self.q = Q.identity()
        self.bias = np.zeros(3)
        self.P = np.eye(7)

    @property
    def quat(self):
        return self.q

    # --- model (eq. 6, 9, 10, 11, 12) ---------------------------------------------------
    @staticmethod
    def h(q, rx, rz):
        """eq. (12): C_bn(q) [r_x, 0, r_z] in the paper's quadratic form."""
        q0, q1, q2, q3 = q
        return np.array([
            rx * (1 - 2 * q2 * q2 - 2 * q3 * q3) + 2 * rz * (q1 * q3 - q0 * q2),
            2 * rx * (q1 * q2 - q0 * q3) + 2 * rz * (q2 * q3 + q0 * q1),
            2 * rx * (q1 * q3 + q0 * q2) + rz * (1 - 2 * q1 * q1 - 2 * q2 * q2),
        ])

    @staticmethod
    def H(q, rx, rz):
        """dh/dq as printed under eq. (12) (acceleration rows: r = [0, 0, -1])."""
        q0, q1, q2, q3 = q
        return np.array([
            [-2 * rz * q2, 2 * rz * q3, -4 * rx * q2 - 2 * rz * q0, -4 * rx * q3 + 2 * rz * q1],
            [-2 * rx * q3 + 2 * rz * q1, 2 * rx * q2 + 2 * rz * q0, 2 * rx * q1 + 2 * rz * q3, -2 * rx * q0 + 2 * rz * q2],
            [2 * rx * q2, 2 * rx * q3 - 4 * rz * q1, 2 * rx * q0 - 4 * rz * q2, 2 * rx * q1],
        ])

    @staticmethod
    def propagate(q, bias, gyr, dt):
        """f(x) = [q * exp((w - b) T), b] (exact for a constant rate) and Phi = df/dx."""
        rv = (np.asarray(gyr, float) - bias) * dt
        dq = Q.from_rotvec(rv)
        Phi = np.eye(7)
        Phi[:4, :4] = Q.right(dq)
        Phi[:4, 4:] = -dt * Q.left(q) @ Q.from_rotvec_jacobian(rv)
        return Q.mul(q, dq), Phi

    # --- filter steps -------------------------------------------------------------------
    def initialize(self, acc, mag=None):
        out = attitude_from_acc_mag(acc, mag)
        if out is None:
            return "zero_norm"
        self.q, mref = out
        self.bias = np.zeros(3)
        self._init_mag_ref(mref)
        X = Q.xi(self.q)
        self.P = np.zeros((7, 7))
        self.P[:4, :4] = (self.p.init_att_sigma / 2) ** 2 * X @ X.T
        self.P[4:, 4:] = np.eye(3) * self.p.init_bias_sigma**2
        self.initialized = True
        return "ok"

    def predict(self, gyr, dt):
        if not self.initialized:
            return "not_initialized"
        if not np.all(np.isfinite(gyr)):
            return "non_finite"
        if not (0 < dt <= self.p.max_dt):
            return "invalid_dt"
        q_new, Phi = self.propagate(self.q, self.bias, gyr, dt)
        X = Q.xi(q_new)
        Qn = np.zeros((7, 7))
        Qn[:4, :4] = dt * self.p.gyro_noise**2 / 4 * X @ X.T
        Qn[4:, 4:] = np.eye(3) * dt * self.p.gyro_bias_noise**2
        P = Phi @ self.P @ Phi.T + Qn
        self.P = 0.5 * (P + P.T)
        self.q = q_new / np.linalg.norm(q_new)
        return "ok"

    def _update3(self, v, rx, rz, sigma, gate):
        status, u = _unit(v)
        if status != "ok":
            return SimpleNamespace(status=status)
        H = np.zeros((3, 7))
        H[:, :4] = self.H(self.q, rx, rz)
        return self._correct(H, np.eye(3) * sigma**2, u - self.h(self.q, rx, rz), gate)

    def update_acc_mag(self, acc, mag, gate=0.0):
        sa, a = _unit(acc)
        sm, m = _unit(mag)
        if sa != "ok" or sm != "ok":
            return SimpleNamespace(status=sa if sa != "ok" else sm)
        self._learn_mag_ref(Q.rotate(self.q, m))
        rx, rz = self.mag_ref[0], self.mag_ref[2]
        H = np.zeros((6, 7))
        H[:3, :4] = self.H(self.q, *GRAVITY_REF)
        H[3:, :4] = self.H(self.q, rx, rz)
        y = np.concatenate([a - self.h(self.q, *GRAVITY_REF), m - self.h(self.q, rx, rz)])
        R = np.diag([self.p.acc_noise**2] * 3 + [self.p.mag_noise**2] * 3)
        return self._correct(H, R, y, gate)

    def _correct(self, H, R, y, gate):
        status, dx, P, S, nis = kalman_correct(self.P, H, R, y, gate)
        res = SimpleNamespace(status=status, innovation=y, innovation_cov=S, nis=nis)
        if status != "ok":
            return res
        # The state correction the paper's listing omits, then renormalization with the
        # covariance projected by J = (I - q q^T)/|q|.
        q = self.q + dx[:4]
        n = np.linalg.norm(q)
        qh = q / n
        J = (np.eye(4) - np.outer(qh, qh)) / n
        P[:4, :4] = J @ P[:4, :4] @ J.T
        P[:4, 4:] = J @ P[:4, 4:]
        P[4:, :4] = P[:4, 4:].T
        self.q, self.bias, self.P = qh, self.bias + dx[4:], P
        return res


class EulerEKF(_Base):
    """Euler-angle EKF (paper 000's baseline) in numpy. State [roll, pitch, yaw, bx, by, bz]."""

    defaults = dict(gyro_noise=0.005, gyro_bias_noise=1e-5, acc_noise=0.05, mag_noise=0.1,
                    init_att_sigma=0.05, init_bias_sigma=0.01, mag_ref_samples=100, max_dt=1.0, singular_cos=0.02)
    n_states = 6

    def __init__(self, **params):
        super().__init__(**params)
        self.euler = np.zeros(3)
        self.bias = np.zeros(3)
        self.P = np.eye(6)
        self.near_singularity = False

    @property
    def quat(self):
        return Q.from_euler(self.euler)

    @staticmethod
    def cbn(e):
        """C_bn(e) (paper 000 eq. 1) and its derivatives with respect to roll, pitch, yaw."""
        cr, sr, cp, sp, cy, sy = np.cos(e[0]), np.sin(e[0]), np.cos(e[1]), np.sin(e[1]), np.cos(e[2]), np.sin(e[2])
        Rx = np.array([[1, 0, 0], [0, cr, sr], [0, -sr, cr]])
        Ry = np.array([[cp, 0, -sp], [0, 1, 0], [sp, 0, cp]])
        Rz = np.array([[cy, sy, 0], [-sy, cy, 0], [0, 0, 1]])
        dRx = np.array([[0, 0, 0], [0, -sr, cr], [0, -cr, -sr]])
        dRy = np.array([[-sp, 0, -cp], [0, 0, 0], [cp, 0, -sp]])
        dRz = np.array([[-sy, cy, 0], [-cy, -sy, 0], [0, 0, 0]])
        return Rx @ Ry @ Rz, [dRx @ Ry @ Rz, Rx @ dRy @ Rz, Rx @ Ry @ dRz]

    def propagate(self, e, bias, gyr, dt):
        """e' = e + T E(roll, pitch) (w - b) (paper 004 eq. 1) and its Jacobian F."""
        c = np.cos(e[1])
        singular = abs(c) < self.p.singular_cos
        cp = (-1 if c < 0 else 1) * self.p.singular_cos if singular else c
        sp, cr, sr = np.sin(e[1]), np.cos(e[0]), np.sin(e[0])
        tp = sp / cp
        E = np.array([[1, sr * tp, cr * tp], [0, cr, -sr], [0, sr / cp, cr / cp]])
        w = np.asarray(gyr, float) - bias
        a = w[1] * sr + w[2] * cr
        b = w[1] * cr - w[2] * sr
        F = np.eye(6)
        F[0, 0] += dt * b * sp / cp
        F[1, 0] += -dt * a
        F[2, 0] += dt * b / cp
        if not singular:
            F[0, 1] += dt * a / cp**2
            F[2, 1] += dt * a * sp / cp**2
        F[:3, 3:] = -dt * E
        return e + dt * E @ w, F, E, singular

    def initialize(self, acc, mag=None):
        out = attitude_from_acc_mag(acc, mag)
        if out is None:
            return "zero_norm"
        q, mref = out
        self.euler = Q.to_euler(q)
        self.bias = np.zeros(3)
        self._init_mag_ref(mref)
        self.P = np.diag([self.p.init_att_sigma**2] * 3 + [self.p.init_bias_sigma**2] * 3)
        self.initialized = True
        return "ok"

    def predict(self, gyr, dt):
        if not self.initialized:
            return "not_initialized"
        if not np.all(np.isfinite(gyr)):
            return "non_finite"
        if not (0 < dt <= self.p.max_dt):
            return "invalid_dt"
        e, F, E, singular = self.propagate(self.euler, self.bias, gyr, dt)
        Qn = np.zeros((6, 6))
        Qn[:3, :3] = dt * self.p.gyro_noise**2 * E @ E.T
        Qn[3:, 3:] = np.eye(3) * dt * self.p.gyro_bias_noise**2
        P = F @ self.P @ F.T + Qn
        self.P = 0.5 * (P + P.T)
        e[0], e[2] = Q.wrap_pi(e[0]), Q.wrap_pi(e[2])
        self.euler = e
        self.near_singularity = singular
        return "ok"

    def _update3(self, v, rx, rz, sigma, gate):
        status, u = _unit(v)
        if status != "ok":
            return SimpleNamespace(status=status)
        C, dC = self.cbn(self.euler)
        r = np.array([rx, 0.0, rz])
        H = np.zeros((3, 6))
        for i in range(3):
            H[:, i] = dC[i] @ r
        status, dx, P, S, nis = kalman_correct(self.P, H, np.eye(3) * sigma**2, u - C @ r, gate)
        res = SimpleNamespace(status=status, innovation=u - C @ r, innovation_cov=S, nis=nis)
        if status != "ok":
            return res
        e = self.euler + dx[:3]
        e[0], e[2] = Q.wrap_pi(e[0]), Q.wrap_pi(e[2])
        self.euler, self.bias, self.P = e, self.bias + dx[3:], P
        return res
