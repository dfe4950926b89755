"""``quatnav eval``: the attitude benchmark from the command line, and the BROAD-only API it grew from.

``quatnav eval [SOURCE ...] [--filters ...] [--peers ...] [--modes 9d,6d] [--align both|heading|none]
[--json FILE] [--plot DIR] [--jobs N]`` runs :func:`quatnav.evaluation.benchmark.benchmark` once on
the sources (``broad``, ``sim``, ``sim:NAME[:SEED]``, a folder of trial files, a trial file; see
:mod:`quatnav.datasets.trials` for the format of a user's own reference data) and prints its tables.
``quatnav eval broad DIR`` reads the BROAD trials of DIR.

The functions below keep the BROAD-only interface of earlier versions (9D, BROAD's own figures
without alignment, results keyed by estimator): :func:`evaluate`, :func:`evaluate_trial`,
:func:`format_table`, :func:`plot_results`. Estimators and how the peers are fed:
:mod:`quatnav.evaluation.algorithms`.

BROAD: D. Laidig, M. Caruso, A. Cereatti, T. Seel, Data 6(7), 2021, doi:10.3390/data6070072,
CC BY 4.0.
"""
from __future__ import annotations

import os
from concurrent.futures import Executor
from pathlib import Path

import numpy as np

from . import metrics as M
from .algorithms import ALGORITHMS, _CLASSES, available, run_algorithm as _run

__all__ = ["FILTERS", "PEERS", "run_algorithm", "evaluate_trial", "evaluate", "format_table",
           "available", "add_parser", "plot_results"]

#: quatnav's own filters (name -> class name in :mod:`quatnav`); a name ending in ``-smoothed``
#: runs the filter with ``smooth=True`` (offline).
FILTERS = dict(_CLASSES)
#: Peer libraries (name -> Python module that must be importable).
PEERS = {a.name: a.module for a in ALGORITHMS.values() if not a.quatnav}


def run_algorithm(name: str, trial, params: dict | None = None):
    """Run one estimator on one trial in 9D (:func:`quatnav.evaluation.algorithms.run_algorithm`).

    Returns
    -------
    quat : (N, 4) ndarray
        ``q_nb`` [w, x, y, z] in NED (x magnetic north).
    att_sigma : (N, 3) ndarray or None
        The filter's body-frame attitude one-sigma, rad (quatnav filters only).
    """
    return _run(name, trial, "9D", params)


def evaluate_trial(trial, name: str, params: dict | None = None, keep_series: bool = False) -> dict:
    """BROAD figures of one estimator on one trial in 9D (degrees, no alignment), plus 3-sigma
    consistency if any (:func:`quatnav.evaluation.benchmark.evaluate_run` with ``align="none"``)."""
    from .benchmark import evaluate_run
    out = evaluate_run(trial, name, "9D", params, align="none", keep_series=keep_series)
    for k in ("align_heading_deg", "align_body_deg", "series_heading_deg", "series_t"):
        out.pop(k, None)
    if keep_series:
        out["series_rate_hz"] = float(trial.rate)
    return out


