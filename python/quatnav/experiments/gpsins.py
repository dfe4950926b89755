"""Paper 004 on the simulated scenarios: ``quatnav experiment gpsins --scenario static|turntable|walk
--json FILE [--seed N] [--outage-start S] [--outage-length S]``.

Runs :class:`quatnav.GpsInsFilter` (GPS with lever arm, altimeter and its vertical velocity,
compass) on the simulator's paper-004 scenario, once with every GPS fix and once with a GPS
outage, and reports against the truth: horizontal and vertical position error (RMS, max), Euler
angle errors (RMS, max, deg), the chi-square rejections, and the horizontal drift during the
outage with the filter's own one-sigma at its end.
"""
from __future__ import annotations

import numpy as np

from ..sim.scenarios import make_scenario

SCENARIOS = ("static", "turntable", "walk")
_A, _E2 = 6378137.0, 6.69437999014e-3  # WGS-84


#: One line for ``quatnav experiment -h``.
SUMMARY = ("GpsInsFilter (loosely coupled GNSS/INS) on the simulated static, turntable or walk run: errors and drift "
           "over a GPS outage (paper 004)")


def add_arguments(parser) -> None:
    parser.add_argument("--scenario", choices=SCENARIOS, default="walk", help="paper 004 scenario (default walk)")
    parser.add_argument("--json", metavar="FILE", help="write the results here ('-': stdout)")
    parser.add_argument("--seed", type=int, default=0, help="simulation seed (default 0)")
    parser.add_argument("--outage-start", type=float, default=None,
                        help="GPS outage start (s); default: the middle of the run")
    parser.add_argument("--outage-length", type=float, default=10.0, help="GPS outage length (s), default 10")


def _aids(s):
    from .. import Aid
    return dict(gps_pos=Aid(s.gps.t_valid, np.column_stack([s.gps.lat, s.gps.lon, s.gps.h])),
                gps_vel=Aid(s.gps.t_valid, s.gps.v_n), baro=Aid(s.baro.t, s.baro.h),
                compass=Aid(s.compass.t, s.compass.yaw))


def errors(s, r) -> dict:
    """Errors of a run against the truth at the IMU times where the filter navigates."""
    nav = r.navigating
    i = np.searchsorted(s.truth.t, r.t[nav])
    lat, h = s.truth.lat[i], s.truth.h[i]
    sl2 = np.sin(lat) ** 2
    rm = _A * (1 - _E2) / (1 - _E2 * sl2) ** 1.5
    rn = _A / np.sqrt(1 - _E2 * sl2)
    dn = (r.lat[nav] - lat) * (rm + h)
    de = (r.lon[nav] - s.truth.lon[i]) * (rn + h) * np.cos(lat)
    dd = -(r.h[nav] - h)
    deul = r.euler[nav] - s.truth.rpy[i]
    deul = np.angle(np.exp(1j * deul))
    return dict(t=r.t[nav], horiz=np.hypot(dn, de), down=dd, euler_deg=np.degrees(deul),
                sigma_h=np.hypot(r.sigma[nav, 0], r.sigma[nav, 1]),
                sigma_psi_deg=np.degrees(r.sigma[nav, 6:9]))


def _stats(x):
    x = np.abs(np.asarray(x))
    return {"rms": float(np.sqrt(np.mean(x ** 2))), "max": float(np.max(x))}


def run_scenario(name: str, seed: int = 0, outage_start=None, outage_length: float = 10.0,
                 keep_series: bool = False) -> dict:
    """Run scenario ``paper004_<name>`` with every fix and with the outage; the summary (see the
    module docstring). ``keep_series`` adds ``"series": {"gps": ..., "outage": ...}``, the
    :func:`errors` of both runs against time (arrays, for :func:`plot`)."""
    import quatnav

    s = make_scenario(f"paper004_{name}", seed=seed)
    lever = tuple(s.params.get("gps", {}).get("lever_arm_b_m", (0.1, 0.0, -0.1))) \
        if isinstance(s.params.get("gps"), dict) else (0.1, 0.0, -0.1)
    f = quatnav.GpsInsFilter(lever_arm_b=lever)
    r = f.run(s.imu.gyro, s.imu.accel, t=s.imu.t, **_aids(s))
    e = errors(s, r)
    out = {"scenario": s.name, "seed": seed, "duration_s": float(s.imu.t[-1] - s.imu.t[0]),
           "navigating_from_s": float(e["t"][0]),
           "horizontal_m": _stats(e["horiz"]), "down_m": _stats(e["down"]),
           "euler_deg": {k: _stats(e["euler_deg"][:, j]) for j, k in enumerate(("roll", "pitch", "yaw"))},
           "rejections": r.rejections}
    t0 = float(s.imu.t[0] + 0.5 * (s.imu.t[-1] - s.imu.t[0])) if outage_start is None else float(outage_start)
    t1 = t0 + outage_length
    r2 = quatnav.GpsInsFilter(lever_arm_b=lever).run(s.imu.gyro, s.imu.accel, t=s.imu.t,
                                                     outages=[(t0, t1)], **_aids(s))
    e2 = errors(s, r2)
    m = (e2["t"] >= t0) & (e2["t"] < t1)
    if not m.any():
        raise ValueError(f"--outage-start: the outage {t0:g} to {t1:g} s lies outside the navigation "
                         f"({e2['t'][0]:g} to {e2['t'][-1]:g} s of {s.name})")
    out["outage"] = {"start_s": t0, "length_s": outage_length,
                     "horizontal_error_at_start_m": float(e2["horiz"][m][0]),
                     "horizontal_error_max_m": float(e2["horiz"][m].max()),
                     "horizontal_error_at_end_m": float(e2["horiz"][m][-1]),
                     "horizontal_sigma_at_end_m": float(e2["sigma_h"][m][-1]),
                     "horizontal_rms_whole_run_m": _stats(e2["horiz"])["rms"]}
    if keep_series:
        out["series"] = {"gps": e, "outage": e2,
                         "compass_bias_deg": float(s.params.get("compass", {}).get("bias_deg", 0.0))}
    return out


