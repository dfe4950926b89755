"""Simulated attitude trials: a :mod:`quatnav.sim` scenario as a :class:`~quatnav.datasets.trials.Trial`.

The reference is the simulator's truth in the IMU's own frame (``q_nb * q_b_imu`` for an IMU
mounted rotated), the magnetometer is put on the IMU's samples (NaN rows between its samples),
and the scored samples are those after the scenario's first rest (``params["scoring"]["from_s"]``
when the scenario states it, else everything after the first 5 s): the start, where every filter
converges from its initial guess, is not scored, as BROAD leaves out its rest phases.

``start="moving"`` gives the same trial started in the motion: the samples of the first rest are
cut off, so a filter starts inside the swing (its levelling from the first accelerometer sample
is off by the linear acceleration, its gyro bias unknown) and every remaining sample is scored,
the convergence included. The trial's name ends in ``:moving`` and its data set is
``sim-moving``: a filter that needs a rest to start, or learns a wrong gyro bias while it
converges in the motion, shows here and not in the set that starts at rest.
"""
from __future__ import annotations

import numpy as np

from ..core import quaternion as Q
from .trials import Trial

__all__ = ["scenario_trial", "parse_sim_source", "SIM_PREFIXES"]


#: The prefixes of a simulated source and the start of its trials (:func:`scenario_trial`).
SIM_PREFIXES = {"sim": "rest", "sim-moving": "moving"}


def parse_sim_source(text: str) -> tuple[str, int]:
    """``"sim:NAME"`` or ``"sim:NAME:SEED"`` (also ``sim-moving:``) -> ``(NAME, SEED)``."""
    parts = str(text).split(":")
    if parts[0] not in SIM_PREFIXES or len(parts) not in (2, 3) or not parts[1]:
        raise ValueError(f"{text!r}: expected sim:NAME or sim:NAME:SEED (or sim-moving:NAME[:SEED])")
    try:
        seed = int(parts[2]) if len(parts) == 3 else 0
    except ValueError:
        raise ValueError(f"{text!r}: the seed must be a non-negative integer") from None
    return parts[1], seed


def scenario_trial(name: str, seed: int = 0, dataset: str | None = None, start: str = "rest") -> Trial:
    """Build scenario ``name`` with ``seed`` and return it as a trial (see the module text):
    ``start="rest"`` as simulated, ``"moving"`` with the first rest cut off (data set
    ``sim-moving`` unless ``dataset`` is given)."""
    if start not in ("rest", "moving"):
        raise ValueError(f"start: expected 'rest' or 'moving', got {start!r}")
    if dataset is None:
        dataset = "sim" if start == "rest" else "sim-moving"
    from .. import sim
    s = sim.make_scenario(name, seed=seed)
    imu = s.imu
    q_ref = s.truth.q_nb[imu.index]
    if not np.allclose(imu.q_b_imu, [1.0, 0.0, 0.0, 0.0]):
        q_ref = Q.mul(q_ref, imu.q_b_imu)  # q_n_imu = q_nb q_b_imu
    mag = None
    if s.mag is not None:
        mag = np.full_like(imu.gyro, np.nan)
        k = np.searchsorted(imu.t, s.mag.t)
        keep = k < len(imu.t)
        mag[k[keep]] = s.mag.mag[keep]
    scoring = s.params.get("scoring", {})
    t0 = float(scoring.get("from_s", 5.0))
    movement = imu.t >= imu.t[0] + t0
    groups = list(s.params.get("groups", [])) or [name]
    t = np.asarray(imu.t, float)
    gyr, acc = imu.gyro, imu.accel
    label, source = f"{name}:{seed}", f"sim:{name}:{seed}"
    if start == "moving":
        cut = int(np.argmax(movement)) if movement.any() else 0
        gyr, acc, t, q_ref = gyr[cut:], acc[cut:], t[cut:], q_ref[cut:]
        mag = mag[cut:] if mag is not None else None
        movement = np.ones(len(t), bool)
        label, source = f"{name}:{seed}:moving", f"sim-moving:{name}:{seed}"
    return Trial(label, gyr, acc, mag, t, q_ref, movement, groups, dataset, source)
