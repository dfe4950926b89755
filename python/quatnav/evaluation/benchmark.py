"""One attitude benchmark across data sets and modes: :func:`benchmark`.

Runs estimators (quatnav's filters and the peer libraries, :mod:`quatnav.evaluation.algorithms`)
in every selected mode (9D with the magnetometer, 6D without; online or offline as the estimator
is) on every trial of the selected sources, and scores each estimate against the trial's
reference:

* **Alignment.** For each estimate separately, the constant rotations a reference system leaves
  open are fitted first (:func:`quatnav.evaluation.metrics.fit_alignment`): a heading offset
  between the earth frames (in 6D the heading is free; in 9D magnetic north need not be the
  reference's) and a rotation between the sensor's and the reference's body frames. The same fit
  for every estimator, on the samples that are scored. ``align="none"`` gives BROAD's own figures
  (no fit), ``"heading"`` the heading offset only.
* **Errors.** The error quaternion in the earth frame ``q_est * conj(q_ref)`` split into total
  ``2 acos(|w|)``, heading ``2 atan(|z / w|)`` and inclination ``2 acos(sqrt(w^2 + z^2))``; the
  RMSE of each over the scored samples (``movement``; NaN references left out), degrees. A
  quatnav filter also reports the fraction of samples within its own 3 sigma.
* **Tables.** Per trial, per group of trials (``trials.json``, or a scenario's groups) and the
  mean over the trials of each data set: one parameter set for all trials.

Sources: ``"broad"`` (the BROAD folder of :func:`quatnav.datasets.broad.default_dir`), ``"sim"``
(the simulated fast-motion set, :data:`quatnav.sim.FAST_MOTION`), ``"sim:NAME[:SEED]"`` (one
:mod:`quatnav.sim` scenario), ``"sim-moving"`` and ``"sim-moving:NAME[:SEED]"`` (the same started
in the motion: the first rest cut off, every sample scored;
:func:`quatnav.datasets.simulated.scenario_trial`), a folder of trial files, one trial file (the generic format of
:mod:`quatnav.datasets.trials`: CSV, HDF5 or .mat), or :class:`~quatnav.datasets.trials.Trial`
objects. The (trial, estimator, mode) runs go through any :class:`concurrent.futures.Executor`
(default: in this process, one after the other); each worker loads a trial once.

Example::

    from concurrent.futures import ProcessPoolExecutor
    from quatnav.evaluation.benchmark import benchmark
    with ProcessPoolExecutor(2) as ex:
        res = benchmark(["broad", "sim"], ["qekf", "qekf-smoothed", "vqf", "vqf-offline"], executor=ex)
    print(res.table())
    res.to_json("bench.json")
"""
from __future__ import annotations

import functools
import hashlib
import json
import sys
import warnings
from concurrent.futures import Executor
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from . import metrics as M
from .algorithms import ALGORITHMS, MODES, available, peer_version, run_algorithm

__all__ = ["benchmark", "BenchmarkResult", "resolve_sources", "load_source_trial", "evaluate_run",
           "DEFAULT_ALGORITHMS", "METRICS"]

#: The estimators run by default.
DEFAULT_ALGORITHMS = ("qekf", "qekf-smoothed", "euler-ekf", "marg", "vqf", "vqf-offline", "imufusion", "madgwick")
#: The error figures of every run, degrees.
METRICS = ("total", "heading", "inclination")


