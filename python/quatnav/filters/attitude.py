"""Attitude filters of paper 000: :class:`QuaternionEKF` and its baseline :class:`EulerEKF`.

Both wrap the C++ classes of ``quatnav._core`` (float64 or float32, chosen by ``dtype``);
batch runs execute in C++ with the GIL released. Plain numpy twins live in
:mod:`quatnav.reference`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from .. import _validate as V
from ..core import quaternion as Q
from ._compiled import compiled
from ._base import Filter, FilterResult, check_run_inputs, marg_inputs, smoother_info, times_of
from .tables import ATTITUDE_FLAGS, EULER_PARAMS, QEKF_PARAMS

__all__ = ["QuaternionEKF", "EulerEKF", "AttitudeResult"]


@dataclass(repr=False, eq=False)
class AttitudeResult(FilterResult):
    """Output of :meth:`QuaternionEKF.run` and :meth:`EulerEKF.run`: the fields of
    :class:`~quatnav.FilterResult` (``quat``, ``bias``, ``sigma`` of the filter's states,
    ``flags`` of :data:`FLAGS`; no aids) and

    Attributes
    ----------
    att_sigma : (N, 3) ndarray
        One-sigma of the attitude error as a body-frame rotation vector, rad.
    """

    FLAGS: ClassVar[dict] = ATTITUDE_FLAGS
    att_sigma: np.ndarray | None = None


class _AttitudeFilter(Filter):
    _core_name: str = ""
    n_states: int = 0
    _sigma_names: tuple = ()

    def _make(self, p):
        if self._opts.get("paper") and hasattr(compiled(self._core_params, self.dtype), "paper"):
            p = self._core_struct(compiled(self._core_params, self.dtype).paper())
        return compiled(self._core_name, self.dtype)(p)

    # -- parameters and state -------------------------------------------------------------
    @property
    def quat(self) -> np.ndarray:
        """Current ``q_nb`` [w, x, y, z]."""
        return np.asarray(self._f.quat, dtype=float)

    @property
    def bias(self) -> np.ndarray:
        """Current gyro bias, rad/s."""
        return np.asarray(self._f.bias, dtype=float)

    @property
    def covariance(self) -> np.ndarray:
        return np.asarray(self._f.covariance, dtype=float)

    @property
    def attitude_covariance(self) -> np.ndarray:
        """3x3 covariance of the body-frame attitude error rotation vector, rad^2."""
        return np.asarray(self._f.attitude_covariance, dtype=float)

    def set_mag_dip(self, dip: float) -> None:
        """Fix the reference field ``[cos(dip), 0, sin(dip)]`` (dip positive down, rad)."""
        dip = float(dip)
        if not np.isfinite(dip) or abs(dip) > np.pi / 2:
            raise ValueError(f"dip: expected a finite angle in [-pi/2, pi/2] rad, got {dip!r}")
        self._f.set_mag_dip(dip)

    # -- single steps --------------------------------------------------------------------
    def initialize(self, acc, mag=None) -> None:
        """Tilt from one accelerometer sample, heading from one magnetometer sample."""
        a = V.vector(acc, "acc", dtype=self.dtype, nonzero=True)
        m = None if mag is None else V.vector(mag, "mag", dtype=self.dtype, nonzero=True)
        status = self._f.initialize(a, m)
        if status != "ok":
            raise ValueError(f"acc, mag: cannot initialize ({status})")

    def predict(self, gyr, dt: float) -> str:
        """Time update with one gyro sample (rad/s) over ``dt`` seconds."""
        g = V.vector(gyr, "gyr", dtype=self.dtype)
        d = V.positive(dt, "dt")
        status = self._f.predict(g, d)
        if status == "not_initialized":
            raise ValueError("predict: the filter is not initialized (call initialize or reset first)")
        if status == "invalid_dt":
            if d > self._f.params.max_dt:
                raise ValueError(f"dt: {d} s exceeds max_dt={self._f.params.max_dt} s")
            raise ValueError(f"dt: {d} s is not a positive {self.dtype} number")
        return status

    def update_acc(self, acc, gate: float = 0.0):
        """Accelerometer update; returns an UpdateResult (status, innovation, innovation_cov, nis)."""
        self._require_init("update_acc")
        return self._f.update_acc(V.vector(acc, "acc", dtype=self.dtype, nonzero=True),
                                  V.positive(gate, "gate", allow_zero=True))

    def update_mag(self, mag, gate: float = 0.0):
        """Magnetometer update; returns an UpdateResult."""
        self._require_init("update_mag")
        return self._f.update_mag(V.vector(mag, "mag", dtype=self.dtype, nonzero=True),
                                  V.positive(gate, "gate", allow_zero=True))

    @staticmethod
    def _check_reset(status: str) -> None:
        if status != "ok":
            raise ValueError(f"quat, bias, P: reset refused ({status}; P needs a non-negative diagonal)")

    def _require_init(self, what: str) -> None:
        if not self._f.initialized:
            raise ValueError(f"{what}: the filter is not initialized (call initialize or reset first)")

    # -- batch ---------------------------------------------------------------------------
    def run(self, gyr, acc, mag=None, *, t=None, dt=None, on_invalid: str = "raise",
            smooth: bool = False) -> AttitudeResult:
        """Run the filter over N samples (in C++, GIL released), continuing from the current state.

        A new filter starts uninitialized and initializes itself on the first sample (tilt from
        the accelerometer, heading from the magnetometer); a second call continues where the
        first ended (its first step uses ``dt[0]``, or ``t[1] - t[0]``). For an unrelated log use
        a new filter.

        Parameters
        ----------
        gyr : (N, 3) array_like
            Angular rate, rad/s, body frame.
        acc : (N, 3) array_like
            Specific force (any unit; normalized).
        mag : (N, 3) array_like, optional
            Magnetic field (any unit; normalized). Rows that are entirely NaN mean "no
            magnetometer sample" (sensors at different rates). Without ``mag`` the filter runs
            in 6D mode and heading is free.
        t : (N,) array_like, keyword
            Strictly increasing timestamps, seconds; or
        dt : float or (N,) array_like, keyword
            Step length in seconds (``t`` is then ``0`` and the cumulated steps).
        on_invalid : {"raise", "skip"}
            "raise": the first non-finite or zero-norm row raises ``ValueError`` naming the
            argument and row. "skip": such samples skip the affected update; the result's
            ``flags`` and ``skipped_rows`` report them. In both modes a reading at or above
            ``gyro_range`` / ``acc_range`` (when set) skips its step and is reported under
            ``"saturated"`` (with ``"predict_skipped"`` or ``"acc_skipped"``).
        smooth : bool
            Also run the Rauch-Tung-Striebel backward pass (in C++, after the forward pass; see
            ``docs/SMOOTHING.md``): ``quat``, ``bias``, ``sigma`` and ``att_sigma`` are then the
            smoothed estimates, each using every sample of the run (offline processing), and
            ``forward`` holds the causal result. The forward pass's decisions (rejected and
            skipped updates, rest detection) are kept. The error-state QuaternionEKF (the
            default) and EulerEKF have it; ``QuaternionEKF(paper=True)`` does not (ValueError).

        Returns
        -------
        AttitudeResult
        """
        mode = V.on_invalid(on_invalid)
        strict = mode == "raise"
        g, a, m = marg_inputs(gyr, acc, mag, self.dtype, strict)
        n = g.shape[0]
        steps = V.time_steps(n, dt=dt, t=t, dtype=self.dtype,
                             max_dt=float(self._f.params.max_dt) if strict else None)
        check_run_inputs(self, g, a, steps=steps)
        if smooth and self.n_states != 6:
            raise ValueError("smooth: QuaternionEKF(paper=True), the paper's 7-state filter, has no smoother; "
                             "the default error-state filter has")
        out = self._f.run(g, a, m, steps, bool(smooth))
        quat, bias, sigma, att_sigma, flags = out[:5]
        skipped = {}
        for name in ("predict_skipped", "acc_skipped", "mag_skipped", "saturated"):
            rows = np.flatnonzero(flags & ATTITUDE_FLAGS[name])
            if rows.size:
                skipped[name] = rows
        times = times_of(n, t, steps)
        fwd = AttitudeResult(type(self).__name__, times, quat, bias, sigma, flags, skipped_rows=skipped,
                             sigma_names=self._sigma_names, att_sigma=att_sigma)
        if not smooth:
            return fwd
        sm = out[5]
        return AttitudeResult(type(self).__name__, times, sm["quat"], sm["bias"], sm["sigma"], flags,
                              skipped_rows=skipped, sigma_names=self._sigma_names, att_sigma=sm["att_sigma"],
                              forward=fwd, smoother=smoother_info(sm["info"]))


class QuaternionEKF(_AttitudeFilter):
    """Quaternion EKF with gyro-bias states (Kim & Jang 2019; paper 000), robust on real data.

    The default filter is the error-state (multiplicative) form: the nominal ``q_nb`` and gyro
    bias, with the 6x6 covariance of ``[dtheta, db]``, ``dtheta`` the attitude error as a
    rotation vector in the BODY frame (``q_true = q * exp(dtheta)``); ``sigma`` has the columns
    ``dtheta_x..z, bx..bz``. ``paper=True`` gives paper 000's 7-state filter, state
    ``[q0, q1, q2, q3, bx, by, bz]`` (``sigma`` columns ``q0..q3, bx..bz``). Measurements: the
    normalized accelerometer (gravity ``[0, 0, -1]`` in NED) and the magnetometer (reference
    ``[m_x, 0, m_z]``, x = magnetic north, learned from the first samples unless
    :meth:`set_mag_dip` is called). ``QuaternionEKF(paper=True)`` is the plain filter of the
    paper with its original noise values; the defaults add the robustness options below.

    The parameters in more detail (the full list with units and defaults follows under
    *Parameters*; defaults chosen on BROAD, the paper's values in brackets):

    gyro_noise : float, default 0.01 [0.005]
        Gyro white-noise density, rad/s/sqrt(Hz).
    gyro_bias_noise : float, default 1e-4 [1e-5]
        Gyro bias random-walk density, rad/s^2/sqrt(Hz).
    gyro_rate_noise : float, default 0.004 [0]
        Tilt process noise that grows with the rate, 1/sqrt(Hz): a white-noise density
        ``gyro_rate_noise * |w - b|`` (rad/s/sqrt(Hz)) on roll and pitch only, for the gyro's
        scale-factor and misalignment errors in fast motion (the accelerometer corrects them;
        a heading noise would hand the heading to the magnetometer). 0: off.
    acc_sigma : float, default 0.4 [0.05]
        Standard deviation of each component of the normalized accelerometer (dimensionless).
    mag_sigma : float, default 1.0 [0.1]
        Standard deviation of each component of the normalized magnetometer (dimensionless).
    init_att_sigma : float, default 0.5 [0.05]
        Attitude one-sigma after :meth:`initialize`, rad.
    init_gyro_bias_sigma : float, default 0.1 [0.01]
        Gyro-bias one-sigma after :meth:`initialize`, rad/s.
    mag_ref_samples : int, default 100
        Magnetometer samples over which the dip of the reference field is averaged (unless
        :meth:`set_mag_dip` fixes it).
    max_dt : float, default 1.0
        Longest accepted time step, s.
    gyro_range : float, default 0
        Gyro range per axis, rad/s: a sample with any ``|w_i| >= gyro_range`` is saturated and
        its predict is skipped (status ``"saturated"``). 0: unlimited.
    acc_range : float, default 0
        Accelerometer range per axis, in the unit of ``acc`` (m/s^2): a saturated sample skips
        its update. 0: unlimited.
    cov_floor : float, default 1e-12
        Eigenvalue floor of the error-state covariance (rad^2 and (rad/s)^2): after every step
        an eigenvalue below it is raised to it (a healthy covariance is left untouched). 0: off.
    declination : float, default 0
        Magnetic declination, east of true north, rad in [-pi, pi] (use ``np.radians`` for
        degrees). 0: the navigation frame's x axis is magnetic north, so the yaw is a magnetic
        heading. Otherwise x is true north, like the navigation filters' NED frame: the
        magnetometer's heading reference is turned by the declination and :meth:`initialize`
        adds it to the magnetic heading.

    The default noise values are effective ones: they cover what the model leaves out
    (residual linear acceleration after the low-pass, field deviations, scale factors), so
    that the attitude error stays within the filter's own 3 sigma on real data. Scaling all
    noise values by one factor leaves the estimates unchanged and scales the covariance.

    Robustness for real data (each off with 0 / False). They compare ``|acc|`` with
    ``gravity``, so ``acc`` must be in m/s^2 (or set ``gravity`` to 1 g in the unit used).

    mag_heading_only : bool, default True
        The magnetometer corrects heading only (a scalar update of the heading of the field's
        horizontal projection, gain projected on the yaw direction): it never tilts roll and
        pitch. False: the paper's 3-row magnetometer update.
    acc_tilt_only : bool, default True [False]
        The accelerometer corrects the tilt and the horizontal gyro bias only: gravity carries
        no heading information, so its update (a Schmidt-Kalman update, gain projected off the
        vertical) never turns the heading nor the earth-vertical gyro bias, which linear
        accelerations taken for gravity would otherwise move (the 6D heading drift). False: the
        optimal gain of the paper, which turns them through the correlations of the covariance.
    gravity : float, default 9.81
        Magnitude of gravity, m/s^2.
    acc_adapt : float, default 0
        Adaptive accelerometer noise: std ``acc_sigma + acc_adapt * ||a| - g| / g``.
    acc_reject : float, default 0
        Reject the accelerometer update when ``||a| - g|`` exceeds this, m/s^2.
    acc_gate : float, default 0
        Default NIS gate of the accelerometer update (3 dof).
    acc_recovery_time : float, default 0
        After this long with every accelerometer update rejected, accept again, s.
    acc_lp_tau : float, default 3
        Low-pass the accelerometer in a quasi-inertial frame (carried by the bias-corrected
        gyro) with this time constant before the update, s; linear accelerations average out.
    acc_lp_bias_sigma : float, default 0.006 [0]
        While the largest gyro-bias one-sigma ``sigma_b`` exceeds this (rad/s), the low-pass time
        constant is ``acc_lp_tau * (acc_lp_bias_sigma / sigma_b)**2``: the low-pass frame, carried
        by the bias-corrected gyro, is only trusted as far as the bias is known (error-state
        filter only). 0: always ``acc_lp_tau``.
    acc_lp_dev : float, default 1 [0]
        The shrink above fades out as the raw samples' ``||a| - g|``, low-passed over
        ``acc_lp_tau``, approaches this (m/s^2): under sustained linear acceleration (a swing's
        centripetal acceleration) the low-pass stays long even while the bias is unknown. 0: off.
    acc_bias_dev : float, default 2 [0]
        The accelerometer's weight in the gyro-bias block falls as ``1 / (1 + (dev_lp /
        acc_bias_dev)**2)``, ``dev_lp`` the raw samples' ``||a| - g|`` low-passed over
        ``acc_lp_tau`` (m/s^2): the low-passed sample's error, the linear acceleration the low-pass
        lets through, is correlated over its time constant, so under a swing or a run the
        accelerometer teaches the bias little (rest does). 0: off.
    mag_norm_tol : float, default 0.05
        Reject the magnetometer when ``||m| / m_ref - 1|`` exceeds this (m_ref learned).
    mag_dip_tol : float, default 0.05
        Reject the magnetometer when its dip differs from the learned dip by more, rad.
    mag_dip_sigmas : float, default 0
        The dip test's tolerance grows to ``sqrt(mag_dip_tol**2 + (mag_dip_sigmas *
        sigma_dip)**2)``, ``sigma_dip`` the dip's one-sigma from the filter's own attitude
        covariance: the dip is the field's at the estimated attitude, so a tilt error the filter
        knows it has (2-3 deg in a run's turns) need not reject good samples. 0 (default): the
        fixed tolerance alone. 3 halves the rejections of a simulated run but lets in part of a
        magnet's field on BROAD (docs/broad.md). MargFilter keeps no covariance and ignores it.
    mag_gate : float, default 9
        Default NIS gate of the magnetometer update.
    mag_settle_time : float, default 0
        After a disturbance, the field must pass the norm and dip tests this long before the
        magnetometer is used again, s.
    mag_ref_tau : float, default 30
        Time constant with which the reference norm and dip follow accepted samples, s.
    mag_recovery_time : float, default 0
        After this long with every magnetometer sample disturbed, the current field becomes
        the reference, s.
    rest_detection : bool, default True
        Detect rest (gyro and accelerometer steady for ``rest_time``) and use it as a
        zero-rate measurement of the gyro bias; flag ``at_rest``.
    rest_gyr_th, rest_acc_th, rest_time, rest_tau, rest_rate_noise : float
        Rest thresholds (rad/s, m/s^2), minimum duration (s), low-pass time constant (s) and the
        std of the residual rate at rest (rad/s); defaults 0.03, 0.5, 1.5, 0.5, 0.02.
    gyro_clip : bool, default True [False]
        Recognize clipped gyro readings without ``gyro_range``: an axis that repeats its previous
        ``gyro_clip_repeats`` (2) readings exactly, at or above every magnitude seen so far and at
        least ``gyro_clip_min_rate`` (1 rad/s). The step is taken, its axis's attitude variance
        grows by ``(gyro_clip_noise |w_i| dt)^2`` (``gyro_clip_noise`` 1) and the accelerometer's
        low-pass restarts, so that the accelerometer (and magnetometer) take the attitude back.
    dtype : float64 or float32
        Precision of the C++ filter.

    The defaults of the robustness parameters were chosen with :mod:`quatnav.evaluation.tuning` on the
    BROAD benchmark (one set for all trials); see ``docs/broad.md``.
    """

    _core_name = "QuaternionEKF"
    _core_params = "QuaternionEKFParams"
    PARAMS = QEKF_PARAMS
    FLAGS = ATTITUDE_FLAGS
    _sigma_names = ("dtheta_x", "dtheta_y", "dtheta_z", "bx", "by", "bz")
    n_states = 6
    _PAPER_SIGMA_NAMES = ("q0", "q1", "q2", "q3", "bx", "by", "bz")

    def _make(self, p):
        if self._opts.get("paper"):
            # paper 000's 7-state filter [q, b], exactly as the paper (with its listed fixes)
            self._sigma_names, self.n_states = self._PAPER_SIGMA_NAMES, 7
            p = self._core_struct(compiled(self._core_params, self.dtype).paper())
            return compiled("QuaternionEKFPaper", self.dtype)(p)
        return compiled(self._core_name, self.dtype)(p)

    @property
    def at_rest(self) -> bool:
        """True while rest is detected."""
        return bool(self._f.at_rest)

    def reset(self, quat, bias=None, P=None) -> None:
        """Start from a given ``q_nb``, gyro bias (rad/s) and covariance: 6x6 of the error state
        ``[dtheta (body, rad), db (rad/s)]`` by default, 7x7 of ``[q, b]`` with ``paper=True``."""
        q = V.vector(quat, "quat", 4, dtype=self.dtype, nonzero=True)
        b = np.zeros(3, self.dtype) if bias is None else V.vector(bias, "bias", dtype=self.dtype)
        n = self.n_states
        if P is None:
            p = self._f.params
            if n == 7:
                X = Q.xi(q / np.linalg.norm(q))
                P = np.zeros((7, 7))
                P[:4, :4] = (p.init_att_sigma / 2) ** 2 * X @ X.T
                P[4:, 4:] = np.eye(3) * p.init_gyro_bias_sigma**2
            else:
                P = np.diag([p.init_att_sigma**2] * 3 + [p.init_gyro_bias_sigma**2] * 3)
        P = np.asarray(P, dtype=self.dtype)
        if P.shape != (n, n) or not np.all(np.isfinite(P)):
            raise ValueError(f"P: expected a finite {n}x{n} matrix, got shape {P.shape}")
        self._check_reset(self._f.reset(q, b, P))

    def update_acc_mag(self, acc, mag, gate: float = 0.0):
        """Joint accelerometer + magnetometer update, paper 000 eq. (11)-(12)."""
        self._require_init("update_acc_mag")
        return self._f.update_acc_mag(V.vector(acc, "acc", dtype=self.dtype, nonzero=True),
                                      V.vector(mag, "mag", dtype=self.dtype, nonzero=True),
                                      V.positive(gate, "gate", allow_zero=True))


class EulerEKF(_AttitudeFilter):
    """Euler-angle EKF, the baseline paper 000 compares against.

    State ``[roll, pitch, yaw, bx, by, bz]``; Euler-rate kinematics (paper 004 eq. 1), the angles
    propagated exactly through the quaternion for the constant rate over each step
    (``exact_propagation``, default True; False with ``paper=True``: the paper's one Euler step,
    whose error over fast periodic swings turns the heading); the same measurements as
    :class:`QuaternionEKF`. Near pitch = +/-90 deg the parametrization is
    singular: the ``"singular"`` flag reports it (``singular_cos``: the |cos(pitch)| threshold).
    Parameters as :class:`QuaternionEKF` (including ``gyro_range``, ``acc_range`` and
    ``cov_floor``, here a floor on the eigenvalues of P itself) plus ``singular_cos`` (default 0.02);
    ``init_att_sigma`` is the one-sigma of each Euler angle. The noise defaults are the paper's.
    ``acc_tilt_only`` (default True, False with ``paper=True``) as QuaternionEKF's: the
    accelerometer turns neither the yaw nor the vertical gyro bias.

    The robustness parts are QuaternionEKF's, with the same names and defaults except
    ``acc_lp_tau`` (1 s here, 3 s there: this filter learns its gyro bias more slowly, and the
    low-pass frame drifts by the bias error over ``acc_lp_tau``): rest detection
    (``rest_*``: at rest a zero-rate measurement of the gyro bias, flag ``at_rest``), the
    accelerometer part (``gravity``, ``acc_lp_tau``, ``acc_lp_bias_sigma``, ``acc_reject``,
    ``acc_adapt``, ``acc_recovery_time``; flag ``acc_rejected``) and the magnetometer part
    (``mag_ref_samples``, ``mag_norm_tol``, ``mag_dip_tol``, ``mag_dip_sigmas``, ``mag_settle_time``, ``mag_ref_tau``,
    ``mag_recovery_time``; flag ``mag_rejected``). ``EulerEKF(paper=True)`` switches them off: the
    plain baseline of paper 000.
    """

    _core_name = "EulerEKF"
    _core_params = "EulerEKFParams"
    PARAMS = EULER_PARAMS
    FLAGS = ATTITUDE_FLAGS
    _sigma_names = ("roll", "pitch", "yaw", "bx", "by", "bz")
    n_states = 6

    @property
    def euler(self) -> np.ndarray:
        return np.asarray(self._f.euler, dtype=float)

    @property
    def near_singularity(self) -> bool:
        return bool(self._f.near_singularity)

    @property
    def at_rest(self) -> bool:
        """True while rest is detected."""
        return bool(self._f.at_rest)

    def reset(self, euler, bias=None, P=None) -> None:
        e = V.euler(euler, "euler", dtype=self.dtype)
        b = np.zeros(3, self.dtype) if bias is None else V.vector(bias, "bias", dtype=self.dtype)
        if P is None:
            p = self._f.params
            P = np.diag([p.init_att_sigma**2] * 3 + [p.init_gyro_bias_sigma**2] * 3)
        P = np.asarray(P, dtype=self.dtype)
        if P.shape != (6, 6) or not np.all(np.isfinite(P)):
            raise ValueError(f"P: expected a finite 6x6 matrix, got shape {P.shape}")
        self._check_reset(self._f.reset(e, b, P))
