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
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["optimize", "OptimizationResult", "broad_metric", "scenario_heading_metric", "SerialExecutor"]


class SerialExecutor(Executor):
    """An Executor that runs each call at once in the calling thread (the default)."""

    def submit(self, fn, /, *args, **kwargs):
        """Call ``fn(*args, **kwargs)`` now; a finished Future with its result or exception."""
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


# ----------------------------------------------------------------------------------------------
# quatnav tune
# ----------------------------------------------------------------------------------------------
TUNE_EPILOG = """\
examples:
  quatnav tune --param gyro_noise=1e-4:1e-1 --param acc_sigma=0.01:1 --budget 40 --jobs 2
  quatnav tune DIR --filter euler-ekf --param gain=0.1:10 --method lhs --budget 64
  quatnav tune --param mag_sigma=0.02:3 --scheduler tcp://host:8786 --json best.json

Each evaluation runs every trial (in parallel with --jobs N or on a dask.distributed cluster
with --scheduler) and takes the mean of BROAD's RMSE over the movement phases. The report gives
the best parameters, the RMSE per trial, and the change of the mean when each parameter moves
by -+10 %% (a flat optimum: the parameter hardly matters there)."""


def _parse_param(text):
    from ..cliutil import UsageError
    try:
        name, rng = text.split("=", 1)
        lo, hi = (float(x) for x in rng.split(":"))
    except ValueError:
        raise UsageError(f"--param {text}: expected NAME=LOW:HIGH (e.g. gyro_noise=1e-4:1e-1)") from None
    if not (0 < lo < hi):
        raise UsageError(f"--param {text}: needs 0 < LOW < HIGH (the search is in log-space)")
    return name.strip(), (lo, hi)


def _tune(args) -> int:
    import quatnav
    from ..cliutil import UsageError, write_json
    from ..datasets import broad
    from .evaluate import FILTERS
    if not args.param:
        raise UsageError("give at least one --param NAME=LOW:HIGH")
    bounds = dict(_parse_param(p) for p in args.param)
    cls = getattr(quatnav, FILTERS[args.filter])
    try:
        cls(**{k: float(np.sqrt(lo * hi)) for k, (lo, hi) in bounds.items()})
    except (TypeError, ValueError) as e:
        raise UsageError(f"--param: {e}") from None
    directory = args.dir or broad.default_dir()
    try:
        paths = [str(p) for p in broad.list_trials(directory)]
    except (FileNotFoundError, NotADirectoryError):
        paths = []
    if args.trials:
        paths = [p for p in paths if any(t in p for t in args.trials.split(","))]
    if not paths:
        raise UsageError(f"no BROAD trials in {directory}" + (f" matching {args.trials!r}" if args.trials else ""))
    evaluate = broad_metric(args.filter, args.metric)
    if args.scheduler:
        from distributed import Client
        client = Client(args.scheduler)
        ex, close = client.get_executor(), client.close
    elif args.jobs > 1:
        ex = ProcessPoolExecutor(max_workers=args.jobs)
        close = ex.shutdown
    else:
        ex, close = None, (lambda: None)
    try:
        r = optimize(evaluate, paths, bounds, method=args.method, budget=args.budget, executor=ex, seed=args.seed)
    finally:
        close()
    print(r.summary())
    for p, v in zip(paths, r.per_log):
        print(f"  {Path(p).stem}: {v:.3f} deg")
    if args.json:
        write_json({"params": r.params, "score": r.score, "per_log": dict(zip((Path(p).stem for p in paths), r.per_log)),
                    "flatness": {k: list(v) for k, v in r.flatness.items()}, "evaluations": r.evaluations,
                    "method": r.method}, args)
    return 0


def add_parser(subparsers):
    """Register ``quatnav tune`` on an argparse subparsers object."""
    import argparse
    from .evaluate import FILTERS
    p = subparsers.add_parser("tune", help="optimize filter parameters on BROAD (Powell or Latin hypercube)",
                              description="Minimize the mean BROAD RMSE over all trials within bounds, in log-space: "
                                          "bounded Powell (default) or a seeded Latin-hypercube search.",
                              epilog=TUNE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dir", nargs="?", default=None, metavar="DIR", help="folder of BROAD trials (default: the shared data)")
    p.add_argument("--filter", choices=sorted(FILTERS), default="qekf", help="filter to tune (default qekf)")
    p.add_argument("--param", action="append", metavar="NAME=LOW:HIGH", help="a parameter and its bounds (repeat)")
    p.add_argument("--metric", choices=("total", "heading", "inclination"), default="total",
                   help="BROAD RMSE averaged over the trials (default total)")
    p.add_argument("--method", choices=("powell", "lhs"), default="powell", help="search method (default powell)")
    p.add_argument("--budget", type=int, default=40, help="most evaluations (lhs: candidates), default 40")
    p.add_argument("--trials", metavar="A,B", help="only trials whose file name contains one of these")
    p.add_argument("--seed", type=int, default=0, help="seed of the Latin hypercube")
    p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="a dask.distributed scheduler to run the trials on")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON ('-': to stdout)")
    p.set_defaults(func=_tune)
    return p
