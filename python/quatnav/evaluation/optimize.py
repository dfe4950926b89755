"""Parameter optimization of a filter over one or many logs with a reference.

:func:`optimize` minimizes the mean over logs of a metric (BROAD's RMSE, a heading RMSE on a
simulated run, the GNSS/INS horizontal RMS of :func:`gnss_ins_metric`, any
``evaluate(params, log) -> float``; on a user's own logs :func:`attitude_metric` (trials with a
reference, :mod:`quatnav.datasets.trials`) and :func:`gnss_ins_metric` (a GNSS/INS log scored
against its own GNSS during held-out outages)) over chosen parameters within bounds.
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

__all__ = ["optimize", "OptimizationResult", "broad_metric", "attitude_metric", "scenario_heading_metric",
           "gnss_ins_metric", "held_out_outages", "log_outage_error", "parse_gnss_ins_log", "SerialExecutor"]


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


def _attitude(params, spec, filter="qekf", mode="9D", metric="total", align="both"):
    from ..plausibility import checked_by_caller
    from .benchmark import evaluate_run, load_source_trial
    trial = load_source_trial(spec)
    with checked_by_caller():  # the trials are checked once (_check_inputs), not in every evaluation
        return float(evaluate_run(trial, filter, mode, dict(params), align)[metric])


def attitude_metric(filter="qekf", mode="9D", metric="total", align="both"):
    """``evaluate(params, spec)``: the ``metric`` RMSE (deg, scored samples) of ``filter`` in ``mode``
    on one trial after the benchmark's alignment ``align``
    (:func:`quatnav.evaluation.benchmark.evaluate_run`); ``spec`` is one of
    :func:`quatnav.evaluation.benchmark.resolve_sources` (a user's trial file, a BROAD trial, a
    simulated scenario)."""
    return functools.partial(_attitude, filter=filter, mode=mode, metric=metric, align=align)


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


def parse_gnss_ins_log(text):
    """A log of :func:`gnss_ins_metric` from its text: ``walk``, ``walk-degraded``, ``navego``,
    ``sim:NAME[:SEED]`` (e.g. ``sim:paper004_walk:2``), or the path of a user's own log with IMU
    and GNSS (any format :func:`quatnav.io.read` reads; files joined by ``+``, ``imu.csv+gnss.csv``,
    merge); a tuple is returned as it is."""
    if isinstance(text, tuple):
        return text
    t = str(text).strip()
    if all(Path(x).is_file() for x in t.split("+")):
        return ("file", t)
    if t in ("walk", "walk-rtk"):
        return ("walk", "rtk")
    if t == "walk-degraded":
        return ("walk", "degraded")
    if t == "navego":
        return ("navego",)
    if t.startswith("sim:"):
        parts = t.split(":")
        if len(parts) in (2, 3) and parts[1]:
            try:
                return ("sim", parts[1], int(parts[2]) if len(parts) == 3 else 0)
            except ValueError:
                pass
    raise ValueError(f"log {text!r}: expected walk, walk-degraded, navego, sim:NAME[:SEED] or the path of a log file")


@functools.lru_cache(maxsize=8)
def _sim_inputs(name, seed):
    from .. import sim
    return sim.make_scenario(name, seed=seed)


def _sim_horizontal(params, name, seed, skip_s=0.0):
    """GpsInsFilter on a simulated scenario's GNSS (+ altimeter, compass): horizontal RMS (m)
    of the IMU position against the truth while navigating."""
    import quatnav
    from ..core import earth as E
    s = _sim_inputs(name, int(seed))
    imu, g, tr = s.imu, s.gps, s.truth
    p = dict(params)
    p.setdefault("lever_arm_b", tuple(float(x) for x in np.broadcast_to(
        np.asarray(s.params.get("gps", {}).get("lever_arm_b_m", 0.0), float), (3,))))
    gs = s.params.get("gps", {})
    sig = np.broadcast_to([gs.get("pos_sigma_h_m", 2.0), gs.get("pos_sigma_h_m", 2.0), gs.get("pos_sigma_v_m", 4.0)],
                          (len(g.t), 3))
    kw = dict(gps_pos=quatnav.Aid(g.t_stamp, np.column_stack([g.lat, g.lon, g.h]), sig),
              gps_vel=quatnav.Aid(g.t_stamp, g.v_n, np.full((len(g.t), 3), gs.get("vel_sigma_m_s", 0.1))))
    if s.baro is not None:
        kw["baro"] = quatnav.Aid(s.baro.t, s.baro.h)
    if s.compass is not None:
        kw["compass"] = quatnav.Aid(s.compass.t, s.compass.yaw)
    r = quatnav.GpsInsFilter(**p).run(imu.gyro, imu.accel, t=imu.t, on_invalid="skip", **kw)
    m = r.navigating & (r.t >= imu.t[0] + skip_s)
    if not m.any():
        return float("inf")  # never navigated: the worst score
    k = imu.index[m]
    d = E.geodetic_to_ned(r.lat[m], r.lon[m], r.h[m], tr.lat[0], tr.lon[0], tr.h[0]) - tr.pos_n[k]
    return float(np.sqrt(np.mean(d[:, 0] ** 2 + d[:, 1] ** 2)))


@functools.lru_cache(maxsize=8)
def _read_log(path):
    """A user's log: one file, or files joined by ``+`` (``imu.csv+gnss.csv``) whose streams merge."""
    from .. import io
    logs = [io.read(p) for p in str(path).split("+")]
    log = logs[0]
    for other in logs[1:]:
        log = log.merge(other)
    log.require("imu", "gnss")
    return log


