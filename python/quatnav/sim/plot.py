"""Plot a scenario: track, attitude and sensor signals (matplotlib, imported only when called)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_scenario"]


def plot_scenario(scenario, path=None, show=False):
    """Draw a 2x3 overview of a scenario (long signals are thinned to about 4000 points).

    Panels: horizontal track (truth and GPS), height (truth, GPS, altimeter), attitude in
    degrees (truth and compass yaw; roll and yaw unwrapped, so an angle through +/-180 deg
    draws no jump, and each compass reading shifted by whole turns to lie next to it), gyro (deg/s),
    accelerometer (m/s^2), magnetometer (uT) or speed. Legends sit to the right of the panels.

    Parameters
    ----------
    scenario : Scenario
    path : str or path-like, optional
        Save the figure there (format from the extension).
    show : bool
        Call ``plt.show()``.

    Returns
    -------
    matplotlib.figure.Figure
    """
    import matplotlib
    if path is not None and not show:
        matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    tr = scenario.truth

    def thin(n):
        """Index step that keeps at most about 4000 points per line."""
        return max(1, n // 4000)

    def legend(a, **kw):
        a.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0, frameon=False,
                 fontsize="small", **kw)

    st, si = thin(len(tr.t)), thin(len(scenario.imu.t))
    fig, ax = plt.subplots(2, 3, figsize=(18, 8.5), constrained_layout=True)
    fig.suptitle(f"{scenario.name} (seed {scenario.seed})")
    a = ax[0, 0]
    a.plot(tr.pos_n[::st, 1], tr.pos_n[::st, 0], "k-", label="truth", zorder=3)
    if scenario.gps is not None:
        a.plot(scenario.gps.pos_n[:, 1], scenario.gps.pos_n[:, 0], ".", ms=2, label="GPS")
    a.set_xlabel("east [m]")
    a.set_ylabel("north [m]")
    a.set_aspect("equal", adjustable="datalim")
    legend(a, markerscale=4)
    a.set_title("track")

    a = ax[0, 1]
    a.plot(tr.t[::st], tr.h[::st], "k-", label="truth", zorder=3)
    if scenario.gps is not None:
        a.plot(scenario.gps.t_valid, scenario.gps.h, ".", ms=2, label="GPS")
    if scenario.baro is not None:
        a.plot(scenario.baro.t, scenario.baro.h, ".", ms=2, label="altimeter")
    a.set_xlabel("time [s]")
    a.set_ylabel("height [m]")
    legend(a, markerscale=4)
    a.set_title("height")

    a = ax[0, 2]
    yaw_u = np.unwrap(tr.rpy[:, 2])
    deg = np.degrees(np.column_stack([np.unwrap(tr.rpy[:, 0]), tr.rpy[:, 1], yaw_u])[::st])
    for i, n in enumerate(("roll", "pitch", "yaw")):
        a.plot(tr.t[::st], deg[:, i], label=n)
    if scenario.compass is not None:
        near = np.interp(scenario.compass.t, tr.t, yaw_u)
        cmp_u = near + np.angle(np.exp(1j * (scenario.compass.yaw - near)))
        a.plot(scenario.compass.t, np.degrees(cmp_u), ".", ms=2, label="compass")
    a.set_xlabel("time [s]")
    a.set_ylabel("angle [deg]")
    legend(a, markerscale=4)
    a.set_title("attitude (truth; roll and yaw unwrapped)")

    imu = scenario.imu
    for a, y, yt, unit, title in ((ax[1, 0], np.degrees(imu.gyro), np.degrees(tr.omega_ib_b),
                                   "deg/s", "gyro"),
                                  (ax[1, 1], imu.accel, tr.f_ib_b, "m/s^2", "accelerometer")):
        for i, c in enumerate("xyz"):
            a.plot(imu.t[::si], y[::si, i], lw=0.5, label=f"{c} measured")
            a.plot(tr.t[::st], yt[::st, i], "k-", lw=0.5)
        a.set_xlabel("time [s]")
        a.set_ylabel(f"{title} [{unit}]")
        legend(a)
        a.set_title(f"{title} (black: truth)")

    a = ax[1, 2]
    if scenario.mag is not None:
        sm = thin(len(scenario.mag.t))
        for i, c in enumerate("xyz"):
            a.plot(scenario.mag.t[::sm], scenario.mag.mag[::sm, i] * 1e6, lw=0.5, label=c)
        if np.any(scenario.mag.disturbed):
            a.fill_between(scenario.mag.t, 0, 1, where=scenario.mag.disturbed, color="r",
                           alpha=0.15, transform=a.get_xaxis_transform(), label="disturbed")
        a.set_ylabel("magnetic field [uT]")
        a.set_title("magnetometer")
    else:
        a.plot(tr.t[::st], np.linalg.norm(tr.v_n[::st], axis=1), "k-")
        a.set_ylabel("speed [m/s]")
        a.set_title("speed (truth)")
    a.set_xlabel("time [s]")
    if scenario.mag is not None:
        legend(a)
    if path is not None:
        fig.savefig(path, dpi=110)
    if show:
        plt.show()
    return fig
