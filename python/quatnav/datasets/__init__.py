"""Loaders of third-party datasets into arrays with quatnav's conventions (SI, NED, [w, x, y, z]).

Each loader lives in its own module (``quatnav.datasets.broad``, ...); the data itself is never
shipped with the package. :mod:`quatnav.datasets.trials` is the one format of an attitude trial
with a reference (BROAD's files, a user's own CSV / HDF5 / .mat, simulated runs through
:mod:`quatnav.datasets.simulated`) that the attitude benchmark reads. :func:`data_dir` finds the
project's shared data folder.
"""
from __future__ import annotations

import os
from pathlib import Path

__all__ = ["data_dir"]


def data_dir() -> Path:
    """The shared data folder: ``$QUATNAV_DATA`` if set, else ``<repo>/../shared/data``."""
    env = os.environ.get("QUATNAV_DATA")
    if env:
        return Path(env)
    return Path(__file__).resolve().parents[3].parent / "shared" / "data"
