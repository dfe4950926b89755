"""Reference (numpy) MargFilter of paper 001; see quatnav.filters.marg and marg_filter.hpp.

Gauss-Newton attitude from gravity and field (eq. 1-5) blended with gyro integration (eq. 6),
the accelerometer corrected by the GPS antenna acceleration and the lever-arm terms (eq. 7,
as corrected in marg_filter.hpp: f_b + w_dot x d + w x (w x d) = C_bn (a_g_n - g_n)), and the
robustness parts of :mod:`quatnav.reference.parts` composed as in the C++ filter (at rest the
low-passed gyro is the bias; a rejected accelerometer sample skips the update; a disturbed field
leaves the update to gravity alone).
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..core import quaternion as Q
from ..filters.tables import MARG_PARAMS
from ..filters.tables import FLAGS
from .attitude import _unit, attitude_from_acc_mag, make_params, sample_times, table_defaults
from .lowpass import lowpass_weight
from .parts import AccFilter, MagDisturbance, Rest


def h(q, r):
    """eq. (1)-(2): y = R^{n->b}(q) r written out from the matrix of eq. (2) (homogeneous in q)."""
    q0, q1, q2, q3 = q
    R = np.array([
        [q0**2 + q1**2 - q2**2 - q3**2, 2 * (q1 * q2 + q3 * q0), 2 * (q1 * q3 - q2 * q0)],
        [2 * (q1 * q2 - q3 * q0), q0**2 + q2**2 - q1**2 - q3**2, 2 * (q2 * q3 + q1 * q0)],
        [2 * (q1 * q3 + q2 * q0), 2 * (q2 * q3 - q1 * q0), q0**2 + q3**2 - q2**2 - q1**2],
    ])
    return R @ np.asarray(r, float)


def jacobian(q, r):
    """eq. (4): X_ij = dy_i / dq_j of :func:`h` (3x4), differentiated entry by entry."""
    q0, q1, q2, q3 = q
    rx, ry, rz = r
    d0 = 2 * np.array([q0 * rx + q3 * ry - q2 * rz, -q3 * rx + q0 * ry + q1 * rz, q2 * rx - q1 * ry + q0 * rz])
    d1 = 2 * np.array([q1 * rx + q2 * ry + q3 * rz, q2 * rx - q1 * ry + q0 * rz, q3 * rx - q0 * ry - q1 * rz])
    d2 = 2 * np.array([-q2 * rx + q1 * ry - q0 * rz, q1 * rx + q2 * ry + q3 * rz, q0 * rx + q3 * ry - q2 * rz])
    d3 = 2 * np.array([-q3 * rx + q0 * ry + q1 * rz, -q0 * rx - q3 * ry + q2 * rz, q1 * rx + q2 * ry + q3 * rz])
    return np.column_stack([d0, d1, d2, d3])


def gauss_newton(q0, meas, refs, max_iter, tol):
    """eq. (3)-(5) from q0 on the unit-vector pairs (meas[j] in body, refs[j] in navigation frame).

    Returns (status, q (unnormalized), iterations, converged).
    """
    q = np.array(q0, float)
    for it in range(max_iter):
        eps = np.concatenate([m - h(q, r) for m, r in zip(meas, refs)])      # eq. (3)
        X = np.vstack([jacobian(q, r) for r in refs])                        # eq. (4)
        if X.shape[0] >= 4:
            A = X.T @ X                                                      # eq. (5)
            rhs = X.T @ eps
        else:  # 6D mode: minimum-norm pseudo-inverse X^T (X X^T)^-1
            A = X @ X.T
            rhs = eps
        try:
            L = np.linalg.cholesky(A)
        except np.linalg.LinAlgError:
            return "solve_failed", q0, it, False
        d = np.diag(L)
        if not d.min() > d.max() * np.sqrt(np.finfo(float).eps):
            return "solve_failed", q0, it, False
        sol = np.linalg.solve(A, rhs)
        dq = sol if X.shape[0] >= 4 else X.T @ sol
        if not (np.all(np.isfinite(dq)) and np.linalg.norm(dq) < 2):
            return "solve_failed", q0, it, False
        q = q + dq
        if np.linalg.norm(dq) < tol:
            return "ok", q, it + 1, True
    return "ok", q, max_iter, False


def residual(q, meas, refs):
    return float(np.sqrt(sum(np.sum((m - h(q, r)) ** 2) for m, r in zip(meas, refs))))


def lever_corrected(f_b, omega_b, omega_dot_b, d_b):
    """eq. (7'): f_b + w_dot x d + w x (w x d)."""
    return f_b + np.cross(omega_dot_b, d_b) + np.cross(omega_b, np.cross(omega_b, d_b))


class MargFilter:
    """MargFilter (paper 001) in numpy, method for method like the C++ class."""

    defaults = table_defaults(MARG_PARAMS)
    #: MargFilterParams::paper(): the robustness parts off (a test compares it with the C++).
    paper_overrides = dict(acc_adapt=0.0, acc_reject=0.0, acc_recovery_time=0.0, acc_lp_tau=0.0,
                           acc_lp_bias_sigma=0.0, acc_lp_dev=0.0, acc_bias_dev=0.0, mag_norm_tol=0.0, mag_dip_tol=0.0, mag_dip_sigmas=0.0, mag_settle_time=0.0,
                           mag_ref_tau=0.0, mag_recovery_time=0.0, rest_detection=False)

    def __init__(self, paper=False, **params):
        if paper:
            params = {**self.paper_overrides, **params}
        self.p = make_params("MargFilter", self.defaults, params)
        self.q = Q.identity()
        self.bias = np.zeros(3)
        self.mag = MagDisturbance(self.p)
        self.rest, self.acc = Rest(self.p), AccFilter(self.p)
        self.dt_last = 0.0
        self.flags = 0
        self.omega_b = np.zeros(3)
        self.omega_dot_b = np.zeros(3)
        self.omega_set = False
        self.gps_vel_n = np.zeros(3)
        self.gps_acc_n = np.zeros(3)
        self.gps_t = 0.0
        self.gps_fixes = 0
        self.time_since_gps = 0.0
        self.time_since_update = 0.0
        self.initialized = False

    @property
    def quat(self):
        return self.q

    @property
    def mag_ref(self):
        """The reference field [m_x, 0, m_z]."""
        return self.mag.ref.mag_ref

    @property
    def at_rest(self):
        return self.rest.at_rest()

    def set_mag_dip(self, dip):
        self.mag.ref.fix(dip)

    def gps_acc_available(self):
        return (self.p.gps_correction and self.gps_fixes >= 2
                and self.time_since_gps <= self.p.gps_timeout)

    def initialize(self, acc, mag=None):
        out = attitude_from_acc_mag(acc, mag)
        if out is None:
            return "zero_norm"
        self.q, mref = out
        self.bias = np.zeros(3)
        self.dt_last = 0.0
        self.rest.restart()
        self.acc.restart()
        self.mag.restart()
        self.flags = 0
        if mref is not None:
            self.mag.start(mref / np.linalg.norm(mref), np.linalg.norm(mag))
        self.time_since_update = 0.0
        self.initialized = True
        return "ok"

    def predict(self, gyr, dt):
        """Gyro integration, q- = q * exp((w - b) T) (eq. 6's 1/2 q * w term), and w_dot."""
        if not self.initialized:
            return "not_initialized"
        if not np.all(np.isfinite(gyr)):
            return "non_finite"
        if not (0 < dt <= self.p.max_dt):
            return "invalid_dt"
        w = np.asarray(gyr, float) - self.bias
        q = Q.mul(self.q, Q.from_rotvec(w * dt))
        if self.omega_set:
            raw = (w - self.omega_b) / dt
            self.omega_dot_b = self.omega_dot_b + lowpass_weight(dt, self.p.omega_dot_tau) * (raw - self.omega_dot_b)
        self.q = q / np.linalg.norm(q)
        self.omega_b, self.omega_set = w, True
        self.time_since_gps += dt
        self.time_since_update += dt
        self.dt_last = dt
        self.flags = 0
        self.acc.predict_rate(w, dt)
        self.rest.predict(gyr, dt)
        return "ok"

    def update_gps_velocity(self, v_n, t):
        """One GPS velocity fix (true NED), rotated into the filter's magnetic NED frame."""
        v_n = np.asarray(v_n, float)
        if not (np.all(np.isfinite(v_n)) and np.isfinite(t)):
            return "non_finite"
        c, s = np.cos(self.p.declination), np.sin(self.p.declination)
        v_n = np.array([c * v_n[0] + s * v_n[1], -s * v_n[0] + c * v_n[1], v_n[2]])
        if self.gps_fixes == 0:
            self.gps_fixes = 1
        else:
            dt = t - self.gps_t
            if not dt > 0:
                return "invalid_dt"
            if dt > self.p.gps_timeout:
                self.gps_fixes = 1
            else:
                raw = (v_n - self.gps_vel_n) / dt
                if self.gps_fixes == 1:
                    self.gps_acc_n = raw
                else:
                    self.gps_acc_n = self.gps_acc_n + lowpass_weight(dt, self.p.gps_acc_tau) * (raw - self.gps_acc_n)
                self.gps_fixes = 2
        self.gps_vel_n, self.gps_t, self.time_since_gps = v_n, float(t), 0.0
        return "ok"

    def update_acc(self, acc):
        return self._update(acc, None)

    def update_acc_mag(self, acc, mag):
        return self._update(acc, mag)

    @staticmethod
    def _result(status):
        return SimpleNamespace(status=status, iterations=0, converged=False, gps_corrected=False, residual=0.0,
                               residual_final=0.0, correction=np.zeros(3))

    def _update(self, acc, mag):
        """The parts around the Gauss-Newton update (marg_filter.hpp, update_parts)."""
        if not self.initialized:
            return self._result("not_initialized")
        acc = np.asarray(acc, float)
        if not np.all(np.isfinite(acc)) or (mag is not None and not np.all(np.isfinite(mag))):
            return self._result("non_finite")
        st, _ = _unit(acc)  # bad input leaves the state untouched: checked before the parts
        if st != "ok":
            return self._result(st)
        m0 = None
        if mag is not None:
            st, m0 = _unit(mag)
            if st != "ok":
                return self._result(st)
        dt = self.dt_last
        if self.rest.update(acc, self.bias, dt):
            self.flags |= FLAGS["at_rest"]
            self.bias = self.rest.gyr_lp.copy()  # no covariance: the low-passed gyro is the bias
        sample = self.acc.screen(acc, dt, 0.0)
        gps = self.gps_acc_available()
        mc = None
        if m0 is not None:
            mc = self.mag.screen(float(np.linalg.norm(mag)), Q.rotate(self.q, m0), dt)
            if not mc.use:
                self.flags |= FLAGS["mag_rejected"]
        use_mag = mc is not None and mc.use
        if sample.rejected and not gps:
            res = self._result("rejected")
        else:
            a = acc if gps else sample.acc
            gain = self.p.gain if gps else self.p.gain / (1.0 + sample.sigma_add)
            res = self._gauss_newton_update(a, m0 if use_mag else None, gain)
        self.acc.finish(res.status, dt)
        if res.status == "rejected":
            self.flags |= FLAGS["acc_rejected"]
            if use_mag and not mc.disturbed:
                self.mag.ref = mc.before  # the field was not used
        elif use_mag:
            self.mag.finish(mc, res.status, lambda: Q.rotate(self.q, m0), dt)
        return res

    def _gauss_newton_update(self, acc, m0, gain):
        res = self._result("ok")
        f, ref_n = acc, np.array([0.0, 0.0, -1.0])
        res.gps_corrected = self.gps_acc_available()
        if res.gps_corrected:  # eq. (7')
            f = lever_corrected(acc, self.omega_b, self.omega_dot_b, np.asarray(self.p.lever_arm_b, float))
            ref_n = self.gps_acc_n - np.array([0.0, 0.0, self.p.gravity])  # the accelerometer part's g
        st, n0 = _unit(f)
        if st != "ok":
            res.status = st
            return res
        st, n_ref = _unit(ref_n)
        if st != "ok":
            res.status = st
            return res
        meas, refs = [n0], [n_ref]
        if m0 is not None:  # the reference learned from it by the magnetometer part's screen()
            meas, refs = [m0, n0], [self.mag_ref.copy(), n_ref]
        q_pred = self.q
        st, q_gn, res.iterations, res.converged = gauss_newton(q_pred, meas, refs, int(self.p.gn_max_iter),
                                                               self.p.gn_tol)
        if st != "ok":
            res.status = st
            return res
        res.residual = residual(q_pred, meas, refs)
        res.residual_final = residual(q_gn, meas, refs)
        q_gn = q_gn / np.linalg.norm(q_gn)
        T = self.time_since_update
        alpha = 1.0 - np.exp(-gain * T)                          # eq. (6) over T
        q_new = q_pred + alpha * (q_gn - q_pred)
        q_new = q_new / np.linalg.norm(q_new)
        if self.p.bias_gain > 0:
            e = Q.canonical(Q.mul(Q.conj(q_pred), q_gn))
            self.bias = self.bias - self.p.bias_gain * T * 2 * e[1:]
        res.correction = Q.to_rotvec(Q.mul(Q.conj(q_pred), q_new))
        self.q = q_new
        self.time_since_update = 0.0
        return res

    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_vel=None):
        """The loop of run_marg_batch (marg_filter.hpp) with the public ``run``'s signature: times
        as ``t`` or ``dt``; ``gps_vel`` an ``Aid(t, v_n)`` (or anything with ``.t`` and ``.value``),
        each fix used from the first IMU sample at or after its time. Returns ``t``, ``quat``, ``bias``."""
        gyr, acc = np.asarray(gyr, float), np.asarray(acc, float)
        n = len(gyr)
        t, steps = sample_times(n, t, dt)
        gps_t = np.zeros(0) if gps_vel is None else np.asarray(gps_vel.t, float)
        gps_v = None if gps_vel is None else np.asarray(gps_vel.value, float)
        quat = np.empty((n, 4))
        bias = np.empty((n, 3))
        flags = np.zeros(n, dtype=np.uint32)
        j = 0
        for k in range(n):
            while j < len(gps_t) and gps_t[j] <= t[k]:
                self.update_gps_velocity(gps_v[j], gps_t[j])
                j += 1
            mk = None if mag is None or np.all(np.isnan(mag[k])) else mag[k]
            if not self.initialized:
                self.initialize(acc[k], mk)
            else:
                self.predict(gyr[k], steps[k])
                if mk is None:
                    self.update_acc(acc[k])
                else:
                    self.update_acc_mag(acc[k], mk)
            quat[k] = self.q
            bias[k] = self.bias
            flags[k] = self.flags
        return SimpleNamespace(t=t, quat=quat, bias=bias, flags=flags)
