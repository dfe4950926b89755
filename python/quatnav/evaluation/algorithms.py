"""The attitude estimators the benchmark runs: quatnav's filters and the peer libraries.

Each entry of :data:`ALGORITHMS` names one estimator, how it runs (online: causal; offline:
every sample of the run for every estimate) and which modes it has: ``"9D"`` (gyroscope,
accelerometer, magnetometer) and ``"6D"`` (no magnetometer: the heading is free).
:func:`run_algorithm` runs one on a trial and returns ``q_nb`` in NED.

How each peer is fed (checked on BROAD: each mapping gives the peer's errors within a fraction of
a degree of the reference, any other mapping tens of degrees):

* ``vqf``: ``vqf.VQF(Ts).updateBatch`` (gyro rad/s, acc m/s^2, mag as is); ``quat6D`` /
  ``quat9D`` are ENU (earth frame y = magnetic north), converted with
  :func:`quatnav.core.quaternion.enu_to_ned`. ``vqf-offline``: ``vqf.offlineVQF``, VQF's acausal
  mode, fed and converted the same way.
* ``imufusion``: ``imufusion.Ahrs`` with ``convention = CONVENTION_NED``, the sample period set,
  gyro in deg/s, acc in g; ``update`` (9D) or ``update_no_magnetometer`` (6D); NED directly.
* ``madgwick``: ``ahrs.filters.Madgwick`` (default gain), gyro rad/s, acc m/s^2, mag; its earth
  frame is NWU (x north, z up): ``q_nb = [0, 1, 0, 0] * q_nwu_b``.

Peers run with their default parameters at the trial's median sampling period (they take a
constant one); a missing magnetometer sample (NaN row) is given to VQF as NaN-free by holding
the last sample, to the per-sample peers by a 6D step. quatnav's filters take the trial's times.
"""
from __future__ import annotations

import importlib
from dataclasses import dataclass

import numpy as np

from ..core import quaternion as Q

__all__ = ["Algorithm", "ALGORITHMS", "MODES", "available", "run_algorithm", "peer_version"]

#: 9D: gyroscope, accelerometer and magnetometer; 6D: gyroscope and accelerometer.
MODES = ("9D", "6D")
_Q_NED_NWU = np.array([0.0, 1.0, 0.0, 0.0])  # rotates NWU vectors into NED (180 deg about x)


@dataclass(frozen=True)
class Algorithm:
    """One estimator of the benchmark.

    Attributes
    ----------
    name : str
        Its key (``qekf``, ``vqf-offline``, ...).
    label : str
        What it is, for tables and figures.
    module : str
        The Python module that must be importable (``quatnav`` for quatnav's filters).
    offline : bool
        Acausal (smoothed / offline) rather than online.
    quatnav : bool
        One of quatnav's filters (takes ``params``; reports its own sigma).
    """

    name: str
    label: str
    module: str
    offline: bool = False
    quatnav: bool = False


ALGORITHMS = {a.name: a for a in (
    Algorithm("qekf", "QuaternionEKF", "quatnav", quatnav=True),
    Algorithm("qekf-smoothed", "QuaternionEKF smoothed", "quatnav", offline=True, quatnav=True),
    Algorithm("euler-ekf", "EulerEKF", "quatnav", quatnav=True),
    Algorithm("euler-ekf-smoothed", "EulerEKF smoothed", "quatnav", offline=True, quatnav=True),
    Algorithm("marg", "MargFilter", "quatnav", quatnav=True),
    Algorithm("vqf", "VQF", "vqf"),
    Algorithm("vqf-offline", "VQF offline", "vqf", offline=True),
    Algorithm("imufusion", "imufusion", "imufusion"),
    Algorithm("madgwick", "ahrs Madgwick", "ahrs"),
)}

_CLASSES = {"qekf": "QuaternionEKF", "qekf-smoothed": "QuaternionEKF", "euler-ekf": "EulerEKF",
            "euler-ekf-smoothed": "EulerEKF", "marg": "MargFilter"}


def available(name: str) -> tuple[bool, str]:
    """Whether algorithm ``name`` can run here, and a note when it cannot."""
    if name not in ALGORITHMS:
        raise ValueError(f"unknown algorithm {name!r}; known: {', '.join(ALGORITHMS)}")
    a = ALGORITHMS[name]
    if a.quatnav:
        import quatnav
        if hasattr(quatnav, _CLASSES[name]):
            return True, ""
        return False, f"{name}: quatnav.{_CLASSES[name]} is not available in this build; skipped"
    try:
        importlib.import_module(a.module)
        return True, ""
    except ImportError:
        return False, f"{name}: package {a.module!r} is not installed; skipped"