# ----------------------------------------------------------------------------------------------
# sources -> picklable trial specs
# ----------------------------------------------------------------------------------------------
def resolve_sources(sources, ref_frame: str | None = None) -> list:
    """The trials of ``sources`` as small picklable specs for :func:`load_source_trial`:
    ``("file", path, ref_frame)``, ``("sim", name, seed, start)`` or a Trial itself.

    Raises FileNotFoundError / ValueError naming a source that gives no trial."""
    from ..datasets import broad
    from ..datasets.simulated import SIM_PREFIXES, parse_sim_source
    from ..datasets.trials import Trial, TRIAL_SUFFIXES, list_trial_files
    if isinstance(sources, (str, Path, Trial)):
        sources = [sources]
    specs = []
    for src in sources:
        if isinstance(src, Trial):
            specs.append(src)
            continue
        s = str(src)
        if s == "broad":
            d = broad.default_dir()
            files = list_trial_files(d) if d.is_dir() else []
            if not files:
                raise FileNotFoundError(2, "no BROAD trials (give the folder, or set QUATNAV_DATA to the folder "
                                           "that holds broad/)", str(d))
            specs += [("file", str(p), ref_frame) for p in files]
        elif s in SIM_PREFIXES:
            from ..sim import FAST_MOTION
            specs += [("sim", name, seed, SIM_PREFIXES[s]) for name, seed in FAST_MOTION]
        elif s.split(":", 1)[0] in SIM_PREFIXES and ":" in s:
            name, seed = parse_sim_source(s)
            from ..sim import list_scenarios
            if name not in list_scenarios():
                raise ValueError(f"{s}: unknown scenario {name!r} (quatnav simulate --list)")
            specs.append(("sim", name, seed, SIM_PREFIXES[s.split(":", 1)[0]]))
        else:
            p = Path(s)
            if p.is_dir():
                files = list_trial_files(p)
                if not files:
                    raise FileNotFoundError(2, f"no trial files ({', '.join(TRIAL_SUFFIXES)}) in the folder", str(p))
                specs += [("file", str(f), ref_frame) for f in files]
            elif p.is_file():
                specs.append(("file", str(p), ref_frame))
            else:
                raise FileNotFoundError(2, "no such file or folder (a source is broad, sim, sim:NAME[:SEED], sim-moving, "
                                           "a folder of trials or a trial file)", str(p))
    return specs


@functools.lru_cache(maxsize=64)
def _load_cached(spec):
    from ..datasets.simulated import scenario_trial
    from ..datasets.trials import load_trial
    if spec[0] == "file":
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # the main process checked the references already
            return load_trial(spec[1], ref_frame=spec[2])
    return scenario_trial(spec[1], spec[2], start=spec[3] if len(spec) > 3 else "rest")


def load_source_trial(spec):
    """The Trial of a spec of :func:`resolve_sources` (cached per process)."""
    from ..datasets.trials import Trial
    return spec if isinstance(spec, Trial) else _load_cached(spec)


# ----------------------------------------------------------------------------------------------
# one run
# ----------------------------------------------------------------------------------------------
def _trial_hash(trial) -> str:
    h = hashlib.sha1()
    for a in (trial.gyr, trial.acc, trial.mag, getattr(trial, "t", None)):
        if a is not None:
            h.update(np.ascontiguousarray(a, float).tobytes())
    return h.hexdigest()


def _estimate(trial, name, mode, params, cache_dir):
    """(quat, att_sigma) of one run; a peer's estimate is read from / written to ``cache_dir``."""
    if cache_dir is None or ALGORITHMS[name].quatnav:
        return run_algorithm(name, trial, mode, params)
    key = hashlib.sha1(f"{_trial_hash(trial)}|{name}|{mode}|{peer_version(name)}".encode()).hexdigest()[:24]
    path = Path(cache_dir) / f"{name}_{mode}_{key}.npy"
    if path.is_file():
        return np.load(path), None
    q, s = run_algorithm(name, trial, mode, params)
    Path(cache_dir).mkdir(parents=True, exist_ok=True)
    tmp = path.with_suffix(f".{id(q)}.tmp.npy")
    np.save(tmp, q)
    tmp.replace(path)
    return q, s


