"""The tables of the filters, in one place: statuses, flag bits and constructor parameters.

One flag table for every filter (name -> bit of a result's ``flags``; each filter sets a subset) and one parameter table
(a tuple of :class:`Param`: Python name, default, unit, meaning, check, and
the C++ ``Params`` field it sets). The filter classes, their signatures and docstrings, ``repr``
and ``docs/PARAMETERS.md`` (checked by a test) come from these tables; a test checks the defaults
against the C++ ``Params`` structs.
"""
from __future__ import annotations

import enum
import numbers
from dataclasses import dataclass
from typing import Any

import numpy as np

from .. import _validate as V

__all__ = ["STATUS_NAMES", "FLAGS", "Flag", "Status", "ATTITUDE_FLAGS", "MARG_FLAGS", "NAV13_FLAGS", "GPSINS_FLAGS", "GPSINS_DECISIONS", "GNSS_SOLUTIONS", "QEKF_PARAMS",
           "EULER_PARAMS", "MARG_PARAMS", "NAV13_PARAMS", "GPSINS_PARAMS", "FLAG_TABLES", "PARAM_TABLES"]

#: ``quatnav::Status`` names by code (the ``status`` arrays of :class:`~quatnav.AidResult`);
#: a test checks them against the compiled module's ``_core.status_names()``.
STATUS_NAMES = ("ok", "not_initialized", "non_finite", "zero_norm", "invalid_dt", "saturated", "solve_failed",
                "rejected", "numerical_failure", "invalid_argument")

#: The one flag table of every filter (``QUATNAV_FLAG_TABLE`` in ``core/flags.hpp``): name -> bit of
#: a result's ``flags``. Each name has one bit in every filter; a test checks the table against the
#: compiled module's ``_core.flag_table()``.
FLAGS = {
    "initialized": 1 << 0, "predict_skipped": 1 << 1, "acc_skipped": 1 << 2, "mag_skipped": 1 << 3,
    "acc_rejected": 1 << 4, "mag_rejected": 1 << 5, "solve_failed": 1 << 6, "singular": 1 << 7,
    "at_rest": 1 << 8, "no_mag": 1 << 9, "saturated": 1 << 10,
    "gps_corrected": 1 << 11, "gn_not_converged": 1 << 12,
    "aligning": 1 << 13, "levelled": 1 << 14, "navigating": 1 << 15,
    "gps_pos_used": 1 << 16, "gps_pos_rejected": 1 << 17, "gps_vel_used": 1 << 18, "gps_vel_rejected": 1 << 19,
    "baro_used": 1 << 20, "baro_rejected": 1 << 21, "baro_vd_used": 1 << 22, "baro_vd_rejected": 1 << 23,
    "heading_used": 1 << 24, "heading_rejected": 1 << 25, "aid_skipped": 1 << 26, "gps_reset": 1 << 27,
    "coasted": 1 << 28, "adapted": 1 << 29, "constraint_used": 1 << 30,
}

#: The flags as an :class:`enum.IntFlag`: ``quatnav.Flag.acc_rejected``, ``Flag(r.flags[k])`` lists
#: the flags of sample ``k``.
Flag = enum.IntFlag("Flag", FLAGS, module=__name__)
Flag.__doc__ = "The per-sample flags of every filter's result (one table, unique bits)."

#: ``quatnav::Status`` as an :class:`enum.IntEnum` (the code of an update's ``status``).
Status = enum.IntEnum("Status", {n: i for i, n in enumerate(STATUS_NAMES)}, module=__name__)
Status.__doc__ = "What one update did (``quatnav::Status``); anything but ok and rejected left the state untouched."


def _subset(*names: str) -> dict:
    return {n: FLAGS[n] for n in names}


_ATT = ("initialized", "predict_skipped", "acc_skipped", "mag_skipped", "acc_rejected", "mag_rejected",
        "solve_failed", "singular", "at_rest", "no_mag", "saturated")
#: The flags QuaternionEKF and EulerEKF set.
ATTITUDE_FLAGS = _subset(*_ATT)
#: The flags MargFilter sets: the attitude flags and two of its own.
MARG_FLAGS = _subset(*_ATT, "gps_corrected", "gn_not_converged")
#: The flags NavFilter13 sets (its ``yaw`` aid is a heading).
NAV13_FLAGS = _subset("predict_skipped", "solve_failed", "saturated", "gps_vel_used", "gps_vel_rejected",
                      "heading_used", "heading_rejected", "aid_skipped")
#: The flags GpsInsFilter sets (its ``compass`` aid is a heading).
GPSINS_FLAGS = _subset("aligning", "levelled", "navigating", "initialized", "predict_skipped", "gps_pos_used",
                       "gps_pos_rejected", "gps_vel_used", "gps_vel_rejected", "baro_used", "baro_rejected",
                       "baro_vd_used", "baro_vd_rejected", "heading_used", "heading_rejected", "aid_skipped",
                       "gps_reset", "saturated", "adapted", "coasted", "constraint_used", "at_rest",
                       "mag_skipped", "mag_rejected")

