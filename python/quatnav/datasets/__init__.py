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
    """The shared data folder: ``$QUATNAV_DATA`` if set; else, when quatnav runs from its source
    tree (``<repo>/python/quatnav``), ``<repo>/../shared/data``; else ``./shared/data`` below the
    current folder. An installed package never looks inside its own installation (a virtual
    environment holds no data)."""
    env = os.environ.get("QUATNAV_DATA")
    if env:
        return Path(env)
    here = Path(__file__).resolve()
    repo = here.parents[3]  # <repo>/python/quatnav/datasets/__init__.py
    if here.parents[2].name == "python" and (repo / "pyproject.toml").is_file():
        return repo.parent / "shared" / "data"
    return Path.cwd() / "shared" / "data"