def evaluate_run(trial, name: str, mode: str = "9D", params: dict | None = None, align: str = "both",
                 keep_series: bool = False, cache_dir=None) -> dict:
    """Figures of one estimator in one mode on one trial (degrees): ``total``, ``heading``,
    ``inclination`` after the alignment ``align``, the fitted rotations' angles, and for
    quatnav's filters ``within_3sigma``; with ``keep_series`` the total error over time."""
    quat, sig = _estimate(trial, name, mode, params, cache_dir)
    mask = np.asarray(trial.movement, bool)
    q_e, q_b = M.fit_alignment(quat, trial.quat_ref, mask, align)
    from ..core import quaternion as Q
    ref = Q.mul(Q.mul(q_e, trial.quat_ref), q_b)
    out = M.attitude_rmse_deg(quat, ref, mask)
    out = {k: float(v) for k, v in out.items()}
    out["align_heading_deg"] = float(np.degrees(2.0 * np.arctan2(q_e[3], q_e[0])))
    out["align_body_deg"] = float(np.degrees(2.0 * np.arccos(np.clip(abs(q_b[0]), 0.0, 1.0))))
    if sig is not None:
        out["within_3sigma"] = M.sigma_consistency(quat, ref, sig, mask)
    if keep_series:
        e = M.error_quat(quat, ref)
        out["series_total_deg"] = np.degrees(M.total_error(e))
        out["series_heading_deg"] = np.degrees(M.heading_error(e))
        out["series_t"] = np.asarray(getattr(trial, "t", np.arange(len(quat)) * trial.dt), float)
        out["series_movement"] = mask
    return out


def _job(spec, name, mode, params, align, keep_series, cache_dir):
    from ..plausibility import checked_by_caller
    trial = load_source_trial(spec)
    meta = {"name": trial.name, "dataset": trial.dataset, "groups": list(trial.groups), "samples": len(trial),
            "rate_hz": float(trial.rate), "has_mag": bool(trial.has_mag), "source": trial.source}
    if mode == "9D" and not trial.has_mag:
        return meta, None
    # benchmark() checks the IMU of a trial file once, with the file's name; the simulated ones are
    # quatnav's own: the filters do not check again in every run
    with checked_by_caller():
        return meta, evaluate_run(trial, name, mode, params, align, keep_series, cache_dir)


def _trial_key(meta) -> str:
    return f"{meta['dataset']}/{meta['name']}"


# ----------------------------------------------------------------------------------------------
# the benchmark
# ----------------------------------------------------------------------------------------------
def run_label(name: str, mode: str) -> str:
    """``"qekf 9D"``: the label of a run (an estimator in a mode)."""
    return f"{name} {mode}"


