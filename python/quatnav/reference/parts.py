"""Numpy twins of the attitude filters' robustness parts (``cpp/include/quatnav/attitude/parts/``).

One class per part, holding the part's state as attributes named as the C++ fields and its steps
as methods of the same names: :class:`Rest` (``rest.hpp``), :class:`AccFilter`
(``acc_filter.hpp``), :class:`MagDisturbance` (``mag_disturbance.hpp``, with :class:`MagRef`, the
learned reference field of ``attitude.hpp``). A part reads its parameters from the filter's
parameter namespace ``p`` (the parts' names are unique: ``rest_time``, ``acc_lp_tau``,
``mag_norm_tol``, ...). The twin filters in :mod:`quatnav.reference.attitude` and
:mod:`quatnav.reference.marg` compose them as the C++ filters do.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from ..core import quaternion as Q
from ..filters.tables import FLAGS
from .lowpass import lowpass

__all__ = ["lowpass", "MagRef", "Rest", "AccFilter", "MagDisturbance"]


class MagRef:
    """The normalized reference field [m_x, 0, m_z]: the mean of sin(dip) over the first
    ``mag_ref_samples`` samples, unless fixed by :meth:`fix`."""

    def __init__(self):
        self.mag_ref = np.array([1.0, 0.0, 0.0])
        self.mag_sin_dip_sum = 0.0
        self.mag_ref_count = 0
        self.mag_ref_fixed = False

    def copy(self) -> MagRef:
        c = MagRef()
        c.mag_ref, c.mag_sin_dip_sum = self.mag_ref.copy(), self.mag_sin_dip_sum
        c.mag_ref_count, c.mag_ref_fixed = self.mag_ref_count, self.mag_ref_fixed
        return c

    def fix(self, dip):
        self.mag_ref = np.array([np.cos(dip), 0.0, np.sin(dip)])
        self.mag_ref_fixed = True

    def learn(self, m_n_unit, max_samples):
        if self.mag_ref_fixed or self.mag_ref_count >= max_samples:
            return
        self.mag_sin_dip_sum += m_n_unit[2]
        self.mag_ref_count += 1
        sd = np.clip(self.mag_sin_dip_sum / self.mag_ref_count, -1.0, 1.0)
        self.mag_ref = np.array([np.sqrt(1 - sd * sd), 0.0, sd])

    def restart(self, m_n_unit, max_samples):
        if not self.mag_ref_fixed:
            self.__init__()
        self.learn(m_n_unit, max_samples)


class GyroClip:
    """Clipped gyro readings (``gyro_clip.hpp``): an axis whose reading repeats its previous
    ``gyro_clip_repeats`` readings exactly, at or above every magnitude seen so far and at least
    ``gyro_clip_min_rate``."""

    def __init__(self, p):
        self.p = p
        self.gyr_prev, self.gyr_repeats = np.zeros(3), np.zeros(3)
        self.restart()

    def restart(self):
        self.gyr_max, self.clip_init = 0.0, False

    def step(self, gyr, dt):
        """At every predict: the variance [rad^2] to add to each body axis's attitude error,
        ``(gyro_clip_noise |w_i| dt)^2`` on the clipped axes, zero elsewhere."""
        p = self.p
        var = np.zeros(3)
        if not p.gyro_clip:
            return var
        g = np.asarray(gyr, float)
        a = np.abs(g)
        self.gyr_repeats = np.where(self.clip_init & (g == self.gyr_prev), self.gyr_repeats + 1, 0.0)
        hit = (self.gyr_repeats >= p.gyro_clip_repeats) & (a >= self.gyr_max) & (a >= p.gyro_clip_min_rate)
        var = np.where(hit, (p.gyro_clip_noise * a * dt) ** 2, 0.0)
        self.gyr_max = max(self.gyr_max, float(a.max()))
        self.gyr_prev, self.clip_init = g.copy(), True
        return var


class Rest:
    """Rest detection and its zero-rate measurement of the gyro bias (``rest.hpp``)."""

    FLAG = FLAGS["at_rest"]

    def __init__(self, p):
        self.p = p
        self.gyr_last = np.zeros(3)
        self.gyr_lp = np.zeros(3)
        self.acc_lp = np.zeros(3)
        self.rest_lp_init = False
        self.rest_t = 0.0

    def restart(self):
        self.rest_lp_init, self.rest_t = False, 0.0

    def predict(self, gyr, dt):
        if not self.p.rest_detection:
            return
        self.gyr_last = np.array(gyr, float)
        if self.rest_lp_init:
            self.gyr_lp = lowpass(self.gyr_lp, self.gyr_last, dt, self.p.rest_tau)

    def update(self, acc, gyro_bias, dt) -> bool:
        """The rest test at an accelerometer sample; True at rest."""
        p = self.p
        if not p.rest_detection:
            return False
        acc = np.asarray(acc, float)
        if not self.rest_lp_init or not dt > 0:
            self.gyr_lp, self.acc_lp = self.gyr_last.copy(), acc.copy()
            self.rest_lp_init, self.rest_t = dt > 0, 0.0
            return False
        self.acc_lp = lowpass(self.acc_lp, acc, dt, p.rest_tau)
        still = (np.linalg.norm(self.gyr_last - self.gyr_lp) < p.rest_gyr_th
                 and (np.linalg.norm(self.gyr_lp - gyro_bias) < p.rest_gyr_th
                      or np.linalg.norm(self.gyr_lp) < p.rest_gyr_th)  # a wrong bias never locks rest out
                 and np.linalg.norm(acc - self.acc_lp) < p.rest_acc_th)
        self.rest_t = self.rest_t + dt if still else 0.0
        return self.rest_t >= p.rest_time

    def at_rest(self) -> bool:
        return bool(self.p.rest_detection and self.rest_t >= self.p.rest_time)

    def zero_rate_innovation(self, gyro_bias):
        return self.gyr_last - gyro_bias

    def zero_rate_variance(self, gyro_noise, dt):
        return gyro_noise**2 / dt + self.p.rest_rate_noise**2


class AccFilter:
    """The accelerometer part: quasi-inertial low-pass, norm rejection, adaptive noise, recovery
    (``acc_filter.hpp``)."""

    FLAG = FLAGS["acc_rejected"]

    def __init__(self, p):
        self.p = p
        self.restart()
        self.acc_i_lp = np.zeros(3)
        self.C_i_lp = np.eye(3)
        self.g_i_lp = np.zeros(3)
        self.acc_dev_lp = 0.0
        self.acc_lp_age = 0.0

    def restart(self):
        self.acc_lp_init, self.q_i, self.acc_reject_t = False, Q.identity(), 0.0

    def predict(self, dq):
        if self.p.acc_lp_tau > 0:
            qi = Q.mul(self.q_i, dq)
            self.q_i = qi / np.linalg.norm(qi)

    def predict_rate(self, rate, dt):
        if self.p.acc_lp_tau > 0:
            self.predict(Q.from_rotvec(np.asarray(rate, float) * dt))

    def time_constant(self, max_bias_var):
        p = self.p
        sb = p.acc_lp_bias_sigma
        if not sb > 0:
            return p.acc_lp_tau
        return p.acc_lp_tau * (sb * sb / max_bias_var) if max_bias_var > sb * sb else p.acc_lp_tau

    def time_constant_dev(self, max_bias_var, dev_lp):
        """The same, the shrink faded out by the low-passed linear acceleration (acc_lp_dev)."""
        p = self.p
        tau_b = self.time_constant(max_bias_var)
        if not p.acc_lp_dev > 0 or tau_b == p.acc_lp_tau:
            return tau_b
        return tau_b + (p.acc_lp_tau - tau_b) * min(1.0, dev_lp / p.acc_lp_dev)

    def screen(self, acc, dt, max_bias_var, up=None):
        """The sample to use (``acc``), its extra one-sigma (``sigma_add``), ``rejected``, ``recovering``;
        ``up``: the filter's body-frame vertical, low-passed in the frame for the bias weight."""
        p = self.p
        acc = np.asarray(acc, float)
        used = acc
        if p.acc_lp_tau > 0:
            a_i = Q.rotate(self.q_i, acc)
            C_ib = Q.to_rotmat(self.q_i)
            g_i = C_ib @ (np.zeros(3) if up is None else np.asarray(up, float))
            dev_raw = abs(np.linalg.norm(acc) - p.gravity)
            if not self.acc_lp_init or not dt > 0:
                self.acc_i_lp, self.C_i_lp, self.acc_lp_init = a_i, C_ib, True
                self.g_i_lp = g_i
                self.acc_dev_lp = dev_raw
                self.acc_lp_age = 0.0
            else:
                self.acc_lp_age = min(self.acc_lp_age + dt, 2.0 * p.acc_lp_tau)
                self.acc_dev_lp = lowpass(self.acc_dev_lp, dev_raw, dt, p.acc_lp_tau)
                tau = self.time_constant_dev(max_bias_var, self.acc_dev_lp)
                self.acc_i_lp = lowpass(self.acc_i_lp, a_i, dt, tau)
                self.C_i_lp = lowpass(self.C_i_lp, C_ib, dt, tau)
                self.g_i_lp = lowpass(self.g_i_lp, g_i, dt, tau)
            used = Q.rotate_inv(self.q_i, self.acc_i_lp)
        g = p.gravity
        dev = abs(np.linalg.norm(used) - g) if g > 0 else 0.0
        recovering = p.acc_recovery_time > 0 and self.acc_reject_t >= p.acc_recovery_time
        return SimpleNamespace(acc=used, sigma_add=p.acc_adapt * dev / g if g > 0 else 0.0,
                               rejected=bool(p.acc_reject > 0 and dev > p.acc_reject and not recovering),
                               recovering=recovering,
                               gate=lambda given, default: given if given > 0 else (0.0 if recovering else default))

    def bias_weight(self, u):
        """The weight of the accelerometer's gain in the gyro-bias block for the body-frame vertical
        ``u``: ``C^T (I - g g^T) C`` with C the low-passed C_ib, g the low-passed C_ib u normalized
        (the current one where that average is shorter than 0.5) (``acc_filter.hpp``);
        ``I - u u^T`` without the low-pass or before its first sample; times the ramp
        ``min(1, age / (2 acc_lp_tau))`` over the low-pass's first 2 time constants and by
        ``1 / (1 + (dev_lp / acc_bias_dev)**2)``, dev_lp the low-passed ``||a| - g|``."""
        if not (self.p.acc_lp_tau > 0 and self.acc_lp_init):
            return np.eye(3) - np.outer(u, u)
        n2 = float(self.g_i_lp @ self.g_i_lp)
        g = self.g_i_lp / np.sqrt(n2) if n2 > 0.25 else Q.rotate(self.q_i, u)
        W = self.C_i_lp.T @ (np.eye(3) - np.outer(g, g)) @ self.C_i_lp
        ramp_end = 2.0 * self.p.acc_lp_tau
        if self.acc_lp_age < ramp_end:
            W = W * (self.acc_lp_age / ramp_end)
        if self.p.acc_bias_dev > 0:
            W = W / (1.0 + (self.acc_dev_lp / self.p.acc_bias_dev) ** 2)
        return W

    def finish(self, status, dt):
        if status == "ok":
            self.acc_reject_t = 0.0
        elif status == "rejected" and self.p.acc_recovery_time > 0:
            self.acc_reject_t += dt

    def update(self, acc, dt, max_bias_var, filter_update, up=None):
        """screen(), the filter's ``filter_update(sample)`` (not for a refused sample), finish()."""
        sample = self.screen(acc, dt, max_bias_var, up)
        res = SimpleNamespace(status="rejected") if sample.rejected else filter_update(sample)
        self.finish(res.status, dt)
        return res


