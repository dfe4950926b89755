"""Real-data attitude accuracy: quatnav's filters and the peer libraries on BROAD, side by side.

``quatnav eval broad DIR [--filters qekf,euler-ekf,marg] [--peers vqf,imufusion,madgwick]
[--json FILE] [--plot DIR]`` runs every selected algorithm on every trial of DIR in the same run
and prints, per trial, per group and on average, BROAD's total / heading / inclination RMSE over
the movement phases (:mod:`quatnav.evaluation.metrics`), and for quatnav's filters the fraction of samples
whose attitude error lies within the filter's own 3 sigma.

Every algorithm runs with its default parameters, one parameter set for all trials, online
(causal) except the offline ones: ``qekf-smoothed`` and ``euler-ekf-smoothed`` (quatnav's filter
with the Rauch-Tung-Striebel backward pass, ``run(..., smooth=True)``, docs/SMOOTHING.md) and
``vqf-offline`` (``vqf.offlineVQF``, VQF's acausal mode). How each peer is fed (checked on the data: each mapping gives the peer's errors within
a fraction of a degree of the reference, any other mapping gives tens of degrees):

* ``vqf``: ``vqf.VQF(Ts)`` 9D, gyro rad/s, acc m/s^2, mag as is; ``quat9D`` is ENU (earth
  frame y = magnetic north), converted with :func:`quatnav.core.quaternion.enu_to_ned`.
  ``vqf-offline``: ``vqf.offlineVQF(gyr, acc, mag, Ts)``, fed and converted the same way.
* ``imufusion``: ``imufusion.Ahrs`` with ``convention = CONVENTION_NED``, sample period set,
  gyro in deg/s, acc in g; its quaternion is then NED directly.
* ``madgwick``: ``ahrs.filters.Madgwick`` (default gain), gyro rad/s, acc m/s^2, mag; its earth
  frame is NWU (x north, z up): ``q_nb = [0, 1, 0, 0] * q_nwu_b``.

Peers are optional: a peer whose package is not installed is skipped with a note.

BROAD: D. Laidig, M. Caruso, A. Cereatti, T. Seel, Data 6(7), 2021, doi:10.3390/data6070072,
CC BY 4.0.
"""
from __future__ import annotations

import importlib
import os
import sys
from concurrent.futures import Executor
from pathlib import Path

import numpy as np

from . import metrics as M
from ..core import quaternion as Q

__all__ = ["FILTERS", "PEERS", "run_algorithm", "evaluate_trial", "evaluate", "format_table",
           "available", "add_parser", "plot_results"]

#: quatnav's own filters (name -> class name in :mod:`quatnav`); a name ending in ``-smoothed``
#: runs the filter with ``smooth=True`` (offline).
FILTERS = {"qekf": "QuaternionEKF", "euler-ekf": "EulerEKF", "marg": "MargFilter",
           "qekf-smoothed": "QuaternionEKF", "euler-ekf-smoothed": "EulerEKF"}
#: Peer libraries (name -> Python module that must be importable).
PEERS = {"vqf": "vqf", "imufusion": "imufusion", "madgwick": "ahrs", "vqf-offline": "vqf"}

_Q_NED_NWU = np.array([0.0, 1.0, 0.0, 0.0])  # rotates NWU vectors into NED (180 deg about x)


def available(name: str) -> tuple[bool, str]:
    """Whether algorithm ``name`` can run here, and a note when it cannot."""
    if name in FILTERS:
        import quatnav
        if hasattr(quatnav, FILTERS[name]):
            return True, ""
        return False, f"{name}: quatnav.{FILTERS[name]} is not available in this build; skipped"
    if name in PEERS:
        try:
            importlib.import_module(PEERS[name])
            return True, ""
        except ImportError:
            return False, f"{name}: package {PEERS[name]!r} is not installed; skipped"
    raise ValueError(f"unknown algorithm {name!r}; known: {', '.join([*FILTERS, *PEERS])}")