#: What GpsInsFilter did with each aiding sample (``quatnav::GpsInsDecision``), by code: the
#: ``decision`` arrays of its aids' reports; a test checks them against the compiled module.
GPSINS_DECISIONS = ("none", "accepted", "rejected", "inflated", "reset", "skipped", "aligned", "weighted")
#: ``quatnav::GnssSolution`` names by code: the receiver's solution kind of a GNSS fix.
GNSS_SOLUTIONS = ("unknown", "rtk_fixed", "rtk_float", "dgnss", "single")


@dataclass(frozen=True)
class Param:
    """One constructor parameter: its name, default, unit, check and one-line meaning.

    ``kind``: ``"pos"`` (> 0), ``"pos0"`` (>= 0), ``"real"`` (finite), ``"int1"`` (integer >= 1),
    ``"iter"`` (integer 1..100), ``"bool"``, ``"angle"`` (rad within ``limits``, a value that reads
    as degrees gets the ``np.radians`` hint), ``"vec3"``, ``"choice"`` (one of ``limits``).
    ``core``: the C++ ``Params`` field it sets (None: used by the Python wrapper itself).
    """

    name: str
    default: Any
    unit: str
    doc: str
    kind: str = "pos"
    core: str | None = "same"
    limits: tuple | None = None

    @property
    def core_name(self) -> str | None:
        return self.name if self.core == "same" else self.core

    def check(self, value, dtype=np.float64):
        k, name = self.kind, self.name
        if k in ("pos", "pos0"):
            return V.positive(value, name, allow_zero=k == "pos0")
        if k == "real":
            if isinstance(value, bool) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
                raise TypeError(f"{name}: expected a real number, got {type(value).__name__}")
            if not np.isfinite(float(value)):
                raise ValueError(f"{name}: expected a finite number, got {value!r}")
            return float(value)
        if k in ("int1", "iter"):
            if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Integral, np.integer)):
                raise TypeError(f"{name}: expected an integer, got {type(value).__name__}")
            lo, hi = (1, 100) if k == "iter" else (1, None)
            if value < lo or (hi is not None and value > hi):
                raise ValueError(f"{name}: expected an integer in {lo}..{hi or 'inf'}, got {value!r}")
            return int(value)
        if k == "bool":
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{name}: expected a bool, got {type(value).__name__}")
            return bool(value)
        if k == "angle":
            return _angle(value, name, self.limits)
        if k == "vec3":
            return V.vector(value, name, 3, dtype=dtype)
        if k == "mat3":
            return rotation_matrix(value, name, dtype)
        if k == "choice":
            if value not in self.limits:
                raise ValueError(f"{name}: expected one of {self.limits}, got {value!r}")
            return value
        raise AssertionError(k)  # pragma: no cover - a table entry of an unknown kind

    def same(self, a, b) -> bool:
        return bool(np.all(np.asarray(a) == np.asarray(b))) if self.kind in ("vec3", "mat3") else a == b


def rotation_matrix(value, name, dtype=np.float64) -> np.ndarray:
    """A rotation matrix (3, 3) from a matrix or from ZYX Euler angles ``[roll, pitch, yaw]`` in
    rad; anything that is not a rotation (orthonormal, determinant +1, to 1e-6) is a ValueError
    naming ``name``."""
    a = np.asarray(V._numeric(value, name), dtype=np.float64)
    if a.shape == (3,):
        if not np.all(np.isfinite(a)):
            raise ValueError(f"{name}: expected finite Euler angles [roll, pitch, yaw] in rad, got {a}")
        from ..core import quaternion as Q
        a = Q.to_rotmat(Q.from_euler(a))
    elif a.shape != (3, 3):
        raise ValueError(f"{name}: expected a (3, 3) rotation matrix or Euler angles [roll, pitch, yaw] (rad), "
                         f"got shape {a.shape}")
    if not np.all(np.isfinite(a)) or np.abs(a @ a.T - np.eye(3)).max() > 1e-6 or abs(np.linalg.det(a) - 1) > 1e-6:
        raise ValueError(f"{name}: not a rotation matrix (orthonormal with determinant +1): {a.tolist()}")
    return np.ascontiguousarray(a, dtype=dtype)


_RANGE_TEXT = {-np.pi: "-pi", 0.0: "0", 1.0: "1", np.pi / 2: "pi/2", np.pi: "pi"}