class MagDisturbance:
    """The magnetometer part: the reference field and norm, the disturbance tests, settling,
    recovery and the learning of the reference (``mag_disturbance.hpp``)."""

    FLAG = FLAGS["mag_rejected"]

    def __init__(self, p):
        self.p = p
        self.ref = MagRef()
        self.mag_norm_ref = 0.0
        self.restart()

    def restart(self):
        self.mag_reject_t, self.mag_ok_t = 0.0, 1e9

    def start(self, m_n_unit, norm):
        self.ref.restart(m_n_unit, self.p.mag_ref_samples)
        self.mag_norm_ref = float(norm)

    @staticmethod
    def dip(m_n):
        return float(np.arcsin(np.clip(m_n[2], -1.0, 1.0)))

    @staticmethod
    def dip_offset(ref, m_n):
        """The dip of the unit field ``m_n`` minus the unit reference's, in (-pi, pi]."""
        d = MagDisturbance.dip(m_n) - np.arctan2(ref[2], ref[0])
        return float(np.arctan2(np.sin(d), np.cos(d)))

    @staticmethod
    def dip_differs(ref, m_n, tol):
        """The dip test |d - d_ref| > tol."""
        return abs(MagDisturbance.dip_offset(ref, m_n)) > tol

    def dip_tolerance(self, dip_var):
        """mag_dip_tol widened in quadrature by mag_dip_sigmas of the filter's own dip sigma."""
        p = self.p
        if not (p.mag_dip_sigmas > 0 and dip_var > 0):
            return p.mag_dip_tol
        return float(np.sqrt(p.mag_dip_tol**2 + p.mag_dip_sigmas**2 * dip_var))

    def dip_variance(self, q, m_n, P_att):
        """The dip's variance from the body-frame attitude covariance ``P_att`` at ``q`` (rad^2):
        a . dtheta_n, a = (m_y, -m_x, 0) / cos(dip); 0 when the widening is off or the field is
        vertical (mag_disturbance.hpp ``dip_variance``)."""
        p = self.p
        if not (p.mag_dip_sigmas > 0 and p.mag_dip_tol > 0):
            return 0.0
        h2 = m_n[0] ** 2 + m_n[1] ** 2
        if not h2 > 1e-12:
            return 0.0
        a_b = Q.to_rotmat(q).T @ (np.array([m_n[1], -m_n[0], 0.0]) / np.sqrt(h2))
        return float(a_b @ np.asarray(P_att, float) @ a_b)

    def screen(self, norm, m_n, dt, dip_var=0.0):
        p = self.p
        c = SimpleNamespace(use=True, disturbed=False, norm=norm, before=self.ref.copy())
        self.ref.learn(m_n, p.mag_ref_samples)
        if not self.mag_norm_ref > 0:
            self.mag_norm_ref = norm
        c.disturbed = bool((p.mag_norm_tol > 0 and abs(norm / self.mag_norm_ref - 1) > p.mag_norm_tol)
                           or (p.mag_dip_tol > 0 and self.dip_differs(self.ref.mag_ref, m_n, self.dip_tolerance(dip_var))))
        if p.mag_settle_time > 0:
            self.mag_ok_t = 0.0 if c.disturbed else self.mag_ok_t + dt
        if c.disturbed or self.mag_ok_t < p.mag_settle_time:
            self.mag_reject_t += dt
            if not c.disturbed or not (p.mag_recovery_time > 0 and self.mag_reject_t >= p.mag_recovery_time):
                self.ref, c.use = c.before, False
                return c
            self.ref.restart(m_n, p.mag_ref_samples)  # a steady new field: the new reference
            self.mag_norm_ref = norm
        return c

    def finish(self, c, status, m_n_after, dt):
        p = self.p
        if status == "ok":
            self.mag_reject_t = 0.0
            if p.mag_ref_tau > 0 and dt > 0:
                if not self.ref.mag_ref_fixed and self.ref.mag_ref_count >= p.mag_ref_samples:
                    # the dip d_ref + a (d - d_ref): the reference turned in its plane
                    r = self.ref.mag_ref
                    d_ref = np.arctan2(r[2], r[0])
                    d = lowpass(d_ref, d_ref + self.dip_offset(r, m_n_after()), dt, p.mag_ref_tau)
                    self.ref.mag_ref = np.array([np.cos(d), 0.0, np.sin(d)])
                self.mag_norm_ref = lowpass(self.mag_norm_ref, c.norm, dt, p.mag_ref_tau)
        elif status == "rejected" and p.mag_recovery_time > 0:
            self.mag_reject_t += dt
        if status != "ok" and not c.disturbed:
            self.ref = c.before

    def update(self, norm, field_n, dt, filter_update, dip_var=0.0):
        """screen(), the filter's ``filter_update()`` (not for a rejected sample), finish();
        ``dip_var``: the dip's variance from the filter's attitude covariance (dip_variance)."""
        c = self.screen(float(norm), field_n(), dt, dip_var)
        if not c.use:
            return SimpleNamespace(status="rejected")
        res = filter_update()
        self.finish(c, res.status, field_n, dt)
        return res