def run_algorithm(name: str, trial, params: dict | None = None):
    """Run one algorithm on one trial.

    Parameters
    ----------
    name : str
        A key of :data:`FILTERS` or :data:`PEERS`.
    trial : quatnav.datasets.broad.Trial
    params : dict, optional
        Keyword parameters of a quatnav filter (ignored for peers: they run with defaults).

    Returns
    -------
    quat : (N, 4) ndarray
        ``q_nb`` [w, x, y, z] in NED (x magnetic north).
    att_sigma : (N, 3) ndarray or None
        The filter's body-frame attitude one-sigma, rad (quatnav filters only).
    """
    gyr, acc, mag = trial.gyr, trial.acc, trial.mag
    if name in FILTERS:
        import warnings

        import quatnav
        cls = getattr(quatnav, FILTERS[name])
        f = cls(**(params or {}))
        with warnings.catch_warnings():
            # BROAD's body frame is its sensor's own, z up (the reference is in the same frame)
            warnings.simplefilter("ignore", quatnav.AxesWarning)
            res = f.run(gyr, acc, mag, dt=trial.dt, on_invalid="skip",
                        **({"smooth": True} if name.endswith("-smoothed") else {}))
        return np.asarray(res.quat, float), getattr(res, "att_sigma", None)
    if name in ("vqf", "vqf-offline"):
        import vqf
        g, a, m = np.ascontiguousarray(gyr), np.ascontiguousarray(acc), np.ascontiguousarray(mag)
        out = vqf.offlineVQF(g, a, m, trial.dt) if name == "vqf-offline" else vqf.VQF(trial.dt).updateBatch(g, a, m)
        return Q.enu_to_ned(out["quat9D"]), None
    if name == "imufusion":
        import imufusion
        ahrs = imufusion.Ahrs()
        s = imufusion.AhrsSettings()
        s.convention = imufusion.CONVENTION_NED
        s.sample_rate = int(round(trial.rate))
        ahrs.set_settings(s)
        ahrs.set_sample_period(trial.dt)
        gd, ag = np.degrees(gyr), acc / 9.80665
        q = np.empty((len(trial), 4))
        for k in range(len(trial)):
            ahrs.update(gd[k], ag[k], mag[k])
            q[k] = ahrs.get_quaternion()
        return q, None
    if name == "madgwick":
        import ahrs
        mw = ahrs.filters.Madgwick(gyr=gyr, acc=acc, mag=mag, frequency=trial.rate)
        return Q.mul(_Q_NED_NWU, np.asarray(mw.Q, float)), None
    raise ValueError(f"unknown algorithm {name!r}")


def evaluate_trial(trial, name: str, params: dict | None = None, keep_series: bool = False) -> dict:
    """BROAD figures of one algorithm on one trial (degrees), plus 3-sigma consistency if any."""
    quat, sig = run_algorithm(name, trial, params)
    out = M.attitude_rmse_deg(quat, trial.quat_ref, trial.movement)
    if sig is not None:
        out["within_3sigma"] = M.sigma_consistency(quat, trial.quat_ref, sig, trial.movement)
    if keep_series:
        e = M.error_quat(quat, trial.quat_ref)
        out["series_total_deg"] = np.degrees(M.total_error(e))
        out["series_movement"] = np.asarray(trial.movement, bool)
        out["series_rate_hz"] = float(trial.rate)
    return out


def _job(path: str, name: str, params, keep_series: bool):
    from ..datasets import broad
    trial = broad.load_trial(path)
    return trial.name, name, evaluate_trial(trial, name, params, keep_series)


def _progress(total: int, enabled: bool):
    if not enabled:
        return None
    try:
        from tqdm import tqdm
        # disable=None: no bar when stderr is not a terminal (logs, CI, pipes)
        return tqdm(total=total, unit="run", file=sys.stderr, disable=None)
    except ImportError:  # pragma: no cover
        return None