def _angle(value, name, limits) -> float:
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (numbers.Real, np.floating, np.integer)):
        raise TypeError(f"{name}: expected an angle in rad (a real number), got {type(value).__name__}")
    v = float(value)
    lo, hi = limits
    if not np.isfinite(v):
        raise ValueError(f"{name}: expected a finite angle in rad, got {v!r}")
    if not lo <= v <= hi:
        rng = f"[{_RANGE_TEXT.get(lo, f'{lo:g}')}, {_RANGE_TEXT.get(hi, f'{hi:g}')}]"
        hint = (f"; angles are in radians: for {v:g} deg pass np.radians({v:g}) = {np.radians(v):.6g}"
                if abs(v) <= 360.0 else "")
        raise ValueError(f"{name}: {v:g} is outside {rng} rad{hint}")
    return v


_p = Param


_PI = np.pi

# Shared entries: one name, one unit, one meaning in every filter that has them.
def _gyro_noise(d):
    return _p("gyro_noise", d, "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)")


def _gyro_bias_noise(d, kind="pos", core="same"):
    return _p("gyro_bias_noise", d, "rad/s^2/sqrt(Hz)", "gyro-bias random-walk density", kind, core)


def _max_dt():
    return _p("max_dt", 1.0, "s", "longest accepted IMU step")


def _ranges():
    return (_p("gyro_range", 0.0, "rad/s", "gyro range per axis: a reading at or above it is saturated "
               "and its step skipped (0: unlimited)", "pos0"),
            _p("acc_range", 0.0, "m/s^2", "accelerometer range per axis, as gyro_range (0: unlimited)", "pos0"))


def _cov_floor(d):
    return _p("cov_floor", d, "state units^2", "eigenvalue floor of the error covariance (0: off)", "pos0")


# The robustness parts of the attitude filters (cpp/include/quatnav/attitude/parts/): one entry per
# field, with each filter's default (a test checks them against the parts' C++ declarations).
def _acc_part(gravity=9.81, adapt=0.0, reject=0.0, recovery_time=0.0, lp_tau=3.0, lp_bias_sigma=0.006,
              lp_dev=1.0, bias_dev=2.0):
    """The accelerometer part (parts/acc_filter.hpp)."""
    return (
        _p("gravity", gravity, "m/s^2", "magnitude of gravity, in the unit of acc", "pos0"),
        _p("acc_adapt", adapt, "1", "adaptive accelerometer noise: std acc_sigma + acc_adapt * ||a|-g|/g", "pos0"),
        _p("acc_reject", reject, "m/s^2", "reject the accelerometer when ||a|-g| exceeds it (0: off)", "pos0"),
        _p("acc_recovery_time", recovery_time, "s", "after this long with every accelerometer update rejected, "
           "accept again (0: never)", "pos0"),
        _p("acc_lp_tau", lp_tau, "s", "low-pass time constant of the accelerometer in a quasi-inertial frame "
           "(0: off)", "pos0"),
        _p("acc_lp_bias_sigma", lp_bias_sigma, "rad/s", "above this gyro-bias one-sigma the accelerometer "
           "low-pass time constant shrinks by (acc_lp_bias_sigma / sigma_b)^2 (0: off)", "pos0"),
        _p("acc_lp_dev", lp_dev, "m/s^2", "the shrink of acc_lp_bias_sigma fades out as the low-passed "
           "||a|-g| of the raw samples approaches this (0: off)", "pos0"),
        _p("acc_bias_dev", bias_dev, "m/s^2", "the accelerometer's weight in the gyro-bias block falls as "
           "1 / (1 + (dev_lp / acc_bias_dev)^2), dev_lp the low-passed ||a|-g| of the raw samples (0: off)", "pos0"),
    )


def _mag_part(ref_samples=100, norm_tol=0.05, dip_tol=0.05, dip_sigmas=0.0, settle_time=0.0, ref_tau=30.0,
              recovery_time=0.0):
    """The magnetometer part (parts/mag_disturbance.hpp)."""
    return (
        _p("mag_ref_samples", ref_samples, "1", "magnetometer samples over which the reference dip is averaged",
           "int1"),
        _p("mag_norm_tol", norm_tol, "1", "reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off)",
           "pos0"),
        _p("mag_dip_tol", dip_tol, "rad", "reject the magnetometer when its dip differs from the reference by "
           "more (0: off)", "pos0"),
        _p("mag_dip_sigmas", dip_sigmas, "1", "the dip test's tolerance grows by this many of the filter's own "
           "one-sigmas of the dip, in quadrature: sqrt(mag_dip_tol^2 + (mag_dip_sigmas sigma_dip)^2) "
           "(0: mag_dip_tol alone)", "pos0"),
        _p("mag_settle_time", settle_time, "s", "after a disturbance, the field must pass the tests this long",
           "pos0"),
        _p("mag_ref_tau", ref_tau, "s", "time constant with which the reference norm and dip follow the field",
           "pos0"),
        _p("mag_recovery_time", recovery_time, "s", "after this long with every sample disturbed, the field "
           "becomes the reference (0: never)", "pos0"),
    )