def evaluate(directory=None, filters=("qekf",), peers=("vqf", "imufusion", "madgwick"),
             params: dict | None = None, executor: Executor | None = None, progress: bool = False,
             keep_series: bool = False) -> dict:
    """Run filters and peers in 9D on every trial of a BROAD folder (BROAD's figures, no
    alignment; :func:`quatnav.evaluation.benchmark.benchmark` with ``modes=("9D",)``,
    ``align="none"``).

    Parameters
    ----------
    directory : str or Path, optional
        Folder of BROAD trial files (default: the shared data folder's ``broad``).
    filters, peers : sequence of str
        Keys of :data:`FILTERS` / :data:`PEERS`. Unavailable ones are skipped with a note.
    params : dict, optional
        ``{filter name: {parameter: value}}`` overriding quatnav filters' defaults.
    executor : concurrent.futures.Executor, optional
        Runs the (trial, algorithm) jobs; in-process and sequential if None.
    progress : bool
        Show a progress bar (tqdm) on stderr.
    keep_series : bool
        Keep each run's total error over time (degrees) for plots.

    Returns
    -------
    dict
        ``{"algorithms": [...], "trials": {name: {"groups": [...], "results": {alg: figures}}},
        "groups": {group: {alg: {"total": ...}}}, "mean": {alg: figures}, "notes": [...]}``.
    """
    from ..datasets import broad
    from .benchmark import benchmark
    directory = Path(directory) if directory is not None else broad.default_dir()
    if not broad.list_trials(directory):
        raise FileNotFoundError(f"directory: no BROAD trials (.mat/.hdf5) in {directory}")
    notes, algs = [], []
    for name in [*filters, *peers]:
        if name not in FILTERS and name not in PEERS:
            raise ValueError(f"unknown algorithm {name!r}; known: {', '.join([*FILTERS, *PEERS])}")
        ok, note = _available_legacy(name)
        (algs.append(name) if ok else notes.append(note))
    res = benchmark([str(directory)], algs, ("9D",), params=params, align="none", executor=executor,
                    keep_series=keep_series, progress=progress)
    trials = {}
    for t in res.trials.values():
        results = {r.rsplit(" ", 1)[0]: v for r, v in t["results"].items()}
        for v in results.values():
            if keep_series:
                v["series_rate_hz"] = t["rate_hz"]
        trials[t["name"]] = {"groups": list(t["groups"]), "results": results}
    ds = res.datasets[0]
    groups = {g: {"trials": [res.trials[k]["name"] for k in d["trials"]],
                  **{r.rsplit(" ", 1)[0]: v for r, v in d.items() if r != "trials"}}
              for g, d in res.groups(ds).items()}
    return {"algorithms": [r.rsplit(" ", 1)[0] for r in res.runs], "trials": trials, "groups": groups,
            "mean": {r.rsplit(" ", 1)[0]: v for r, v in res.mean(ds).items()}, "notes": notes + res.notes,
            "directory": str(directory)}


def _available_legacy(name):
    """:func:`available`; a name added to :data:`FILTERS` / :data:`PEERS` that the benchmark does
    not know is skipped with a note."""
    if name in ALGORITHMS:
        return available(name)
    return False, f"{name}: not an estimator of quatnav.evaluation.algorithms; skipped"


def format_table(results: dict, metric: str = "total") -> str:
    """Plain-text tables: per trial, per group and the mean (``metric`` RMSE, degrees), and
    for the mean also heading / inclination and the 3-sigma consistency of quatnav's filters."""
    algs = results["algorithms"]
    w = max(12, *(len(a) + 1 for a in algs))
    head = f"{'trial':34s}" + "".join(f"{a:>{w}s}" for a in algs)
    lines = [f"{metric} RMSE over the movement phases, deg", head, "-" * len(head)]
    for t, d in results["trials"].items():
        lines.append(f"{t[:34]:34s}" + "".join(f"{d['results'][a][metric]:{w}.2f}" for a in algs))
    lines.append("-" * len(head))
    for g, d in results["groups"].items():
        lines.append(f"{'group ' + g:34s}" + "".join(f"{d[a].get(metric, np.nan):{w}.2f}" for a in algs))
    lines.append("-" * len(head))
    for k in ("total", "heading", "inclination"):
        lines.append(f"{'mean ' + k:34s}" + "".join(f"{results['mean'][a][k]:{w}.2f}" for a in algs))
    cons = [results["mean"][a].get("within_3sigma") for a in algs]
    if any(c is not None for c in cons):
        lines.append(f"{'within own 3 sigma (fraction)':34s}" +
                     "".join(f"{c:{w}.3f}" if c is not None else f"{'-':>{w}s}" for c in cons))
    for n in results.get("notes", []):
        lines.append("note: " + n)
    return "\n".join(lines)


def _jsonable(results: dict) -> dict:
    def conv(x):
        if isinstance(x, dict):
            return {k: conv(v) for k, v in x.items() if not k.startswith("series_")}
        if isinstance(x, (list, tuple)):
            return [conv(v) for v in x]
        if isinstance(x, (np.floating, np.integer)):
            return x.item()
        return x
    return conv(results)


