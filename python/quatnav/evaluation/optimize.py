"""Parameter optimization of a filter over one or many logs with a reference.

:func:`optimize` minimizes the mean over logs of a metric (BROAD's RMSE, a heading RMSE on a
simulated run, any ``evaluate(params, log) -> float``) over chosen parameters within bounds.
Two methods:

* ``"powell"`` (default): :func:`scipy.optimize.minimize` with Powell's method, bounded, in
  log-space (noise parameters span decades and are positive; a step in log-space is a
  relative change). Powell needs no derivatives (the metric of a filter run has none usable:
  it is piecewise smooth and slightly noisy) and, unlike Nelder-Mead, takes bounds; for the
  1-5 parameters of a filter it converges in some tens of evaluations.
* ``"lhs"``: a budgeted Latin-hypercube search (:class:`scipy.stats.qmc.LatinHypercube`,
  seeded) in log-space: every candidate is known in advance, so all (candidate, log) pairs
  run in parallel; robust to several local minima; its result is a sample, not a converged
  optimum.

Each objective evaluation runs the logs through any :class:`concurrent.futures.Executor`
(default: serial in this process; a ``ProcessPoolExecutor``, or dask.distributed's
``client.get_executor()``, spread them). The result reports the parameters, the metric per
log, and the flatness of the optimum: the metric change when each parameter alone is moved
by +-``flat_step`` (relative).
"""
from __future__ import annotations

import functools
from concurrent.futures import Executor
from dataclasses import dataclass, field

import numpy as np

__all__ = ["optimize", "OptimizationResult", "broad_metric", "scenario_heading_metric", "SerialExecutor"]


class SerialExecutor(Executor):
    """An Executor that runs each call at once in the calling thread (the default)."""

    def submit(self, fn, /, *args, **kwargs):
        from concurrent.futures import Future
        f = Future()
        try:
            f.set_result(fn(*args, **kwargs))
        except BaseException as e:  # noqa: BLE001 - handed to the caller through the future
            f.set_exception(e)
        return f


def _broad(params, path, filter="qekf", metric="total"):
    from .tuning import evaluate_params
    per = evaluate_params(dict(params), [path], filter)
    return float(next(iter(per.values()))[metric])


def broad_metric(filter="qekf", metric="total"):
    """``evaluate(params, path)``: BROAD's ``metric`` RMSE (deg, movement phases) of ``filter``
    (a key of :data:`quatnav.evaluation.evaluate.FILTERS`) on the trial file ``path``."""
    return functools.partial(_broad, filter=filter, metric=metric)


@functools.lru_cache(maxsize=16)
def _scenario(name, seed, duration):
    from .. import sim
    return sim.make_scenario(name, seed=seed, duration=duration)


def _scenario_heading(params, log, filter="QuaternionEKF", skip_s=10.0):
    import quatnav
    from . import metrics
    name, seed, duration = log
    scn = _scenario(name, int(seed), float(duration))
    imu, mag = scn.imu, scn.mag
    m = np.full_like(imu.gyro, np.nan)
    m[np.searchsorted(imu.t, mag.t)] = mag.mag
    p = dict(params)
    p.setdefault("declination", np.radians(scn.params["mag"]["declination_deg"]))
    r = getattr(quatnav, filter)(**p).run(imu.gyro, imu.accel, m, t=imu.t)
    q_true = scn.truth.q_nb[imu.index]
    e = metrics.heading_error(metrics.error_quat(r.quat, q_true))
    return float(np.degrees(metrics.rmse(e, imu.t >= imu.t[0] + skip_s)))


def scenario_heading_metric(filter="QuaternionEKF"):
    """``evaluate(params, (scenario, seed, duration))``: heading RMSE (deg, after the first 10 s)
    of ``filter`` in 9D on a simulated MARG scenario (``handheld_marg``...)."""
    return functools.partial(_scenario_heading, filter=filter)


@dataclass
class OptimizationResult:
    """Outcome of :func:`optimize`.

    Attributes
    ----------
    params : dict
        The best parameters found (the fixed ``base`` ones included).
    score : float
        Mean metric over the logs at ``params``.
    per_log : list of float
        The metric of each log at ``params`` (in the order of ``logs``).
    flatness : dict
        ``{name: (score at -step, score at +step)}`` minus ``score``: how much worse the metric
        gets when that parameter alone moves by -+``flat_step`` (clipped to the bounds). Small
        values: a flat optimum, the parameter hardly matters there.
    evaluations : int
        Objective evaluations (each over all logs).
    history : list of (dict, float)
        Every evaluated parameter set and its mean.
    method : str
    """

    params: dict
    score: float
    per_log: list
    flatness: dict
    evaluations: int
    method: str
    history: list = field(default_factory=list)

    def summary(self) -> str:
        p = ", ".join(f"{k}={v:.4g}" if isinstance(v, float) else f"{k}={v}" for k, v in self.params.items())
        fl = ", ".join(f"{k} {lo:+.3g}/{hi:+.3g}" for k, (lo, hi) in self.flatness.items())
        return (f"{self.method}: mean {self.score:.4g} over {len(self.per_log)} logs after {self.evaluations} "
                f"evaluations: {p}; metric change at -/+ step: {fl}")