def _acc_tilt_only():
    """The accelerometer's Schmidt-Kalman update (quaternion_ekf.hpp, euler_ekf.hpp)."""
    return _p("acc_tilt_only", True, "-", "the accelerometer corrects the tilt and the horizontal gyro bias only "
              "(false: the optimal gain)", "bool")


def _rest_part(detection=True, gyr_th=0.03, acc_th=0.5, time=1.5, tau=0.5, rate_noise=0.02):
    """Rest detection (parts/rest.hpp)."""
    return (
        _p("rest_detection", detection, "-", "detect rest and use it as a zero-rate measurement of the gyro bias",
           "bool"),
        _p("rest_gyr_th", gyr_th, "rad/s", "rest: largest deviation of the low-passed gyro"),
        _p("rest_acc_th", acc_th, "m/s^2", "rest: largest deviation of the low-passed accelerometer"),
        _p("rest_time", time, "s", "rest: shortest duration"),
        _p("rest_tau", tau, "s", "rest: low-pass time constant"),
        _p("rest_rate_noise", rate_noise, "rad/s", "std of the residual rate at rest", "pos0"),
    )


def _clip_part():
    """Clipped gyro readings (parts/gyro_clip.hpp)."""
    return (
        _p("gyro_clip", True, "-", "recognize clipped gyro readings (an axis stuck at the largest magnitude seen) "
           "and distrust them", "bool"),
        _p("gyro_clip_min_rate", 1.0, "rad/s", "smallest reading taken for a clip", "pos0"),
        _p("gyro_clip_repeats", 2, "1", "a clip: the reading repeats this many previous readings exactly", "int1"),
        _p("gyro_clip_noise", 1.0, "1", "std of a clipped step's attitude error about that axis, as a fraction of "
           "reading times dt", "pos0"),
    )


#: QuaternionEKF (``QuaternionEKF<S>::Params``); defaults chosen on BROAD.
QEKF_PARAMS = (
    _p("paper", False, "-", "start from the paper's values (plain filter of paper 000, robustness off); "
       "the other arguments are applied on top", "bool", None),
    _gyro_noise(0.01),
    _gyro_bias_noise(1e-4),
    _p("gyro_rate_noise", 0.004, "1/sqrt(Hz)", "rate-proportional attitude process noise: density "
       "gyro_rate_noise * |w - b| (0: off); the attitude filters apply it to the tilt only", "pos0"),
    _p("acc_sigma", 0.4, "1 (normalized)", "std of each component of the normalized accelerometer"),
    _p("mag_sigma", 1.0, "1 (normalized)", "std of each component of the normalized magnetometer"),
    _p("init_att_sigma", 0.5, "rad", "attitude one-sigma after initialize"),
    _p("init_gyro_bias_sigma", 0.1, "rad/s", "gyro-bias one-sigma after initialize"),
    _max_dt(),
    *_ranges(),
    _cov_floor(1e-12),
    _p("declination", 0.0, "rad", "magnetic declination, east of true north (0: x is magnetic north)",
       "angle", limits=(-_PI, _PI)),
    _p("mag_heading_only", True, "-", "the magnetometer corrects heading only (false: 3-row update)", "bool"),
    _acc_tilt_only(),
    _p("acc_gate", 0.0, "1 (chi-square, 3 dof)", "NIS gate of the accelerometer update (0: off)", "pos0"),
    _p("mag_gate", 9.0, "1 (chi-square)", "NIS gate of the magnetometer update (0: off)", "pos0"),
    *_acc_part(),
    *_mag_part(),
    *_rest_part(),
    *_clip_part(),
)

#: EulerEKF (``EulerEKF<S>::Params``): the paper's noise values and QuaternionEKF's robustness parts
#: (``paper=True`` switches the parts off).
EULER_PARAMS = (
    _p("paper", False, "-", "the plain baseline of paper 000: the robustness parts off; the other arguments "
       "are applied on top", "bool", None),
    _gyro_noise(0.005),
    _gyro_bias_noise(1e-5),
    _p("acc_sigma", 0.05, "1 (normalized)", "std of each component of the normalized accelerometer"),
    _p("mag_sigma", 0.1, "1 (normalized)", "std of each component of the normalized magnetometer"),
    _p("init_att_sigma", 0.05, "rad", "one-sigma of each Euler angle after initialize"),
    _p("init_gyro_bias_sigma", 0.01, "rad/s", "gyro-bias one-sigma after initialize"),
    _max_dt(),
    _p("singular_cos", 0.02, "1", "the Euler parametrization is flagged singular where abs(cos(pitch)) is below it"),
    _p("exact_propagation", True, "-", "propagate the angles exactly through the quaternion (false: paper 004 eq. "
       "1's Euler step)", "bool"),
    *_ranges(),
    _cov_floor(1e-12),
    _acc_tilt_only(),
    *_acc_part(lp_tau=1.0),
    *_mag_part(),
    *_rest_part(),
)