@dataclass
class BenchmarkResult:
    """Outcome of :func:`benchmark`.

    Attributes
    ----------
    runs : list of str
        ``"<algorithm> <mode>"`` for every run that could run.
    trials : dict
        ``{"<dataset>/<trial>": {"name", "dataset", "groups", "samples", "rate_hz", "has_mag",
        "source", "results": {run: figures}}}``, figures as :func:`evaluate_run`.
    align : str
    notes : list of str
        What was skipped and why.
    params : dict
        The quatnav filters' parameters given (``{algorithm: {...}}``); empty: the defaults.
    """

    runs: list
    trials: dict
    align: str = "both"
    notes: list = field(default_factory=list)
    params: dict = field(default_factory=dict)

    # -- aggregation -------------------------------------------------------------------------
    @property
    def datasets(self) -> list:
        """The data sets, in the order of the trials."""
        return list(dict.fromkeys(t["dataset"] for t in self.trials.values()))

    def _mean(self, keys, run) -> dict:
        out = {}
        for k in (*METRICS, "within_3sigma"):
            vals = [self.trials[t]["results"][run][k] for t in keys
                    if run in self.trials[t]["results"] and k in self.trials[t]["results"][run]]
            if vals:
                out[k] = float(np.mean(vals))
                if k == "total":
                    out["trials"] = len(vals)
        return out

    def groups(self, dataset: str) -> dict:
        """``{group: {"trials": [...], run: mean figures}}`` of one data set (groups with more
        than one trial of it, or with a name other than the trial's own)."""
        members: dict = {}
        for key, t in self.trials.items():
            if t["dataset"] != dataset:
                continue
            for g in t["groups"]:
                if g != "all_trials":
                    members.setdefault(g, []).append(key)
        return {g: {"trials": m, **{r: self._mean(m, r) for r in self.runs}} for g, m in members.items()}

    def mean(self, dataset: str | None = None) -> dict:
        """``{run: mean figures}`` over the trials of ``dataset`` (all trials if None)."""
        keys = [k for k, t in self.trials.items() if dataset is None or t["dataset"] == dataset]
        return {r: self._mean(keys, r) for r in self.runs}

    def score(self, run: str, metric: str = "total") -> float:
        """Mean over the data sets of each data set's mean ``metric`` of ``run`` (each data set
        counts once whatever its number of trials): one number to choose parameters on."""
        vals = [self.mean(d)[run].get(metric) for d in self.datasets]
        vals = [v for v in vals if v is not None]
        return float(np.mean(vals)) if vals else float("nan")

    # -- output ------------------------------------------------------------------------------
    def table(self, metric: str = "total", mode: str | None = None) -> str:
        """Plain-text tables, one per mode: per trial, per group, and per data set the mean total,
        heading and inclination RMSE (degrees) and quatnav's 3-sigma consistency."""
        out = []
        modes = [m for m in MODES if mode in (None, m)]
        for md in modes:
            runs = [r for r in self.runs if r.endswith(" " + md)]
            if not runs:
                continue
            algs = [r.rsplit(" ", 1)[0] for r in runs]
            w = max(10, *(len(a) + 1 for a in algs))
            lw = max([36] + [len(k) + 1 for k in self.trials] +
                     [len(f"{d} within own 3 sigma") + 1 for d in self.datasets])
            head = f"{'trial':{lw}s}" + "".join(f"{a:>{w}s}" for a in algs)
            lines = [f"{md}: {metric} RMSE over the scored samples, deg (alignment: {self.align})", head,
                     "-" * len(head)]

            def row(label, figs, k=metric, fmt=".2f"):
                cells = []
                for r in runs:
                    v = figs.get(r, {}).get(k)
                    cells.append(f"{v:{w}{fmt}}" if v is not None and np.isfinite(v) else f"{'-':>{w}s}")
                return f"{label:{lw}s}" + "".join(cells)

            for d in self.datasets:
                for key, t in self.trials.items():
                    if t["dataset"] == d:
                        lines.append(row(f"{d}/{t['name']}", t["results"]))
                groups = self.groups(d)
                if groups:
                    lines.append("-" * len(head))
                    for g, gd in groups.items():
                        lines.append(row(f"{d} group {g}", gd))
                lines.append("-" * len(head))
                m = self.mean(d)
                for k in METRICS:
                    lines.append(row(f"{d} mean {k}", m, k))
                if any("within_3sigma" in m[r] for r in runs):
                    lines.append(row(f"{d} within own 3 sigma", m, "within_3sigma", ".3f"))
                lines.append("-" * len(head))
            out.append("\n".join(lines))
        out += [f"note: {n}" for n in self.notes]
        return "\n\n".join(out) if out else "no runs"

    def to_dict(self) -> dict:
        """Everything but the time series, JSON-ready: runs, trials, per data set the groups and
        means, the alignment, notes and parameters."""
        def conv(x):
            if isinstance(x, dict):
                return {k: conv(v) for k, v in x.items() if not str(k).startswith("series_")}
            if isinstance(x, (list, tuple)):
                return [conv(v) for v in x]
            if isinstance(x, (np.floating, np.integer, np.bool_)):
                return x.item()
            if isinstance(x, float) and not np.isfinite(x):
                return None
            return x
        return conv({"align": self.align, "runs": self.runs, "trials": self.trials,
                     "datasets": {d: {"groups": self.groups(d), "mean": self.mean(d)} for d in self.datasets},
                     "notes": self.notes, "params": self.params})

    def to_json(self, path) -> Path:
        """Write :meth:`to_dict` as JSON; returns the path."""
        path = Path(path)
        path.write_text(json.dumps(self.to_dict(), indent=1))
        return path

    def plot(self, outdir) -> list:
        """Figures into ``outdir`` (:func:`quatnav.evaluation.benchmark_plot.plot_benchmark`)."""
        from .benchmark_plot import plot_benchmark
        return plot_benchmark(self, outdir)


def _progress(total: int, enabled: bool):
    if not enabled:
        return None
    try:
        from tqdm import tqdm
        return tqdm(total=total, unit="run", file=sys.stderr, disable=None)  # no bar off a terminal
    except ImportError:  # pragma: no cover
        return None