def held_out_outages(t_gnss, count: int = 3, length: float = 10.0, start: float | None = None):
    """``count`` GNSS outages of ``length`` s spread evenly over a log whose fixes are at ``t_gnss``:
    the first begins a third of the log in (at the latest 60 s after the first fix, the filter's
    alignment first; or at ``start``), the last ends ``length`` s before the last fix. Returns the
    ``(t_start, t_end)`` pairs (fewer when the log is too short for them)."""
    t = np.asarray(t_gnss, float)
    t0, t1 = float(t[0]), float(t[-1])
    first = t0 + min(60.0, (t1 - t0) / 3.0) if start is None else float(start)
    last = t1 - 2.0 * length
    if count < 1 or last < first:
        return []
    starts = [first] if count == 1 else list(np.linspace(first, last, count))
    out = []
    for a in starts:
        if not out or a >= out[-1][1]:
            out.append((float(a), float(a) + float(length)))
    return out


def log_outage_error(params, path, outages: int = 3, outage_length: float = 10.0) -> float:
    """The horizontal RMS error (m) of :class:`quatnav.GpsInsFilter` with ``params`` at the GNSS
    fixes held out in :func:`held_out_outages` of a user's log (IMU and GNSS; any format of
    :func:`quatnav.io.read`): the filter runs on the other fixes (``run(outages=...)``) and its
    antenna position (the IMU's plus the lever arm turned by the attitude) is compared with each
    held-out fix. ``inf`` when the filter is not navigating during the outages."""
    import quatnav
    from ..core import earth as E
    from ..core import quaternion as Q
    log = _read_log(str(path))
    g, imu = log.gnss, log.imu
    llh = np.column_stack([g.lat, g.lon, g.h])
    kw = {"gps_pos": quatnav.Aid(g.t, llh, g.sigma)}
    if g.vel_n is not None:
        kw["gps_vel"] = quatnav.Aid(g.t, g.vel_n, g.sigma_vel)
    outs = held_out_outages(g.t, outages, outage_length)
    if not outs:
        raise ValueError(f"{path}: too short for {outages} outages of {outage_length} s")
    from ..plausibility import checked_by_caller
    f = quatnav.GpsInsFilter(**dict(params))
    with checked_by_caller():  # the log is checked once (log_warnings), not in every evaluation
        r = f.run(imu.gyr, imu.acc, t=imu.t, outages=outs, on_invalid="skip", **kw)
    held = np.zeros(len(g.t), bool)
    for a, b in outs:
        held |= (g.t >= a) & (g.t < b)
    k = np.clip(np.searchsorted(r.t, g.t[held]), 0, len(r.t) - 1)
    if not held.any() or not np.all(r.navigating[k]):
        return float("inf")
    lever = np.asarray(f.params.get("lever_arm_b", (0.0, 0.0, 0.0)), float)
    d = E.geodetic_to_ned(r.lat[k], r.lon[k], r.h[k], g.lat[held], g.lon[held], g.h[held])
    d = d + Q.rotate(r.quat[k], np.broadcast_to(lever, (len(k), 3)))
    return float(np.sqrt(np.mean(d[:, 0] ** 2 + d[:, 1] ** 2)))


