"""NaveGo's synthetic INS/GNSS example (R. Gonzalez et al., NaveGo, LGPL-3.0).

Three MATLAB v5 files in ``<shared data>/navego_synthetic``:

* ``imu1_adis16405.mat``: struct ``imu1``: ``t`` (s), ``fb`` (specific force, m/s^2), ``wb``
  (angular rate, rad/s) at 200 Hz, body frame forward-right-down, and the ADIS16405 error profile
  already in SI units by NaveGo's ``imu_si_errors``: ``arw`` (rad/s/sqrt(Hz) = rad/sqrt(s); the
  data sheet's 2 deg/sqrt(h) is 5.818e-4), ``vrw`` (m/s^2/sqrt(Hz); 0.2 m/s/sqrt(h) is 3.333e-3),
  ``gb_sta``/``ab_sta`` (turn-on bias bounds, rad/s and m/s^2: 3 deg/s and 50 mg),
  ``gb_dyn``/``ab_dyn`` (bias instability, rad/s and m/s^2), ``gb_corr``/``ab_corr``
  (Gauss-Markov correlation times, s), ``ini_align`` (true initial [roll, pitch, yaw], rad) and
  ``ini_align_err`` (its one-sigma, rad).
* ``gnss.mat``: struct ``gnss``: ``t`` (s), ``lat``/``lon`` (rad), ``h`` (m), ``vel`` (NED m/s)
  at 5 Hz, lever arm ``larm`` (m, body frame), position one-sigma ``stdm`` (m: N, E, D) and
  ``stdv`` (m/s).
* ``ref.mat``: struct ``ref``: truth ``t``, ``lat``, ``lon``, ``h``, ``vel``, ``roll``,
  ``pitch``, ``yaw`` and ``DCMnb_m`` (row-major body-to-NED direction cosines) at 200 Hz.

NaveGo's IMU samples are instantaneous values at ``t``; quatnav's filters take sample k as the
mean over (t[k-1], t[k]], which at 200 Hz differs by half a sample (2.5 ms).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["NaveGoSynthetic", "load", "default_dir", "gm_driving_noise"]


def default_dir() -> Path:
    """``<shared data>/navego_synthetic`` (see :func:`quatnav.datasets.data_dir`)."""
    from . import data_dir
    return data_dir() / "navego_synthetic"


@dataclass
class NaveGoSynthetic:
    """The NaveGo synthetic run in quatnav's conventions (SI, NED, radians).

    Attributes
    ----------
    imu_t : (N,) ndarray, s
    gyro : (N, 3) ndarray, rad/s (body FRD)
    accel : (N, 3) ndarray, m/s^2 (specific force, body FRD)
    imu_profile : dict
        The ADIS16405 error profile as stored (SI units, see the module docstring): ``arw``,
        ``vrw``, ``gb_sta``, ``ab_sta``, ``gb_dyn``, ``ab_dyn``, ``gb_corr``, ``ab_corr``, ...
        (each a (3,) array).
    ini_align, ini_align_err : (3,) ndarray
        Initial [roll, pitch, yaw] and its one-sigma, rad.
    gnss_t : (K,) ndarray, s
    gnss_llh : (K, 3) ndarray
        Antenna [lat (rad), lon (rad), h (m)].
    gnss_vel : (K, 3) ndarray, NED m/s
    gnss_pos_sigma : (3,) ndarray
        One-sigma N, E, D (m).
    gnss_vel_sigma : (3,) ndarray, m/s
    lever_arm_b : (3,) ndarray, m
    ref_t : (M,) ndarray, s
    ref_llh : (M, 3) ndarray
    ref_vel : (M, 3) ndarray, NED m/s
    ref_rpy : (M, 3) ndarray, rad
    ref_C_nb : (M, 3, 3) ndarray
    """

    imu_t: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    imu_profile: dict
    ini_align: np.ndarray
    ini_align_err: np.ndarray
    gnss_t: np.ndarray
    gnss_llh: np.ndarray
    gnss_vel: np.ndarray
    gnss_pos_sigma: np.ndarray
    gnss_vel_sigma: np.ndarray
    lever_arm_b: np.ndarray
    ref_t: np.ndarray
    ref_llh: np.ndarray
    ref_vel: np.ndarray
    ref_rpy: np.ndarray
    ref_C_nb: np.ndarray
    path: Path = field(default_factory=Path)


def _struct(path: Path, name: str):
    from scipy.io import loadmat
    if not path.is_file():
        raise FileNotFoundError(f"NaveGo synthetic data: {path} not found")
    m = loadmat(str(path), squeeze_me=True, struct_as_record=False)
    if name not in m:
        raise ValueError(f"{path}: no struct {name!r} (found {sorted(k for k in m if not k.startswith('__'))})")
    return m[name]


def _f(s, name, shape=None):
    a = np.asarray(getattr(s, name), dtype=np.float64)
    if shape is not None and a.shape != shape:
        raise ValueError(f"field {name!r}: expected shape {shape}, got {a.shape}")
    return a


def load(directory=None) -> NaveGoSynthetic:
    """Load the three files of ``directory`` (default :func:`default_dir`)."""
    d = Path(directory) if directory is not None else default_dir()
    imu = _struct(d / "imu1_adis16405.mat", "imu1")
    gnss = _struct(d / "gnss.mat", "gnss")
    ref = _struct(d / "ref.mat", "ref")
    t = _f(imu, "t")
    n = len(t)
    prof = {k: _f(imu, k) for k in ("arw", "vrw", "gb_sta", "ab_sta", "gb_dyn", "ab_dyn", "gb_corr", "ab_corr",
                                    "gb_psd", "ab_psd", "a_std", "g_std") if hasattr(imu, k)}
    tg = _f(gnss, "t")
    k = len(tg)
    tr = _f(ref, "t")
    m = len(tr)
    return NaveGoSynthetic(
        imu_t=t, gyro=_f(imu, "wb", (n, 3)), accel=_f(imu, "fb", (n, 3)), imu_profile=prof,
        ini_align=_f(imu, "ini_align", (3,)), ini_align_err=_f(imu, "ini_align_err", (3,)),
        gnss_t=tg, gnss_llh=np.column_stack([_f(gnss, "lat", (k,)), _f(gnss, "lon", (k,)), _f(gnss, "h", (k,))]),
        gnss_vel=_f(gnss, "vel", (k, 3)), gnss_pos_sigma=_f(gnss, "stdm", (3,)),
        gnss_vel_sigma=_f(gnss, "stdv", (3,)), lever_arm_b=_f(gnss, "larm", (3,)),
        ref_t=tr, ref_llh=np.column_stack([_f(ref, "lat", (m,)), _f(ref, "lon", (m,)), _f(ref, "h", (m,))]),
        ref_vel=_f(ref, "vel", (m, 3)),
        ref_rpy=np.column_stack([_f(ref, "roll", (m,)), _f(ref, "pitch", (m,)), _f(ref, "yaw", (m,))]),
        ref_C_nb=_f(ref, "DCMnb_m", (m, 9)).reshape(m, 3, 3), path=d)


def gm_driving_noise(sigma, tau):
    """Driving-noise density (unit/sqrt(s)) of a first-order Gauss-Markov process with
    steady-state one-sigma ``sigma`` and correlation time ``tau`` (s): ``sigma * sqrt(2 / tau)``
    (so that ``q * tau / 2 = sigma^2``)."""
    return float(sigma) * np.sqrt(2.0 / float(tau))
