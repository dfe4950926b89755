"""The BROAD benchmark (Berlin Robust Orientation Estimation Assessment Dataset).

D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD - A Benchmark for Robust Inertial
Orientation Estimation", Data 6(7), 2021, doi:10.3390/data6070072 (CC BY 4.0).

Each trial holds IMU data (gyro rad/s, accelerometer m/s^2, magnetometer uT) at ~285.7 Hz and
an optical reference ``opt_quat`` (sensor to earth, earth frame ENU, NaN where the markers were
lost). The dataset's earth frame is already aligned with the magnetometer's (y = magnetic
north): the benchmark compares estimates with the reference without any heading alignment
(its ``calculateErrorQuatEarth``), and so does :mod:`quatnav.evaluation.metrics`. :func:`load_trial`
converts the reference to quatnav's NED convention (x = magnetic north, z down) with
:func:`enu_to_ned`; the body frame is the sensor's own.
"""
from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core import quaternion as Q

__all__ = ["Trial", "load_trial", "list_trials", "load_trial_info", "enu_to_ned", "default_dir"]


def default_dir() -> Path:
    """``<shared data>/broad`` (see :func:`quatnav.datasets.data_dir`)."""
    from . import data_dir
    return data_dir() / "broad"


def enu_to_ned(q_enu_b) -> np.ndarray:
    """Attitude w.r.t. NED from attitude w.r.t. ENU, row-wise; NaN rows stay NaN.

    ``q_ned_b = q_ned_enu * q_enu_b`` with ``q_ned_enu`` the rotation that maps ENU vectors to
    NED (``x_n = y_e, y_n = x_e, z_n = -z_e``); the body frame is unchanged.

    Parameters
    ----------
    q_enu_b : (N, 4) or (4,) array_like
        ``[w, x, y, z]``, body to ENU.

    Returns
    -------
    (N, 4) or (4,) ndarray
        ``[w, x, y, z]``, body to NED.
    """
    return Q.enu_to_ned(np.asarray(q_enu_b, dtype=float))


@dataclass
class Trial:
    """One BROAD trial in quatnav's conventions.

    Attributes
    ----------
    name : str
        Trial name, e.g. ``"02_undisturbed_slow_rotation_B"``.
    gyr : (N, 3) ndarray
        Angular rate, rad/s, sensor frame.
    acc : (N, 3) ndarray
        Specific force, m/s^2, sensor frame.
    mag : (N, 3) ndarray
        Magnetic field, uT, sensor frame.
    quat_ref : (N, 4) ndarray
        Reference ``q_nb`` [w, x, y, z], navigation frame NED (x magnetic north); NaN rows
        where the optical system lost the markers.
    movement : (N,) bool ndarray
        Samples of the movement phases (the ones the benchmark's errors are computed over).
    rate : float
        Sampling rate, Hz.
    groups : list of str
        Groups of the trial (from ``trials.json``), e.g. ``["undisturbed", "rotation", ...]``.
    """

    name: str
    gyr: np.ndarray
    acc: np.ndarray
    mag: np.ndarray
    quat_ref: np.ndarray
    movement: np.ndarray
    rate: float
    groups: list = field(default_factory=list)
    pos_ref: np.ndarray | None = None

    @property
    def dt(self) -> float:
        """Sampling period, s."""
        return 1.0 / self.rate

    @property
    def quat_ref_enu(self) -> np.ndarray:
        """The reference as stored in the dataset (earth frame ENU)."""
        return Q.ned_to_enu(self.quat_ref)

    def __len__(self) -> int:
        return self.gyr.shape[0]


def load_trial_info(directory) -> dict:
    """Contents of ``trials.json`` (names, descriptions, groups), or ``{}`` when absent."""
    p = Path(directory) / "trials.json"
    if not p.exists():
        return {}
    with open(p) as f:
        return json.load(f)


def list_trials(directory=None) -> list[Path]:
    """Trial files (``.mat``, else ``.hdf5``) in ``directory``, sorted by name."""
    d = Path(directory) if directory is not None else default_dir()
    if not d.is_dir():
        raise FileNotFoundError(f"directory: {d} does not exist")
    files = sorted(d.glob("*.mat"))
    if not files:
        files = sorted(d.glob("*.hdf5"))
    return files


def _read(path: Path) -> dict:
    if path.suffix == ".mat":
        import scipy.io as sio
        raw = sio.loadmat(path)
        return {k: v for k, v in raw.items() if not k.startswith("__")}
    if path.suffix in (".hdf5", ".h5"):
        try:
            import h5py
        except ImportError as e:  # pragma: no cover - optional dependency
            raise ImportError("reading BROAD .hdf5 files needs h5py (pip install h5py)") from e
        out = {}
        with h5py.File(path, "r") as f:
            for k in f.keys():
                out[k] = np.array(f[k])
        return out
    raise ValueError(f"path: unsupported file type {path.suffix!r} (expected .mat or .hdf5)")


def load_trial(path, info: dict | None = None) -> Trial:
    """Load one BROAD trial.

    Parameters
    ----------
    path : str or Path
        A ``.mat`` (scipy) or ``.hdf5`` (h5py) trial file.
    info : dict, optional
        ``trials.json`` contents, for the trial's groups (read from the same folder if None).

    Returns
    -------
    Trial
    """
    path = Path(path)
    raw = _read(path)
    missing = [k for k in ("imu_gyr", "imu_acc", "imu_mag", "opt_quat", "sampling_rate", "movement")
               if k not in raw]
    if missing:
        raise ValueError(f"path: {path.name} lacks fields {missing}")

    def arr(k, cols):
        a = np.ascontiguousarray(np.asarray(raw[k], dtype=float))
        if a.ndim == 2 and a.shape[1] != cols and a.shape[0] == cols:
            a = np.ascontiguousarray(a.T)  # hdf5 files may store (3, N)
        return a

    gyr, acc, mag, q_enu = arr("imu_gyr", 3), arr("imu_acc", 3), arr("imu_mag", 3), arr("opt_quat", 4)
    movement = np.asarray(raw["movement"]).reshape(-1).astype(bool)
    rate = float(np.asarray(raw["sampling_rate"]).reshape(-1)[0])
    q_ned = enu_to_ned(q_enu)
    name = path.stem
    if info is None:
        info = load_trial_info(path.parent)
    groups = list(info.get("trials", {}).get(name, {}).get("groups", []))
    pos = arr("opt_pos", 3) if "opt_pos" in raw else None
    return Trial(name, gyr, acc, mag, q_ned, movement, rate, groups, pos)