def plot_results(results: dict, outdir) -> list[Path]:
    """Write plots: total error over time per trial (needs ``keep_series``; RMS over 1 s windows
    on a log axis, the rest phases that the RMSE leaves out shaded) and a bar chart of the total RMSE per group.
    Returns the files written."""
    from matplotlib.patches import Patch

    from .._plotting import figure, legend_right, moving_rms, save
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    algs = results["algorithms"]
    cite = "BROAD (Laidig et al. 2021, CC BY 4.0)"
    for t, d in results["trials"].items():
        res = {a: d["results"][a] for a in algs if d["results"][a].get("series_total_deg") is not None}
        if not res:
            continue
        fig = figure((11.5, 4.2))
        ax = fig.add_subplot()
        first = next(iter(res.values()))
        rate = first.get("series_rate_hz", 285.714)
        lows = []
        for k, (a, r) in enumerate(res.items()):
            # RMS over 1 s windows: the instantaneous error dips towards zero whenever it changes
            # sign in some axis, which a log axis would draw as a comb of spikes.
            s = moving_rms(np.asarray(r["series_total_deg"], float), max(1, int(round(rate))))
            tt = np.arange(len(s)) / rate
            ax.plot(tt, s, lw=0.6, color=f"C{k}", label=f"{a} ({r['total']:.2f} deg)")
            fin = s[np.isfinite(s) & (s > 0)]
            if fin.size:
                lows.append(np.percentile(fin, 1.0))
        mov = first.get("series_movement")
        handles, labels = ax.get_legend_handles_labels()
        if mov is not None and not np.all(mov):
            ax.fill_between(np.arange(len(mov)) / rate, 0, 1, where=~np.asarray(mov, bool), color="0.9",
                            lw=0, step="mid", transform=ax.get_xaxis_transform(), zorder=0)
            handles.append(Patch(color="0.9"))
            labels.append("rest: not in the RMSE")
        ax.set_yscale("log")
        if lows:
            ax.set_ylim(bottom=max(1e-3, 0.5 * min(lows)))
        ax.set_xlim(0, len(first["series_total_deg"]) / rate)
        ax.set_xlabel(f"time [s] ({rate:.1f} Hz)")
        ax.set_ylabel("total attitude error [deg]\n(1 s moving RMS)")
        ax.grid(True, which="major", alpha=0.35)
        ax.grid(True, which="minor", alpha=0.12)
        ax.set_title(f"{cite}: trial {t}", fontsize=10)
        legend_right(ax, handles, labels, title="total RMSE in motion", title_fontsize=8)
        p = save(fig, outdir / f"error_{t}.png")
        written.append(p)
    names = list(results["groups"]) + ["mean"]
    vals = {a: [results["groups"][g][a].get("total", np.nan) for g in results["groups"]] +
            [results["mean"][a]["total"]] for a in algs}
    fig = figure((max(8, len(names) * 0.9) + 2.0, 4.5))
    ax = fig.add_subplot()
    x = np.arange(len(names))
    wid = 0.8 / max(1, len(algs))
    for i, a in enumerate(algs):
        ax.bar(x + i * wid - 0.4 + wid / 2, vals[a], wid, label=a)
    ax.set_xticks(x)
    ax.set_xticklabels(names, rotation=30, ha="right")
    ax.set_ylabel("mean total RMSE [deg]")
    ax.set_title(f"{cite}: mean total RMSE per group of trials", fontsize=10)
    legend_right(ax)
    ax.grid(axis="y", alpha=0.3)
    p = save(fig, outdir / "groups_total_rmse.png")
    written.append(p)
    return written


def _split(s: str) -> list[str]:
    return [x.strip() for x in s.split(",") if x.strip()] if s else []


def _names(option: str, value: str, known) -> list[str]:
    """Names of a comma list option; ``none`` (or an empty list) selects nothing."""
    names = _split(value)
    if [n.lower() for n in names] == ["none"]:
        return []
    for n in names:
        if n not in known:
            from .._command import UsageError
            raise UsageError(f"{option}: unknown name {n!r}; known: {', '.join(known)}, or none")
    return names


