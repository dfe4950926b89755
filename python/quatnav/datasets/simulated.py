"""Simulated attitude trials: a :mod:`quatnav.sim` scenario as a :class:`~quatnav.datasets.trials.Trial`.

The reference is the simulator's truth in the IMU's own frame (``q_nb * q_b_imu`` for an IMU
mounted rotated), the magnetometer is put on the IMU's samples (NaN rows between its samples),
and the scored samples are those after the scenario's first rest (``params["scoring"]["from_s"]``
when the scenario states it, else everything after the first 5 s): the start, where every filter
converges from its initial guess, is not scored, as BROAD leaves out its rest phases.
"""
from __future__ import annotations

import numpy as np

from ..core import quaternion as Q
from .trials import Trial

__all__ = ["scenario_trial", "parse_sim_source"]


def parse_sim_source(text: str) -> tuple[str, int]:
    """``"sim:NAME"`` or ``"sim:NAME:SEED"`` -> ``(NAME, SEED)``."""
    parts = str(text).split(":")
    if parts[0] != "sim" or len(parts) not in (2, 3) or not parts[1]:
        raise ValueError(f"{text!r}: expected sim:NAME or sim:NAME:SEED")
    try:
        seed = int(parts[2]) if len(parts) == 3 else 0
    except ValueError:
        raise ValueError(f"{text!r}: the seed must be a non-negative integer") from None
    return parts[1], seed


def scenario_trial(name: str, seed: int = 0, dataset: str = "sim") -> Trial:
    """Build scenario ``name`` with ``seed`` and return it as a trial (see the module text)."""
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
    return Trial(f"{name}:{seed}", imu.gyro, imu.accel, mag, np.asarray(imu.t, float), q_ref, movement,
                 groups, dataset, f"sim:{name}:{seed}")
