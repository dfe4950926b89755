"""Attitude trials with a reference: one format for BROAD, simulated runs and a user's own data.

A *trial* is an IMU recording (gyroscope, accelerometer, optionally magnetometer) with a
reference attitude at the same samples (optical motion capture, a simulator's truth, a better
system). :class:`Trial` holds one in quatnav's conventions (SI units, ``q_nb`` [w, x, y, z],
navigation frame NED); :func:`load_trial` reads one from a file and :func:`load_folder` a data
set (a folder of trial files, optionally with a ``trials.json`` naming groups).

File formats (the same names in every container):

=================  ==============================================================================
field              meaning
=================  ==============================================================================
``time``           (N,) s, strictly increasing; or ``rate`` (Hz, one number) for a constant rate
``gyro``           (N, 3) rad/s, sensor frame (CSV: columns ``gyro_x gyro_y gyro_z``)
``accel``          (N, 3) m/s^2, sensor frame (CSV: ``accel_x accel_y accel_z``)
``mag``            optional (N, 3), any unit; rows of NaN: no sample (CSV: ``mag_x mag_y mag_z``,
                   empty cells)
``quat``           (N, 4) reference [w, x, y, z], sensor (or marker) to earth; NaN rows where
                   the reference was lost (CSV: ``q_w q_x q_y q_z``, empty cells there)
``ref_frame``      ``"NED"`` or ``"ENU"``: the earth frame of ``quat`` (CSV: a comment line
                   ``# ref_frame: ENU``); when the file does not say, ``ref_frame=`` must
``movement``       optional (N,) 0/1: the samples that are scored (default: all)
=================  ==============================================================================

* CSV (``.csv``, ``.txt``): a header row of the names above (any order, any case; the delimiter
  is sniffed, ``#`` lines are comments; :func:`quatnav.io.table.read_table`); ``# rate: 100``
  may replace the ``time`` column.
* HDF5 (``.h5``, ``.hdf5``; needs h5py) and MATLAB (``.mat``; needs scipy): datasets / variables
  of those names; ``ref_frame`` a string dataset, variable or file attribute. BROAD's own files
  (``imu_gyr``, ``imu_acc``, ``imu_mag``, ``opt_quat``, ``sampling_rate``, ``movement``) are
  recognised by their names and read with ``ref_frame="ENU"`` (BROAD's earth frame).

The reference's body frame may differ from the sensor's by a constant rotation (the markers'
frame), and its earth frame from the filters' by a constant heading: the benchmark
(:mod:`quatnav.evaluation.benchmark`) fits both. :func:`check_reference` tells a reference
whose vertical disagrees with the accelerometer (the usual sign of an ENU reference read as NED);
:func:`check_trial` adds the IMU's units, saturation and clock (:func:`quatnav.plausibility.check_imu`).
"""
from __future__ import annotations

import json
import warnings
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..core import quaternion as Q
from ..plausibility.categories import PlausibilityWarning

__all__ = ["Trial", "ReferenceWarning", "load_trial", "load_folder", "list_trial_files", "check_reference",
           "check_trial", "save_trial", "TRIAL_SUFFIXES"]

#: File suffixes read as trials.
TRIAL_SUFFIXES = (".mat", ".h5", ".hdf5", ".csv", ".txt")
_FRAMES = ("NED", "ENU")
_BROAD_KEYS = ("imu_gyr", "imu_acc", "opt_quat", "sampling_rate")


class ReferenceWarning(PlausibilityWarning):
    """A trial's reference looks inconsistent with its IMU data (frame, axes, clock)."""