def plot(res: dict, path):
    """Figure of one :func:`run_scenario` result (run with ``keep_series=True``): horizontal and
    vertical position error of the run with every fix and of the run with the outage (the two
    are the same run until the outage starts), with the filter's one-sigma; roll, pitch and yaw
    errors of the run with every fix with the filter's three-sigma."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from .._plotting import figure, legend_right, save
    if "series" not in res:
        raise ValueError("res: run run_scenario(..., keep_series=True) to plot it")
    e, e2 = res["series"]["gps"], res["series"]["outage"]
    o = res["outage"]
    t0, t1 = o["start_s"], o["start_s"] + o["length_s"]
    fig = figure((11.0, 8.5))
    ax = [fig.add_subplot(3, 1, 1)]
    ax += [fig.add_subplot(3, 1, k, sharex=ax[0]) for k in (2, 3)]
    ax[0].plot(e["t"], e["horiz"], color="C0", lw=0.9)
    ax[0].plot(e["t"], e["sigma_h"], color="C0", lw=0.8, ls="--")
    ax[0].plot(e2["t"], e2["horiz"], color="C3", lw=0.9)
    ax[0].plot(e2["t"], e2["sigma_h"], color="C3", lw=0.8, ls="--")
    ax[0].set_ylim(bottom=0.0)
    ax[0].set_ylabel("horizontal error [m]")
    ax[1].plot(e["t"], e["down"], color="C0", lw=0.9)
    ax[1].plot(e2["t"], e2["down"], color="C3", lw=0.9)
    ax[1].axhline(0.0, color="k", lw=0.5)
    ax[1].set_ylabel("down error [m]")
    colors = {"roll": "#1b9e77", "pitch": "#d95f02", "yaw": "#7570b3"}
    for j, (name, c) in enumerate(colors.items()):
        ax[2].plot(e["t"], e["euler_deg"][:, j], color=c, lw=0.8)
        ax[2].plot(e["t"], 3 * e["sigma_psi_deg"][:, j], color=c, lw=0.6, ls="--")
        ax[2].plot(e["t"], -3 * e["sigma_psi_deg"][:, j], color=c, lw=0.6, ls="--")
    cb = res["series"].get("compass_bias_deg", 0.0)
    if cb:
        ax[2].axhline(cb, color="k", ls=":", lw=1.0)
    ax[2].axhline(0.0, color="k", lw=0.5)
    m = max(np.percentile(np.abs(e["euler_deg"]), 99.5), abs(cb))
    ax[2].set_ylim(-1.4 * m, 1.4 * m)  # the alignment's first second may leave the axis
    ax[2].set_ylabel("attitude error [deg]")
    ax[2].set_xlabel("time [s]")
    for a in ax:
        a.axvspan(t0, t1, color="#f4d6a0", lw=0, zorder=0)
        a.grid(True, alpha=0.3)
        a.set_xlim(res["navigating_from_s"], e["t"][-1])
    for a in ax[:2]:
        a.tick_params(labelbottom=False)
    h = [Line2D([], [], color="C0", lw=1.5, label="every GPS fix"),
         Line2D([], [], color="C3", lw=1.5, label=f"GPS outage {t0:.0f}-{t1:.0f} s"),
         Line2D([], [], color="0.3", lw=0.8, ls="--", label="filter's 1-sigma"),
         Patch(color="#f4d6a0", label="outage")]
    legend_right(ax[0], h, [x.get_label() for x in h])
    h = [Line2D([], [], color=c, lw=1.5, label=n) for n, c in colors.items()]
    h.append(Line2D([], [], color="0.3", lw=0.6, ls="--", label="filter's 3-sigma"))
    if cb:
        h.append(Line2D([], [], color="k", ls=":", lw=1.0, label=f"compass bias {cb:g} deg\n(not a filter state)"))
    legend_right(ax[2], h, [x.get_label() for x in h], title="run with every fix", title_fontsize=8)
    fig.suptitle(f"GpsInsFilter (paper 004) on {res['scenario']}, seed {res['seed']}", fontsize=11)
    save(fig, path)
    return fig


def run(args) -> int:
    from .._command import UsageError, write_json
    if not args.outage_length > 0:
        raise UsageError(f"--outage-length: expected a positive number of seconds, got {args.outage_length:g}")
    res = run_scenario(args.scenario, args.seed, args.outage_start, args.outage_length)
    write_json(res, args)
    h, o = res["horizontal_m"], res["outage"]
    print(f"{res['scenario']} seed {res['seed']}: horizontal RMS {h['rms']:.2f} m, max {h['max']:.2f} m; "
          f"Euler RMS (deg) " + ", ".join(f"{k} {v['rms']:.2f}" for k, v in res["euler_deg"].items()))
    print(f"GPS outage {o['length_s']:.0f} s from {o['start_s']:.1f} s: horizontal error "
          f"{o['horizontal_error_at_start_m']:.2f} -> {o['horizontal_error_at_end_m']:.2f} m "
          f"(max {o['horizontal_error_max_m']:.2f} m, filter 1-sigma {o['horizontal_sigma_at_end_m']:.2f} m)")
    return 0
