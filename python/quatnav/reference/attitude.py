"""Reference (numpy) QuaternionEKF and EulerEKF of paper 000; see quatnav.filters.attitude.

The robustness parts (rest detection, the accelerometer part, the magnetometer reference and
disturbance tests) are the twins of :mod:`quatnav.reference.parts`, composed as in the C++ filters.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from .._validate import did_you_mean
from ..core import quaternion as Q
from ..filters.tables import EULER_PARAMS, FLAGS, QEKF_PARAMS
from .kalman import kalman_correct, kalman_correct_rows
from .parts import AccFilter, GyroClip, MagDisturbance, Rest

GRAVITY_REF = (0.0, -1.0)  # [r_x, r_z] of the normalized specific force at rest, NED


def _unit(v):
    v = np.asarray(v, dtype=float)
    if not np.all(np.isfinite(v)):
        return "non_finite", None
    with np.errstate(over="ignore"):
        n = np.linalg.norm(v)
    if not np.isfinite(n):  # finite components whose norm overflows (detail::unit_vector)
        return "non_finite", None
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
        raise TypeError(f"{name}: unknown parameter {unknown[0]!r}{did_you_mean(unknown[0], defaults)}; "
                        f"known: {', '.join(defaults)}")
    p = dict(defaults)
    for k, v in given.items():
        d = defaults[k]
        p[k] = bool(v) if isinstance(d, bool) else int(v) if isinstance(d, int) else \
            np.asarray(v, float) if isinstance(d, tuple) else float(v)
    return SimpleNamespace(**p)


class _Base:
    defaults: dict = {}
    rts_model = None  # the 7-state filter of paper 000 has no smoother (neither has the C++ one)

    def __init__(self, **params):
        self.p = make_params(type(self).__name__, self.defaults, params)
        self.mag = MagDisturbance(self.p)  # the reference field (and its disturbance tests)
        self.initialized = False
        self.flags = 0  # the parts' flags of the current sample

    @property
    def mag_ref(self):
        """The reference field [m_x, 0, m_z]."""
        return self.mag.ref.mag_ref

    def set_mag_dip(self, dip):
        self.mag.ref.fix(dip)

    def update_mag(self, mag, gate=0.0):
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, m = _unit(mag)
        if status != "ok":
            return SimpleNamespace(status=status)
        before = self.mag.ref.copy()
        self.mag.ref.learn(Q.rotate(self.quat, m), self.p.mag_ref_samples)
        res = self._update3(mag, self.mag_ref[0], self.mag_ref[2], self.p.mag_sigma, gate)
        if res.status != "ok":
            self.mag.ref = before  # a refused update changes nothing
        return res

    def update_acc(self, acc, gate=0.0):
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        return self._update3(acc, *GRAVITY_REF, self.p.acc_sigma, gate)

    def run(self, gyr, acc, mag=None, *, t=None, dt=None, smooth=False, observer=None):
        """The loop of run_attitude_batch (attitude/batch.hpp) with the public ``run``'s signature:
        initialize at the first sample, then predict, update_acc and update_mag (an all-NaN
        magnetometer row: no sample). Times as ``t`` (timestamps) or ``dt`` (a step or one per
        sample). Returns ``t``, ``quat``, ``bias``, ``sigma`` and the parts' ``flags``.
        ``smooth=True`` (QuaternionEKF, EulerEKF: ``rts_model``): the smoothed estimates
        (:func:`quatnav.reference.attitude_smoother.run_smoothed`), the forward ones in ``forward``.
        ``observer.after_predict(k, self)`` and ``after_sample(k, self)`` as in batch.hpp."""
        gyr, acc = np.asarray(gyr, float), np.asarray(acc, float)
        if smooth:
            from .attitude_smoother import run_smoothed
            t, steps = sample_times(len(gyr), t, dt)
            out = run_smoothed(self, gyr, acc, mag, dt=steps)
            sm = out.smoothed
            return SimpleNamespace(t=t, quat=sm.quat, bias=sm.bias, sigma=sm.sigma, flags=out.flags, forward=out)
        n = len(gyr)
        t, steps = sample_times(n, t, dt)
        quat, bias, sigma = np.empty((n, 4)), np.empty((n, 3)), np.empty((n, self.n_states))
        flags = np.zeros(n, dtype=np.uint32)
        for k in range(n):
            m = None if mag is None or np.all(np.isnan(mag[k])) else mag[k]
            if not self.initialized:
                self.initialize(acc[k], m)
            else:
                self.predict(gyr[k], steps[k])
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
            flags[k] = self.flags
        return SimpleNamespace(t=t, quat=quat, bias=bias, sigma=sigma, flags=flags)


def sample_times(n, t=None, dt=None):
    """(t, steps) of n samples, as the public filters read their times: ``dt`` a step or one per
    sample (t: 0 and the cumulated steps after the first), or timestamps ``t`` (the first step
    repeats t[1] - t[0]). Exactly one of them."""
    if (t is None) == (dt is None):
        raise ValueError("dt, t: give exactly one of dt (seconds) or t (timestamps, seconds)")
    if t is not None:
        t = np.asarray(t, float)
        d = np.diff(t)
        return t, np.concatenate([d[:1], d])
    steps = np.broadcast_to(np.asarray(dt, float), (n,)).copy()
    return np.concatenate([[0.0], np.cumsum(steps[1:])]) if n else np.zeros(0), steps


FLAG_ACC_REJECTED, FLAG_MAG_REJECTED, FLAG_AT_REST = FLAGS["acc_rejected"], FLAGS["mag_rejected"], FLAGS["at_rest"]


def tilt_rate_noise(q, rate, k, dt):
    """The rate-proportional tilt noise (attitude.hpp ``detail::tilt_rate_noise``):
    ``dt (k |rate|)^2 (I - u u^T)``, u the body-frame vertical of ``q`` (rad^2, body frame)."""
    q = np.asarray(q, float) / np.linalg.norm(q)
    u = Q.rotate(Q.conj(q), np.array([0.0, 0.0, 1.0]))
    return dt * (k * np.linalg.norm(rate)) ** 2 * (np.eye(3) - np.outer(u, u))


class QuaternionEKF(_Base):
    """Quaternion EKF of paper 000 in numpy, with the robustness options of quaternion_ekf_paper.hpp.

    State x = [q0 q1 q2 q3 bx by bz]. ``QuaternionEKF(paper=True)`` is the plain paper filter.
    """

    defaults = table_defaults(QEKF_PARAMS)
    #: QuaternionEKFParams::paper(): the plain filter of paper 000 (a test compares it with the C++).
    paper_overrides = dict(gyro_noise=0.005, gyro_bias_noise=1e-5, gyro_rate_noise=0.0, acc_sigma=0.05, mag_sigma=0.1,
                           init_att_sigma=0.05, init_gyro_bias_sigma=0.01, mag_heading_only=False,
                           acc_tilt_only=False, acc_adapt=0.0,
                           acc_reject=0.0, acc_gate=0.0, acc_recovery_time=0.0, acc_lp_tau=0.0,
                           acc_lp_bias_sigma=0.0, acc_lp_dev=0.0, acc_bias_dev=0.0, mag_norm_tol=0.0, mag_dip_tol=0.0, mag_dip_sigmas=0.0, mag_gate=0.0,
                           mag_settle_time=0.0, mag_ref_tau=0.0, mag_recovery_time=0.0, rest_detection=False,
                           gyro_clip=False)
    n_states = 7

    def __new__(cls, paper=False, **params):
        # As the public QuaternionEKF: the default is the 6-state error-state filter
        # (_QuaternionEKFErrorState), paper=True the 7-state filter of paper 000 (QuaternionEKFPaper with the
        # robust defaults).
        if cls is QuaternionEKF and not paper:
            return super().__new__(_QuaternionEKFErrorState)
        return super().__new__(cls)

    def __init__(self, paper=False, **params):
        if paper:
            params = {**self.paper_overrides, **params}
        super().__init__(**params)
        self.q = Q.identity()
        self.bias = np.zeros(3)
        self.P = np.eye(7)
        self.dt_last = 0.0
        self.rest, self.acc = Rest(self.p), AccFilter(self.p)
        self.clip = GyroClip(self.p)  # parts/gyro_clip.hpp (the quaternion EKFs)
        self.flags = 0

    @property
    def at_rest(self):
        return self.rest.at_rest()

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
        """f(x) = [q * exp((w - b) T), b] (exact for a constant rate), Phi = df/dx and the step's dq."""
        rv = (np.asarray(gyr, float) - bias) * dt
        dq = Q.from_rotvec(rv)
        Phi = np.eye(7)
        Phi[:4, :4] = Q.right(dq)
        Phi[:4, 4:] = -dt * Q.left(q) @ Q.from_rotvec_jacobian(rv)
        return Q.mul(q, dq), Phi, dq

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
        self.dt_last = 0.0
        self.rest.restart()
        self.acc.restart()
        self.mag.restart()
        self.clip.restart()
        self.flags = 0
        if mref is not None:
            self.mag.start(mref, np.linalg.norm(mag))
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
        q_new, Phi, dq = self.propagate(self.q, self.bias, gyr, dt)
        X = Q.xi(q_new)
        Qn = np.zeros((7, 7))
        Qn[:4, :4] = dt * self.p.gyro_noise**2 / 4 * X @ X.T
        if self.p.gyro_rate_noise > 0:
            Qn[:4, :4] += X @ tilt_rate_noise(q_new, np.asarray(gyr, float) - self.bias,
                                              self.p.gyro_rate_noise, dt) @ X.T / 4
        clip_var = self.clip.step(gyr, dt)
        if clip_var.any():  # gyro_clip.hpp, mapped by X / 2 as the tilt noise
            Qn[:4, :4] += X @ np.diag(clip_var) @ X.T / 4
        Qn[4:, 4:] = np.eye(3) * dt * self.p.gyro_bias_noise**2
        P = Phi @ self.P @ Phi.T + Qn
        self.P = 0.5 * (P + P.T)
        self.q = q_new / np.linalg.norm(q_new)
        self._parts_predict(gyr, dq, dt, clip_var)
        return "ok"

    def _parts_predict(self, gyr, dq, dt, clip_var):
        self.flags = 0
        self.dt_last = dt
        self.acc.predict(dq)
        if clip_var.any():  # the low-pass frame was carried by a clipped rate
            self.acc.restart()
        self.rest.predict(gyr, dt)

    # --- measurements with the robustness parts -------------------------------------------
    def update_acc(self, acc, gate=0.0):
        """Accelerometer update: the rest test (at rest a zero-rate update of the bias), then the
        accelerometer part's low-pass, rejection and adaptive noise, then rows 1-3 of eq. (12)."""
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, _ = _unit(acc)
        if status != "ok":
            return SimpleNamespace(status=status)
        if self.rest.update(acc, self.bias, self.dt_last):
            self._update_zero_rate()
        res = self.acc.update(acc, self.dt_last, self._max_bias_var(), lambda a: self._update_gravity(
            a.acc, self.p.acc_sigma + a.sigma_add, a.gate(gate, self.p.acc_gate)), self._acc_up())
        if res.status == "rejected":
            self.flags |= FLAG_ACC_REJECTED
        return res

    def _max_bias_var(self):
        return 0.0  # the 7-state filter keeps acc_lp_tau (acc_lp_bias_sigma: error-state filter only)

    def _acc_up(self):
        return None  # the 7-state filter uses no bias weight (error-state filter only)

    def _update_gravity(self, acc, sigma, gate):
        """The accelerometer's rows 1-3 of eq. (12) (the 7-state filter: the paper's update)."""
        return self._update3(acc, *GRAVITY_REF, sigma, gate)

    def _update_zero_rate(self):
        self.flags |= FLAG_AT_REST
        H = np.zeros((3, self.n_states))
        H[:, -3:] = np.eye(3)
        r = self.rest.zero_rate_variance(self.p.gyro_noise, self.dt_last)
        self._correct(H, np.eye(3) * r, self.rest.zero_rate_innovation(self.bias), 0.0)

    def update_mag(self, mag, gate=0.0):
        """Magnetometer update: the magnetometer part's disturbance tests, then the heading-only
        (or the paper's 3-row) update."""
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, m = _unit(mag)
        if status != "ok":
            return SimpleNamespace(status=status)
        gt = gate if gate > 0 else self.p.mag_gate

        def update():
            if self.p.mag_heading_only:
                return self.update_heading(m, gt)
            rx, rz, ry = self.mag_reference()
            return self._update3(mag, rx, rz, self.p.mag_sigma, gt, ry=ry)

        field_n = lambda: Q.rotate(self.q, m)  # noqa: E731
        dip_var = self.mag.dip_variance(self.q, field_n(), self.attitude_covariance())
        res = self.mag.update(np.linalg.norm(mag), field_n, self.dt_last, update, dip_var)
        if res.status == "rejected":
            self.flags |= FLAG_MAG_REJECTED
        return res

    def attitude_covariance(self):
        """Covariance of the body-frame rotation vector: 4 Xi^T P_qq Xi (quat_block.hpp)."""
        X = Q.xi(self.q)
        return 4.0 * X.T @ self.P[:4, :4] @ X

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
        before = self.mag.ref.copy()
        self.mag.ref.learn(Q.rotate(self.q, m), self.p.mag_ref_samples)
        r = self.mag_reference()
        H = np.zeros((6, 7))
        H[:3, :4] = self.H(self.q, *GRAVITY_REF)
        H[3:, :4] = self.H(self.q, *r)
        y = np.concatenate([a - self.h(self.q, *GRAVITY_REF), m - self.h(self.q, *r)])
        R = np.diag([self.p.acc_sigma**2] * 3 + [self.p.mag_sigma**2] * 3)
        res = self._correct(H, R, y, gate)
        if res.status != "ok":
            self.mag.ref = before  # a refused update changes nothing
        return res

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