def log_warnings(path, imu_rotation=None) -> list:
    """The plausibility warnings of a user's GNSS/INS log (:func:`log_outage_error`'s ``path``),
    named by the file: the IMU's units, axes (in the body axes of ``imu_rotation``, (3, 3)),
    saturation and clock, the GNSS's units and clocks
    (:func:`quatnav.plausibility.plausibility_warnings`, as ``quatnav ins run`` checks its logs)."""
    from ..plausibility import gnss_speed, gnss_velocity_ne, plausibility_warnings
    log = _read_log(str(path))
    g, imu = log.gnss, log.imu
    rot = np.eye(3) if imu_rotation is None else np.asarray(imu_rotation, float).reshape(3, 3)
    d_g = {"time": g.t, "lat": np.degrees(g.lat), "lon": np.degrees(g.lon), "h": g.h}
    if g.vel_n is not None:
        d_g["v_n"], d_g["v_e"] = g.vel_n[:, 0], g.vel_n[:, 1]
    return plausibility_warnings(imu.t, imu.gyr @ rot.T, imu.acc @ rot.T, g.t, d_g["lat"], d_g["lon"],
                                 imu=f"IMU {path}", gnss=f"GNSS {path}", gnss_speed=gnss_speed(d_g),
                                 gnss_vel=gnss_velocity_ne(d_g),
                                 rotation_fix="imu_rotation with --set imu_rotation=ROLL,PITCH,YAW (rad)")


def _gnss_ins(params, log, seconds=None, directory=None, outages=3, outage_length=10.0):
    log = parse_gnss_ins_log(log)
    if log[0] == "file":
        return log_outage_error(params, log[1], outages, outage_length)
    if log[0] == "walk":
        from ..experiments.walk_rtk import run_walk
        run = log[1]
        summary, _ = run_walk(directory=None if directory is None else Path(directory) / "gnss_imu_walk",
                              runs=(run,), params=dict(params), seconds=seconds)
        return float(summary[run]["all_fixed"]["horizontal_m"]["rms"])
    if log[0] == "navego":
        from ..experiments.navego import run_navego
        summary, _ = run_navego(directory=None if directory is None else Path(directory) / "navego_synthetic",
                                seconds=seconds, params=dict(params))
        return float(summary["ins_gnss"]["horizontal_rmse_m"])
    return _sim_horizontal(params, log[1], log[2])


def gnss_ins_metric(seconds=None, directory=None, outages=3, outage_length=10.0):
    """``evaluate(params, log)``: the horizontal position RMS (m) of :class:`quatnav.GpsInsFilter`
    with ``params`` on ``log``:

    * ``"walk"``: the real walk (``gnss_imu_walk``) with its RTK fixes, scored at the RTK-fixed
      epochs (:func:`quatnav.experiments.walk_rtk.run_walk`, its parameters overridden by
      ``params``); ``"walk-degraded"``: the same walk fed GNSS with 2.5 m of added noise, scored
      against the RTK fixes (the case where tuning matters);
    * ``"navego"``: NaveGo's synthetic ADIS16405 run against its truth
      (:func:`quatnav.experiments.navego.run_navego`);
    * ``"sim:NAME[:SEED]"``: a simulated scenario with GNSS (``paper004_walk``,
      ``paper001_constant_turn``, ...) against its truth.

    * the path of a user's own log (IMU and GNSS): scored against its own GNSS at the fixes of
      ``outages`` held-out outages of ``outage_length`` s (:func:`log_outage_error`).

    ``seconds`` shortens the real logs (their first seconds); ``directory`` is the shared data
    folder (default: ``QUATNAV_DATA`` or ``../shared/data``). Picklable, for process pools and
    dask. A run that never navigates scores ``inf``.
    """
    return functools.partial(_gnss_ins, seconds=seconds, directory=directory, outages=outages,
                             outage_length=outage_length)


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
  quatnav tune my_trials/ --ref-frame ENU --mode 6d --param acc_sigma=0.05:2 --jobs 2
  quatnav tune broad sim --filter marg --param gain=0.1:10 --method lhs --budget 64
  quatnav tune --param mag_sigma=0.02:3 --scheduler tcp://host:8786 --json best.json
  quatnav tune --target gnss-ins --logs walk-degraded,navego,sim:paper004_walk \\
               --param gyro_noise=1e-4:1e-2 --param acc_noise=1e-3:1e-1 --jobs 2
  quatnav tune --target gnss-ins --logs flight.ulg,imu.csv+gnss.csv --outages 4 --outage-length 15 \\
               --set lever_arm_b=0.2,0,-0.1 --param gps_pos_sigma_h=0.5:10

