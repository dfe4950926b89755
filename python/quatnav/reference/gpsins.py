"""Plain numpy twin of ``cpp/include/quatnav/nav/gps_ins.hpp``: the 16-state feedback GPS/INS
filter of paper 004 with altimeter (and its offset as a state) and compass, optionally with the
accelerometer and gyro scale factors as six more states (``GpsInsFilter(scale_factors=True)``, 22
states; C++ ``GpsInsFilter<S, true>``).

Same method names and the same algorithm step by step as the C++ class (see the header comment
there for the equations, the error definitions and the paper's slips). Written to be read and
compared with the C++, not to be fast: per-sample Python.

Error state ``dx = [dp_n (m), dv_n (m/s), psi (rad), db_a (m/s^2), db_g (rad/s), d_baro_offset (m)]``,
estimate minus truth, attitude error the phi-angle ``C_nb_est = (I + [psi x]) C_nb``. Each aid is
one function giving ``(y, H, R)`` (``_gps_position``, ...), sent through the one gated path
:meth:`GpsInsFilter._apply`, as the C++ pieces of ``nav/gps_ins/aids.hpp``.

Scale factors (the model shared with the C++ ``GpsInsFilter<S, true>``): ``dx`` continues with
``[ds_a (1), ds_g (1)]`` (indices SA, SG) for the sensor model, per axis in the body axes,
``f_m = (1 + s_a) f + b_a + noise``, ``w_m = (1 + s_g) w + b_g + noise``. The IMU is corrected as
``(m - b) / (1 + s)`` in every phase (:func:`_corrected`), F gains the terms of :func:`gpsins_F`,
the scale factors are random walks (``acc_scale_noise``, ``gyro_scale_noise``) without decay, no aid
sees them directly (their H columns are zero), a correction is injected as ``s -= ds``. Without
them everything is as with 16 states, bit for bit.
"""
from __future__ import annotations

import math

import numpy as np

from ..core import earth
from ..core import quaternion as Q
from ..core.strapdown import StrapdownState, strapdown_step
from . import gpsins_batch
from .gpsins_model import (ALIGNING, BA, BG, BO, DECISIONS, DEFAULTS, KINDS, LEVELLED, NAVIGATING, N, N_SF,  # noqa: F401
                           POS, SA, SG, VEL, ATT, GpsInsParams, Result, _baro_height, _baro_vd, _compass,
                           _corrected, _from_euler, _gps_position, _gps_velocity, _mag_heading, _new_state,
                           _gnss_aided, _nhc, _nhc_evidence, _odometer, _qc_diag, _qc_rate, _reset_position, _reset_velocity, _result,
                           _triad, _zaru, _zupt, geodetic_add, geodetic_diff, gnss_correlation_scale, gnss_sigma_floor, gpsins_F, huber_scales,
                           inject)
from .gpsins_smoother import GpsInsRtsModel, run_smoothed  # noqa: F401
from .kalman import kalman_correct
from .lowpass import lowpass_weight

__all__ = ["DEFAULTS", "GpsInsParams", "GpsInsFilter", "gpsins_F", "ALIGNING", "LEVELLED", "NAVIGATING",
           "GpsInsRtsModel", "run_smoothed"]