def _broad_dir(arg) -> Path:
    """The BROAD folder of ``quatnav eval broad [DIR]``, or a UsageError saying what to give."""
    from .._command import UsageError
    from ..datasets import broad
    if arg is not None:
        d = Path(arg)
        if not d.is_dir():
            raise UsageError(f"DIR {d}: {'not a directory' if d.exists() else 'no such directory'}; "
                             "give the folder of the BROAD trial files (.mat/.hdf5)")
        if not broad.list_trials(d):
            raise UsageError(f"DIR {d}: no BROAD trials (.mat/.hdf5) in it; give the folder of the BROAD trial files")
        return d
    d = broad.default_dir()
    if not d.is_dir() or not broad.list_trials(d):
        src = "$QUATNAV_DATA/broad" if os.environ.get("QUATNAV_DATA") else "the default data folder"
        raise UsageError(f"no DIR given and no BROAD trials in {d} ({src}): give DIR, the folder of the "
                         "BROAD trial files, or set QUATNAV_DATA to the folder that holds broad/")
    return d


def _is_sim(word: str) -> bool:
    from ..datasets.simulated import SIM_PREFIXES
    return word.split(":", 1)[0] in SIM_PREFIXES


def _sources(words) -> list:
    """The sources of ``quatnav eval``: ``broad`` (alone: the default BROAD folder; followed by a
    folder: that folder), ``sim``, ``sim:NAME[:SEED]``, ``sim-moving[:NAME[:SEED]]``, folders and
    files."""
    from .._command import UsageError
    words = list(words)
    if not words:
        raise UsageError("give a source (broad, sim, sim:NAME[:SEED], sim-moving, a folder of trial files or a trial file; "
                         "see 'quatnav eval -h')")
    out = []
    i = 0
    while i < len(words):
        w = words[i]
        if w == "broad":
            nxt = words[i + 1] if i + 1 < len(words) else None
            if nxt is not None and not _is_sim(nxt) and nxt != "broad":
                out.append(str(_broad_dir(nxt)))
                i += 2
                continue
            out.append(str(_broad_dir(None)))
        elif _is_sim(w):
            out.append(w)
        else:
            p = Path(w)
            if not p.exists():
                raise UsageError(f"{w}: no such file or folder (a source is broad, sim, sim:NAME[:SEED], sim-moving, a folder "
                                 "of trial files or a trial file)")
            out.append(w)
        i += 1
    return out


def _cmd_eval(args) -> int:
    from .._command import UsageError, write_json
    from .algorithms import MODES
    from .benchmark import benchmark
    filters = _names("--filters", args.filters, FILTERS)
    peers = _names("--peers", args.peers, PEERS)
    if not filters and not peers:
        raise UsageError("--filters and --peers select nothing to run; give at least one filter or peer")
    if args.jobs < 1:
        raise UsageError(f"--jobs: expected a positive integer, got {args.jobs}")
    modes = [m.upper() for m in _split(args.modes)]
    if not modes or any(m not in MODES for m in modes):
        raise UsageError(f"--modes {args.modes}: expected a comma list of 9d, 6d")
    sources = _sources(args.source)
    executor = None
    if args.jobs > 1:
        from concurrent.futures import ProcessPoolExecutor
        executor = ProcessPoolExecutor(max_workers=args.jobs)
    try:
        res = benchmark(sources, [*filters, *peers], modes, align=args.align, ref_frame=args.ref_frame,
                        executor=executor, keep_series=bool(args.plot), cache_dir=args.cache, progress=not args.quiet)
    finally:
        if executor is not None:
            executor.shutdown()
    if not res.runs:
        raise UsageError("none of the selected estimators can run here (" + "; ".join(res.notes) + ")")
    print(res.table())
    write_json(res.to_dict(), args)
    if args.plot:
        for p in res.plot(args.plot):
            print(f"wrote {p}")
    if any("broad" in d.lower() for d in res.datasets):
        print("BROAD: Laidig, Caruso, Cereatti, Seel, Data 6(7), 2021, doi:10.3390/data6070072 (CC BY 4.0)")
    return 0


