"""Reference (numpy) 13-state navigation filter of paper 002; see :mod:`quatnav.filters.nav13`.

Written to be read next to ``cpp/include/quatnav/nav_filter13.hpp`` (same algorithm, same
method names; the tests compare the two step by step). State ``x = [v_n, q_nb, b_a, b_g]``.
"""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from .._validate import did_you_mean
from ..core import earth
from ..core import quaternion as Q
from ..filters.tables import FLAGS, NAV13_PARAMS
from .kalman import kalman_correct
from .smoother import rts

TIME_UPDATES = ("ekf", "second_order", "ukf")
V, QI, BA, BG = slice(0, 3), slice(3, 7), slice(7, 10), slice(10, 13)

#: The parameters of the C++ filter with its defaults (the one table, quatnav.filters.tables).
DEFAULTS = {p.name: p.default for p in NAV13_PARAMS if p.core_name is not None}
#: The options of the batch run that are no C++ parameter (the NIS gates of the two aids).
GATES = {p.name: p.default for p in NAV13_PARAMS if p.core_name is None and p.name != "time_update"}


def quad_rotmat(M):
    """Eq. (5) with q_i q_j replaced by M_ij: ``C(q) = quad_rotmat(outer(q, q))``."""
    ww, xx, yy, zz = M[0, 0], M[1, 1], M[2, 2], M[3, 3]
    wx, wy, wz, xy, xz, yz = M[0, 1], M[0, 2], M[0, 3], M[1, 2], M[1, 3], M[2, 3]
    return np.array([[ww + xx - yy - zz, 2 * (xy - wz), 2 * (xz + wy)],
                     [2 * (xy + wz), ww - xx + yy - zz, 2 * (yz - wx)],
                     [2 * (xz - wy), 2 * (yz + wx), ww - xx - yy + zz]])


def rotmat_hom(q):
    return quad_rotmat(np.outer(q, q))


def dCa_dq(q, a):
    """J(q, a) = d(C(q) a)/dq, 3x4 (eq. A.9)."""
    w, x, y, z = q
    ax, ay, az = a
    return 2.0 * np.array([
        [w * ax - z * ay + y * az, x * ax + y * ay + z * az, -y * ax + x * ay + w * az, -z * ax - w * ay + x * az],
        [z * ax + w * ay - x * az, y * ax - x * ay - w * az, x * ax + y * ay + z * az, w * ax - z * ay + y * az],
        [-y * ax + x * ay + w * az, z * ax + w * ay - x * az, -w * ax + z * ay - y * az, x * ax + y * ay + z * az]])


def _pure(v):
    return np.array([0.0, v[0], v[1], v[2]])


def rhs(x, u):
    """Continuous-time eq. (1), (3), (7)."""
    q = x[QI]
    a = u.f_ib_b - x[BA]
    w = u.omega_ib_b - x[BG]
    alpha = 2 * u.omega_ie_n + u.omega_en_n
    w_in = u.omega_ie_n + u.omega_en_n
    d = np.zeros(13)
    d[V] = rotmat_hom(q) @ a - np.cross(alpha, x[V]) + u.g_n
    d[QI] = 0.5 * (Q.xi(q) @ w - Q.left(_pure(w_in)) @ q)
    return d


def rotation_correction(f_ib_b, omega_ib_b, b_a, b_g, dt):
    """First-order rotation correction of the velocity increment over a step (see the C++
    header, eq. 12): ``f + dt/2 (w - b_g) x (f - b_a)`` for inputs that are means over the step."""
    return f_ib_b + 0.5 * dt * np.cross(omega_ib_b - b_g, f_ib_b - b_a)


def f_d(x, u):
    """Eq. (12): one Euler step."""
    return x + u.dt * rhs(x, u)


def jacobian(x, u):
    q = x[QI]
    a = u.f_ib_b - x[BA]
    w = u.omega_ib_b - x[BG]
    alpha = 2 * u.omega_ie_n + u.omega_en_n
    w_in = u.omega_ie_n + u.omega_en_n
    dt = u.dt
    F = np.eye(13)
    F[V, V] -= dt * Q.skew(alpha)
    F[V, QI] = dt * dCa_dq(q, a)
    F[V, BA] = -dt * rotmat_hom(q)
    F[QI, QI] += dt / 2 * (Q.omega(w) - Q.left(_pure(w_in)))
    F[QI, BG] = -dt / 2 * Q.xi(q)
    return F