--target attitude (default): each evaluation runs an attitude filter (--filter) in --mode on every
trial of the SOURCEs and takes the mean of the --metric RMSE (deg) over the scored samples, after
the benchmark's alignment (--align; quatnav eval -h): broad (default: $QUATNAV_DATA/broad), sim,
sim:NAME[:SEED], or your own trials with a reference (a folder or files; CSV, HDF5 or .mat, see
quatnav.datasets.trials).
--target gnss-ins: each evaluation runs quatnav.GpsInsFilter (its parameter names, SI units) on
every log of --logs and takes the mean horizontal position RMS (m): walk (the real walk, RTK,
scored at the fixed epochs), walk-degraded (the walk fed GNSS with 2.5 m of noise, scored against
RTK), navego (NaveGo's synthetic run against its truth), sim:NAME[:SEED] (a simulated scenario
with GNSS against its truth), or the path of your own log with IMU and GNSS (any format 'ins run
--log' reads; IMU.csv+GNSS.csv for two files): scored against its own GNSS at the fixes of --outages held-out outages of
--outage-length s; SOURCE is then the shared data folder of the named logs, --seconds N uses the
first N s of the real ones.
--set NAME=VALUE fixes a parameter (a vector as comma-separated numbers) for every evaluation.
Logs run in parallel with --jobs N or on a dask.distributed cluster with --scheduler. The report
gives the best parameters, the figure per log, and the change of the mean when each parameter
moves by -+10 % (a flat optimum: the parameter hardly matters there)."""


def _parse_param(text):
    from .._command import UsageError
    try:
        name, rng = text.split("=", 1)
        lo, hi = (float(x) for x in rng.split(":"))
    except ValueError:
        raise UsageError(f"--param {text}: expected NAME=LOW:HIGH (e.g. gyro_noise=1e-4:1e-1)") from None
    if not (0 < lo < hi):
        raise UsageError(f"--param {text}: needs 0 < LOW < HIGH (the search is in log-space)")
    return name.strip(), (lo, hi)


def _parse_set(text):
    from .._command import UsageError
    name, sep, value = str(text).partition("=")
    if not sep or not name.strip():
        raise UsageError(f"--set {text}: expected NAME=VALUE (e.g. lever_arm_b=0.2,0,-0.1)")
    vals = []
    for v in value.split(","):
        v = v.strip()
        if v.lower() in ("true", "false"):
            vals.append(v.lower() == "true")
            continue
        try:
            vals.append(float(v))
        except ValueError:
            raise UsageError(f"--set {text}: {v!r} is not a number") from None
    return name.strip(), (vals[0] if len(vals) == 1 else tuple(vals))


def _no_data_hint(what, where) -> str:
    import os
    src = "$QUATNAV_DATA" if os.environ.get("QUATNAV_DATA") else "the default data folder"
    return (f"no {what} in {where} ({src}): give the folder (or files) to tune on, or set QUATNAV_DATA to the folder "
            "that holds the shared data")


def _target_class(args):
    """The filter class that ``quatnav tune``'s --target tunes."""
    import quatnav
    if args.target == "gnss-ins":
        return quatnav.GpsInsFilter
    from .evaluate import FILTERS
    return getattr(quatnav, FILTERS[args.filter])


def _targets(args):
    """(filter class, logs, their labels, evaluate, unit) of ``quatnav tune``'s --target."""
    import quatnav
    from .._command import UsageError
    if args.target == "gnss-ins":
        from ..datasets import data_dir
        labels = [x.strip() for x in (args.logs or "walk-degraded,navego").split(",") if x.strip()]
        try:
            logs = [parse_gnss_ins_log(x) for x in labels]
        except ValueError as e:
            raise UsageError(f"--logs: {e}") from None
        if len(args.source) > 1:
            raise UsageError("--target gnss-ins takes one SOURCE, the shared data folder of the named logs "
                             "(your own logs go to --logs)")
        directory = args.source[0] if args.source else None
        root = Path(directory) if directory else data_dir()
        for lab, lg in zip(labels, logs):
            sub = {"walk": "gnss_imu_walk", "navego": "navego_synthetic"}.get(lg[0])
            if sub and not (root / sub).is_dir():
                raise UsageError(f"--logs {lab}: no {sub} folder in {root} (give SOURCE, the shared data folder, or "
                                 "set QUATNAV_DATA)")
            if lg[0] == "sim":
                from ..sim import list_scenarios
                if lg[1] not in list_scenarios():
                    raise UsageError(f"--logs {lab}: unknown scenario {lg[1]!r} (quatnav simulate --list)")
            if lg[0] == "file":
                try:
                    _read_log(lg[1])
                except (ValueError, OSError) as e:
                    raise UsageError(f"--logs {lab}: {e}") from None
        evaluate = gnss_ins_metric(seconds=args.seconds, directory=directory, outages=args.outages,
                                   outage_length=args.outage_length)
        return quatnav.GpsInsFilter, logs, labels, evaluate, "m"
    from .benchmark import resolve_sources
    from .evaluate import FILTERS
    from ..datasets import broad
    sources = list(args.source) or ["broad"]
    try:
        specs = resolve_sources(sources, args.ref_frame)
    except FileNotFoundError as e:
        where = e.filename or str(broad.default_dir())
        raise UsageError(_no_data_hint("trials", where) if sources == ["broad"] else f"{where}: {e.strerror}") from None
    except ValueError as e:
        raise UsageError(str(e)) from None
    if args.trials:
        keys = [x for x in args.trials.split(",") if x]
        specs = [sp for sp in specs if any(k in str(sp[1]) for k in keys)]
    if not specs:
        raise UsageError(f"no trials in {', '.join(sources)}" + (f" matching {args.trials!r}" if args.trials else ""))
    mode = args.mode.upper()
    labels = [Path(sp[1]).stem if sp[0] == "file" else f"{sp[1]}:{sp[2]}" for sp in specs]
    evaluate = attitude_metric(args.filter, mode, args.metric, args.align)
    return getattr(quatnav, FILTERS[args.filter]), specs, labels, evaluate, "deg"


def _check_inputs(args, cls, logs, base) -> None:
    """The plausibility warnings of the user's own inputs, once each, named by their files: the
    trial files of --target attitude (:func:`quatnav.datasets.trials.check_trial`), the logs of
    --target gnss-ins (:func:`log_warnings`); the evaluations then run without them."""
    from ..plausibility.categories import issue
    if args.target == "gnss-ins":
        rot = cls(**base).params["imu_rotation"]
        for lg in logs:
            if lg[0] == "file":
                issue(log_warnings(lg[1], rot))
        return
    from ..datasets.trials import check_trial
    from .benchmark import load_source_trial
    for sp in logs:
        if sp[0] == "file":
            check_trial(load_source_trial(sp))


def _tune(args) -> int:
    from .._command import UsageError, write_json
    if not args.param:
        raise UsageError("give at least one --param NAME=LOW:HIGH")
    bounds = dict(_parse_param(p) for p in args.param)
    base = dict(_parse_set(p) for p in (args.set or []))
    if args.outages < 1 or not args.outage_length > 0:
        raise UsageError("--outages and --outage-length must be positive")
    # The parameters are checked before any data is looked for: a misspelled name is the mistake
    # to report, wherever the data are.
    cls = _target_class(args)
    try:
        cls(**{k: float(np.sqrt(lo * hi)) for k, (lo, hi) in bounds.items()})
    except (TypeError, ValueError) as e:
        raise UsageError(f"--param: {e}") from None
    try:
        cls(**base)
    except (TypeError, ValueError) as e:
        raise UsageError(f"--set: {e}") from None
    cls, logs, labels, evaluate, unit = _targets(args)
    _check_inputs(args, cls, logs, base)
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
        r = optimize(evaluate, logs, bounds, base=base, method=args.method, budget=args.budget, executor=ex,
                     seed=args.seed)
    finally:
        close()
    print(r.summary())
    for lab, v in zip(labels, r.per_log):
        print(f"  {lab}: {v:.4g} {unit}")
    if args.json:
        write_json({"target": "attitude" if args.target == "broad" else args.target, "params": r.params, "score": r.score, "unit": unit,
                    "per_log": dict(zip(labels, r.per_log)),
                    "flatness": {k: list(v) for k, v in r.flatness.items()}, "evaluations": r.evaluations,
                    "method": r.method}, args)
    return 0


def add_parser(subparsers):
    """Register ``quatnav tune`` on an argparse subparsers object."""
    import argparse
    from .evaluate import FILTERS
    from .metrics import ALIGNMENTS
    p = subparsers.add_parser("tune", help="optimize filter parameters on your own logs, BROAD, simulated runs or "
                                           "GNSS/INS logs (Powell or Latin hypercube)",
                              description="Minimize a mean metric over logs within bounds, in log-space: the attitude "
                                          "error of an attitude filter on trials with a reference, or the horizontal "
                                          "error of the GNSS/INS filter; bounded Powell (default) or a seeded "
                                          "Latin-hypercube search.",
                              epilog=TUNE_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("source", nargs="*", metavar="SOURCE",
                   help="attitude: broad (default), sim, sim:NAME[:SEED], folders or files of trials; gnss-ins: the "
                        "shared data folder of the named --logs (default $QUATNAV_DATA)")
    p.add_argument("--target", choices=("attitude", "broad", "gnss-ins"), default="attitude",
                   help="attitude (an attitude filter on trials with a reference, default; broad: the same) or "
                        "gnss-ins (GpsInsFilter, horizontal RMS)")
    p.add_argument("--logs", metavar="A,B", help="with --target gnss-ins: walk, walk-degraded, navego, sim:NAME[:SEED], "
                                                 "or paths of your own logs (default walk-degraded,navego)")
    p.add_argument("--outages", type=int, default=3, help="with --target gnss-ins on your own logs: held-out GNSS "
                                                          "outages per log (default 3)")
    p.add_argument("--outage-length", type=float, default=10.0, help="their length, s (default 10)")
    p.add_argument("--seconds", type=float, help="with --target gnss-ins: only the first seconds of the real logs")
    p.add_argument("--filter", choices=sorted(FILTERS), default="qekf", help="attitude filter to tune (default qekf)")
    p.add_argument("--mode", choices=("9d", "6d", "9D", "6D"), default="9d",
                   help="attitude: with the magnetometer (9d, default) or without (6d)")
    p.add_argument("--align", choices=ALIGNMENTS, default="both",
                   help="attitude: the benchmark's alignment before scoring (default both)")
    p.add_argument("--ref-frame", choices=("NED", "ENU"), type=str.upper, default=None,
                   help="attitude: earth frame of the references of trial files that do not say it")
    p.add_argument("--param", action="append", metavar="NAME=LOW:HIGH", help="a parameter and its bounds (repeat)")
    p.add_argument("--set", action="append", metavar="NAME=VALUE", help="a fixed parameter (repeat)")
    p.add_argument("--metric", choices=("total", "heading", "inclination"), default="total",
                   help="attitude: the RMSE averaged over the trials (default total)")
    p.add_argument("--method", choices=("powell", "lhs"), default="powell", help="search method (default powell)")
    p.add_argument("--budget", type=int, default=40, help="most evaluations (lhs: candidates), default 40")
    p.add_argument("--trials", metavar="A,B", help="only trials whose file name contains one of these")
    p.add_argument("--seed", type=int, default=0, help="seed of the Latin hypercube")
    p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="a dask.distributed scheduler to run the trials on")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON ('-': to stdout)")
    p.set_defaults(func=_tune)
    return p
