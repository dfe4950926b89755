"""Figures of :func:`quatnav.evaluation.benchmark.benchmark`: the summary per group and mode, and
the error over time of each trial (when the runs kept their series)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .algorithms import MODES

__all__ = ["plot_benchmark", "plot_summary", "plot_trial"]

_BROAD_CITE = "BROAD: Laidig et al. 2021, CC BY 4.0"


def _algs(result, mode):
    return [r.rsplit(" ", 1)[0] for r in result.runs if r.endswith(" " + mode)]


def plot_summary(result, path) -> Path:
    """Mean total RMSE per group and per data set, one panel per mode (9D, 6D), bars per
    estimator, on a log axis (the estimators differ by decades on some groups)."""
    from .._plotting import figure, legend_right, save
    modes = [m for m in MODES if _algs(result, m)]
    cols = []  # (label, dataset, group or None)
    for d in result.datasets:
        for g in result.groups(d):
            cols.append((f"{d}: {g}", d, g))
        cols.append((f"{d}: mean", d, None))
    fig = figure((max(8.0, 0.75 * len(cols)) + 2.5, 3.8 * len(modes)))
    axes = fig.subplots(len(modes), 1, squeeze=False)[:, 0]
    for ax, mode in zip(axes, modes):
        algs = _algs(result, mode)
        x = np.arange(len(cols))
        wid = 0.8 / max(1, len(algs))
        for i, a in enumerate(algs):
            run = f"{a} {mode}"
            vals = []
            for _, d, g in cols:
                figs = result.groups(d)[g] if g is not None else result.mean(d)
                vals.append(figs.get(run, {}).get("total", np.nan))
            ax.bar(x + i * wid - 0.4 + wid / 2, vals, wid, label=a, color=f"C{i % 10}")
        ax.set_yscale("log")
        ax.set_xticks(x)
        ax.set_xticklabels([c[0] for c in cols], rotation=30, ha="right", fontsize=8)
        ax.set_ylabel("mean total RMSE [deg]")
        ax.grid(axis="y", which="both", alpha=0.3)
        ax.set_title(f"{mode}: mean total error per group (alignment: {result.align})", fontsize=10)
        legend_right(ax, title=mode, title_fontsize=8)
    if any("broad" in d.lower() for d in result.datasets):
        fig.suptitle(_BROAD_CITE, fontsize=8, x=0.01, ha="left")
    return save(fig, Path(path))


def plot_trial(result, key: str, path) -> Path | None:
    """The total error over time (1 s moving RMS, log axis) of every run of one trial, a panel
    per mode; the samples left out of the score shaded. None when no run kept its series."""
    from matplotlib.patches import Patch

    from .._plotting import figure, legend_right, moving_rms, save
    t = result.trials[key]
    modes = [m for m in MODES if any(r.endswith(" " + m) and "series_total_deg" in t["results"].get(r, {})
                                     for r in result.runs)]
    if not modes:
        return None
    fig = figure((11.5, 3.4 * len(modes)))
    axes = fig.subplots(len(modes), 1, squeeze=False, sharex=True)[:, 0]
    for ax, mode in zip(axes, modes):
        lows, first = [], None
        for i, a in enumerate(_algs(result, mode)):
            r = t["results"].get(f"{a} {mode}")
            if not r or "series_total_deg" not in r:
                continue
            first = first or r
            tt = np.asarray(r["series_t"], float)
            n = max(1, int(round(1.0 / max(np.median(np.diff(tt)), 1e-9))))
            s = moving_rms(np.asarray(r["series_total_deg"], float), n)
            ax.plot(tt - tt[0], s, lw=0.7, color=f"C{i % 10}", label=f"{a} ({r['total']:.2f} deg)")
            fin = s[np.isfinite(s) & (s > 0)]
            if fin.size:
                lows.append(np.percentile(fin, 1.0))
        handles, labels = ax.get_legend_handles_labels()
        mov = np.asarray(first["series_movement"], bool)
        tt = np.asarray(first["series_t"], float) - first["series_t"][0]
        if not mov.all():
            ax.fill_between(tt, 0, 1, where=~mov, color="0.9", lw=0, step="mid", transform=ax.get_xaxis_transform(),
                            zorder=0)
            handles.append(Patch(color="0.9"))
            labels.append("not scored")
        ax.set_yscale("log")
        if lows:
            ax.set_ylim(bottom=max(1e-3, 0.5 * min(lows)))
        ax.set_xlim(0, tt[-1])
        ax.set_ylabel(f"{mode} total error [deg]\n(1 s moving RMS)")
        ax.grid(True, which="major", alpha=0.35)
        legend_right(ax, handles, labels, title="RMSE when scored", title_fontsize=8)
    axes[-1].set_xlabel("time [s]")
    cite = f" ({_BROAD_CITE})" if "broad" in t["dataset"].lower() else ""
    axes[0].set_title(f"{key}{cite}", fontsize=10)
    return save(fig, Path(path))


def plot_benchmark(result, outdir) -> list:
    """The summary figure and, for the runs that kept their series, one figure per trial.
    Returns the files written."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = [plot_summary(result, outdir / "summary.png")]
    for key in result.trials:
        p = plot_trial(result, key, outdir / f"error_{key.replace('/', '_').replace(':', '_')}.png")
        if p is not None:
            written.append(p)
    return written