def optimize(evaluate, logs, bounds: dict, *, base: dict | None = None, method: str = "powell",
             budget: int = 40, x0: dict | None = None, executor: Executor | None = None, seed: int = 0,
             flat_step: float = 0.1) -> OptimizationResult:
    """Minimize the mean of ``evaluate(params, log)`` over ``logs`` within ``bounds``.

    Parameters
    ----------
    evaluate : callable ``(params: dict, log) -> float``
        The metric of one log (picklable for a process pool or a cluster: a module-level
        function or a ``functools.partial`` of one, e.g. :func:`broad_metric`).
    logs : sequence
        The logs (paths, or whatever ``evaluate`` takes).
    bounds : dict ``name -> (low, high)``
        The parameters to optimize; both bounds positive (the search is in log-space).
    base : dict, optional
        Fixed parameters passed with every set.
    method : {"powell", "lhs"}
        See the module doc.
    budget : int
        Most objective evaluations (Powell: ``maxfev``; lhs: the number of candidates).
    x0 : dict, optional
        Starting point of Powell (default: the geometric middle of the bounds).
    executor : concurrent.futures.Executor, optional
        Where the logs are evaluated; default serial.
    seed : int
        Seed of the Latin hypercube.
    flat_step : float
        Relative step of the flatness report.

    Returns
    -------
    OptimizationResult
    """
    if not bounds:
        raise ValueError("bounds: give at least one parameter")
    names = list(bounds)
    lo = np.array([float(bounds[n][0]) for n in names])
    hi = np.array([float(bounds[n][1]) for n in names])
    if not (np.all(lo > 0) and np.all(hi > lo)):
        raise ValueError("bounds: each (low, high) must have 0 < low < high (the search is in log-space)")
    logs = list(logs)
    if not logs:
        raise ValueError("logs: empty")
    if method not in ("powell", "lhs"):
        raise ValueError(f"method: expected 'powell' or 'lhs', got {method!r}")
    ex = executor if executor is not None else SerialExecutor()
    base = dict(base or {})
    history = []
    cache = {}

    def params_of(z):
        # rounded to 12 significant digits: the same point reached twice is evaluated once
        v = [float(f"{x:.12g}") for x in np.exp(np.clip(z, np.log(lo), np.log(hi)))]
        return dict(base, **{n: float(x) for n, x in zip(names, v)})

    def run_many(sets):
        futs = [[ex.submit(evaluate, p, log) for log in logs] for p in sets]
        out = []
        for p, fs in zip(sets, futs):
            per = [float(f.result()) for f in fs]
            mean = float(np.mean(per)) if np.all(np.isfinite(per)) else np.inf
            cache[tuple(sorted((k, v) for k, v in p.items() if k in bounds))] = (mean, per)
            history.append((p, mean))
            out.append((mean, per))
        return out

    def objective(z):
        p = params_of(z)
        key = tuple(sorted((k, v) for k, v in p.items() if k in bounds))
        if key not in cache:
            run_many([p])
        return cache[key][0]

    zlo, zhi = np.log(lo), np.log(hi)
    if method == "powell":
        from scipy.optimize import minimize
        z0 = (np.log([float(x0[n]) for n in names]) if x0 else 0.5 * (zlo + zhi))
        minimize(objective, np.clip(z0, zlo, zhi), method="Powell", bounds=list(zip(zlo, zhi)),
                 options={"maxfev": int(budget), "xtol": 1e-3, "ftol": 1e-4})
        # the best set evaluated (when the budget stops Powell inside a line search, its
        # returned point need not be the best one seen)
        best = min(history, key=lambda h: h[1])[0]
    else:
        from scipy.stats import qmc
        u = qmc.LatinHypercube(d=len(names), seed=seed).random(int(budget))
        sets = [params_of(zlo + ui * (zhi - zlo)) for ui in u]
        scores = run_many(sets)
        best = sets[int(np.argmin([s[0] for s in scores]))]
    n_eval = len(history)
    score = objective(np.log([best[n] for n in names]))
    per_log = cache[tuple(sorted((k, v) for k, v in best.items() if k in bounds))][1]
    # flatness: one parameter at a time, -+ flat_step
    probes = []
    for n in names:
        for f in (1.0 - flat_step, 1.0 + flat_step):
            p = dict(best)
            p[n] = float(np.clip(best[n] * f, bounds[n][0], bounds[n][1]))
            probes.append(p)
    res_probes = run_many(probes)
    flat = {n: (res_probes[2 * i][0] - score, res_probes[2 * i + 1][0] - score) for i, n in enumerate(names)}
    return OptimizationResult(best, score, per_log, flat, n_eval, method, history)
