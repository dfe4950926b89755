"""The figures of the pipelines: a GNSS/INS run (:func:`plot_nav`), an attitude run
(:func:`plot_attitude`), the differences between two tracks (:func:`plot_differences`)."""
from __future__ import annotations

import numpy as np

__all__ = ["plot_nav", "plot_attitude", "plot_differences"]


def _angles(ax, t, deg, sigma3=None, labels=("roll", "pitch", "yaw")):
    """Angles (deg, within +-180) on ``ax`` without the vertical stroke of a wrap through
    +-180 deg (the line and its band are broken there), each with its band of ``sigma3`` (deg)
    clipped to +-180 (a heading the filter does not know yet spans the circle, not +-1000 deg)."""
    for i, c in enumerate(labels):
        y = np.asarray(deg[:, i], float)
        jumps = np.flatnonzero(np.abs(np.diff(y)) > 180.0) + 1
        tt, yy = np.insert(np.asarray(t, float), jumps, np.nan), np.insert(y, jumps, np.nan)
        ax.plot(tt, yy, label=c, color=f"C{i}", lw=0.9)
        if sigma3 is not None:
            s3 = np.insert(np.minimum(np.asarray(sigma3[:, i], float), 180.0), jumps, np.nan)
            ax.fill_between(tt, np.maximum(yy - s3, -180.0), np.minimum(yy + s3, 180.0), color=f"C{i}",
                            alpha=0.2, lw=0)
    # the axis holds the angles (a band as wide as the circle would squash them), within +-190 deg
    lo, hi = (np.nanmin(deg), np.nanmax(deg)) if np.isfinite(deg).any() else (-180.0, 180.0)
    pad = max(1.0, 0.1 * (hi - lo))
    ax.set_ylim(max(-190.0, lo - pad), min(190.0, hi + pad))
    if hi - lo > 180.0:
        ax.set_yticks(np.arange(-180, 181, 90))


def plot_nav(path, r, nav, gnss, log=None):
    """Track (north/east m about the first GNSS fix) with the fixes; roll, pitch and yaw with
    their three-sigma bands (clipped to +-180 deg, the lines broken where the yaw wraps); the
    gyro bias per axis; the difference to the log's own attitude estimate when it has one (else
    the accelerometer bias per axis); the horizontal and vertical position one-sigma; and the
    innovations of every aid over time as their NIS (its chi-square gate is the filter's),
    samples not applied marked. Times as seconds since the first navigating sample when they
    are absolute (a GPS or Unix clock)."""
    from .._plotting import figure, save, time_axis
    from ..core import earth as E
    lat0, lon0, h0 = np.radians(gnss["lat"][0]), np.radians(gnss["lon"][0]), gnss["h"][0]
    p = E.geodetic_to_ned(r.lat[nav], r.lon[nav], r.h[nav], lat0, lon0, h0)
    g = E.geodetic_to_ned(np.radians(gnss["lat"]), np.radians(gnss["lon"]), gnss["h"], lat0, lon0, h0)
    ref = log.reference if log is not None and log.reference is not None and log.reference.quat is not None else None
    fig = figure((12.0, 10.0))
    grid = fig.add_gridspec(3, 2)
    track = fig.add_subplot(grid[0, 0])
    att = fig.add_subplot(grid[0, 1])
    ax = [att] + [fig.add_subplot(grid[i, j], sharex=att) for i, j in ((1, 0), (1, 1), (2, 0), (2, 1))]
    track.plot(g[:, 1], g[:, 0], ".", ms=3, color="C1", label="GNSS fixes")
    track.plot(p[:, 1], p[:, 0], lw=0.9, color="C0", label="INS")
    track.set_xlabel("east [m]")
    track.set_ylabel("north [m]")
    track.axis("equal")
    track.legend(fontsize=8)
    t_abs = r.t[nav]
    t0 = float(t_abs[0]) if len(t_abs) else 0.0
    t, xlabel = time_axis(t_abs, t0)
    e = np.degrees(r.euler[nav])
    s3 = None
    if r.sigma is not None and r.sigma.shape[1] >= 9:  # tilt errors about north and east, heading about down
        psi = np.degrees(r.sigma[nav][:, 6:9])
        tilt = np.maximum(psi[:, 0], psi[:, 1])  # roll and pitch: the larger tilt sigma (heading-independent)
        s3 = 3.0 * np.column_stack([tilt, tilt, psi[:, 2]])
    _angles(att, t, e, s3)
    att.set_ylabel("attitude [deg] (band: 3 sigma)")
    att.legend(fontsize=8, loc="upper right")
    ax[1].plot(t, np.degrees(r.bias[nav]) * 3600, lw=0.9)
    ax[1].set_ylabel("gyro bias [deg/h]")
    ax[1].legend(["x", "y", "z"], fontsize=8, loc="upper right")
    if ref is not None:
        from ..evaluation.track_difference import attitude_difference
        d = attitude_difference(t_abs, r.quat[nav], ref.t, ref.quat)
        ax[2].plot(time_axis(d["t"], t0)[0], d["inclination_deg"], label="inclination", lw=0.9)
        ax[2].plot(time_axis(d["t"], t0)[0], d["heading_deg"], label="heading", lw=0.9)
        ax[2].set_ylabel(f"difference to {ref.name} [deg]")
        ax[2].legend(fontsize=8)
    else:
        ax[2].plot(t, r.acc_bias[nav], lw=0.9)
        ax[2].set_ylabel("accelerometer bias [m/s^2]")
        ax[2].legend(["x", "y", "z"], fontsize=8, loc="upper right")
    if r.sigma is not None:
        ax[3].plot(t, np.hypot(r.sigma[nav][:, 0], r.sigma[nav][:, 1]), label="horizontal", lw=0.9)
        ax[3].plot(t, r.sigma[nav][:, 2], label="vertical", lw=0.9)
        ax[3].set_yscale("log")
        ax[3].set_ylabel("position one-sigma, m")
        ax[3].legend(fontsize=8)
    nis = ax[4]
    for i, (name, a) in enumerate(sorted((getattr(r, "aids", None) or {}).items())):
        if a.nis is None or not len(a.t):
            continue
        ok = np.isfinite(a.nis)
        if not ok.any():
            continue
        ta = time_axis(a.t, t0)[0]
        nis.plot(ta[ok], a.nis[ok], ".", ms=2, color=f"C{i % 10}", label=name)
        bad = ok & (np.asarray(a.status) != 0)
        if bad.any():
            nis.plot(ta[bad], a.nis[bad], "x", ms=4, color=f"C{i % 10}")
    if nis.lines:
        nis.set_yscale("log")
        nis.legend(fontsize=8, ncol=2, title="x: not applied", title_fontsize=8)
    nis.set_ylabel("innovation NIS")
    for a in ax:
        a.grid(True, alpha=0.3)
        a.set_xlabel(xlabel)
    if len(t):
        att.set_xlim(t[0], t[-1])
    save(fig, path, dpi=100)


