"""The figures of the pipelines: a GNSS/INS run (:func:`plot_nav`), an attitude run
(:func:`plot_attitude`), the differences between two tracks (:func:`plot_differences`)."""
from __future__ import annotations

import numpy as np

__all__ = ["plot_nav", "plot_attitude", "plot_differences"]


def plot_nav(path, r, nav, gnss, log=None):
    """Track (north/east m about the first GNSS fix) with the fixes; attitude with its three-sigma
    band; biases; the difference to the log's own attitude estimate when it has one (else the
    accelerometer bias); the horizontal and vertical position one-sigma; and the innovations of
    every aid over time as their NIS (its chi-square gate is the filter's), rejected samples
    marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ..core import earth as E
    lat0, lon0, h0 = np.radians(gnss["lat"][0]), np.radians(gnss["lon"][0]), gnss["h"][0]
    p = E.geodetic_to_ned(r.lat[nav], r.lon[nav], r.h[nav], lat0, lon0, h0)
    g = E.geodetic_to_ned(np.radians(gnss["lat"]), np.radians(gnss["lon"]), gnss["h"], lat0, lon0, h0)
    ref = log.reference if log is not None and log.reference is not None and log.reference.quat is not None else None
    fig, ax = plt.subplots(3, 2, figsize=(11, 10))
    ax[0, 0].plot(p[:, 1], p[:, 0], label="INS")
    ax[0, 0].plot(g[:, 1], g[:, 0], ".", ms=3, label="GNSS fixes")
    ax[0, 0].set_xlabel("east, m")
    ax[0, 0].set_ylabel("north, m")
    ax[0, 0].axis("equal")
    ax[0, 0].legend(fontsize=7)
    t = r.t[nav]
    e = np.degrees(r.euler[nav])
    s_att = None
    if r.sigma is not None and r.sigma.shape[1] >= 9:  # tilt errors about north and east, heading about down
        psi = np.degrees(r.sigma[nav][:, 6:9])
        tilt = np.maximum(psi[:, 0], psi[:, 1])  # roll and pitch: the larger tilt sigma (heading-independent)
        s_att = np.column_stack([tilt, tilt, psi[:, 2]])
    for i, c in enumerate(("roll", "pitch", "yaw")):
        ax[0, 1].plot(t, e[:, i], label=c, color=f"C{i}")
        if s_att is not None:
            ax[0, 1].fill_between(t, e[:, i] - 3 * s_att[:, i], e[:, i] + 3 * s_att[:, i], color=f"C{i}",
                                  alpha=0.2, lw=0)
    ax[0, 1].set_ylabel("deg (band: 3 sigma)")
    ax[0, 1].legend(fontsize=7)
    ax[1, 0].plot(t, np.degrees(r.bias[nav]) * 3600)
    ax[1, 0].set_ylabel("gyro bias, deg/h")
    if ref is not None:
        from ..evaluation.track_difference import attitude_difference
        d = attitude_difference(t, r.quat[nav], ref.t, ref.quat)
        ax[1, 1].plot(d["t"], d["inclination_deg"], label="inclination")
        ax[1, 1].plot(d["t"], d["heading_deg"], label="heading")
        ax[1, 1].set_ylabel(f"difference to {ref.name}, deg")
        ax[1, 1].legend(fontsize=7)
    else:
        ax[1, 1].plot(t, r.acc_bias[nav])
        ax[1, 1].set_ylabel("accelerometer bias, m/s^2")
    if r.sigma is not None:
        ax[2, 0].plot(t, np.hypot(r.sigma[nav][:, 0], r.sigma[nav][:, 1]), label="horizontal")
        ax[2, 0].plot(t, r.sigma[nav][:, 2], label="vertical")
        ax[2, 0].set_yscale("log")
        ax[2, 0].set_ylabel("position one-sigma, m")
        ax[2, 0].legend(fontsize=7)
    for i, (name, a) in enumerate(sorted((getattr(r, "aids", None) or {}).items())):
        if a.nis is None or not len(a.t):
            continue
        ok = np.isfinite(a.nis)
        if not ok.any():
            continue
        ax[2, 1].plot(a.t[ok], a.nis[ok], ".", ms=2, color=f"C{i % 10}", label=name)
        bad = ok & (np.asarray(a.status) != 0)
        if bad.any():
            ax[2, 1].plot(a.t[bad], a.nis[bad], "x", ms=4, color=f"C{i % 10}")
    if ax[2, 1].lines:
        ax[2, 1].set_yscale("log")
        ax[2, 1].legend(fontsize=7, ncol=2, title="x: not applied", title_fontsize=7)
    ax[2, 1].set_ylabel("innovation NIS")
    for a in (ax[0, 1], ax[1, 0], ax[1, 1], ax[2, 0], ax[2, 1]):
        a.set_xlabel("t, s")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def plot_attitude(res, log, path):
    """Attitude (with the log's own estimate, dotted, when it has one), gyro bias and the
    inclination and heading difference to that estimate."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ref = log.reference if log is not None and log.reference is not None and log.reference.quat is not None else None
    n = 3 if ref is not None else 2
    fig, ax = plt.subplots(n, 1, figsize=(9, 2.6 * n), sharex=True)
    e = np.degrees(res.euler)
    for i, c in enumerate(("roll", "pitch", "yaw")):
        ax[0].plot(res.t, e[:, i], label=c)
    if ref is not None:
        from ..core import quaternion as Q
        er = np.degrees(Q.to_euler(ref.quat))
        for i in range(3):
            ax[0].plot(ref.t, er[:, i], "k:", lw=0.8, label=ref.name if i == 0 else None)
    ax[0].set_ylabel("deg")
    ax[0].legend(fontsize=7)
    ax[1].plot(res.t, np.degrees(res.bias))
    ax[1].set_ylabel("gyro bias, deg/s")
    if ref is not None:
        from ..evaluation.track_difference import attitude_difference
        d = attitude_difference(res.t, res.quat, ref.t, ref.quat)
        ax[2].plot(d["t"], d["inclination_deg"], label="inclination")
        ax[2].plot(d["t"], d["heading_deg"], label="heading")
        ax[2].set_ylabel(f"difference to\n{ref.name}, deg")
        ax[2].legend(fontsize=7)
    ax[-1].set_xlabel("t, s")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


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