@dataclass
class Trial:
    """One recording with a reference attitude, in quatnav's conventions.

    Attributes
    ----------
    name : str
        Trial name (the file's stem, or the scenario's name and seed).
    gyr : (N, 3) ndarray
        Angular rate, rad/s, sensor frame.
    acc : (N, 3) ndarray
        Specific force, m/s^2, sensor frame.
    mag : (N, 3) ndarray or None
        Magnetic field (any unit), sensor frame; NaN rows: no sample. None: no magnetometer.
    t : (N,) ndarray
        Sample times, s, strictly increasing.
    quat_ref : (N, 4) ndarray
        Reference ``q_nb`` [w, x, y, z], navigation frame NED; NaN rows where it is missing.
    movement : (N,) bool ndarray
        The samples that are scored.
    groups : list of str
        Groups the trial belongs to (from ``trials.json``, or the scenario's).
    dataset : str
        The data set (folder name, ``"sim"``, ...).
    source : str
        Where it was read from (a path or a scenario spec).
    """

    name: str
    gyr: np.ndarray
    acc: np.ndarray
    mag: np.ndarray | None
    t: np.ndarray
    quat_ref: np.ndarray
    movement: np.ndarray
    groups: list = field(default_factory=list)
    dataset: str = ""
    source: str = ""

    def __post_init__(self):
        n = len(self.gyr)
        for name in ("acc", "t", "quat_ref", "movement"):
            if len(getattr(self, name)) != n:
                raise ValueError(f"{name}: {len(getattr(self, name))} rows, gyr has {n}")
        if self.mag is not None and len(self.mag) != n:
            raise ValueError(f"mag: {len(self.mag)} rows, gyr has {n}")

    def __len__(self) -> int:
        return len(self.gyr)

    @property
    def dt(self) -> float:
        """Median sampling period, s."""
        return float(np.median(np.diff(self.t))) if len(self.t) > 1 else 0.0

    @property
    def rate(self) -> float:
        """Median sampling rate, Hz."""
        return 1.0 / self.dt

    @property
    def has_mag(self) -> bool:
        """True when the trial has magnetometer samples."""
        return self.mag is not None and bool(np.isfinite(self.mag).all(axis=1).any())

    def __repr__(self) -> str:
        return (f"Trial({self.name!r}, {len(self)} samples at {self.rate:.1f} Hz, "
                f"{'9D' if self.has_mag else '6D'}, {int(self.movement.sum())} scored, dataset {self.dataset!r})")


def _frame(value, where) -> str:
    s = str(value).strip().upper()
    if s not in _FRAMES:
        raise ValueError(f"ref_frame: expected NED or ENU, got {value!r} ({where})")
    return s


def _arr(a, cols, name, where):
    a = np.asarray(a, dtype=float)
    if a.ndim == 2 and a.shape[1] != cols and a.shape[0] == cols:
        a = a.T  # stored (cols, N) (MATLAB / HDF5 column-major writers)
    if a.ndim != 2 or a.shape[1] != cols:
        raise ValueError(f"{where}: {name} has shape {a.shape}, expected (N, {cols})")
    return np.ascontiguousarray(a)


def _text(v) -> str:
    if isinstance(v, bytes):
        return v.decode()
    a = np.asarray(v)
    if a.dtype.kind in "US":
        return "".join(str(x) for x in a.reshape(-1))
    if a.dtype.kind == "O" and a.size:
        return _text(a.reshape(-1)[0])
    return str(v)


def _read_container(path: Path) -> dict:
    """Variables of a .mat or HDF5 file (and the HDF5 file's attributes)."""
    if path.suffix == ".mat":
        from .._optional import require
        sio = require("scipy.io", "reading .mat trials")
        return {k: v for k, v in sio.loadmat(path).items() if not k.startswith("__")}
    from .._optional import require
    h5py = require("h5py", "reading HDF5 trials")
    out = {}
    with h5py.File(path, "r") as f:
        for k in f.keys():
            if isinstance(f[k], h5py.Dataset):
                out[k] = f[k][()]
        for k, v in f.attrs.items():
            out.setdefault(k, v)
    return out


def _from_container(raw: dict, where: str, ref_frame):
    if all(k in raw for k in _BROAD_KEYS):  # BROAD's layout: ENU reference, fixed rate
        n = len(_arr(raw["imu_gyr"], 3, "imu_gyr", where))
        rate = float(np.asarray(raw["sampling_rate"]).reshape(-1)[0])
        mov = np.asarray(raw["movement"]).reshape(-1).astype(bool) if "movement" in raw else None
        return dict(gyr=_arr(raw["imu_gyr"], 3, "imu_gyr", where), acc=_arr(raw["imu_acc"], 3, "imu_acc", where),
                    mag=_arr(raw["imu_mag"], 3, "imu_mag", where) if "imu_mag" in raw else None,
                    t=np.arange(n) / rate, quat=_arr(raw["opt_quat"], 4, "opt_quat", where), movement=mov,
                    ref_frame=_frame(ref_frame or "ENU", where))
    missing = [k for k in ("gyro", "accel", "quat") if k not in raw]
    if "time" not in raw and "rate" not in raw:
        missing.append("time or rate")
    if missing:
        raise ValueError(f"{where}: lacks {', '.join(missing)} (a trial holds time or rate, gyro, accel, "
                         "quat, ref_frame and optionally mag, movement; or BROAD's imu_gyr, imu_acc, opt_quat, "
                         "sampling_rate)")
    gyr = _arr(raw["gyro"], 3, "gyro", where)
    if "time" in raw:
        t = np.asarray(raw["time"], float).reshape(-1)
    else:
        t = np.arange(len(gyr)) / float(np.asarray(raw["rate"]).reshape(-1)[0])
    frame = ref_frame or (raw.get("ref_frame") is not None and _text(raw["ref_frame"])) or None
    mov = np.asarray(raw["movement"]).reshape(-1).astype(bool) if "movement" in raw else None
    return dict(gyr=gyr, acc=_arr(raw["accel"], 3, "accel", where),
                mag=_arr(raw["mag"], 3, "mag", where) if "mag" in raw else None, t=t,
                quat=_arr(raw["quat"], 4, "quat", where), movement=mov,
                ref_frame=None if frame is None else _frame(frame, where))