def second_order_term(x, P, u):
    """1/2 sum_ij P_ij d2 f_d / dx_i dx_j (eq. 16-17), non-zero blocks only."""
    q = x[QI]
    a = u.f_ib_b - x[BA]
    s = np.zeros(13)
    sv = quad_rotmat(P[QI, QI]) @ a
    for k in range(3):
        sv -= dCa_dq(q, np.eye(3)[k]) @ P[QI, 7 + k]
    s[V] = u.dt * sv
    sq = np.zeros(4)
    for k in range(3):
        sq += Q.xi(P[QI, 10 + k])[:, k]
    s[QI] = -u.dt / 2 * sq
    return s


def process_noise(q, dt, p):
    Qm = np.zeros((13, 13))
    C = rotmat_hom(q)
    X = Q.xi(q)
    Qm[V, V] = dt * p.acc_noise**2 * C @ C.T
    Qm[QI, QI] = dt * p.gyro_noise**2 / 4 * X @ X.T
    Qm[BA, BA] = dt * p.acc_bias_noise**2 * np.eye(3)
    Qm[BG, BG] = dt * p.gyro_bias_noise**2 * np.eye(3)
    return Qm


def yaw_of(q):
    """Eq. (14), atan2 form."""
    return np.arctan2(2 * (q[1] * q[2] + q[0] * q[3]), q[0]**2 + q[1]**2 - q[2]**2 - q[3]**2)


def yaw_jacobian(q):
    n = 2 * (q[1] * q[2] + q[0] * q[3])
    d = q[0]**2 + q[1]**2 - q[2]**2 - q[3]**2
    dn = 2 * np.array([q[3], q[2], q[1], q[0]])
    dd = 2 * np.array([q[0], q[1], -q[2], -q[3]])
    return (d * dn - n * dd) / (n * n + d * d)


def normalize(x, P):
    q = x[QI]
    n = np.linalg.norm(q)
    qh = q / n
    J = (np.eye(4) - np.outer(qh, qh)) / n
    P = P.copy()
    P[QI, :] = J @ P[QI, :]
    P[:, QI] = P[:, QI] @ J.T
    P = 0.5 * (P + P.T)
    x = x.copy()
    x[QI] = qh
    return x, P


def to_error(q):
    T = np.zeros((12, 13))
    T[0:3, V] = np.eye(3)
    T[3:6, QI] = 2 * Q.xi(q).T
    T[6:9, BA] = np.eye(3)
    T[9:12, BG] = np.eye(3)
    return T


def from_error(q):
    T = np.zeros((13, 12))
    T[V, 0:3] = np.eye(3)
    T[QI, 3:6] = 0.5 * Q.xi(q)
    T[BA, 6:9] = np.eye(3)
    T[BG, 9:12] = np.eye(3)
    return T


def ukf_weights(alpha, beta, kappa, n=12):
    lam = alpha**2 * (n + kappa) - n
    if not n + lam > 0:
        return None
    wm = np.full(2 * n + 1, 1 / (2 * (n + lam)))
    wc = wm.copy()
    wm[0] = lam / (n + lam)
    wc[0] = wm[0] + 1 - alpha**2 + beta
    return SimpleNamespace(gamma=np.sqrt(n + lam), wm=wm, wc=wc)