class GpsInsFilter:
    """Numpy twin of ``quatnav::GpsInsFilter`` (see the C++ header for the model);
    ``scale_factors=True``: with the accelerometer and gyro scale-factor states (22 states)."""

    n_states = N

    def __init__(self, scale_factors=False, **params):
        self.p = GpsInsParams(**params)
        self.scale_factors = bool(scale_factors)
        self.n_states = N_SF if self.scale_factors else N
        self.s = _new_state(self.n_states)

    # --- accessors ------------------------------------------------------------------------
    @property
    def phase(self):
        return self.s.phase

    @property
    def navigating(self):
        return self.s.phase == NAVIGATING

    @property
    def q_nb(self):
        return self.s.nav.q_nb.copy()

    @property
    def v_n(self):
        return self.s.nav.v_n.copy()

    @property
    def llh(self):
        return np.array([self.s.nav.lat, self.s.nav.lon, self.s.nav.h])

    @property
    def acc_bias(self):
        return self.s.acc_bias.copy()

    @property
    def gyro_bias(self):
        return self.s.gyro_bias.copy()

    @property
    def acc_scale(self):
        return self.s.acc_scale.copy()

    @property
    def gyro_scale(self):
        return self.s.gyro_scale.copy()

    @property
    def baro_offset(self):
        return self.s.baro_offset

    @property
    def q_scale(self):
        return self.s.q_scale

    @property
    def covariance(self):
        return self.s.P.copy()

    @property
    def counters(self):
        return {k: dict(v) for k, v in self.s.counters.items()}

    def clear(self):
        self.s = _new_state(self.n_states)

    def initial_covariance(self, pos_sigma, vel_sigma):
        p = self.p
        return self._initial_P(pos_sigma, vel_sigma, p.init_level_sigma, p.init_yaw_sigma)

    def _initial_P(self, pos_sigma, vel_sigma, level_sigma, yaw_sigma):
        """The covariance at the start of navigation (the offset's 0 until the altimeter gives it)."""
        p = self.p
        d = np.concatenate([np.asarray(pos_sigma, float), np.full(3, vel_sigma),
                            [level_sigma, level_sigma, yaw_sigma],
                            np.full(3, p.init_acc_bias_sigma), np.full(3, p.init_gyro_bias_sigma), [0.0]])
        if self.scale_factors:
            d = np.concatenate([d, np.full(3, p.init_acc_scale_sigma), np.full(3, p.init_gyro_scale_sigma)])
        return np.diag(d ** 2)

    def _scales(self, acc_scale, gyro_scale):
        """Given scale factors as arrays (only zeros without the scale-factor states)."""
        a, g = np.array(acc_scale, float).reshape(3), np.array(gyro_scale, float).reshape(3)
        if not self.scale_factors and (a.any() or g.any()):
            raise ValueError("acc_scale, gyro_scale: the filter has no scale-factor states (scale_factors=False)")
        return a, g

    def reset(self, q_nb, v_n, lat, lon, h, acc_bias, gyro_bias, P, acc_scale=(0.0, 0.0, 0.0),
              gyro_scale=(0.0, 0.0, 0.0)):
        P = np.asarray(P, float)
        if P.shape != (self.n_states, self.n_states):
            raise ValueError(f"P: expected shape ({self.n_states}, {self.n_states}), got {P.shape}")
        s = self.s.copy()
        q = np.asarray(q_nb, float)
        s.nav = StrapdownState(q_nb=q / np.linalg.norm(q), v_n=np.asarray(v_n, float).copy(),
                               lat=float(lat), lon=float(lon), h=float(h))
        s.acc_bias = np.asarray(acc_bias, float).copy()
        s.gyro_bias = np.asarray(gyro_bias, float).copy()
        s.acc_scale, s.gyro_scale = self._scales(acc_scale, gyro_scale)
        s.P = P.copy()
        s.phase = NAVIGATING
        s.heading_known = True
        s.baro_offset_valid = False
        s.align_method = s.heading_source = "given"
        s.level_t = s.nav_start_t = s.t
        s.rest_v = s.nav.v_n.copy()
        self.s = s
        return "ok"

    # --- time update ----------------------------------------------------------------------
    def predict(self, omega_ib_b, f_ib_b, dt):
        p = self.p
        dt = float(dt)
        if not (math.isfinite(dt) and 0 < dt <= p.max_dt):
            return "invalid_dt"
        w_m = np.asarray(omega_ib_b, float)
        f_m = np.asarray(f_ib_b, float)
        if not (np.all(np.isfinite(w_m)) and np.all(np.isfinite(f_m))):
            return "non_finite"
        s = self.s.copy()
        if not np.array_equal(p.imu_rotation, np.eye(3)):
            w_m, f_m = p.imu_rotation @ w_m, p.imu_rotation @ f_m
        w, f = _corrected(s, w_m, f_m, self.scale_factors)
        g = float(earth.gravity(s.nav.lat, s.nav.h)) if s.phase == NAVIGATING else 9.80665
        if s.phase == NAVIGATING:
            sv = math.sqrt(np.trace(s.P[VEL:VEL + 3, VEL:VEL + 3]))
            resolved = 3 * sv <= p.rest_speed  # else without the drift of the outage (_rest_velocity)
            if resolved:
                s.rest_v = s.nav.v_n.copy()
            slow = np.linalg.norm(s.rest_v) < p.rest_speed + min(3 * sv, p.rest_speed)
        else:
            slow = not (s.gnss_speed >= 0 and s.t - s.gnss_speed_t < 2.0 and s.gnss_speed > p.rest_speed)
        still = self._rest_step(s, w, f, dt, g, slow)
        if s.phase != NAVIGATING:
            self._window_step(s, w, f, dt)
        if s.phase == ALIGNING:
            if not still:
                s.align_sum = np.zeros(3)
                s.align_time = 0.0
            s.align_sum = s.align_sum + f_m * dt
            s.align_time += dt
            if s.align_time >= p.align_time:
                fm = s.align_sum / s.align_time
                if not np.linalg.norm(fm) > 1.0:
                    s.align_sum = np.zeros(3)
                    s.align_time = 0.0
                    s.t += dt
                    self.s = s
                    return "ok"
                roll = math.atan2(-fm[1], -fm[2])
                pitch = math.atan2(fm[0], math.sqrt(fm[1] ** 2 + fm[2] ** 2))
                s.nav.q_nb = _from_euler(roll, pitch, 0.0)
                s.phase = LEVELLED
                s.align_method = "static"
                s.level_t = s.t + dt
        elif s.phase == LEVELLED:
            q = Q.mul(s.nav.q_nb, Q.from_rotvec(w * dt))
            s.nav.q_nb = q / np.linalg.norm(q)
        else:
            sf = dict(w_b=w, acc_scale=s.acc_scale, gyro_scale=s.gyro_scale) if self.scale_factors else {}
            F = gpsins_F(s.nav, f, p, **sf)
            v0 = s.nav.v_n.copy()
            st = strapdown_step(s.nav, w, f, dt, earth_rotation=p.earth_rotation)
            if st != "ok":
                return st
            if not resolved:
                self._rest_velocity(s, s.nav.v_n - v0, g)
            Fdt = F * dt
            Phi = np.eye(len(F)) + Fdt + 0.5 * Fdt @ Fdt
            self.last_transition = Phi  # the smoother's (GpsInsRtsModel)
            qc = _qc_diag(p, s.q_scale, len(F))
            Qd = 0.5 * dt * (Phi * qc) @ Phi.T + np.diag(0.5 * dt * qc)
            qa = _qc_rate(p, s.q_scale, s.nav.q_nb, w, self.scale_factors)  # at the attitude after the step
            if qa is not None:
                Qd += 0.5 * dt * (Phi[:, ATT:ATT + 3] @ qa @ Phi[:, ATT:ATT + 3].T)
                Qd[ATT:ATT + 3, ATT:ATT + 3] += 0.5 * dt * qa
            P = Phi @ s.P @ Phi.T + Qd
            P = 0.5 * (P + P.T)
            if p.acc_bias_tau > 0:
                s.acc_bias = s.acc_bias * math.exp(-dt / p.acc_bias_tau)
            if p.gyro_bias_tau > 0:
                s.gyro_bias = s.gyro_bias * math.exp(-dt / p.gyro_bias_tau)
            s.P = P
        if s.phase == NAVIGATING:
            _nhc_evidence(s, p, dt)
        s.omega_b = w
        s.f_b = f
        s.dt_last = dt
        s.t += dt
        self.s = s
        return "ok"

    def _rest_velocity(self, s, dv, g):
        """The rest test's velocity in an outage takes the INS velocity change dv only with an
        acceleration that stands out of the drift the covariance allows (tilt times g, accelerometer
        bias, low-passed noise; 3 sigma): quatnav::detail::gpsins_rest_velocity."""
        p, P = self.p, s.P
        a_n = Q.rotate(s.nav.q_nb, s.rest_acc_lp)
        var = (g * g * (P[ATT, ATT] + P[ATT + 1, ATT + 1]) + P[BA, BA] + P[BA + 1, BA + 1] + P[BA + 2, BA + 2]
               + p.acc_noise * p.acc_noise / p.rest_tau)
        if a_n[0] * a_n[0] + a_n[1] * a_n[1] > 9 * var:
            s.rest_v = s.rest_v + dv

    def _rest_step(self, s, w, f, dt, g, slow):
        p = self.p
        if not s.rest_init:
            s.rest_gyr_lp, s.rest_acc_lp, s.rest_init = w.copy(), f.copy(), True
        else:
            a = lowpass_weight(dt, p.rest_tau)
            s.rest_gyr_lp = s.rest_gyr_lp + a * (w - s.rest_gyr_lp)
            s.rest_acc_lp = s.rest_acc_lp + a * (f - s.rest_acc_lp)
        still = (slow and np.linalg.norm(w - s.rest_gyr_lp) < p.rest_gyr_th
                 and np.linalg.norm(f - s.rest_acc_lp) < p.rest_acc_th and abs(np.linalg.norm(s.rest_acc_lp) - g) < p.rest_acc_th)
        s.rest_t = s.rest_t + dt if still else 0.0
        return still

    @staticmethod
    def _window_start(s, llh, v, has_v):
        s.mot_valid, s.mot_llh, s.mot_has_v = True, tuple(llh), has_v
        s.mot_v0 = np.asarray(v, float).copy() if has_v else np.zeros(3)
        s.mot_q, s.mot_dv, s.mot_T = np.array([1.0, 0.0, 0.0, 0.0]), np.zeros(3), 0.0

    @staticmethod
    def _window_step(s, w, f, dt):
        half = Q.mul(s.mot_q, Q.from_rotvec(w * (0.5 * dt)))
        s.mot_dv = s.mot_dv + Q.rotate(half, f) * dt
        q = Q.mul(s.mot_q, Q.from_rotvec(w * dt))
        s.mot_q = q / np.linalg.norm(q)
        s.mot_T += dt

    @property
    def at_rest(self):
        return self.p.rest_time > 0 and self.s.rest_t >= self.p.rest_time

    def set_initial(self, q_nb, v_n=None, acc_bias=(0.0, 0.0, 0.0), gyro_bias=(0.0, 0.0, 0.0),
                    acc_scale=(0.0, 0.0, 0.0), gyro_scale=(0.0, 0.0, 0.0)):
        if self.s.phase == NAVIGATING:
            return "not_initialized"
        s = self.s.copy()
        q = np.asarray(q_nb, float)
        s.nav.q_nb = q / np.linalg.norm(q)
        s.acc_bias, s.gyro_bias = np.asarray(acc_bias, float).copy(), np.asarray(gyro_bias, float).copy()
        s.acc_scale, s.gyro_scale = self._scales(acc_scale, gyro_scale)
        s.init_v = None if v_n is None else np.asarray(v_n, float).copy()
        s.phase, s.heading_known = LEVELLED, True
        s.align_method = s.heading_source = "given"
        s.level_t = s.t
        self.s = s
        return "ok"

    @property
    def nhc_active(self):
        """The non-holonomic constraint applies while moving: forced (nhc) or by evidence (nhc_auto)."""
        return bool(self.p.nhc or (self.p.nhc_auto and self.s.nhc_t >= self.p.nhc_auto_time))

    def update_constraints(self):
        """ZUPT and ZARU at rest, NHC while moving, at most every pseudo_interval."""
        p, s = self.p, self.s
        none = (_result("not_initialized", 3), _result("not_initialized", 3), _result("not_initialized", 2))
        if s.phase != NAVIGATING or s.t - s.pseudo_t < p.pseudo_interval * (1 - 1e-9):
            return none
        zupt, zaru, nhc = none
        if self.at_rest and p.zupt:
            zupt = self._apply("zupt", *_zupt(self.s, p), p.gate_zupt)
            zaru = self._apply("zaru", *_zaru(self.s, p), p.gate_zupt)
            self.s.pseudo_t = self.s.t
        elif not self.at_rest and self.nhc_active:
            var = p.nhc_sigma ** 2 if p.nhc else max(p.nhc_sigma ** 2, self.s.nhc_ms)
            lateral = p.nhc or p.nhc_lateral_aided or not _gnss_aided(self.s)
            nhc = self._apply("nhc", *_nhc(self.s, p, var, lateral), p.gate_nhc)
            self.s.pseudo_t = self.s.t
        return zupt, zaru, nhc

    def update_odometer(self, speed):
        if not math.isfinite(speed):
            return self._count("odometer", _result("non_finite", 1))
        if self.s.phase != NAVIGATING:
            return _result("not_initialized", 1)
        return self._apply("odometer", *_odometer(self.s, self.p, float(speed)), self.p.gate_odometer)

    def update_mag(self, m_imu):
        p = self.p
        m = np.asarray(m_imu, float)
        if not np.all(np.isfinite(m)):
            return self._count("mag", _result("non_finite", 1))
        m_b = p.imu_rotation @ m if not np.array_equal(p.imu_rotation, np.eye(3)) else m
        norm = float(np.linalg.norm(m_b))
        if not norm > 0:
            return self._count("mag", _result("zero_norm", 1))
        if self.s.phase == ALIGNING:
            return _result("not_initialized", 1)
        s = self.s
        m_n = Q.rotate(s.nav.q_nb, m_b)
        dip = math.atan2(m_n[2], math.hypot(m_n[0], m_n[1]))
        if s.mag_ref_n < max(p.mag_ref_samples, 0):
            n1 = s.mag_ref_n + 1
            s.mag_ref_norm += (norm - s.mag_ref_norm) / n1
            s.mag_ref_dip += (dip - s.mag_ref_dip) / n1
            s.mag_ref_n += 1
        elif ((p.mag_norm_tol > 0 and abs(norm / s.mag_ref_norm - 1) > p.mag_norm_tol)
              or (p.mag_dip_tol > 0 and abs(dip - s.mag_ref_dip) > p.mag_dip_tol)):
            res = _result("rejected", 1)
            res.innovation[0] = float(Q.wrap_pi(math.atan2(m_n[1], m_n[0]) - p.declination))
            res.nis = math.nan
            return self._count("mag", res)
        if s.phase == LEVELLED:
            res = _result("not_initialized", 1)
            if not s.heading_known:
                e = Q.to_euler(s.nav.q_nb)
                self._set_yaw(float(Q.wrap_pi(e[2] - (math.atan2(m_n[1], m_n[0]) - p.declination))))
                self.s.heading_source = "magnetometer"
                res.decision = "aligned"
            return res
        return self._apply("mag", *_mag_heading(s, p, m_b), p.gate_mag)

    # --- the one gated correction path ----------------------------------------------------
    def _count(self, kind, res):
        c = self.s.counters[kind]
        if res.status == "ok":
            c["accepted"] += 1
            if kind in ("gps_pos", "gps_vel"):
                self.s.gnss_t = self.s.t
            res.decision = "accepted" if res.decision == "none" else res.decision
        elif res.status == "rejected":
            c["rejected"] += 1
            res.decision = "rejected" if res.decision == "none" else res.decision
        else:
            c["skipped"] += 1
            res.decision = "skipped"
        if res.decision == "inflated":
            c["inflated"] += 1
        if res.decision == "weighted":
            c["weighted"] += 1
        if res.decision == "reset":
            c["resets"] += 1
        return res

    def _correct_commit(self, P, H, R, y, gate, robust_k=0.0):
        """Correct, inject, commit; with robust_k > 0 a correction is made again with R raised where
        the innovation lies beyond robust_k sigmas (huber_scales), and a fix the gate refused is
        judged again by the gate on that weighted innovation (detail::gpsins_huber_correct: only a
        gross outlier stays refused). Returns (status, S, nis, weighted) with the S and NIS of the
        fix as it came."""
        status, dx, P_new, S, nis = kalman_correct(P, H, R, y, gate)
        weighted = False
        if status in ("ok", "rejected") and robust_k > 0:
            d = huber_scales(y, S, robust_k)
            if d is not None:
                status, dx, P_new, _, _ = kalman_correct(P, H, d[:, None] * R * d[None, :], y,
                                                         gate if status == "rejected" else 0.0)
                weighted = status == "ok"
        if status == "ok":
            s = self.s.copy()
            s.P = P_new
            self._inject(s, dx)
            self.s = s
        return status, S, nis, weighted

    def _apply(self, kind, y, H, R, gate, adaptive=False, reset=None):
        """Gate; for a GNSS aid robust weighting, outlier isolation, inflation or reset,
        adaptation; correction."""
        p, m = self.p, len(y)
        y = np.asarray(y, float)
        status, S, nis, weighted = self._correct_commit(self.s.P, H, R, y, gate, p.gps_robust_k if adaptive else 0.0)
        res = Result(status, y, S, nis)
        if status == "ok":
            self.s.reject_run[kind] = 0
            if weighted:
                res.decision = "weighted"
            if adaptive:
                self._adapt(nis / m)
            return self._count(kind, res)
        if status != "rejected":
            return self._count(kind, res)
        if adaptive and p.inflate_after > 0 and self.s.reject_run[kind] >= p.inflate_after:
            a = self._inflation(H, S, y)
            if a <= p.inflate_max:
                P = self.s.P.copy()
                P[:6, :6] *= a
                if self._correct_commit(P, H, R, y, 0.0)[0] == "ok":
                    res.status, res.decision, res.inflation = "ok", "inflated", a
                    self.s.reject_run[kind] = 0
                    self._adapt(nis / m)
                    return self._count(kind, res)
            else:
                s = self.s.copy()
                reset(s, R)
                self.s = s
                res.decision = "reset"
                self.s.reject_run[kind] = 0
                return self._count(kind, res)
        self.s.reject_run[kind] += 1
        return self._count(kind, res)

    def _inflation(self, H, S, y):
        """Smallest a in [1, inflate_max] with y^T (S + (a - 1) H_n P_nn H_n^T)^-1 y <= rows."""
        Hn = H[:, :6]
        B = Hn @ self.s.P[:6, :6] @ Hn.T
        m = len(y)

        def nis(a):
            try:
                L = np.linalg.cholesky(S + (a - 1.0) * B)
            except np.linalg.LinAlgError:
                return np.inf
            w = np.linalg.solve(L, y)
            return float(w @ w)
        amax = max(self.p.inflate_max, 1.0)
        if not nis(amax) <= m:
            return 2.0 * amax
        lo, hi = 0.0, math.log(amax)
        for _ in range(40):
            mid = 0.5 * (lo + hi)
            if nis(math.exp(mid)) <= m:
                hi = mid
            else:
                lo = mid
        return math.exp(hi)

    def _adapt(self, r):
        """ln q_scale moves by adapt_gain (ln r -+ ln 3) outside [1/3, 3], within [1, adapt_q_max]."""
        p = self.p
        if not p.adapt_q_max > 1 or not r > 0 or not math.isfinite(r):
            return
        l3, lr = math.log(3.0), math.log(min(r, 1e3))
        step = p.adapt_gain * (lr - l3) if lr > l3 else (p.adapt_gain * (lr + l3) if lr < -l3 else 0.0)
        if step == 0.0:
            return
        l = min(max(math.log(self.s.q_scale) + step, 0.0), math.log(p.adapt_q_max))
        self.s.q_scale = math.exp(l)

    _inject = staticmethod(inject)

    # --- measurement updates --------------------------------------------------------------
    def _pos_sigma(self, sigma):
        s = np.asarray(sigma, float)
        d = np.array([self.p.gps_pos_sigma_h, self.p.gps_pos_sigma_h, self.p.gps_pos_sigma_v])
        return np.where(np.isnan(s), d, s)

    def _vel_sigma(self, sigma):
        s = np.asarray(sigma, float)
        return np.where(np.isnan(s), self.p.gps_vel_sigma, s)

    def _set_yaw(self, yaw):
        e = Q.to_euler(self.s.nav.q_nb)
        self.s.nav.q_nb = _from_euler(e[0], e[1], yaw)
        self.s.heading_known = True

    def _init_baro_offset(self, s, h_baro):
        """The offset state from one altimeter sample: its error is dp_D plus the sample's noise."""
        s.baro_offset = h_baro - s.nav.h
        P = s.P.copy()
        P[BO, :] = P[POS + 2, :]
        P[:, BO] = P[:, POS + 2]
        P[BO, BO] = P[POS + 2, POS + 2] + self.p.baro_sigma ** 2
        s.P = P
        s.baro_offset_valid = True

    def _start(self, lat, lon, h, sig, q, v0, vel_sigma, level_sigma, yaw_sigma, method, heading):
        s = self.s.copy()
        q = np.asarray(q, float) / np.linalg.norm(q)
        lat, lon, h = geodetic_add(lat, lon, h, -Q.rotate(q, self.p.lever_arm_b))
        s.nav = StrapdownState(q_nb=q, v_n=np.asarray(v0, float).copy(), lat=lat, lon=lon, h=h)
        s.P = self._initial_P(sig, vel_sigma, level_sigma, yaw_sigma)
        s.phase, s.heading_known = NAVIGATING, True
        s.align_method, s.heading_source, s.nav_start_t = method, heading, s.t
        s.gps_pos_t = s.t  # the fix it starts from (gnss_correlation_scale)
        s.rest_v = s.nav.v_n.copy()
        s.mot_valid = False
        s.baro_offset_valid = False
        if s.baro_last_valid:
            self._init_baro_offset(s, s.baro_last)
        self.s = s
        return "ok"

    def _align_in_motion(self, lat, lon, h, psig, v2, vsig):
        """Alignment in motion at a fix: TRIAD with GNSS velocity, else the course between fixes."""
        p, s = self.p, self.s
        have_v = bool(np.all(np.isfinite(v2)))
        if not s.mot_valid:
            self._window_start(s, (lat, lon, h), v2, have_v)
            return "not_initialized"
        T = s.mot_T
        if T >= p.align_motion_time:
            g = float(earth.gravity(lat, h))
            dv_b = Q.rotate_inv(s.mot_q, s.mot_dv)
            if have_v and s.mot_has_v:
                speed = math.hypot(v2[0], v2[1])
                C = _triad(dv_b, np.array([1.0, 0, 0]), v2 - s.mot_v0 - np.array([0, 0, g * T]),
                           np.array([v2[0], v2[1], 0.0])) if speed >= p.min_speed_for_heading else None
                if C is not None:
                    e = math.sqrt(2) * float(np.max(vsig)) / (g * T)
                    b = p.init_gyro_bias_sigma * T
                    st = self._start(lat, lon, h, psig, Q.from_rotmat(C), v2, p.init_vel_sigma,
                                     math.sqrt(p.init_level_sigma ** 2 + e ** 2 + b ** 2), p.init_yaw_sigma,
                                     "gnss_velocity", "gnss_velocity")
                    self.s.level_t = self.s.t
                    return st
            elif not have_v:
                c = self._window_course(lat, lon, h, psig, True)
                if c is not None:
                    q, v, vs, ys, ls = c
                    st = self._start(lat, lon, h, psig, q, v, vs, ls, ys, "gnss_course", "gnss_course")
                    self.s.level_t = self.s.t
                    return st
        if T > p.align_motion_max:
            self._window_start(self.s, (lat, lon, h), v2, have_v)
        return "not_initialized"

    def _window_course(self, lat, lon, h, psig, level):
        p, s = self.p, self.s
        if not s.mot_valid:
            self._window_start(s, (lat, lon, h), np.zeros(3), False)
            return None
        d = geodetic_diff(lat, lon, h, *s.mot_llh)
        dist = math.hypot(d[0], d[1])
        sh = math.hypot(psig[0], psig[1])
        T = s.mot_T
        if T > 0 and 2 * sh / T < 0.5 * p.rest_speed:  # the window tells rest from motion
            s.gnss_speed, s.gnss_speed_t = dist / T, s.t
        if not (dist >= max(p.align_course_distance, 4 * sh)) or not T > 0:
            if T > p.align_motion_max:
                self._window_start(s, (lat, lon, h), np.zeros(3), False)
            return None
        course = math.atan2(d[1], d[0])
        a, ls = 0.0, p.init_level_sigma
        if level:
            dv_b = Q.rotate_inv(s.mot_q, s.mot_dv)
            g = float(earth.gravity(lat, h))
            dev = abs(np.linalg.norm(dv_b) / T - g)
            if not dev < p.rest_acc_th:  # accelerating: wait
                if T > p.align_motion_max:
                    self._window_start(s, (lat, lon, h), np.zeros(3), False)
                return None
            C = _triad(dv_b, np.array([1.0, 0, 0]), np.array([0, 0, -1.0]),
                       np.array([math.cos(course), math.sin(course), 0.0]))
            if C is None:
                return None
            q = Q.from_rotmat(C)
            a = math.sqrt(2 * g * dev)
            l0 = max(p.align_level_sigma, p.init_level_sigma)
            ls = math.sqrt(l0 ** 2 + (a / g) ** 2 + (p.init_gyro_bias_sigma * T) ** 2)
        else:
            e = Q.to_euler(s.nav.q_nb)
            q = _from_euler(e[0], e[1], course)
        v = np.array([d[0] / T, d[1] / T, 0.0])
        return q, v, max(2 * sh / T + a * T / 2, p.init_vel_sigma), max(2 * sh / dist, p.init_yaw_sigma), ls

    def update_gps_position(self, lat, lon, h, sigma, age=0.0, v0_n=(np.nan, np.nan, np.nan),
                            vel_sigma=(np.nan, np.nan, np.nan), solution=0):
        if not (math.isfinite(lat) and math.isfinite(lon) and math.isfinite(h) and math.isfinite(age)) \
                or abs(lat) > math.pi / 2:
            return self._count("gps_pos", _result("non_finite", 3))
        sig = self._pos_sigma(sigma)
        if not (np.all(np.isfinite(sig)) and sig.min() > 0):
            return self._count("gps_pos", _result("invalid_argument", 3))
        p = self.p
        floor = gnss_sigma_floor(p, solution)
        psig = np.maximum(sig, floor)
        v0_n = np.asarray(v0_n, float)
        if self.s.phase == ALIGNING:
            st = self._align_in_motion(lat, lon, h, psig, v0_n, self._vel_sigma(vel_sigma))
            return _result(st, 3, "aligned" if st == "ok" else "none")
        if self.s.phase == LEVELLED:
            s = self.s
            if not s.heading_known:
                c = self._window_course(lat, lon, h, psig, False)
                if c is None:
                    return _result("not_initialized", 3)
                q, v, vs, ys, _ = c
                st = self._start(lat, lon, h, psig, q, v, vs, p.init_level_sigma, ys, s.align_method, "gnss_course")
            else:
                v0 = s.init_v if s.init_v is not None else (v0_n if np.all(np.isfinite(v0_n)) else np.zeros(3))
                st = self._start(lat, lon, h, psig, s.nav.q_nb, v0, p.init_vel_sigma, p.init_level_sigma,
                                 p.init_yaw_sigma, s.align_method, s.heading_source)
            return _result(st, 3, "aligned")
        # a fix whose error wanders repeats much of the last one's: its R raised accordingly
        t_fix = self.s.t - age
        k = gnss_correlation_scale(p, solution, t_fix - self.s.gps_pos_t)
        y, H, R = _gps_position(self.s, self.p, lat, lon, h, k * sig, age, k * floor)
        r = self._apply("gps_pos", y, H, R, self.p.gate_gps_pos, True,
                        lambda s, R: _reset_position(s, self.p, (lat, lon, h), R))
        if r.status == "ok" or r.decision == "reset":
            self.s.gps_pos_t = t_fix
        return r

    def update_gps_velocity(self, v_n, sigma, age=0.0):
        v_n = np.asarray(v_n, float)
        if not (np.all(np.isfinite(v_n)) and math.isfinite(age)):
            return self._count("gps_vel", _result("non_finite", 3))
        sig = self._vel_sigma(sigma)
        if not (np.all(np.isfinite(sig)) and sig.min() > 0):
            return self._count("gps_vel", _result("invalid_argument", 3))
        if self.s.phase != NAVIGATING:
            res = _result("not_initialized", 3)
            speed = math.hypot(v_n[0], v_n[1])
            self.s.gnss_speed = max(speed - 3 * math.hypot(sig[0], sig[1]), 0.0)  # less three sigmas
            self.s.gnss_speed_t = self.s.t
            if self.s.phase == LEVELLED and not self.s.heading_known and self.p.heading_from_gps:
                if math.hypot(v_n[0], v_n[1]) >= self.p.min_speed_for_heading:
                    self._set_yaw(math.atan2(v_n[1], v_n[0]))
                    self.s.heading_source = "gnss_velocity"
                    res.decision = "aligned"
            return res
        y, H, R = _gps_velocity(self.s, self.p, v_n, sig, age)
        return self._apply("gps_vel", y, H, R, self.p.gate_gps_vel, True,
                           lambda s, R: _reset_velocity(s, self.p, v_n, R))

    def update_gps(self, lat, lon, h, v_n, pos_sigma, vel_sigma, age=0.0, solution=0):
        """Returns ``(pos_result, vel_result)`` (see the C++ ``update_gps``)."""
        v = np.asarray(v_n, float)
        have_vel = not np.all(np.isnan(v))
        vel = _result("not_initialized", 3)
        if self.s.phase != NAVIGATING:
            if have_vel:
                vel = self.update_gps_velocity(v, vel_sigma, age)
            pos = self.update_gps_position(lat, lon, h, pos_sigma, age, v, vel_sigma, solution)
            return pos, vel
        pos = self.update_gps_position(lat, lon, h, pos_sigma, age, v, vel_sigma, solution)
        if have_vel:
            vel = self.update_gps_velocity(v, vel_sigma, age)
        return pos, vel

    def update_baro(self, h_baro):
        """Returns ``(height_result, vd_result)``."""
        p = self.p
        vd = _result("not_initialized", 1)
        if not math.isfinite(h_baro):
            return self._count("baro", _result("non_finite", 1)), vd
        s = self.s
        s.baro_last = float(h_baro)
        s.baro_last_valid = True
        if s.phase != NAVIGATING:
            return _result("not_initialized", 1), vd
        if not s.baro_offset_valid:
            self._init_baro_offset(s, float(h_baro))
            height = _result("ok", 1, "aligned")
        else:
            height = self._apply("baro", *_baro_height(s, p, float(h_baro)), p.gate_baro)
        s = self.s
        if p.baro_rate_baseline > 0:
            if not s.baro_ref_valid:
                s.baro_ref_valid = True
                s.baro_ref_h = float(h_baro)
                s.baro_ref_t = s.t
            elif s.t - s.baro_ref_t >= p.baro_rate_baseline:
                T = s.t - s.baro_ref_t
                vd = self._apply("baro_vd", *_baro_vd(s, p, float(h_baro), s.baro_ref_h, T), p.gate_baro)
                if vd.status in ("ok", "rejected"):
                    self.s.baro_ref_h = float(h_baro)
                    self.s.baro_ref_t = self.s.t
        return height, vd

    def update_compass(self, heading):
        p = self.p
        if not math.isfinite(heading):
            return self._count("compass", _result("non_finite", 1))
        if self.s.phase == ALIGNING:
            return _result("not_initialized", 1)
        yaw_meas = float(Q.wrap_pi(heading + p.declination))
        if self.s.phase == LEVELLED:
            if self.s.heading_source == "given":
                return _result("not_initialized", 1)
            self._set_yaw(yaw_meas)
            self.s.heading_source = "compass"
            return _result("not_initialized", 1, "aligned")
        return self._apply("compass", *_compass(self.s, p, yaw_meas), p.gate_compass)

    # --- batch (quatnav.reference.gpsins_batch) ---------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
            odometer=None, outages=(), imu_input="rate", smooth=False, observer=None, gps_solution=None):
        """The loop of ``quatnav::gpsins_batch`` with the public ``run``'s signature
        (:func:`quatnav.reference.gpsins_batch.run`)."""
        return gpsins_batch.run(self, gyr, acc, mag, t=t, dt=dt, gps_pos=gps_pos, gps_vel=gps_vel, baro=baro,
                                compass=compass, odometer=odometer, outages=outages, imu_input=imu_input,
                                smooth=smooth, observer=observer, gps_solution=gps_solution)

    def _loop(self, t, gyro, accel, **kw):
        """The batch loop over arrays (:func:`quatnav.reference.gpsins_batch.batch_loop`)."""
        return gpsins_batch.batch_loop(self, t, gyro, accel, **kw)