def _csv_comments(path: Path) -> dict:
    """``# key: value`` lines before the header."""
    out = {}
    with open(path, encoding="utf-8-sig", errors="replace") as fh:
        for line in fh:
            s = line.strip()
            if not s:
                continue
            if not s.startswith("#"):
                break
            key, sep, value = s.lstrip("#").partition(":")
            if not sep:
                key, sep, value = s.lstrip("#").partition("=")
            if sep:
                out[key.strip().lower()] = value.strip()
    return out


def _from_csv(path: Path, where: str, ref_frame):
    from ..io.table import read_table
    meta = _csv_comments(path)
    need = ["gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
    has_rate = "rate" in meta
    if not has_rate:
        need.insert(0, "time")
    # the reference may be missing in rows (NaN, markers lost): its columns are optional to the
    # reader, which requires finite numbers in every row of a required column, and checked here
    quat = ["q_w", "q_x", "q_y", "q_z"]
    tab = read_table(path, need, quat + ["mag_x", "mag_y", "mag_z", "movement"], what="trial",
                     increasing=None if has_rate else "time", min_rows=2)
    absent = [c for c in quat if c not in tab.header]
    if absent:
        raise ValueError(f"{where}: missing column {absent[0]!r} (a trial's reference is q_w q_x q_y q_z)")
    n = len(tab)
    t = np.arange(n) / float(meta["rate"]) if has_rate else tab["time"]
    mag = tab.stack(["mag_x", "mag_y", "mag_z"])
    frame = ref_frame or meta.get("ref_frame")
    return dict(gyr=tab.stack(["gyro_x", "gyro_y", "gyro_z"]), acc=tab.stack(["accel_x", "accel_y", "accel_z"]),
                mag=None if np.isnan(mag).all() else mag, t=t, quat=tab.stack(["q_w", "q_x", "q_y", "q_z"]),
                movement=None if np.isnan(tab["movement"]).all() else np.nan_to_num(tab["movement"]) > 0.5,
                ref_frame=None if frame is None else _frame(frame, where))


def load_trial(path, *, ref_frame: str | None = None, groups=None, dataset: str | None = None,
               check: bool = True) -> Trial:
    """Read one trial file (CSV, HDF5, .mat; see the module text).

    Parameters
    ----------
    path : str or Path
    ref_frame : {"NED", "ENU"}, optional
        Earth frame of the reference; overrides what the file says (BROAD's files: ENU).
    groups : list of str, optional
        The trial's groups (default: from ``trials.json`` beside the file, else none).
    dataset : str, optional
        The data set's name (default: the folder's name).
    check : bool
        Run :func:`check_trial` and warn: a :class:`ReferenceWarning` when the reference's vertical
        disagrees with the accelerometer, the IMU's units, saturation and clock as
        :func:`quatnav.plausibility.check_imu` does.

    Returns
    -------
    Trial
    """
    path = Path(path)
    where = str(path)
    if not path.is_file():
        raise FileNotFoundError(2, "no such trial file", str(path))
    suffix = path.suffix.lower()
    if suffix not in TRIAL_SUFFIXES:
        raise ValueError(f"{where}: unsupported file type {path.suffix!r} (a trial is {', '.join(TRIAL_SUFFIXES)})")
    d = _from_csv(path, where, ref_frame) if suffix in (".csv", ".txt") else _from_container(_read_container(path),
                                                                                              where, ref_frame)
    if d["ref_frame"] is None:
        raise ValueError(f"{where}: the file does not say the reference's earth frame; give ref_frame NED or ENU "
                         "(quatnav eval: --ref-frame)")
    n = len(d["gyr"])
    if len(d["acc"]) != n or len(d["quat"]) != n or len(d["t"]) != n:
        raise ValueError(f"{where}: gyro, accel, quat and time must have the same number of rows")
    if n < 2 or not np.all(np.diff(d["t"]) > 0):
        raise ValueError(f"{where}: time must be strictly increasing (at least 2 samples)")
    q = np.asarray(d["quat"], float)
    q = Q.enu_to_ned(q) if d["ref_frame"] == "ENU" else q
    mov = d["movement"] if d["movement"] is not None else np.ones(n, bool)
    if groups is None:
        info = _trial_info(path.parent)
        groups = list(info.get("trials", {}).get(path.stem, {}).get("groups", []))
    trial = Trial(path.stem, d["gyr"], d["acc"], d["mag"], np.asarray(d["t"], float), q, np.asarray(mov, bool),
                  list(groups), dataset if dataset is not None else path.parent.name, str(path))
    if check:
        check_trial(trial)
    return trial


def _trial_info(folder: Path) -> dict:
    p = Path(folder) / "trials.json"
    if not p.is_file():
        return {}
    with open(p) as f:
        return json.load(f)


def list_trial_files(folder) -> list[Path]:
    """Trial files in ``folder`` (suffixes :data:`TRIAL_SUFFIXES`), sorted by name; BROAD's
    ``.mat`` files win over its ``.hdf5`` copies of the same trials."""
    folder = Path(folder)
    if not folder.is_dir():
        raise FileNotFoundError(2, "no such folder", str(folder))
    files = sorted(p for p in folder.iterdir() if p.is_file() and p.suffix.lower() in TRIAL_SUFFIXES)
    stems = {p.stem for p in files if p.suffix.lower() == ".mat"}
    return [p for p in files if not (p.suffix.lower() in (".h5", ".hdf5") and p.stem in stems)]


def load_folder(folder, *, ref_frame: str | None = None, check: bool = True) -> list[Trial]:
    """Every trial of a folder (:func:`list_trial_files`), groups from its ``trials.json``."""
    return [load_trial(p, ref_frame=ref_frame, check=check) for p in list_trial_files(folder)]


def check_reference(trial: Trial, *, warn: bool = False, max_residual_deg: float = 15.0) -> dict:
    """Does the reference's vertical agree with the accelerometer's gravity?

    On the quasi-static samples (``||a| - 9.81| < 0.5 m/s^2``, reference present) the
    accelerometer's direction in the sensor frame is compared with the direction of ``-down``
    that the reference gives, after the best constant rotation between the two body frames
    (the markers' frame need not be the sensor's): the median residual angle. A reference read
    in the wrong earth frame (ENU as NED or back) flips the vertical and leaves tens of degrees;
    the other frame is tried and named.

    Returns
    -------
    dict
        ``{"residual_deg": ..., "other_frame_residual_deg": ..., "samples": n}`` (NaN when there
        are fewer than 50 quasi-static samples).
    """
    acc, q = trial.acc, trial.quat_ref
    ok = np.isfinite(q).all(axis=1) & np.isfinite(acc).all(axis=1)
    ok &= np.abs(np.linalg.norm(acc, axis=1) - 9.81) < 0.5
    out = {"residual_deg": float("nan"), "other_frame_residual_deg": float("nan"), "samples": int(ok.sum())}
    if ok.sum() < 50:
        return out
    idx = np.flatnonzero(ok)
    if idx.size > 20000:
        idx = idx[:: idx.size // 20000 + 1]
    a = acc[idx] / np.linalg.norm(acc[idx], axis=1, keepdims=True)

    def residual(q_nb):
        up_b = Q.rotate_inv(Q.normalize(q_nb), np.array([0.0, 0.0, -1.0]))  # specific force at rest
        R = _wahba(a, up_b)  # a ~ R up_b
        c = np.clip(np.sum(a * (up_b @ R.T), axis=1), -1.0, 1.0)
        return float(np.degrees(np.median(np.arccos(c))))

    out["residual_deg"] = residual(q[idx])
    # the other frame: NED <-> ENU is the same map both ways
    out["other_frame_residual_deg"] = residual(Q.enu_to_ned(q[idx]))
    w = _reference_warning(trial, out, max_residual_deg)
    if warn and w is not None:
        warnings.warn(w, stacklevel=2)
    return out


def _reference_warning(trial: Trial, out: dict, max_residual_deg: float):
    """The :class:`ReferenceWarning` of a result of :func:`check_reference` (or None)."""
    if not out["residual_deg"] > max_residual_deg:
        return None
    better = out["other_frame_residual_deg"] < max_residual_deg
    hint = (" read as the other earth frame (NED <-> ENU) it agrees within "
            f"{out['other_frame_residual_deg']:.1f} deg: give the other ref_frame") if better else \
        " check the reference's frames and the accelerometer's axes and unit"
    return ReferenceWarning(f"{trial.name}: the reference's vertical disagrees with the accelerometer by "
                            f"{out['residual_deg']:.1f} deg (median over {out['samples']} quasi-static "
                            f"samples);{hint}")


def check_trial(trial: Trial, *, warn: bool = True, max_residual_deg: float = 15.0) -> list:
    """The plausibility warnings of a trial: its IMU's units (a gyro in deg/s, an accelerometer in
    g), saturation and clock (:func:`quatnav.plausibility.check_imu`; not the axes, since the
    reference is given in the sensor's own frame or a constant rotation away), then the
    reference's vertical (:func:`check_reference`). With ``warn`` they are also issued
    (:func:`warnings.warn`, to the first caller outside quatnav).

    Returns
    -------
    list of quatnav.PlausibilityWarning
    """
    from ..plausibility import check_imu
    from ..plausibility.categories import issue
    where = f"trial {trial.source or trial.name}"
    out = check_imu(trial.gyr, trial.acc, t=trial.t, where=where, axes="none", names=("gyro", "accel"))
    ref = _reference_warning(trial, check_reference(trial), max_residual_deg)
    out += [ref] if ref is not None else []
    if warn:
        issue(out)
    return out


def _wahba(a, b) -> np.ndarray:
    """The rotation R minimizing sum |a_k - R b_k|^2 (Kabsch / SVD)."""
    H = b.T @ a
    U, _, Vt = np.linalg.svd(H)
    D = np.diag([1.0, 1.0, np.sign(np.linalg.det(Vt.T @ U.T))])
    return Vt.T @ D @ U.T


def save_trial(trial: Trial, path, *, ref_frame: str = "NED") -> Path:
    """Write a trial in the generic format (``.csv``, ``.h5``/``.hdf5`` or ``.mat``, by suffix);
    :func:`load_trial` reads it back. The reference is written in ``ref_frame``."""
    path = Path(path)
    frame = _frame(ref_frame, str(path))
    q = Q.ned_to_enu(trial.quat_ref) if frame == "ENU" else trial.quat_ref
    suffix = path.suffix.lower()
    if suffix in (".csv", ".txt"):
        cols = [trial.t[:, None], trial.gyr, trial.acc]
        names = ["time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z"]
        if trial.mag is not None:
            cols.append(trial.mag)
            names += ["mag_x", "mag_y", "mag_z"]
        cols += [q, trial.movement[:, None].astype(float)]
        names += ["q_w", "q_x", "q_y", "q_z", "movement"]
        data = np.hstack(cols)
        with open(path, "w") as fh:
            fh.write(f"# ref_frame: {frame}\n" + ",".join(names) + "\n")
            for row in data:  # a missing value (no reference, no field sample) is an empty cell
                fh.write(",".join("" if not np.isfinite(x) else repr(float(x)) for x in row) + "\n")
        return path
    d = {"time": trial.t, "gyro": trial.gyr, "accel": trial.acc, "quat": q,
         "movement": trial.movement.astype(np.uint8), "ref_frame": frame}
    if trial.mag is not None:
        d["mag"] = trial.mag
    if suffix == ".mat":
        from .._optional import require
        require("scipy.io", "writing .mat trials").savemat(path, d)
    elif suffix in (".h5", ".hdf5"):
        from .._optional import require
        h5py = require("h5py", "writing HDF5 trials")
        with h5py.File(path, "w") as f:
            for k, v in d.items():
                if k == "ref_frame":
                    f.attrs[k] = v
                else:
                    f[k] = v
    else:
        raise ValueError(f"path: unsupported suffix {path.suffix!r} (.csv, .h5, .hdf5, .mat)")
    return path