class NavFilter13:
    """Plain numpy twin of :class:`quatnav.NavFilter13` (same steps, same method names)."""

    def __init__(self, time_update="ekf", **params):
        if time_update not in TIME_UPDATES:
            raise ValueError(f"time_update: expected one of {TIME_UPDATES}, got {time_update!r}")
        self.time_update = time_update
        unknown = sorted(set(params) - set(DEFAULTS) - set(GATES))
        if unknown:
            known = {**DEFAULTS, **GATES}
            raise TypeError(f"NavFilter13: unknown parameter {unknown[0]!r}{did_you_mean(unknown[0], known)}; "
                            f"known: {', '.join(known)}")
        self.gates = {k: float(params.pop(k, v)) for k, v in GATES.items()}
        p = dict(DEFAULTS)
        p.update(params)
        self.params = SimpleNamespace(**p)
        self.weights = ukf_weights(p["ukf_alpha"], p["ukf_beta"], p["ukf_kappa"])
        self.x = np.zeros(13)
        self.x[3] = 1.0
        self.P = np.eye(13)
        self.lat = self.lon = self.h = 0.0
        self.initialized = False
        self.fresh = True  # no step since reset/set_state (run's measurement at the start time)

    # -- state --------------------------------------------------------------------------
    def reset(self, v_n, q_nb, acc_bias, gyro_bias, P, lat, lon, h):
        x = np.concatenate([v_n, q_nb, acc_bias, gyro_bias]).astype(float)
        P = np.asarray(P, float)
        self.x, self.P = normalize(x, 0.5 * (P + P.T))
        self.lat, self.lon, self.h = float(lat), float(lon), float(h)
        self.initialized = True
        self.fresh = True  # run: a measurement at the start time is applied
        return "ok"

    def get_state(self):
        return dict(v_n=self.x[V].copy(), q_nb=self.x[QI].copy(), acc_bias=self.x[BA].copy(),
                    gyro_bias=self.x[BG].copy(), P=self.P.copy(), lat=self.lat, lon=self.lon, h=self.h,
                    initialized=self.initialized)

    def set_state(self, s):
        self.x = np.concatenate([s["v_n"], s["q_nb"], s["acc_bias"], s["gyro_bias"]]).astype(float)
        self.P = np.array(s["P"], float)
        self.lat, self.lon, self.h = float(s["lat"]), float(s["lon"]), float(s["h"])
        self.initialized = bool(s["initialized"])
        self.fresh = True
        return "ok"

    def error_covariance(self):
        T = to_error(self.x[QI])
        return T @ self.P @ T.T

    # -- time update ----------------------------------------------------------------------
    def _input(self, f_ib_b, omega_ib_b, dt):
        p = self.params
        u = SimpleNamespace(f_ib_b=np.asarray(f_ib_b, float), omega_ib_b=np.asarray(omega_ib_b, float), dt=float(dt))
        u.g_n = earth.gravity_n(self.lat, self.h)
        if p.earth_rotation:
            u.omega_ie_n = earth.earth_rate_n(self.lat)
            u.omega_en_n = earth.transport_rate_n(self.lat, self.h, self.x[V])
        else:
            u.omega_ie_n = np.zeros(3)
            u.omega_en_n = np.zeros(3)
        return u

    def predict(self, omega_ib_b, f_ib_b, dt):
        """The time update over ``dt``; refused (a status, the state untouched) like the C++ step:
        before :meth:`reset`, for a non-finite input, a ``dt`` outside (0, max_dt] or a sample at
        or above ``gyro_range`` / ``acc_range`` (when positive). ``cov_floor`` is not modelled."""
        self.fresh = False
        p = self.params
        w, f = np.asarray(omega_ib_b, float), np.asarray(f_ib_b, float)
        if not self.initialized:
            return "not_initialized"
        if not (np.all(np.isfinite(w)) and np.all(np.isfinite(f))):
            return "non_finite"
        if not (0.0 < dt <= p.max_dt):
            return "invalid_dt"
        if ((p.gyro_range > 0 and np.abs(w).max() >= p.gyro_range)
                or (p.acc_range > 0 and np.abs(f).max() >= p.acc_range)):
            return "saturated"
        u = self._input(f_ib_b, omega_ib_b, dt)
        u.f_ib_b = rotation_correction(u.f_ib_b, u.omega_ib_b, self.x[BA], self.x[BG], u.dt)
        x, P = self.x, self.P
        self._last_step = (x, u)
        if self.time_update == "ukf":
            xn, Pn = self._ukf(x, P, u)
        else:
            xn = f_d(x, u)
            if self.time_update == "second_order":
                xn = xn + second_order_term(x, P, u)          # (16)-(17)
            F = jacobian(x, u)
            Pn = F @ P @ F.T + process_noise(x[QI], u.dt, self.params)  # (19)-(20)
            Pn = 0.5 * (Pn + Pn.T)
            xn, Pn = normalize(xn, Pn)
        v_mid = 0.5 * (x[V] + xn[V])
        rl, rlon, rh = earth.geodetic_rates(self.lat, self.h, v_mid)
        self.x, self.P = xn, Pn
        self.lat += rl * u.dt
        self.lon += rlon * u.dt
        self.h += rh * u.dt
        return "ok"

    def _ukf(self, x, P, u):
        w = self.weights
        q0 = x[QI]
        T = to_error(q0)
        P12 = T @ P @ T.T
        P12 = 0.5 * (P12 + P12.T)
        L = w.gamma * np.linalg.cholesky(P12)
        off = np.hstack([np.zeros((12, 1)), L, -L])
        Y = np.zeros((13, 25))
        for i in range(25):
            d = off[:, i]
            xi = x.copy()
            xi[V] += d[0:3]
            xi[QI] = Q.mul(q0, Q.from_rotvec(d[3:6]))
            xi[BA] += d[6:9]
            xi[BG] += d[9:12]
            yi = f_d(xi, u)
            yi[QI] /= np.linalg.norm(yi[QI])
            Y[:, i] = yi
        ysum = Y @ w.wm
        qref = Y[QI, 0]
        qs = Y[QI, :] * np.where(qref @ Y[QI, :] < 0, -1.0, 1.0)
        qm = qs @ w.wm
        qm /= np.linalg.norm(qm)
        D = np.zeros((12, 25))
        D[0:3] = Y[V] - ysum[V, None]
        for i in range(25):
            D[3:6, i] = Q.to_rotvec(Q.mul(Q.conj(qm), Y[QI, i]))
        D[6:9] = Y[BA] - ysum[BA, None]
        D[9:12] = Y[BG] - ysum[BG, None]
        dmean = D[3:6] @ w.wm
        qm = Q.mul(qm, Q.from_rotvec(dmean))
        qm /= np.linalg.norm(qm)
        D[3:6] -= dmean[:, None]
        self._last_cross = (off * w.wc) @ D.T, P12       # the smoother's gain (last_transition)
        P12n = (D * w.wc) @ D.T + T @ process_noise(q0, u.dt, self.params) @ T.T
        P12n = 0.5 * (P12n + P12n.T)
        xn = ysum.copy()
        xn[QI] = qm
        Tb = from_error(qm)
        Pn = Tb @ P12n @ Tb.T
        return xn, 0.5 * (Pn + Pn.T)

    def last_transition(self):
        """The error-state transition (12x12) of the last predict (the smoother's gain, see
        :func:`smooth`): for the EKF and second-order time updates the EKF's ``T(q+) J F T'(q)``,
        F = :func:`jacobian` at the state before the step, J the renormalization's Jacobian, q+ the
        quaternion after it; for the unscented one its statistical linearization ``D^T P^-1``
        (D the sigma points' cross-covariance, P the error covariance before the step), which
        gives the gain ``D P_prior^-1`` of the C++ smoother."""
        if self.time_update == "ukf":
            D, P12 = self._last_cross
            return np.linalg.solve(P12, D).T
        x, u = self._last_step
        xn = f_d(x, u)
        n = np.linalg.norm(xn[QI])
        qh = xn[QI] / n
        J = np.eye(13)
        J[QI, QI] = (np.eye(4) - np.outer(qh, qh)) / n
        return to_error(self.x[QI]) @ J @ jacobian(x, u) @ from_error(x[QI])

    def snapshot(self):
        """The posterior as the smoother keeps it: ``(x, P)``."""
        return self.x.copy(), self.P.copy()

    # -- measurement updates -----------------------------------------------------------------
    def _correct(self, H, R, y, gate):
        self.fresh = False
        status, dx, Pn, S, nis = kalman_correct(self.P, H, R, y, gate)
        res = SimpleNamespace(status=status, innovation=y, innovation_cov=S, nis=nis)
        if status == "ok":
            self.x, self.P = normalize(self.x + dx, Pn)   # (23)
        return res

    def update_velocity(self, v_meas, gate=0.0):
        H = np.zeros((3, 13))
        H[:, V] = np.eye(3)
        R = np.eye(3) * self.params.gps_vel_sigma**2
        return self._correct(H, R, np.asarray(v_meas, float) - self.x[V], gate)

    def update_yaw(self, yaw, gate=0.0):
        H = np.zeros((1, 13))
        H[0, QI] = yaw_jacobian(self.x[QI])
        R = np.array([[self.params.yaw_sigma**2]])
        y = np.array([Q.wrap_pi(float(yaw) - yaw_of(self.x[QI]))])
        return self._correct(H, R, y, gate)

    def update_velocity_yaw(self, v_meas, yaw, gate=0.0):
        H = np.zeros((4, 13))
        H[0:3, V] = np.eye(3)
        H[3, QI] = yaw_jacobian(self.x[QI])
        R = np.diag([self.params.gps_vel_sigma**2] * 3 + [self.params.yaw_sigma**2])
        y = np.concatenate([np.asarray(v_meas, float) - self.x[V], [Q.wrap_pi(float(yaw) - yaw_of(self.x[QI]))]])
        return self._correct(H, R, y, gate)


    # -- batch -----------------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, gps_vel=None, yaw=None, return_covariance=False,
            smooth=False):
        """The loop of ``quatnav::run_nav13_batch`` (nav/nav_filter13.hpp) with the public ``run``'s
        signature (:meth:`quatnav.NavFilter13.run`, without ``on_invalid``), continuing from the
        state given to :meth:`reset`.

        Times: ``t`` (the first step repeats ``t[1] - t[0]``) or ``dt`` (a step or one per sample,
        ``t = cumsum(dt)``), as the public class reads them. The aids as ``Aid(t, value)`` (anything
        with ``.t`` and ``.value``): ``gps_vel`` NED velocities (K, 3), ``yaw`` angles (M,). A
        measurement at time ``tm`` is applied after the predict of the first sample k with
        ``tm <= t[k] + 1e-4 dt[k]``; one older than the state (``tm < t[0] - dt[0] - 1e-4 dt[0]``)
        never; one at the state's time before the first predict if the run starts from
        :meth:`reset` or :meth:`set_state`, never if it continues a previous run (which applied
        it after its last sample); on one sample every due velocity before every due yaw, with the gates
        ``gate_gps_vel`` and ``gate_yaw`` of the constructor.

        Returns a namespace: ``t``, ``x`` (N, 13), ``quat``, ``velocity``, ``acc_bias``,
        ``gyro_bias``, ``sigma`` (N, 13), ``att_sigma`` (N, 3), ``P`` (N, 13, 13, or None without
        ``return_covariance``), ``flags`` (the C++ bits) and ``aids`` (per given aid: ``t``,
        ``innovation``, ``nis``, ``status`` names; "not_initialized" for a measurement never applied:
        older than the state, or after the last sample). ``smooth=True``: the estimates, sigmas and P are the Rauch-Tung-Striebel
        smoothed ones (:func:`smooth`), the forward namespace in ``forward``."""
        if mag is not None:
            raise TypeError("mag: NavFilter13 uses no magnetometer (pass None)")
        if not self.initialized:
            raise ValueError("run: the filter is not initialized (call reset first)")
        gyr, acc = np.asarray(gyr, float), np.asarray(acc, float)
        n = len(gyr)
        if (t is None) == (dt is None):
            raise ValueError("dt, t: give exactly one of dt (seconds) or t (timestamps, seconds)")
        if t is not None:
            t = np.asarray(t, float)
            d = np.diff(t)
            steps = np.concatenate([d[:1], d])
        else:
            steps = np.broadcast_to(np.asarray(dt, float), (n,)).copy()
            t = np.cumsum(steps)
        aids = {}
        for name, aid, cols in (("gps_vel", gps_vel, 3), ("yaw", yaw, 1)):
            ta = np.zeros(0) if aid is None else np.asarray(aid.t, float)
            va = np.zeros((0, cols)) if aid is None else np.asarray(aid.value, float).reshape(len(ta), cols)
            aids[name] = SimpleNamespace(t=ta, value=va, innovation=np.full((len(ta), cols), np.nan),
                                         nis=np.full(len(ta), np.nan),
                                         status=np.full(len(ta), "not_initialized", dtype=object))
        vel, yw = aids["gps_vel"], aids["yaw"]
        next_ = {"gps_vel": 0, "yaw": 0}
        used = {"gps_vel": (FLAGS["gps_vel_used"], FLAGS["gps_vel_rejected"]),
                "yaw": (FLAGS["heading_used"], FLAGS["heading_rejected"])}

        def apply(t_now):
            fl = 0
            for name, a, update in (("gps_vel", vel, lambda v: self.update_velocity(v, self.gates["gate_gps_vel"])),
                                    ("yaw", yw, lambda v: self.update_yaw(v[0], self.gates["gate_yaw"]))):
                i = next_[name]
                while i < len(a.t) and a.t[i] <= t_now:
                    r = update(a.value[i])
                    a.innovation[i], a.nis[i], a.status[i] = r.innovation, r.nis, r.status
                    ok, rejected = used[name]
                    skipped = FLAGS["aid_skipped"]
                    fl |= {"ok": ok, "rejected": rejected,
                           "solve_failed": FLAGS["solve_failed"] | skipped}.get(r.status, skipped)
                    i += 1
                next_[name] = i
            return fl

        out = dict(x=np.empty((n, 13)), sigma=np.empty((n, 13)), att_sigma=np.empty((n, 3)),
                   P=np.empty((n, 13, 13)), flags=np.zeros(n, np.uint32))
        posts, links = [], []
        fl0 = 0
        if n:
            # Older than the state: never applied (not_initialized). At the state's time: applied
            # before the first predict by a run from reset/set_state, never by one that continues.
            tol, t_start = 1e-4 * steps[0], t[0] - steps[0]
            for name, a in (("gps_vel", vel), ("yaw", yw)):
                next_[name] = int(np.searchsorted(a.t, t_start - tol, side="left"))
            if self.fresh:
                fl0 = apply(t_start + tol)
            else:
                for name, a in (("gps_vel", vel), ("yaw", yw)):
                    next_[name] = int(np.searchsorted(a.t, t_start + tol, side="right"))
            self.fresh = False
        for k in range(n):
            fl = fl0 if k == 0 else 0
            status = self.predict(gyr[k], acc[k], steps[k])
            if status != "ok":
                fl |= FLAGS["predict_skipped"] | (FLAGS["saturated"] if status == "saturated" else 0)
            if k:
                links.append((self.snapshot(), self.last_transition()) if status == "ok" else "same")
            fl |= apply(t[k] + 1e-4 * steps[k])
            posts.append(self.snapshot())
            out["x"][k], out["P"][k], out["flags"][k] = self.x, self.P, fl
            out["sigma"][k] = np.sqrt(np.maximum(np.diag(self.P), 0.0))
            out["att_sigma"][k] = np.sqrt(np.maximum(np.diag(self.error_covariance())[3:6], 0.0))

        def result(x, sigma, att_sigma, P, **kw):
            return SimpleNamespace(t=t, x=x, quat=x[:, QI], velocity=x[:, V], acc_bias=x[:, BA], gyro_bias=x[:, BG],
                                   sigma=sigma, att_sigma=att_sigma, P=P if return_covariance else None,
                                   flags=out["flags"], aids={k: aids[k] for k, a in (("gps_vel", gps_vel), ("yaw", yaw))
                                                             if a is not None}, **kw)

        fwd = result(out["x"], out["sigma"], out["att_sigma"], out["P"])
        if not smooth or n == 0:
            return fwd
        xs, Pe = rts(posts, links, error_covariance, local, retract)  # smooth(posts, links)
        x = np.array([s[0] for s in xs])
        P = np.array([s[1] for s in xs])
        Pe = np.array(Pe)
        sigma = np.sqrt(np.maximum(np.diagonal(P, axis1=1, axis2=2), 0.0))
        att_sigma = np.sqrt(np.maximum(np.diagonal(Pe[:, 3:6, 3:6], axis1=1, axis2=2), 0.0))
        return result(x, sigma, att_sigma, P, forward=fwd)