#: MargFilter (``MargFilter<S>::Params``) with the robustness parts of the other attitude filters
#: (``paper=True`` switches them off; the accelerometer part's ``gravity`` is the g of eq. 7).
MARG_PARAMS = (
    _p("paper", False, "-", "the plain filter of paper 001: the robustness parts off; the other arguments "
       "are applied on top", "bool", None),
    _p("gain", 1.0, "1/s", "k of eq. (6): pull towards the Gauss-Newton attitude (0: gyro only)", "pos0"),
    _p("bias_gain", 0.0, "1/s^2", "gyro-bias integral gain (0: no bias estimate)", "pos0"),
    _p("gn_max_iter", 3, "1", "Gauss-Newton iterations per update, at most", "iter"),
    _p("gn_tol", 1e-6, "1", "the iteration stops when |dq| is below it"),
    _p("lever_arm_b", (0.0, 0.0, 0.0), "m", "GPS antenna relative to the IMU, body FRD", "vec3"),
    _p("gps_correction", True, "-", "apply eq. (7) when a GPS acceleration is available", "bool"),
    _p("gps_acc_tau", 0.05, "s", "low-pass time constant of the GPS acceleration", "pos0"),
    _p("omega_dot_tau", 0.1, "s", "low-pass time constant of the angular acceleration", "pos0"),
    _p("gps_timeout", 0.5, "s", "a GPS acceleration older than this is not used"),
    _max_dt(),
    _p("declination", 0.0, "rad", "magnetic declination, east of true north (GPS velocities are rotated "
       "into the magnetic frame)", "angle", limits=(-_PI, _PI)),
    *_acc_part(gravity=9.80665, lp_tau=1.0),
    *_mag_part(),
    *_rest_part(),
)

#: NavFilter13 (``NavFilter13Params<S>``); the paper's values.
NAV13_PARAMS = (
    _p("time_update", "ekf", "-", "'ekf', 'second_order' (eq. 16-17) or 'ukf' (25 sigma points)", "choice",
       None, limits=("ekf", "second_order", "ukf")),
    _p("acc_noise", 2.942e-5, "m/s^2/sqrt(Hz)", "accelerometer white-noise density (velocity random walk)",
       "pos0"),
    _p("gyro_noise", 1.4544e-7, "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)", "pos0"),
    _p("acc_bias_noise", 0.0, "m/s^3/sqrt(Hz)", "accelerometer-bias random-walk density", "pos0"),
    _gyro_bias_noise(0.0, "pos0"),
    _p("gps_vel_sigma", 0.03048, "m/s", "one-sigma of each measured velocity component"),
    _p("yaw_sigma", 0.034906585, "rad", "one-sigma of the measured yaw"),
    _p("gate_gps_vel", 0.0, "1 (chi-square, 3 dof)", "NIS gate of the velocity update (0: off)", "pos0", None),
    _p("gate_yaw", 0.0, "1 (chi-square, 1 dof)", "NIS gate of the yaw update (0: off)", "pos0", None),
    _p("ukf_alpha", 1.0, "1", "unscented transform: alpha"),
    _p("ukf_beta", 2.0, "1", "unscented transform: beta", "pos0"),
    _p("ukf_kappa", 0.0, "1", "unscented transform: kappa (alpha^2 (12 + kappa) must be positive)", "real"),
    _max_dt(),
    *_ranges(),
    _cov_floor(0.0),
    _p("earth_rotation", True, "-", "include the Earth rate, transport rate and Coriolis terms", "bool"),
)