EVAL_EPILOG = """\
sources:
  broad            the BROAD trials in $QUATNAV_DATA/broad ('broad DIR': the BROAD trials in DIR)
  sim              the simulated fast-motion set (quatnav.sim.FAST_MOTION: pendulum, limb swing,
                   running, shaking, gyro saturation, scale factors and misalignment, vibration)
  sim:NAME[:SEED]  one simulated scenario (quatnav simulate --list)
  sim-moving       the same set started in the motion: the first rest cut off, every sample
                   scored, the convergence included (also sim-moving:NAME[:SEED])
  FOLDER, FILE     your own trials: CSV (columns time gyro_x gyro_y gyro_z accel_x accel_y accel_z
                   [mag_x mag_y mag_z] q_w q_x q_y q_z [movement], '# ref_frame: ENU' or NED),
                   HDF5 or .mat (the same names: time or rate, gyro, accel, mag, quat, movement,
                   ref_frame); SI units, the reference quat sensor (or marker) to earth; see
                   quatnav.datasets.trials

Every estimator runs with its defaults, one parameter set for all trials. Before scoring, each
estimate gets the best constant rotations on each side (--align both: a heading offset between
the earth frames and a rotation between the sensor's and the reference's body frames; the same
fit for every estimator); --align none gives BROAD's own figures. Errors: total, heading and
inclination RMSE over the scored samples (the movement mask), per trial, per group and per data set.

examples:
  quatnav eval broad sim --jobs 2 --json bench.json --plot bench/
  quatnav eval my_trials/ --ref-frame ENU --modes 6d --peers vqf
  quatnav eval broad --align none --modes 9d --filters qekf --peers vqf

QUATNAV_DATA: the folder of the shared datasets (default ../shared/data next to the source tree).
Reading .mat needs scipy, HDF5 h5py: pip install 'quatnav[eval]'; peers: pip install
'quatnav[peers]' (a missing peer is skipped with a note)."""


def add_parser(sub) -> None:
    """Register ``quatnav eval SOURCE ...`` on the CLI's subparsers."""
    import argparse
    from .benchmark import DEFAULT_ALGORITHMS
    p = sub.add_parser("eval", help="attitude benchmark: filters and peers on BROAD, simulated fast motion or "
                                    "your own reference data",
                       description="Run quatnav's attitude filters and the peer libraries in 9D and 6D on every "
                                   "trial of the sources and score them against the reference: per trial, per "
                                   "group and per data set.",
                       epilog=EVAL_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("source", nargs="*", metavar="SOURCE", help="broad, sim, sim:NAME[:SEED], sim-moving, a folder or a file")
    default_filters = ",".join(a for a in DEFAULT_ALGORITHMS if a in FILTERS)
    default_peers = ",".join(a for a in DEFAULT_ALGORITHMS if a in PEERS)
    p.add_argument("--filters", default=default_filters,
                   help=f"comma list of {','.join(FILTERS)}, or none (default: {default_filters})")
    p.add_argument("--peers", default=default_peers,
                   help=f"comma list of {','.join(PEERS)}, or none (default: {default_peers}; missing "
                        "packages are skipped)")
    p.add_argument("--modes", default="9d,6d", help="comma list of 9d (with the magnetometer), 6d (default 9d,6d)")
    p.add_argument("--align", choices=M.ALIGNMENTS, default="both",
                   help="constant rotations fitted per estimate before scoring (default both)")
    p.add_argument("--ref-frame", choices=("NED", "ENU"), type=str.upper, default=None,
                   help="earth frame of the references of trial files that do not say it")
    p.add_argument("--json", default=None, metavar="FILE", help="write the results to this JSON file ('-': stdout)")
    p.add_argument("--plot", default=None, metavar="DIR", help="write figures into this folder")
    p.add_argument("--cache", default=None, metavar="DIR",
                   help="keep the peers' estimates in this folder and reuse them in later runs")
    p.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=_cmd_eval)