# -- the Rauch-Tung-Striebel smoother (cpp/include/quatnav/nav/nav13_smoother.hpp) -------------------
def error_covariance(state):
    """The 12x12 covariance of ``[dv, dtheta, db_a, db_g]`` of a snapshot ``(x, P)``."""
    x, P = state
    T = to_error(x[QI])
    Pe = T @ P @ T.T
    return 0.5 * (Pe + Pe.T)


def local(base, state):
    """``state [-] base``: velocity and bias differences, the body-frame rotation ``log(q_b^-1 q)``."""
    xb, x = base[0], state[0]
    return np.concatenate([x[V] - xb[V], Q.to_rotvec(Q.mul(Q.conj(xb[QI]), x[QI])), x[7:] - xb[7:]])


def retract(base, d, Pe):
    """``base [+] d`` with the error covariance ``Pe`` mapped to the 13-state form."""
    x = base[0].copy()
    x[V] += d[0:3]
    q = Q.mul(x[QI], Q.from_rotvec(d[3:6]))
    x[QI] = q / np.linalg.norm(q)
    x[7:] += d[6:]
    Tb = from_error(x[QI])
    P = Tb @ Pe @ Tb.T
    return x, 0.5 * (P + P.T)


def smooth(posts, links):
    """The smoothed snapshots ``(x, P)`` and 12x12 error covariances of a forward run of
    :class:`NavFilter13`: ``posts[k]`` its :meth:`NavFilter13.snapshot` after sample k, ``links[k]``
    ``(snapshot after the predict of sample k + 1, last_transition())``, ``"same"`` when that
    predict was refused, or None (see :func:`quatnav.reference.smoother.rts`)."""
    return rts(posts, links, error_covariance, local, retract)