class QuaternionEKFPaper(QuaternionEKF):
    """The 7-state filter [q, b] of paper 000 whatever ``paper`` says (the robust defaults
    without ``paper=True``); ``QuaternionEKF(paper=True)`` is this class."""


class _QuaternionEKFErrorState(QuaternionEKF):
    """The 6-state error-state form of :class:`QuaternionEKF` (quaternion_ekf.hpp), in numpy.

    Nominal state [q, b]; covariance of dx = [dtheta, db] with q_true = q * exp(dtheta)
    (dtheta in the body frame). Same parameters, measurements and robustness steps.
    """

    #: The model of its smoother (quatnav.reference.attitude_smoother).
    rts_model = "ESKFModel"

    n_states = 6

    def initialize(self, acc, mag=None):
        status = super().initialize(acc, mag)
        if status == "ok":
            self.P = np.diag([self.p.init_att_sigma**2] * 3 + [self.p.init_gyro_bias_sigma**2] * 3)
        return status

    def _max_bias_var(self):
        return float(np.max(np.diag(self.P)[3:]))

    def attitude_covariance(self):
        return self.P[:3, :3]

    def _acc_up(self):
        """The body-frame vertical at the current attitude, for the bias weight's low-pass."""
        return Q.rotate_inv(self.q, np.array([0.0, 0.0, 1.0]))

    @staticmethod
    def propagate(q, bias, gyr, dt):
        """q+ = q * exp((w - b) dt); Phi = [C(dq)^T, -dt I; 0, I]; the step's dq."""
        dq = Q.from_rotvec((np.asarray(gyr, float) - bias) * dt)
        Phi = np.eye(6)
        Phi[:3, :3] = Q.to_rotmat(dq).T
        Phi[:3, 3:] = -dt * np.eye(3)
        return Q.mul(q, dq), Phi, dq

    def predict(self, gyr, dt):
        if not self.initialized:
            return "not_initialized"
        if not np.all(np.isfinite(gyr)):
            return "non_finite"
        if not (0 < dt <= self.p.max_dt):
            return "invalid_dt"
        q_new, Phi, dq = self.propagate(self.q, self.bias, gyr, dt)
        Qn = np.diag([dt * self.p.gyro_noise**2] * 3 + [dt * self.p.gyro_bias_noise**2] * 3)
        if self.p.gyro_rate_noise > 0:
            Qn[:3, :3] += tilt_rate_noise(q_new, np.asarray(gyr, float) - self.bias, self.p.gyro_rate_noise, dt)
        clip_var = self.clip.step(gyr, dt)  # gyro_clip.hpp
        Qn[:3, :3] += np.diag(clip_var)
        P = Phi @ self.P @ Phi.T + Qn
        self.P = 0.5 * (P + P.T)
        self.q = q_new / np.linalg.norm(q_new)
        self._parts_predict(gyr, dq, dt, clip_var)
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

    def heading_free(self, u, rows):
        """The gain of the accelerometer rows (quaternion_ekf.hpp): the first ``rows`` rows' gains
        projected off the body-frame vertical ``u`` in the attitude block and weighted by the
        accelerometer part's ``bias_weight(u)`` in the bias block (``acc_tilt_only``)."""
        W = self.acc.bias_weight(u)

        def gain(i, k):
            if i >= rows:
                return k
            k = k.copy()
            k[:3] -= u * (u @ k[:3])
            k[3:] = W @ k[3:]
            return k
        return gain

    def _update_gravity(self, acc, sigma, gate):
        """The accelerometer update as a Schmidt-Kalman update: no heading, no vertical bias."""
        status, a = _unit(acc)
        if status != "ok":
            return SimpleNamespace(status=status)
        h, H = self.direction_model(self.q, np.array([0.0, 0.0, -1.0]))
        return self._correct(H, np.eye(3) * sigma**2, a - h, gate,
                             gain=self.heading_free(-h, 3 if self.p.acc_tilt_only else 0))

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
        before = self.mag.ref.copy()
        self.mag.ref.learn(Q.rotate(self.q, m), self.p.mag_ref_samples)
        ha, Ha = self.direction_model(self.q, np.array([0.0, 0.0, -1.0]))
        hm, Hm = self.direction_model(self.q, self._mag_reference_vector())
        R = np.diag([self.p.acc_sigma**2] * 3 + [self.p.mag_sigma**2] * 3)
        res = self._correct(np.vstack([Ha, Hm]), R, np.concatenate([a - ha, m - hm]), gate,
                            gain=self.heading_free(-ha, 3 if self.p.acc_tilt_only else 0))
        if res.status != "ok":
            self.mag.ref = before
        return res

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

    def _correct(self, H, R, y, gate, gain=None):
        if gain is None:
            status, dx, P, S, nis = kalman_correct(self.P, H, R, y, gate)
        else:
            status, dx, P, S, nis = kalman_correct_rows(self.P, H, np.diag(R), y, gate, gain)
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
    #: EulerEKFParams::paper(): the robustness parts off (a test compares it with the C++).
    paper_overrides = dict(acc_tilt_only=False, exact_propagation=False, acc_adapt=0.0, acc_reject=0.0, acc_recovery_time=0.0, acc_lp_tau=0.0,
                           acc_lp_bias_sigma=0.0, acc_lp_dev=0.0, acc_bias_dev=0.0, mag_norm_tol=0.0, mag_dip_tol=0.0, mag_dip_sigmas=0.0, mag_settle_time=0.0,
                           mag_ref_tau=0.0, mag_recovery_time=0.0, rest_detection=False)
    rts_model = "EulerModel"  #: the model of its smoother (quatnav.reference.attitude_smoother)
    n_states = 6

    def __init__(self, paper=False, **params):
        if paper:
            params = {**self.paper_overrides, **params}
        super().__init__(**params)
        self.euler = np.zeros(3)
        self.bias = np.zeros(3)
        self.P = np.eye(6)
        self.near_singularity = False
        self.dt_last = 0.0
        self.rest, self.acc = Rest(self.p), AccFilter(self.p)

    @property
    def at_rest(self):
        return self.rest.at_rest()

    @property
    def quat(self):
        return Q.from_euler(self.euler)

    def attitude_covariance(self):
        """Covariance of the body-frame rotation vector, W P_ee W^T (euler_ekf.hpp)."""
        cr, sr, cp, sp = np.cos(self.euler[0]), np.sin(self.euler[0]), np.cos(self.euler[1]), np.sin(self.euler[1])
        W = np.array([[1.0, 0.0, -sp], [0.0, cr, sr * cp], [0.0, -sr, cr * cp]])
        return W @ self.P[:3, :3] @ W.T

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

    @staticmethod
    def nearest_branch(e, near):
        """Of the ZYX triples ``e`` and ``[roll + pi, pi - pitch, yaw + pi]`` of one rotation, the
        one nearest ``near`` (differences wrapped); euler_ekf.hpp's euler_nearest_branch."""
        alt = Q.wrap_pi(np.array([e[0] + np.pi, np.pi - e[1], e[2] + np.pi]))
        return alt if np.sum(Q.wrap_pi(alt - near) ** 2) < np.sum(Q.wrap_pi(e - near) ** 2) else e

    def propagate(self, e, bias, gyr, dt, exact=None):
        """The time update and its Jacobian F (paper 004 eq. 1): one Euler step e' = e + T E (w - b)
        or, with ``exact`` (default: the parameter ``exact_propagation``) and away from the
        singularity, e' = euler(q(e) exp(T (w - b))) on the branch nearest the Euler step; F is the
        Euler step's Jacobian either way."""
        exact = self.p.exact_propagation if exact is None else exact
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
        e_new = e + dt * E @ w
        if exact and not singular:
            q = Q.mul(Q.from_euler(e), Q.from_rotvec(dt * w))
            e_new = self.nearest_branch(Q.to_euler(q / np.linalg.norm(q)), e_new)
        return e_new, F, E, singular

    def initialize(self, acc, mag=None):
        out = attitude_from_acc_mag(acc, mag)
        if out is None:
            return "zero_norm"
        q, mref = out
        self.euler = Q.to_euler(q)
        self.bias = np.zeros(3)
        self.dt_last = 0.0
        self.rest.restart()
        self.acc.restart()
        self.mag.restart()
        self.flags = 0
        if mref is not None:
            self.mag.start(mref, np.linalg.norm(mag))
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
        self.acc.predict_rate(np.asarray(gyr, float) - self.bias, dt)
        self.P = 0.5 * (P + P.T)
        e[0], e[2] = Q.wrap_pi(e[0]), Q.wrap_pi(e[2])
        self.euler = e
        self.near_singularity = singular
        self.flags = 0
        self.dt_last = dt
        self.rest.predict(gyr, dt)
        return "ok"

    # --- measurements with the robustness parts (as QuaternionEKF) ------------------------
    def update_acc(self, acc, gate=0.0):
        """The rest test (at rest a zero-rate update of the bias), the accelerometer part, 3 rows."""
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, _ = _unit(acc)
        if status != "ok":
            return SimpleNamespace(status=status)
        if self.rest.update(acc, self.bias, self.dt_last):
            self.flags |= FLAG_AT_REST
            H = np.zeros((3, 6))
            H[:, 3:] = np.eye(3)
            r = self.rest.zero_rate_variance(self.p.gyro_noise, self.dt_last)
            self._correct(H, np.eye(3) * r, self.rest.zero_rate_innovation(self.bias), 0.0)
        max_bias_var = float(np.max(np.diag(self.P)[3:]))
        up = Q.rotate_inv(self.quat, np.array([0.0, 0.0, 1.0]))
        sin_pitch = np.sin(self.euler[1])

        def update(a):
            W = self.acc.bias_weight(up)  # I - up up^T without rotation

            def heading_free(i, k):  # euler_ekf.hpp: a tilt about a horizontal axis, a horizontal bias
                k = k.copy()
                k[2] = sin_pitch * k[0]
                k[3:] = W @ k[3:]
                return k
            return self._update3(a.acc, *GRAVITY_REF, self.p.acc_sigma + a.sigma_add, a.gate(gate, 0.0),
                                 gain=heading_free if self.p.acc_tilt_only else None)
        res = self.acc.update(acc, self.dt_last, max_bias_var, update)  # the current vertical in W
        if res.status == "rejected":
            self.flags |= FLAG_ACC_REJECTED
        return res

    def update_mag(self, mag, gate=0.0):
        """The magnetometer part's disturbance tests, then the 3-row update."""
        if not self.initialized:
            return SimpleNamespace(status="not_initialized")
        status, m = _unit(mag)
        if status != "ok":
            return SimpleNamespace(status=status)
        field_n = lambda: Q.rotate(self.quat, m)  # noqa: E731
        dip_var = self.mag.dip_variance(self.quat, field_n(), self.attitude_covariance())
        res = self.mag.update(np.linalg.norm(mag), field_n, self.dt_last,
                              lambda: self._update3(mag, self.mag_ref[0], self.mag_ref[2], self.p.mag_sigma, gate),
                              dip_var)
        if res.status == "rejected":
            self.flags |= FLAG_MAG_REJECTED
        return res

    def _update3(self, v, rx, rz, sigma, gate, gain=None):
        status, u = _unit(v)
        if status != "ok":
            return SimpleNamespace(status=status)
        C, dC = self.cbn(self.euler)
        r = np.array([rx, 0.0, rz])
        H = np.zeros((3, 6))
        for i in range(3):
            H[:, i] = dC[i] @ r
        return self._correct(H, np.eye(3) * sigma**2, u - C @ r, gate, gain)

    def _correct(self, H, R, y, gate, gain=None):
        if gain is None:
            status, dx, P, S, nis = kalman_correct(self.P, H, R, y, gate)
        else:
            status, dx, P, S, nis = kalman_correct_rows(self.P, H, np.diag(R), y, gate, gain)
        res = SimpleNamespace(status=status, innovation=y, innovation_cov=S, nis=nis)
        if status != "ok":
            return res
        e = self.euler + dx[:3]
        e[0], e[2] = Q.wrap_pi(e[0]), Q.wrap_pi(e[2])
        self.euler, self.bias, self.P = e, self.bias + dx[3:], P
        return res