def peer_version(name: str) -> str:
    """The installed version of a peer's package (for result caches and reports)."""
    from importlib import metadata
    mod = ALGORITHMS[name].module
    try:
        return metadata.version(mod)
    except metadata.PackageNotFoundError:  # pragma: no cover
        return "unknown"


def _mag_of(trial, mode):
    if mode == "6D":
        return None
    if mode != "9D":
        raise ValueError(f"mode: expected 9D or 6D, got {mode!r}")
    if trial.mag is None:
        raise ValueError(f"{trial.name}: 9D needs a magnetometer; the trial has none")
    return trial.mag


def _held(mag):
    """NaN rows replaced by the last finite row (the first finite row before any)."""
    ok = np.all(np.isfinite(mag), axis=1)
    if ok.all():
        return mag
    idx = np.where(ok, np.arange(len(mag)), 0)
    np.maximum.accumulate(idx, out=idx)
    first = int(np.argmax(ok))
    idx[: first] = first
    return mag[idx]


def run_algorithm(name: str, trial, mode: str = "9D", params: dict | None = None):
    """Run one estimator on one trial.

    Parameters
    ----------
    name : str
        A key of :data:`ALGORITHMS`.
    trial : quatnav.datasets.trials.Trial
        (or anything with ``gyr``, ``acc``, ``mag``, ``dt`` and optionally ``t``).
    mode : {"9D", "6D"}
    params : dict, optional
        Parameters of a quatnav filter (peers run with their defaults).

    Returns
    -------
    quat : (N, 4) ndarray
        ``q_nb`` [w, x, y, z], NED (x magnetic north in 9D).
    att_sigma : (N, 3) ndarray or None
        The filter's one-sigma of the body-frame attitude error, rad (quatnav's filters).
    """
    if name not in ALGORITHMS:
        raise ValueError(f"unknown algorithm {name!r}; known: {', '.join(ALGORITHMS)}")
    gyr, acc = np.ascontiguousarray(trial.gyr, float), np.ascontiguousarray(trial.acc, float)
    mag = _mag_of(trial, mode)
    if ALGORITHMS[name].quatnav:
        import warnings

        import quatnav
        f = getattr(quatnav, _CLASSES[name])(**(params or {}))
        t = getattr(trial, "t", None)
        timing = {"t": t} if t is not None else {"dt": trial.dt}
        kw = {"smooth": True} if ALGORITHMS[name].offline else {}
        with warnings.catch_warnings():
            # A trial's body frame is its sensor's own (BROAD's: z up): the reference is given in
            # it, or a constant rotation away (fitted by the benchmark), so no axes are wrong here.
            warnings.simplefilter("ignore", quatnav.AxesWarning)
            res = f.run(gyr, acc, mag, on_invalid="skip", **timing, **kw)
        return np.asarray(res.quat, float), getattr(res, "att_sigma", None)
    dt = float(trial.dt)
    if name in ("vqf", "vqf-offline"):
        import vqf
        m = None if mag is None else np.ascontiguousarray(_held(np.asarray(mag, float)))
        if name == "vqf-offline":
            out = vqf.offlineVQF(gyr, acc, m, dt)
        else:
            v = vqf.VQF(dt)
            out = v.updateBatch(gyr, acc) if m is None else v.updateBatch(gyr, acc, m)
        return Q.enu_to_ned(out["quat6D" if m is None else "quat9D"]), None
    if name == "imufusion":
        import imufusion
        ahrs = imufusion.Ahrs()
        s = imufusion.AhrsSettings()
        s.convention = imufusion.CONVENTION_NED
        s.sample_rate = int(round(1.0 / dt))
        ahrs.set_settings(s)
        ahrs.set_sample_period(dt)
        gd, ag = np.degrees(gyr), acc / 9.80665
        ok = None if mag is None else np.all(np.isfinite(mag), axis=1)
        q = np.empty((len(gyr), 4))
        for k in range(len(gyr)):
            if ok is not None and ok[k]:
                ahrs.update(gd[k], ag[k], mag[k])
            else:
                ahrs.update_no_magnetometer(gd[k], ag[k])
            q[k] = ahrs.get_quaternion()
        return q, None
    if name == "madgwick":
        import ahrs
        if mag is None:
            mw = ahrs.filters.Madgwick(gyr=gyr, acc=acc, frequency=1.0 / dt)
        else:
            mw = ahrs.filters.Madgwick(gyr=gyr, acc=acc, mag=_held(np.asarray(mag, float)), frequency=1.0 / dt)
        return Q.mul(_Q_NED_NWU, np.asarray(mw.Q, float)), None
    raise ValueError(f"unknown algorithm {name!r}")  # pragma: no cover