#: GpsInsFilter (``GpsInsParams<S>``).
GPSINS_PARAMS = (
    _p("gyro_noise", 0.00087, "rad/s/sqrt(Hz)", "gyro white-noise density (angle random walk)", "pos0"),
    _p("acc_noise", 0.002, "m/s^2/sqrt(Hz)", "accelerometer white-noise density (velocity random walk)", "pos0"),
    _gyro_bias_noise(1e-5, "pos0"),
    _p("acc_bias_noise", 1e-4, "m/s^3/sqrt(Hz)", "accelerometer-bias random-walk density", "pos0"),
    _p("gyro_bias_tau", 0.0, "s", "Gauss-Markov time constant of the gyro bias (0: random walk)", "pos0"),
    _p("acc_bias_tau", 0.0, "s", "Gauss-Markov time constant of the accelerometer bias (0: random walk)",
       "pos0"),
    _p("init_gyro_bias_sigma", 0.005, "rad/s", "gyro-bias one-sigma at the start of navigation", "pos0"),
    _p("gyro_rate_noise", 0.0, "1/sqrt(Hz)", "rate-proportional attitude process noise: density gyro_rate_noise "
       "* |w - b| (0: off); the attitude filters apply it to the tilt only", "pos0"),
    _p("scale_factors", False, "-", "estimate the gyro and accelerometer scale factors (22 error states "
       "instead of 16)", "bool", core=None),
    _p("gyro_scale_noise", 1e-5, "1/sqrt(s)", "gyro scale-factor random-walk density (scale-factor states only)",
       "pos0"),
    _p("acc_scale_noise", 1e-5, "1/sqrt(s)",
       "accelerometer scale-factor random-walk density (scale-factor states only)", "pos0"),
    _p("init_gyro_scale_sigma", 0.005, "1",
       "gyro scale-factor one-sigma at the start of navigation (scale-factor states only)", "pos0"),
    _p("init_acc_scale_sigma", 0.003, "1",
       "accelerometer scale-factor one-sigma at the start of navigation (scale-factor states only)", "pos0"),
    _p("init_acc_bias_sigma", 0.1, "m/s^2", "accelerometer-bias one-sigma at the start of navigation", "pos0"),
    _p("init_level_sigma", 0.035, "rad", "roll/pitch one-sigma after the alignment", "angle",
       limits=(0.0, _PI / 2)),
    _p("init_yaw_sigma", 0.175, "rad", "yaw one-sigma after the alignment", "angle", limits=(0.0, _PI)),
    _p("init_vel_sigma", 0.5, "m/s", "velocity one-sigma at the start of navigation", "pos0"),
    _p("gps_pos_sigma_h", 2.5, "m", "horizontal one-sigma of a GPS position (per-fix sigma overrides)", "pos0"),
    _p("gps_pos_sigma_v", 5.0, "m", "vertical one-sigma of a GPS position", "pos0"),
    _p("gps_vel_sigma", 0.1, "m/s", "one-sigma of each GPS velocity component", "pos0"),
    _p("lever_arm_b", (0.0, 0.0, 0.0), "m", "GPS antenna relative to the IMU, body FRD", "vec3"),
    _p("baro_sigma", 0.5, "m", "one-sigma of an altimeter height", "pos0"),
    _p("baro_rate_baseline", 1.0, "s", "baseline of the altimeter's vertical-velocity difference", "pos0"),
    _p("baro_vd_sigma", 0.1, "m/s", "one-sigma of the altimeter's vertical velocity", "pos0"),
    _p("baro_offset_noise", 0.02, "m/sqrt(s)", "random-walk density of the altimeter offset", "pos0"),
    _p("compass_sigma", 0.035, "rad", "one-sigma of a compass heading", "angle", limits=(0.0, 1.0)),
    _p("declination", 0.0, "rad", "magnetic declination, east of true north (added to compass headings)",
       "angle", limits=(-_PI, _PI)),
    _p("gate_gps_pos", 21.108, "1 (chi-square, 3 dof)", "NIS gate of the GPS position (0: off)", "pos0"),
    _p("gate_gps_vel", 21.108, "1 (chi-square, 3 dof)", "NIS gate of the GPS velocity (0: off)", "pos0"),
    _p("gate_baro", 15.137, "1 (chi-square, 1 dof)", "NIS gate of the altimeter (0: off)", "pos0"),
    _p("gate_compass", 15.137, "1 (chi-square, 1 dof)", "NIS gate of the compass (0: off)", "pos0"),
    _p("gps_pos_sigma_min", 0.01, "m", "floor of a GPS position one-sigma (given or per fix) of an RTK-fixed "
       "solution or one of unknown kind", "pos0"),
    _p("gps_float_sigma_min", 0.3, "m", "floor of a GPS position one-sigma of an RTK-float solution", "pos0"),
    _p("gps_dgnss_sigma_min", 0.6, "m", "floor of a GPS position one-sigma of a DGNSS, SBAS or PPP solution", "pos0"),
    _p("gps_single_sigma_min", 1.5, "m", "floor of a GPS position one-sigma of a single (standalone) solution",
       "pos0"),
    _p("gps_vertical_floor_ratio", 2.0, "1", "floor of a GPS position's down one-sigma over the north and east "
       "floor of its solution kind", "pos0"),
    _p("gps_error_tau", 20.0, "s", "correlation time of the position errors of RTK-float, DGNSS and single "
       "solutions (0: white)", "pos0"),
    _p("gps_vel_sigma_min", 0.01, "m/s", "floor of a GPS velocity one-sigma (given or per fix)", "pos0"),
    _p("gps_time_offset", 0.0, "s", "added to the GNSS times to put them on the IMU clock (a receiver latency L: -L)",
       "real"),
    _p("gps_time_sigma", 0.005, "s", "one-sigma of the GNSS time on the IMU clock", "pos0"),
    _p("lever_arm_sigma", 0.0, "m", "one-sigma of each lever-arm component", "pos0"),
    _p("gps_robust_k", 3.0, "1", "Huber threshold of the GNSS aids: an innovation component beyond it (in its "
       "sigmas) is down-weighted, and the gate judges the fix so weighted (0: off)", "pos0"),
    _p("inflate_after", 1.0, "1", "consecutive gate rejections of a GNSS aid after which the next failing fix "
       "inflates the covariance (0: never)", "pos0"),
    _p("inflate_max", 1e4, "1", "largest covariance inflation; a fix that needs more resets the state to it"),
    _p("adapt_q_max", 100.0, "1", "largest process-noise scale of the innovation-based adaptation (1: off)"),
    _p("adapt_gain", 0.2, "1", "step of the adaptation per GNSS update (natural log of the scale)", "pos0"),
    _p("align_time", 2.0, "s", "duration of the static alignment (still samples; motion restarts it)", "pos0"),
    _p("min_speed_for_heading", 1.0, "m/s", "GPS speed above which the heading comes from the GPS track",
       "pos0"),
    _p("heading_from_gps", True, "-", "initialize the heading from the GPS track (without compass)", "bool"),
    _p("align_motion_time", 1.0, "s", "shortest window of an alignment in motion", "pos0"),
    _p("align_motion_max", 10.0, "s", "longest window of an alignment in motion (then it restarts)", "pos0"),
    _p("align_course_distance", 10.0, "m",
       "distance between the position fixes whose course gives the heading (position-only GNSS)", "pos0"),
    _p("align_level_sigma", 0.1, "rad", "roll/pitch one-sigma after an alignment in motion without GNSS velocity",
       "angle", limits=(0.0, _PI / 2)),
    _p("rest_gyr_th", 0.05, "rad/s", "rest: largest deviation of the gyro from its low-pass", "pos0"),
    _p("rest_acc_th", 0.5, "m/s^2",
       "rest: largest deviation of the accelerometer from its low-pass and of its norm from gravity", "pos0"),
    _p("rest_time", 1.0, "s", "rest: shortest duration", "pos0"),
    _p("rest_tau", 0.5, "s", "rest: low-pass time constant", "pos0"),
    _p("rest_speed", 0.3, "m/s", "rest: largest speed (the GNSS's before navigation; during it the INS's, plus three "
       "sigma up to this value again)", "pos0"),
    _p("zupt", True, "-", "zero-velocity and zero-angular-rate updates at rest", "bool"),
    _p("zupt_sigma", 0.02, "m/s", "one-sigma of the velocity at rest"),
    _p("zaru_sigma", 0.005, "rad/s", "one-sigma of the angular rate at rest beyond the gyro's white noise", "pos0"),
    _p("gate_zupt", 21.108, "1 (chi-square, 3 dof)", "NIS gate of the zero-velocity and zero-rate updates (0: off)",
       "pos0"),
    _p("nhc", False, "-", "non-holonomic constraint: no lateral or vertical velocity (wheeled vehicles)", "bool"),
    _p("nhc_sigma", 0.1, "m/s", "one-sigma of the lateral and vertical body velocity"),
    _p("gate_nhc", 18.421, "1 (chi-square, 2 dof)", "NIS gate of the non-holonomic constraint (0: off)", "pos0"),
    _p("nhc_auto", True, "-", "apply the non-holonomic constraint once the vehicle has shown it: nhc_auto_time s of "
       "GNSS-aided motion above nhc_auto_speed with the lateral and vertical body velocity within nhc_auto_limit "
       "(RMS); its R is then the larger of nhc_sigma^2 and that mean square", "bool"),
    _p("nhc_auto_speed", 3.0, "m/s", "non-holonomic evidence: slowest speed that counts", "pos0"),
    _p("nhc_auto_time", 20.0, "s", "non-holonomic evidence: duration needed (the mean square's time constant is a "
       "quarter of it)", "pos0"),
    _p("nhc_auto_limit", 0.3, "m/s", "non-holonomic evidence: largest RMS lateral and vertical body velocity "
       "(above twice it the evidence is lost)", "pos0"),
    _p("nhc_auto_rate", 0.05, "rad/s", "non-holonomic evidence: largest body yaw rate at which the IMU's mounting "
       "(its mean lateral and vertical velocity per forward speed) is learned", "pos0"),
    _p("nhc_mount_tau_yaw", 300.0, "s", "time constant over which the IMU's mounting in yaw (lateral velocity per "
       "forward speed) is learned from straight GNSS-aided driving (0: not learned)", "pos0"),
    _p("nhc_mount_tau_pitch", 20.0, "s", "time constant over which the IMU's mounting in pitch (vertical velocity per "
       "forward speed) is learned from straight GNSS-aided driving (0: not learned)", "pos0"),
    _p("nhc_lateral_aided", False, "-", "apply the learned non-holonomic constraint's lateral row while GNSS-aided "
       "too (default: in outages only; its mounting yaw is learned from the aided heading)", "bool"),
    _p("nhc_arm", 0.0, "m", "largest distance of the IMU from the non-slipping axle: the constraint's lateral "
       "variance gains (w_z nhc_arm)^2 (0: off)", "pos0"),
    _p("nhc_lever_b", (0.0, 0.0, 0.0), "m", "the non-slipping point (the middle of the rear axle) relative to the IMU, "
       "body FRD: the constraint holds the velocity there, v_b + w x nhc_lever_b", "vec3"),
    _p("pseudo_interval", 0.1, "s", "shortest interval between two zero-velocity or non-holonomic updates", "pos0"),
    _p("odometer_sigma", 0.05, "m/s", "one-sigma of an odometer speed"),
    _p("gate_odometer", 15.137, "1 (chi-square, 1 dof)", "NIS gate of the odometer (0: off)", "pos0"),
    _p("mag_heading_sigma", 0.05, "rad", "one-sigma of a magnetometer heading", "angle", limits=(0.0, 1.0)),
    _p("mag_heading_only", True, "-", "the magnetometer corrects the heading only (its tilt terms go into R; "
       "false: the full row)", "bool"),
    _p("mag_norm_tol", 0.1, "1", "reject the magnetometer when ||m|/m_ref - 1| exceeds it (0: off)", "pos0"),
    _p("mag_dip_tol", 0.1, "rad", "reject the magnetometer when its dip differs from the reference by more (0: off)",
       "pos0"),
    _p("mag_ref_samples", 50, "1", "magnetometer samples over which the reference norm and dip are averaged", "int1"),
    _p("gate_mag", 15.137, "1 (chi-square, 1 dof)", "NIS gate of the magnetometer heading (0: off)", "pos0"),
    _p("imu_rotation", ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), "1",
       "rotation from the IMU axes to the body axes: body = imu_rotation imu", "mat3"),
    _p("max_coast", 10.0, "s", "longest IMU gap the batch run coasts across (in steps of at most max_dt)", "pos0"),
    _p("earth_rotation", True, "-", "include the Earth rate, transport rate and Coriolis terms", "bool"),
    _max_dt(),
    *_ranges(),
    _cov_floor(0.0),
)