def benchmark(sources, algorithms=DEFAULT_ALGORITHMS, modes=MODES, *, params: dict | None = None,
              align: str = "both", ref_frame: str | None = None, executor: Executor | None = None,
              keep_series: bool = False, cache_dir=None, progress: bool = False) -> BenchmarkResult:
    """Run estimators in every mode on every trial of ``sources`` and score them.

    Parameters
    ----------
    sources : str, Path, Trial or a sequence of them
        See the module text (``"broad"``, ``"sim"``, ``"sim:NAME[:SEED]"``, ``"sim-moving"``, folders,
        files, Trials).
    algorithms : sequence of str
        Keys of :data:`quatnav.evaluation.algorithms.ALGORITHMS`; an estimator whose package is
        missing is skipped with a note.
    modes : sequence of {"9D", "6D"}
        A trial without a magnetometer runs in 6D only.
    params : dict, optional
        ``{algorithm: {parameter: value}}`` for quatnav's filters (default: their defaults).
    align : {"both", "heading", "none"}
        The fitted rotations (see the module text).
    ref_frame : {"NED", "ENU"}, optional
        Earth frame of the references of trial files that do not say it.
    executor : concurrent.futures.Executor, optional
        Where the runs go (default: here, in turn).
    keep_series : bool
        Keep the error over time of each run (for :meth:`BenchmarkResult.plot`).
    cache_dir : str or Path, optional
        Keep the peers' estimates here (keyed by the trial's data, the peer, the mode and the
        peer's version): a second benchmark reads them instead of running the peers again.
    progress : bool
        A progress bar (tqdm) on stderr.

    Returns
    -------
    BenchmarkResult
    """
    if align not in M.ALIGNMENTS:
        raise ValueError(f"align: expected one of {', '.join(M.ALIGNMENTS)}, got {align!r}")
    modes = [str(m).upper() for m in modes]
    bad = [m for m in modes if m not in MODES]
    if bad or not modes:
        raise ValueError(f"modes: expected 9D and/or 6D, got {bad or modes}")
    notes, algs = [], []
    for a in algorithms:
        ok, note = available(a)
        (algs.append(a) if ok else notes.append(note))
    params = dict(params or {})
    unknown = sorted(set(params) - {a for a in ALGORITHMS if ALGORITHMS[a].quatnav})
    if unknown:
        raise ValueError(f"params: {unknown[0]!r} is not one of quatnav's filters "
                         f"({', '.join(a for a in ALGORITHMS if ALGORITHMS[a].quatnav)})")
    specs = resolve_sources(sources, ref_frame)
    if not specs:
        raise ValueError("sources: no trials")
    # check the trials read from files once here (a warning per inconsistent trial), not in every
    # run: the reference's vertical, and the IMU's units, saturation and clock
    from ..datasets.trials import check_trial
    for sp in specs:
        if not isinstance(sp, tuple) or sp[0] == "file":
            check_trial(load_source_trial(sp))
    jobs = [(sp, a, m, params.get(a), align, keep_series, None if cache_dir is None else str(cache_dir))
            for sp in specs for a in algs for m in modes]
    bar = _progress(len(jobs), progress)
    raw = []
    if executor is None:
        for j in jobs:
            raw.append((j, *_job(*j)))
            if bar:
                bar.update(1)
    else:
        futures = [(j, executor.submit(_job, *j)) for j in jobs]
        for j, fut in futures:
            raw.append((j, *fut.result()))
            if bar:
                bar.update(1)
    if bar:
        bar.close()
    trials: dict = {}
    runs: list = []
    skipped_9d = set()
    for j, meta, res in raw:
        key = _trial_key(meta)
        t = trials.setdefault(key, {**meta, "results": {}})
        if res is None:
            skipped_9d.add(key)
            continue
        label = run_label(j[1], j[2])
        t["results"][label] = res
        if label not in runs:
            runs.append(label)
    if skipped_9d:
        notes.append(f"9D: {len(skipped_9d)} trial(s) without a magnetometer run in 6D only "
                     f"({', '.join(sorted(skipped_9d)[:5])}{', ...' if len(skipped_9d) > 5 else ''})")
    order = [run_label(a, m) for m in MODES for a in algs]
    runs = [r for r in order if r in runs]
    return BenchmarkResult(runs, trials, align, notes, params)
