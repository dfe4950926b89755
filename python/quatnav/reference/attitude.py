"""Reference (numpy) QuaternionEKF and EulerEKF of paper 000; see quatnav.filters.attitude."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..core import quaternion as Q
from ..filters.tables import EULER_PARAMS, FLAGS, QEKF_PARAMS
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


def table_defaults(table) -> dict:
    """The C++ parameters of a filter with their defaults, from its one table (quatnav.filters.tables).
    The input guards of the C++ step (gyro_range, acc_range, cov_floor) are accepted and not modelled."""
    return {p.name: p.default for p in table if p.core_name is not None}


def make_params(name: str, defaults: dict, given: dict) -> SimpleNamespace:
    """The parameters as attributes: the defaults, overridden by ``given`` (an unknown name is a
    TypeError listing the known ones); each value keeps the type of its default."""
    unknown = sorted(set(given) - set(defaults))
    if unknown:
        raise TypeError(f"{name}: unknown parameter {unknown[0]!r}; known: {', '.join(defaults)}")
    p = dict(defaults)
    for k, v in given.items():
        d = defaults[k]
        p[k] = bool(v) if isinstance(d, bool) else int(v) if isinstance(d, int) else \
            np.asarray(v, float) if isinstance(d, tuple) else float(v)
    return SimpleNamespace(**p)


class _Base:
    defaults: dict = {}

    def __init__(self, **params):
        self.p = make_params(type(self).__name__, self.defaults, params)
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
        return self._update3(mag, self.mag_ref[0], self.mag_ref[2], self.p.mag_sigma, gate)

    def _init_mag_ref(self, mref):
        if mref is not None:
            if not self.mag_ref_fixed:
                self.mag_sin_dip_sum, self.mag_ref_count = 0.0, 0
            self._learn_mag_ref(mref)

    def update_acc(self, acc, gate=0.0):
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        return self._update3(acc, *GRAVITY_REF, self.p.acc_sigma, gate)

    def run(self, gyr, acc, mag=None, dt=None, observer=None):
        """Same loop as quatnav.batch.hpp: initialize, then predict + update_acc + update_mag;
        ``observer.after_predict(k, self)`` and ``after_sample(k, self)`` as there."""
        gyr = np.asarray(gyr, float)
        n = len(gyr)
        dt = np.broadcast_to(np.asarray(dt, float), (n,))
        quat = np.empty((n, 4))
        bias = np.empty((n, 3))
        sigma = np.empty((n, self.n_states))
        flags = np.zeros(n, dtype=np.uint32)
        for k in range(n):
            m = None if mag is None or np.all(np.isnan(mag[k])) else mag[k]
            if not self.initialized:
                self.initialize(acc[k], m)
            else:
                self.predict(gyr[k], dt[k])
                if observer is not None:
                    observer.after_predict(k, self)
                self.update_acc(acc[k])
                if m is not None:
                    self.update_mag(m)
            if observer is not None:
                observer.after_sample(k, self)
            quat[k] = self.quat
            bias[k] = self.bias
            sigma[k] = np.sqrt(np.maximum(np.diag(self.P), 0))
            flags[k] = getattr(self, "flags", 0)
        return SimpleNamespace(quat=quat, bias=bias, sigma=sigma, flags=flags)


def _lowpass(y, x, dt, tau):
    """First-order low-pass step y + a (x - y), a = dt / (tau + dt) (as quaternion_ekf.hpp)."""
    a = dt / (tau + dt)
    return y + a * (x - y)


FLAG_ACC_REJECTED, FLAG_MAG_REJECTED, FLAG_AT_REST = FLAGS["acc_rejected"], FLAGS["mag_rejected"], FLAGS["at_rest"]


class QuaternionEKF(_Base):
    """Quaternion EKF of paper 000 in numpy, with the robustness options of quaternion_ekf.hpp.

    State x = [q0 q1 q2 q3 bx by bz]. ``QuaternionEKF(paper=True)`` is the plain paper filter.
    """

    defaults = table_defaults(QEKF_PARAMS)
    #: QuaternionEKFParams::paper(): the plain filter of paper 000 (a test compares it with the C++).
    paper_overrides = dict(gyro_noise=0.005, gyro_bias_noise=1e-5, acc_sigma=0.05, mag_sigma=0.1,
                           init_att_sigma=0.05, init_gyro_bias_sigma=0.01, mag_heading_only=False, acc_adapt=0.0,
                           acc_reject=0.0, acc_gate=0.0, acc_recovery_time=0.0, acc_lp_tau=0.0,
                           acc_lp_bias_sigma=0.0, mag_norm_tol=0.0, mag_dip_tol=0.0, mag_gate=0.0,
                           mag_settle_time=0.0, mag_ref_tau=0.0, mag_recovery_time=0.0, rest_detection=False)
    n_states = 7

    def __new__(cls, paper=False, **params):
        # As the public QuaternionEKF: the default is the 6-state error-state filter
        # (QuaternionESKF), paper=True the 7-state filter of paper 000 (QuaternionEKF7 with the
        # robust defaults).
        if cls is QuaternionEKF and not paper:
            return super().__new__(QuaternionESKF)
        return super().__new__(cls)

    def __init__(self, paper=False, **params):
        if paper:
            params = {**self.paper_overrides, **params}
        super().__init__(**params)
        self.q = Q.identity()
        self.bias = np.zeros(3)
        self.P = np.eye(7)
        self._reset_bookkeeping()
        self.mag_norm_ref = 0.0
        self.flags = 0

    def _reset_bookkeeping(self):
        self.gyr_last = np.zeros(3)
        self.dt_last = 0.0
        self.gyr_lp = np.zeros(3)
        self.acc_lp = np.zeros(3)
        self.lp_init = False
        self.rest_t = 0.0
        self.acc_reject_t = 0.0
        self.mag_reject_t = 0.0
        self.mag_ok_t = 1e9
        self.q_i = Q.identity()
        self.acc_i_lp = np.zeros(3)
        self.acc_lp_init = False

    @property
    def at_rest(self):
        return self.p.rest_detection and self.rest_t >= self.p.rest_time

    @property
    def quat(self):
        return self.q

    # --- model (eq. 6, 9, 10, 11, 12) ---------------------------------------------------
    @staticmethod
    def h(q, rx, rz, ry=0.0):
        """eq. (12): C_bn(q) [r_x, r_y, r_z] in the paper's quadratic form (the paper has r_y = 0;
        r_y != 0 is the reference field in a true-north frame, see ``declination``)."""
        q0, q1, q2, q3 = q
        return np.array([
            rx * (1 - 2 * q2 * q2 - 2 * q3 * q3) + 2 * ry * (q1 * q2 + q0 * q3) + 2 * rz * (q1 * q3 - q0 * q2),
            2 * rx * (q1 * q2 - q0 * q3) + ry * (1 - 2 * q1 * q1 - 2 * q3 * q3) + 2 * rz * (q2 * q3 + q0 * q1),
            2 * rx * (q1 * q3 + q0 * q2) + 2 * ry * (q2 * q3 - q0 * q1) + rz * (1 - 2 * q1 * q1 - 2 * q2 * q2),
        ])

    @staticmethod
    def H(q, rx, rz, ry=0.0):
        """dh/dq as printed under eq. (12) (acceleration rows: r = [0, 0, -1]), plus the r_y terms."""
        q0, q1, q2, q3 = q
        H = np.array([
            [-2 * rz * q2, 2 * rz * q3, -4 * rx * q2 - 2 * rz * q0, -4 * rx * q3 + 2 * rz * q1],
            [-2 * rx * q3 + 2 * rz * q1, 2 * rx * q2 + 2 * rz * q0, 2 * rx * q1 + 2 * rz * q3, -2 * rx * q0 + 2 * rz * q2],
            [2 * rx * q2, 2 * rx * q3 - 4 * rz * q1, 2 * rx * q0 - 4 * rz * q2, 2 * rx * q1],
        ])
        if ry != 0.0:
            H += ry * np.array([[2 * q3, 2 * q2, 2 * q1, 2 * q0],
                                [0.0, -4 * q1, 0.0, -4 * q3],
                                [-2 * q1, -2 * q0, 2 * q3, 2 * q2]])
        return H

    def mag_reference(self):
        """The reference field (r_x, r_z, r_y) in the filter's frame: the learned [m_x, 0, m_z]
        (magnetic north) turned by the declination about down when x is true north."""
        rx, rz = self.mag_ref[0], self.mag_ref[2]
        d = self.p.declination
        if d == 0.0:
            return rx, rz, 0.0
        return rx * np.cos(d), rz, rx * np.sin(d)

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
        if mref is not None and self.p.declination != 0.0:
            # magnetic heading + declination = true heading
            self.q = Q.mul(Q.from_rotvec([0.0, 0.0, self.p.declination]), self.q)
        self.bias = np.zeros(3)
        self._reset_bookkeeping()
        self.flags = 0
        self._init_mag_ref(mref)
        if mref is not None:
            self.mag_norm_ref = float(np.linalg.norm(mag))
        X = Q.xi(self.q)
        self.P = np.zeros((7, 7))
        self.P[:4, :4] = (self.p.init_att_sigma / 2) ** 2 * X @ X.T
        self.P[4:, 4:] = np.eye(3) * self.p.init_gyro_bias_sigma**2
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
        # Bookkeeping of the robustness features.
        self.flags = 0
        gyr = np.asarray(gyr, float)
        if self.p.acc_lp_tau > 0:
            qi = Q.mul(self.q_i, Q.from_rotvec((gyr - self.bias) * dt))
            self.q_i = qi / np.linalg.norm(qi)
        self.gyr_last = gyr.copy()
        self.dt_last = dt
        if self.p.rest_detection and self.lp_init:
            self.gyr_lp = _lowpass(self.gyr_lp, gyr, dt, self.p.rest_tau)
        return "ok"

    # --- robustness ---------------------------------------------------------------------
    def update_acc(self, acc, gate=0.0):
        """Accelerometer update with rest detection, low-pass, rejection and adaptive noise."""
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, _ = _unit(acc)
        if status != "ok":
            return SimpleNamespace(status=status)
        acc = np.asarray(acc, float)
        dt = self.dt_last
        p = self.p
        if p.rest_detection:
            self._rest_step(acc)
        acc_used = acc
        if p.acc_lp_tau > 0:
            a_i = Q.rotate(self.q_i, acc)
            if not self.acc_lp_init or not dt > 0:
                self.acc_i_lp = a_i
                self.acc_lp_init = True
            else:
                self.acc_i_lp = _lowpass(self.acc_i_lp, a_i, dt, self._acc_lp_tau())
            acc_used = Q.rotate_inv(self.q_i, self.acc_i_lp)
        g = p.gravity
        dev = abs(np.linalg.norm(acc_used) - g) if g > 0 else 0.0
        recovering = p.acc_recovery_time > 0 and self.acc_reject_t >= p.acc_recovery_time
        if p.acc_reject > 0 and dev > p.acc_reject and not recovering:
            if p.acc_recovery_time > 0:
                self.acc_reject_t += dt
            self.flags |= FLAG_ACC_REJECTED
            return SimpleNamespace(status="rejected")
        sigma = p.acc_sigma + (p.acc_adapt * dev / g if g > 0 else 0.0)
        gt = gate if gate > 0 else (0.0 if recovering else p.acc_gate)
        res = self._update3(acc_used, *GRAVITY_REF, sigma, gt)
        if res.status == "ok":
            self.acc_reject_t = 0.0
        elif res.status == "rejected":
            if p.acc_recovery_time > 0:
                self.acc_reject_t += dt
            self.flags |= FLAG_ACC_REJECTED
        return res

    def _acc_lp_tau(self):
        return self.p.acc_lp_tau  # the 7-state filter ignores acc_lp_bias_sigma

    def _rest_step(self, acc):
        p, dt = self.p, self.dt_last
        if not self.lp_init or not dt > 0:
            self.gyr_lp = self.gyr_last.copy()
            self.acc_lp = acc.copy()
            self.lp_init = dt > 0
            self.rest_t = 0.0
            return
        self.acc_lp = _lowpass(self.acc_lp, acc, dt, p.rest_tau)
        still = (np.linalg.norm(self.gyr_last - self.gyr_lp) < p.rest_gyr_th
                 and np.linalg.norm(self.gyr_lp - self.bias) < p.rest_gyr_th
                 and np.linalg.norm(acc - self.acc_lp) < p.rest_acc_th)
        self.rest_t = self.rest_t + dt if still else 0.0
        if self.rest_t < p.rest_time:
            return
        self.flags |= FLAG_AT_REST
        H = np.zeros((3, self.n_states))
        H[:, -3:] = np.eye(3)
        r = p.gyro_noise**2 / dt + p.rest_rate_noise**2
        self._correct(H, np.eye(3) * r, self.gyr_last - self.bias, 0.0)

    def update_mag(self, mag, gate=0.0):
        """Magnetometer update: disturbance tests, then heading-only (or paper) update."""
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, m = _unit(mag)
        if status != "ok":
            return SimpleNamespace(status=status)
        p = self.p
        mnorm = float(np.linalg.norm(mag))
        self._learn_mag_ref(Q.rotate(self.q, m))
        if not self.mag_norm_ref > 0:
            self.mag_norm_ref = mnorm
        dt = self.dt_last
        mn = Q.rotate(self.q, m)
        dip = np.arcsin(np.clip(mn[2], -1.0, 1.0))
        dip_ref = np.arctan2(self.mag_ref[2], self.mag_ref[0])
        disturbed = ((p.mag_norm_tol > 0 and abs(mnorm / self.mag_norm_ref - 1) > p.mag_norm_tol)
                     or (p.mag_dip_tol > 0 and abs(dip - dip_ref) > p.mag_dip_tol))
        if p.mag_settle_time > 0:
            self.mag_ok_t = 0.0 if disturbed else self.mag_ok_t + dt
        if not disturbed and self.mag_ok_t < p.mag_settle_time:
            self.mag_reject_t += dt
            self.flags |= FLAG_MAG_REJECTED
            return SimpleNamespace(status="rejected")
        if disturbed:
            self.mag_reject_t += dt
            if not (p.mag_recovery_time > 0 and self.mag_reject_t >= p.mag_recovery_time):
                self.flags |= FLAG_MAG_REJECTED
                return SimpleNamespace(status="rejected")
            if not self.mag_ref_fixed:
                self.mag_sin_dip_sum, self.mag_ref_count = 0.0, 0
                self._learn_mag_ref(mn)
            self.mag_norm_ref = mnorm
        gt = gate if gate > 0 else p.mag_gate
        if p.mag_heading_only:
            res = self.update_heading(m, gt)
        else:
            rx, rz, ry = self.mag_reference()
            res = self._update3(mag, rx, rz, p.mag_sigma, gt, ry=ry)
        if res.status == "ok":
            self.mag_reject_t = 0.0
            if p.mag_ref_tau > 0 and dt > 0:
                if not self.mag_ref_fixed and self.mag_ref_count >= p.mag_ref_samples:
                    mn2 = Q.rotate(self.q, m)
                    dip2 = np.arcsin(np.clip(mn2[2], -1.0, 1.0))
                    d = _lowpass(dip_ref, dip2, dt, p.mag_ref_tau)
                    self.mag_ref = np.array([np.cos(d), 0.0, np.sin(d)])
                self.mag_norm_ref = _lowpass(self.mag_norm_ref, mnorm, dt, p.mag_ref_tau)
        elif res.status == "rejected":
            if p.mag_recovery_time > 0:
                self.mag_reject_t += dt
            self.flags |= FLAG_MAG_REJECTED
        return res

    @staticmethod
    def heading_model(q, m_unit):
        """h(q) = atan2(m_n,y, m_n,x) with m_n = C_nb m; H keeps its yaw part only.

        Returns (h, horiz2, H (4,), u (4,), J_tilt (2,)) or None for a vertical field.
        """
        mn = Q.rotate(q, m_unit)
        horiz2 = mn[0] ** 2 + mn[1] ** 2
        if not horiz2 > 1e-6:
            return None
        h = np.arctan2(mn[1], mn[0])
        dpsi = np.array([-mn[1] / horiz2, mn[0] / horiz2, 0.0])
        J = -dpsi @ Q.skew(mn)
        u = Q.right(q)[:, 3]
        return h, horiz2, 2.0 * u, u, J[:2]

    def update_heading(self, m_unit, gate=0.0):
        """Heading-only magnetometer update with the gain projected on the yaw direction."""
        out = self.heading_model(self.q, m_unit)
        if out is None:
            return SimpleNamespace(status="zero_norm")
        h, horiz2, Hq, u, Jt = out
        R3 = Q.right(self.q)[:, 1:]
        Sphi = 4.0 * R3.T @ self.P[:4, :4] @ R3
        R = self.p.mag_sigma**2 / horiz2 + Jt @ Sphi[:2, :2] @ Jt
        H = np.zeros(7)
        H[:4] = Hq
        y = float(Q.wrap_pi(self.p.declination - h))  # the field's heading is the declination
        PHt = self.P @ H
        Sv = H @ PHt + R
        res = SimpleNamespace(status="ok", innovation=np.array([y, 0.0, 0.0]),
                              innovation_cov=np.diag([Sv, 0.0, 0.0]), nis=y * y / Sv)
        if gate > 0 and not res.nis <= gate:
            res.status = "rejected"
            return res
        K = PHt / Sv
        K[:4] = u * (u @ K[:4])
        IKH = np.eye(7) - np.outer(K, H)
        P = IKH @ self.P @ IKH.T + R * np.outer(K, K)
        P = 0.5 * (P + P.T)
        dx = K * y
        q = self.q + dx[:4]
        n = np.linalg.norm(q)
        qh = q / n
        J = (np.eye(4) - np.outer(qh, qh)) / n
        P[:4, :4] = J @ P[:4, :4] @ J.T
        P[:4, 4:] = J @ P[:4, 4:]
        P[4:, :4] = P[:4, 4:].T
        self.q, self.bias, self.P = qh, self.bias + dx[4:], P
        return res

    def _update3(self, v, rx, rz, sigma, gate, ry=0.0):
        status, u = _unit(v)
        if status != "ok":
            return SimpleNamespace(status=status)
        H = np.zeros((3, 7))
        H[:, :4] = self.H(self.q, rx, rz, ry)
        return self._correct(H, np.eye(3) * sigma**2, u - self.h(self.q, rx, rz, ry), gate)

    def update_acc_mag(self, acc, mag, gate=0.0):
        sa, a = _unit(acc)
        sm, m = _unit(mag)
        if sa != "ok" or sm != "ok":
            return SimpleNamespace(status=sa if sa != "ok" else sm)
        self._learn_mag_ref(Q.rotate(self.q, m))
        r = self.mag_reference()
        H = np.zeros((6, 7))
        H[:3, :4] = self.H(self.q, *GRAVITY_REF)
        H[3:, :4] = self.H(self.q, *r)
        y = np.concatenate([a - self.h(self.q, *GRAVITY_REF), m - self.h(self.q, *r)])
        R = np.diag([self.p.acc_sigma**2] * 3 + [self.p.mag_sigma**2] * 3)
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


class QuaternionEKF7(QuaternionEKF):
    """The 7-state filter [q, b] of paper 000 whatever ``paper`` says (the robust defaults
    without ``paper=True``); ``QuaternionEKF(paper=True)`` is this class."""


class QuaternionESKF(QuaternionEKF):
    """The 6-state error-state form of :class:`QuaternionEKF` (quaternion_eskf.hpp), in numpy.

    Nominal state [q, b]; covariance of dx = [dtheta, db] with q_true = q * exp(dtheta)
    (dtheta in the body frame). Same parameters, measurements and robustness steps.
    """

    n_states = 6

    def initialize(self, acc, mag=None):
        status = super().initialize(acc, mag)
        if status == "ok":
            self.P = np.diag([self.p.init_att_sigma**2] * 3 + [self.p.init_gyro_bias_sigma**2] * 3)
        return status

    def _acc_lp_tau(self):
        sb = self.p.acc_lp_bias_sigma
        vb = np.max(np.diag(self.P)[3:])
        return self.p.acc_lp_tau * (sb * sb / vb) if sb > 0 and vb > sb * sb else self.p.acc_lp_tau

    @staticmethod
    def propagate(q, bias, gyr, dt):
        """q+ = q * exp((w - b) dt); Phi = [C(dq)^T, -dt I; 0, I]."""
        dq = Q.from_rotvec((np.asarray(gyr, float) - bias) * dt)
        Phi = np.eye(6)
        Phi[:3, :3] = Q.to_rotmat(dq).T
        Phi[:3, 3:] = -dt * np.eye(3)
        return Q.mul(q, dq), Phi

    def predict(self, gyr, dt):
        if not self.initialized:
            return "not_initialized"
        if not np.all(np.isfinite(gyr)):
            return "non_finite"
        if not (0 < dt <= self.p.max_dt):
            return "invalid_dt"
        q_new, Phi = self.propagate(self.q, self.bias, gyr, dt)
        Qn = np.diag([dt * self.p.gyro_noise**2] * 3 + [dt * self.p.gyro_bias_noise**2] * 3)
        P = Phi @ self.P @ Phi.T + Qn
        self.P = 0.5 * (P + P.T)
        self.q = q_new / np.linalg.norm(q_new)
        self.flags = 0
        gyr = np.asarray(gyr, float)
        if self.p.acc_lp_tau > 0:
            qi = Q.mul(self.q_i, Q.from_rotvec((gyr - self.bias) * dt))
            self.q_i = qi / np.linalg.norm(qi)
        self.gyr_last = gyr.copy()
        self.dt_last = dt
        if self.p.rest_detection and self.lp_init:
            self.gyr_lp = _lowpass(self.gyr_lp, gyr, dt, self.p.rest_tau)
        return "ok"

    @staticmethod
    def direction_model(q, r_n):
        """h = C_bn(q) r_n and dh/d[dtheta, db] = [[h x], 0]."""
        h = Q.rotate(Q.conj(q), r_n)
        H = np.zeros((3, 6))
        H[:, :3] = Q.skew(h)
        return h, H

    def _mag_reference_vector(self):
        rx, rz, ry = self.mag_reference()
        return np.array([rx, ry, rz])

    def _update3(self, v, rx, rz, sigma, gate, ry=0.0):
        status, u = _unit(v)
        if status != "ok":
            return SimpleNamespace(status=status)
        h, H = self.direction_model(self.q, np.array([rx, ry, rz]))
        return self._correct(H, np.eye(3) * sigma**2, u - h, gate)

    def update_acc_mag(self, acc, mag, gate=0.0):
        sa, a = _unit(acc)
        sm, m = _unit(mag)
        if sa != "ok" or sm != "ok":
            return SimpleNamespace(status=sa if sa != "ok" else sm)
        self._learn_mag_ref(Q.rotate(self.q, m))
        ha, Ha = self.direction_model(self.q, np.array([0.0, 0.0, -1.0]))
        hm, Hm = self.direction_model(self.q, self._mag_reference_vector())
        R = np.diag([self.p.acc_sigma**2] * 3 + [self.p.mag_sigma**2] * 3)
        return self._correct(np.vstack([Ha, Hm]), R, np.concatenate([a - ha, m - hm]), gate)

    def update_heading(self, m_unit, gate=0.0):
        """Heading-only update: H = [u^T, 0] with u = C_nb^T e_z, gain projected on u, R
        inflated by the navigation-frame tilt covariance seen through the field's dip."""
        C = Q.to_rotmat(self.q)
        mn = C @ m_unit
        horiz2 = mn[0] ** 2 + mn[1] ** 2
        if not horiz2 > 1e-6:
            return SimpleNamespace(status="zero_norm")
        h = np.arctan2(mn[1], mn[0])
        J = -np.array([-mn[1] / horiz2, mn[0] / horiz2, 0.0]) @ Q.skew(mn)
        u = C[2]
        vt = C[0] * J[0] + C[1] * J[1]
        R = self.p.mag_sigma**2 / horiz2 + vt @ self.P[:3, :3] @ vt
        H = np.zeros(6)
        H[:3] = u
        y = float(Q.wrap_pi(self.p.declination - h))
        PHt = self.P @ H
        Sv = H @ PHt + R
        res = SimpleNamespace(status="ok", innovation=np.array([y, 0.0, 0.0]),
                              innovation_cov=np.diag([Sv, 0.0, 0.0]), nis=y * y / Sv)
        if gate > 0 and not res.nis <= gate:
            res.status = "rejected"
            return res
        K = PHt / Sv
        K[:3] = u * (u @ K[:3])
        IKH = np.eye(6) - np.outer(K, H)
        P = IKH @ self.P @ IKH.T + R * np.outer(K, K)
        self._inject(K * y, 0.5 * (P + P.T))
        return res

    def _correct(self, H, R, y, gate):
        status, dx, P, S, nis = kalman_correct(self.P, H, R, y, gate)
        res = SimpleNamespace(status=status, innovation=y, innovation_cov=S, nis=nis)
        if status == "ok":
            self._inject(dx, P)
        return res

    def _inject(self, dx, P):
        """q <- q * exp(dtheta), b <- b + db; covariance reset G = I - [dtheta/2 x]."""
        G = np.eye(6)
        G[:3, :3] -= Q.skew(0.5 * dx[:3])
        P = G @ P @ G.T
        q = Q.mul(self.q, Q.from_rotvec(dx[:3]))
        self.q, self.bias, self.P = q / np.linalg.norm(q), self.bias + dx[3:], 0.5 * (P + P.T)


class EulerEKF(_Base):
    """Euler-angle EKF (paper 000's baseline) in numpy. State [roll, pitch, yaw, bx, by, bz]."""

    defaults = table_defaults(EULER_PARAMS)
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
        self.P = np.diag([self.p.init_att_sigma**2] * 3 + [self.p.init_gyro_bias_sigma**2] * 3)
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