def plot_attitude(res, log, path):
    """Roll, pitch and yaw (the lines broken where an angle wraps through +-180 deg; the log's
    own estimate, dotted, when it has one), the gyro bias per axis, and the inclination and
    heading difference to that estimate. Times as seconds since the first sample when they are
    absolute."""
    from .._plotting import figure, save, time_axis
    ref = log.reference if log is not None and log.reference is not None and log.reference.quat is not None else None
    n = 3 if ref is not None else 2
    fig = figure((10.0, 2.8 * n))
    ax = [fig.add_subplot(n, 1, 1)]
    ax += [fig.add_subplot(n, 1, i + 1, sharex=ax[0]) for i in range(1, n)]
    t0 = float(res.t[0]) if len(res.t) else 0.0
    t, xlabel = time_axis(res.t, t0)
    _angles(ax[0], t, np.degrees(res.euler))
    if ref is not None:
        from ..core import quaternion as Q
        er = np.degrees(Q.to_euler(ref.quat))
        tr = time_axis(ref.t, t0)[0]
        for i in range(3):
            jumps = np.flatnonzero(np.abs(np.diff(er[:, i])) > 180.0) + 1
            ax[0].plot(np.insert(tr, jumps, np.nan), np.insert(er[:, i], jumps, np.nan), "k:", lw=0.8,
                       label=ref.name if i == 0 else None)
    ax[0].set_ylabel("attitude [deg]")
    ax[0].legend(fontsize=8, loc="upper right")
    ax[1].plot(t, np.degrees(res.bias), lw=0.9)
    ax[1].set_ylabel("gyro bias [deg/s]")
    ax[1].legend(["x", "y", "z"], fontsize=8, loc="upper right")
    if ref is not None:
        from ..evaluation.track_difference import attitude_difference
        d = attitude_difference(res.t, res.quat, ref.t, ref.quat)
        td = time_axis(d["t"], t0)[0]
        ax[2].plot(td, d["inclination_deg"], label="inclination", lw=0.9)
        ax[2].plot(td, d["heading_deg"], label="heading", lw=0.9)
        ax[2].set_ylabel(f"difference to\n{ref.name} [deg]")
        ax[2].legend(fontsize=8, loc="upper right")
    for a in ax:
        a.grid(True, alpha=0.3)
    ax[-1].set_xlabel(xlabel)
    if len(t):
        ax[0].set_xlim(t[0], t[-1])
    save(fig, path, dpi=100)


def plot_differences(series, path):
    """The differences of :func:`quatnav.evaluation.track_difference.compare_tracks` over time
    (its ``_series``), one panel per quantity both tracks have: the attitude (heading,
    inclination), the position and the velocity (horizontal, vertical)."""
    from .._plotting import figure, save, time_axis
    panels = [(k, v) for k, v in (
        ("t_att", (("heading", "heading"), ("inclination", "inclination"), "attitude difference [deg]")),
        ("t_pos", (("horizontal", "horizontal"), ("vertical", "vertical"), "position difference [m]")),
        ("t_vel", (("velocity_horizontal", "horizontal"), ("velocity_vertical", "vertical"),
                   "velocity difference [m/s]"))) if k in series]
    t0 = min(float(series[k][0]) for k, _ in panels if len(series[k])) if panels else 0.0
    fig = figure((9.0, 2.6 * max(1, len(panels))))
    axes = [fig.add_subplot(len(panels), 1, 1)] if panels else []
    axes += [fig.add_subplot(len(panels), 1, i + 1, sharex=axes[0]) for i in range(1, len(panels))]
    for ax, (k, (one, two, label)) in zip(axes, panels):
        t, xlabel = time_axis(series[k], t0)
        for name, text in (one, two):
            if name in series:
                ax.plot(t, series[name], lw=0.8, label=text)
        ax.set_ylabel(label)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    if axes:
        axes[-1].set_xlabel(xlabel)
    save(fig, path, dpi=100)
