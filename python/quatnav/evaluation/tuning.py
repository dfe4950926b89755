"""Parameter tuning on BROAD: one parameter set for all trials, lowest mean RMSE.

:func:`tune` evaluates a list (or grid) of parameter sets of a quatnav filter on every trial and
returns them ranked by the mean over trials of the total RMSE (BROAD's figure of merit for one
parameter set used on all trials). The work is spread through any
:class:`concurrent.futures.Executor`; by default a local process pool.

Example, local::

    from quatnav.evaluation import tuning
    res = tuning.tune(tuning.grid(acc_sigma=[0.05, 0.1, 0.2], gyro_noise=[5e-4, 1e-3]))
    print(res.best, res.best_score)

Example, many machines with dask.distributed (``pip install distributed``; not a quatnav
dependency)::

    from dask.distributed import Client
    client = Client("tcp://scheduler:8786")      # every worker needs quatnav and the data
    res = tuning.tune(grid, directory="/data/broad", executor=client.get_executor())

Each job runs one parameter set over all trials; trials are loaded once per worker process.
"""
from __future__ import annotations

import functools
import itertools
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["grid", "tune", "TuningResult", "evaluate_params"]


def grid(**axes) -> list[dict]:
    """Cartesian product of parameter values: ``grid(a=[1, 2], b=[3])`` -> ``[{a:1,b:3}, {a:2,b:3}]``."""
    for k, v in axes.items():
        if not isinstance(v, (list, tuple, np.ndarray)) or len(v) == 0:
            raise ValueError(f"{k}: expected a non-empty list of values")
    names = list(axes)
    return [dict(zip(names, combo)) for combo in itertools.product(*(list(axes[n]) for n in names))]


@functools.lru_cache(maxsize=64)
def _trial(path: str):
    from ..datasets import broad
    return broad.load_trial(path)


def evaluate_params(params: dict, paths, filter: str = "qekf") -> dict:
    """Figures of one parameter set on each trial: ``{trial name: {"total": deg, ...}}``."""
    from .evaluate import evaluate_trial
    return {(t := _trial(str(p))).name: evaluate_trial(t, filter, params) for p in paths}


@dataclass
class TuningResult:
    """Ranked outcome of :func:`tune`.

    Attributes
    ----------
    best : dict
        The parameter set with the lowest mean ``metric`` RMSE over trials.
    best_score : float
        That mean, degrees.
    ranking : list of (float, dict, dict)
        ``(mean, params, per-trial figures)`` for every set, best first.
    """

    best: dict
    best_score: float
    ranking: list = field(default_factory=list)

    def table(self, top: int = 10) -> str:
        lines = []
        for score, p, per in self.ranking[:top]:
            lines.append(f"{score:7.3f}  " + ", ".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                                                     for k, v in p.items()))
        return "\n".join(lines)


def tune(param_sets, directory=None, filter: str = "qekf", base: dict | None = None,
         executor: Executor | None = None, metric: str = "total", progress: bool = False) -> TuningResult:
    """Evaluate parameter sets on every BROAD trial and rank them by mean RMSE.

    Parameters
    ----------
    param_sets : list of dict, or dict of lists
        Parameter sets (a dict of lists is expanded with :func:`grid`).
    directory : str or Path, optional
        Folder of BROAD trials (default: the shared data folder).
    filter : str
        A key of :data:`quatnav.evaluation.evaluate.FILTERS`.
    base : dict, optional
        Parameters common to every set (a set's own values win).
    executor : concurrent.futures.Executor, optional
        Where the jobs run (one job per parameter set). Default: a local
        :class:`~concurrent.futures.ProcessPoolExecutor`, shut down afterwards.
    metric : {"total", "heading", "inclination"}
        The RMSE averaged over trials.
    progress : bool
        Show a progress bar (tqdm) on stderr.

    Returns
    -------
    TuningResult
    """
    from ..datasets import broad
    if isinstance(param_sets, dict):
        param_sets = grid(**param_sets)
    param_sets = [dict(base or {}, **p) for p in param_sets]
    if not param_sets:
        raise ValueError("param_sets: empty")
    if metric not in ("total", "heading", "inclination"):
        raise ValueError(f"metric: expected total, heading or inclination, got {metric!r}")
    directory = Path(directory) if directory is not None else broad.default_dir()
    paths = [str(p) for p in broad.list_trials(directory)]
    if not paths:
        raise FileNotFoundError(f"directory: no BROAD trials in {directory}")
    own = executor is None
    if own:
        from concurrent.futures import ProcessPoolExecutor
        executor = ProcessPoolExecutor()
    try:
        futures = [executor.submit(evaluate_params, p, paths, filter) for p in param_sets]
        bar = None
        if progress:
            try:
                from tqdm import tqdm
                bar = tqdm(total=len(futures), unit="set", disable=None)  # none off a terminal
            except ImportError:  # pragma: no cover
                bar = None
        results = []
        for fut in futures:
            results.append(fut.result())
            if bar:
                bar.update(1)
        if bar:
            bar.close()
    finally:
        if own:
            executor.shutdown()
    ranking = []
    for p, per in zip(param_sets, results):
        score = float(np.mean([per[t][metric] for t in per]))
        ranking.append((score if np.isfinite(score) else np.inf, p, per))
    ranking.sort(key=lambda r: r[0])
    return TuningResult(ranking[0][1], ranking[0][0], ranking)