#: Filter name -> flag table.
FLAG_TABLES = {"QuaternionEKF": ATTITUDE_FLAGS, "EulerEKF": ATTITUDE_FLAGS, "MargFilter": MARG_FLAGS,
               "NavFilter13": NAV13_FLAGS, "GpsInsFilter": GPSINS_FLAGS}
#: Filter name -> parameter table.
PARAM_TABLES = {"QuaternionEKF": QEKF_PARAMS, "EulerEKF": EULER_PARAMS, "MargFilter": MARG_PARAMS,
                "NavFilter13": NAV13_PARAMS, "GpsInsFilter": GPSINS_PARAMS}


def parameters_table_markdown() -> str:
    """The table of ``docs/PARAMETERS.md``: one row per parameter name, its unit and meaning, and
    its default in each filter that has it (a test checks that the page holds this text)."""
    short = {"QuaternionEKF": "QEKF", "EulerEKF": "Euler", "MargFilter": "MARG", "NavFilter13": "Nav13",
             "GpsInsFilter": "GPS/INS"}
    rows: dict = {}
    for f, table in PARAM_TABLES.items():
        for p in table:
            rows.setdefault(p.name, {"p": p, "filters": {}})["filters"][f] = p
    out = ["| name | unit | meaning | " + " | ".join(short.values()) + " |", "|---|---|---|" + "---|" * len(short)]
    for name, r in rows.items():
        p0 = r["p"]
        notes = []
        cells = []
        for f, label in short.items():
            p = r["filters"].get(f)
            if p is None:
                cells.append("")
                continue
            cells.append(("I" if p.kind == "mat3" else "[0, 0, 0]") if isinstance(p.default, tuple) else repr(p.default))
            if p.core_name is None:
                notes.append(f"{label}: Python only")
            elif p.core_name != name:
                notes.append(f"{label}: C++ `{p.core_name}`")
        doc = (p0.doc[0].upper() + p0.doc[1:]).replace("|", "\\|")
        if notes:
            doc += " (" + "; ".join(notes) + ")"
        unit = p0.unit.replace("|", "\\|")
        out.append(f"| `{name}` | {unit} | {doc} | " + " | ".join(cells) + " |")
    return "\n".join(out)