def evaluate(directory=None, filters=("qekf",), peers=("vqf", "imufusion", "madgwick"),
             params: dict | None = None, executor: Executor | None = None, progress: bool = False,
             keep_series: bool = False) -> dict:
    """Run filters and peers on every trial of a BROAD folder.

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
    directory = Path(directory) if directory is not None else broad.default_dir()
    files = broad.list_trials(directory)
    if not files:
        raise FileNotFoundError(f"directory: no BROAD trials (.mat/.hdf5) in {directory}")
    info = broad.load_trial_info(directory)
    notes, algs = [], []
    for name in [*filters, *peers]:
        ok, note = available(name)
        if ok:
            algs.append(name)
        else:
            notes.append(note)
    params = params or {}
    jobs = [(str(f), a, params.get(a), keep_series) for f in files for a in algs]
    bar = _progress(len(jobs), progress)
    raw = []
    if executor is None:
        for j in jobs:
            raw.append(_job(*j))
            if bar:
                bar.update(1)
    else:
        futures = [executor.submit(_job, *j) for j in jobs]
        for fut in futures:
            raw.append(fut.result())
            if bar:
                bar.update(1)
    if bar:
        bar.close()
    trials: dict = {}
    for f in files:
        groups = info.get("trials", {}).get(f.stem, {}).get("groups", [])
        trials[f.stem] = {"groups": list(groups), "results": {}}
    for tname, a, res in raw:
        trials[tname]["results"][a] = res
    keys = ("total", "heading", "inclination", "within_3sigma")

    def mean_over(names, a):
        out = {}
        for k in keys:
            vals = [trials[t]["results"][a][k] for t in names if k in trials[t]["results"][a]]
            if vals:
                out[k] = float(np.mean(vals))
        return out

    groups_present = []
    for g in info.get("groups", []):
        members = [t for t in trials if g["name"] in trials[t]["groups"]]
        if members and g["name"] != "all_trials":
            groups_present.append((g["name"], members))
    return {
        "algorithms": algs,
        "trials": trials,
        "groups": {g: {"trials": m, **{a: mean_over(m, a) for a in algs}} for g, m in groups_present},
        "mean": {a: mean_over(list(trials), a) for a in algs},
        "notes": notes,
        "directory": str(directory),
    }


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


def _names(option: str, value: str, known: dict) -> list[str]:
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


def _cmd_broad(args) -> int:
    from .._command import UsageError, write_json
    filters = _names("--filters", args.filters, FILTERS)
    peers = _names("--peers", args.peers, PEERS)
    if not filters and not peers:
        raise UsageError("--filters and --peers select nothing to run; give at least one filter or peer")
    if args.jobs < 1:
        raise UsageError(f"--jobs: expected a positive integer, got {args.jobs}")
    directory = _broad_dir(args.dir)
    executor = None
    if args.jobs > 1:
        from concurrent.futures import ProcessPoolExecutor
        executor = ProcessPoolExecutor(max_workers=args.jobs)
    try:
        res = evaluate(directory, filters, peers, executor=executor, progress=not args.quiet,
                       keep_series=bool(args.plot))
    finally:
        if executor is not None:
            executor.shutdown()
    if not res["algorithms"]:
        raise UsageError("none of the selected algorithms can run here (" + "; ".join(res["notes"]) + ")")
    print(format_table(res))
    write_json(_jsonable(res), args)
    if args.plot:
        for p in plot_results(res, args.plot):
            print(f"wrote {p}")
    print("BROAD: Laidig, Caruso, Cereatti, Seel, Data 6(7), 2021, doi:10.3390/data6070072 (CC BY 4.0)")
    return 0


def add_parser(sub) -> None:
    """Register ``quatnav eval broad ...`` on the CLI's subparsers."""
    p = sub.add_parser("eval", help="evaluate filters on real datasets (see 'quatnav eval broad -h')")
    evsub = p.add_subparsers(dest="dataset", metavar="DATASET")
    b = evsub.add_parser("broad", help="BROAD benchmark: filters and peers side by side",
                         description="BROAD benchmark (real IMU data with optical truth): quatnav's filters and "
                                     "the peer libraries on every trial of DIR, BROAD's RMSE over the movement "
                                     "phases per trial, per group and on average.",
                         epilog="DIR defaults to $QUATNAV_DATA/broad (QUATNAV_DATA: the folder of the shared "
                                "datasets; default ../shared/data next to the source tree). Needs scipy to read "
                                "the .mat files: pip install 'quatnav[eval]'; peers: pip install 'quatnav[peers]' "
                                "(a missing peer is skipped with a note).")
    b.add_argument("dir", nargs="?", default=None, metavar="DIR",
                   help="folder of the BROAD trial files (default: $QUATNAV_DATA/broad)")
    b.add_argument("--filters", default="qekf",
                   help="comma list of %s, or none (default: qekf)" % ",".join(FILTERS))
    b.add_argument("--peers", default="vqf,imufusion,madgwick",
                   help="comma list of %s, or none (default: vqf,imufusion,madgwick; missing packages are "
                        "skipped)" % ",".join(PEERS))
    b.add_argument("--json", default=None, metavar="FILE", help="write the results to this JSON file ('-': stdout)")
    b.add_argument("--plot", default=None, metavar="DIR", help="write plots into this folder")
    b.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    b.add_argument("--quiet", action="store_true", help="no progress bar")
    b.set_defaults(func=_cmd_broad)
    p.set_defaults(func=None)
