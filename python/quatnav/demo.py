"""``quatnav demo``: the attitude filters on a built-in simulated rotation.

The scenario: smooth random rotation (up to ~2 rad/s) with a magnetometer, constant gyro bias,
white sensor noise; exact truth. Prints RMSE of roll, pitch and yaw and the final gyro-bias
error of :class:`~quatnav.QuaternionEKF` (defaults, tuned for real data, and ``paper=True``:
the plain filter of paper 000), :class:`~quatnav.EulerEKF` and
:class:`~quatnav.MargFilter` (paper defaults, which estimate no gyro bias, and with its bias
integrator on); then :class:`~quatnav.NavFilter13` with its three time updates on paper
002's simulated run, and :class:`~quatnav.GpsInsFilter` on paper 004's simulated runs.
``--plot FILE.png`` writes one figure of all three: the attitude filters' roll, pitch, yaw and
gyro-bias errors against time, NavFilter13's attitude and velocity errors, and GpsInsFilter's
horizontal position error and yaw error through its GPS outage, each with the part left out of
the printed RMSE shaded.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .core import quaternion as Q

GRAVITY = 9.80665


@dataclass
class RotationData:
    t: np.ndarray          #: (N,) s
    q_nb: np.ndarray       #: (N, 4) true attitude
    omega_b: np.ndarray    #: (N, 3) true body rate, rad/s
    gyr: np.ndarray        #: (N, 3) measured rate, rad/s
    acc: np.ndarray        #: (N, 3) measured specific force, m/s^2
    mag: np.ndarray        #: (N, 3) measured field, uT
    gyro_bias: np.ndarray  #: (3,) rad/s
    mag_n: np.ndarray      #: (3,) field in NED, uT
    dt: float


def rotation_scenario(n: int = 6000, rate: float = 100.0, seed: int = 0, max_rate: float = 2.0,
                      gyro_bias=(0.02, -0.015, 0.01), gyro_noise: float = 0.005,
                      acc_noise: float = 0.05, mag_noise: float = 0.5, dip_deg: float = 60.0,
                      start_still: float = 1.0, pitch_limit: float = 1.2) -> RotationData:
    """A smooth random rotation sampled at ``rate`` Hz, consistent by construction.

    Roll, pitch and yaw are sums of random sinusoids (|pitch| below ``pitch_limit`` rad, still
    for the first ``start_still`` s), scaled so the body rate peaks near ``max_rate`` rad/s. The
    body rate of sample k is the constant rate that turns ``q[k-1]`` into ``q[k]`` over one
    interval, ``q[k] = q[k-1] * exp(omega[k] dt)``, so a filter that integrates the gyro that
    way sees exact data. Noise values are standard deviations per sample (gyro_noise rad/s,
    acc_noise m/s^2, mag_noise uT); the field has intensity 50 uT and the given dip.

    The default gyro bias, (0.02, -0.015, 0.01) rad/s = (1.15, -0.86, 0.57) deg/s (norm 1.54
    deg/s, i.e. 5554 deg/h), is the turn-on offset of an uncalibrated consumer MEMS gyro (their
    datasheets give initial zero-rate offsets of about 1 to 20 deg/s): small beside the motion
    (peak rate ``max_rate`` = 2 rad/s = 115 deg/s) but far beyond a navigation-grade gyro's bias,
    which is quoted in deg/h. It is constant over the run, so an attitude filter that estimates
    no bias carries all of it.
    """
    rng = np.random.default_rng(seed)
    dt = 1.0 / rate
    t = np.arange(n) * dt
    freqs = rng.uniform(0.03, 0.3, size=(3, 4))
    phases = rng.uniform(0, 2 * np.pi, size=(3, 4))
    amps = rng.uniform(0.3, 1.0, size=(3, 4))
    ramp = np.clip((t - start_still) / 2.0, 0.0, 1.0)
    ramp = ramp * ramp * (3 - 2 * ramp)  # smooth start
    ang = np.einsum("ij,ijn->ni", amps, np.sin(2 * np.pi * freqs[..., None] * t + phases[..., None])
                    - np.sin(phases[..., None]))
    ang[:, 1] = pitch_limit * np.tanh(ang[:, 1])
    rpy = ang * ramp[:, None]

    def rates(scale):
        q = Q.from_euler(rpy * [scale, 1.0, scale])
        w = np.zeros((n, 3))
        w[1:] = Q.to_rotvec(Q.mul(Q.conj(q[:-1]), q[1:])) / dt
        return q, w

    q, omega = rates(1.0)
    peak = np.max(np.linalg.norm(omega, axis=1))
    if peak > 0:
        # Scale roll and yaw excursions (pitch is bounded) until the peak rate is max_rate.
        for _ in range(3):
            rpy[:, [0, 2]] *= max_rate / peak
            rpy[:, 1] *= min(1.0, max_rate / peak)
            q, omega = rates(1.0)
            peak = np.max(np.linalg.norm(omega, axis=1))
    dip = np.radians(dip_deg)
    mag_n = 50.0 * np.array([np.cos(dip), 0.0, np.sin(dip)])
    bias = np.asarray(gyro_bias, float)
    gyr = omega + bias + gyro_noise * rng.standard_normal((n, 3))
    acc = Q.rotate_inv(q, np.array([0.0, 0.0, -GRAVITY])) + acc_noise * rng.standard_normal((n, 3))
    mag = Q.rotate_inv(q, mag_n) + mag_noise * rng.standard_normal((n, 3))
    return RotationData(t, q, omega, gyr, acc, mag, bias, mag_n, dt)


def euler_errors_deg(q_est, q_true) -> np.ndarray:
    """(N, 3) roll, pitch, yaw errors in degrees, wrapped to (-180, 180]."""
    return np.degrees(Q.wrap_pi(Q.to_euler(q_est) - Q.to_euler(q_true)))


def run_demo(plot: str | None = None, seed: int = 0, quiet: bool = False) -> dict:
    from . import EulerEKF, MargFilter, QuaternionEKF

    d = rotation_scenario(seed=seed)
    results = {}
    filters = (("QuaternionEKF", QuaternionEKF, {}),
               ("QuaternionEKF paper", QuaternionEKF, {"paper": True}), ("EulerEKF", EulerEKF, {}),
               ("MargFilter", MargFilter, {}),
               ("MargFilter+bias", MargFilter, {"bias_gain": 0.05}))
    for name, cls, params in filters:
        # samples/s: the best of three runs after one warm-up call (the first call of a filter
        # pays one-time costs: imports, the parameter tables); `quatnav bench` is the measurement.
        cls(**params).run(d.gyr[:100], d.acc[:100], d.mag[:100], dt=d.dt)
        elapsed = np.inf
        for _ in range(3):
            t0 = time.perf_counter()
            r = cls(**params).run(d.gyr, d.acc, d.mag, dt=d.dt)
            elapsed = min(elapsed, time.perf_counter() - t0)
        err = euler_errors_deg(r.quat, d.q_nb)
        settle = d.t >= 5.0
        rmse = np.sqrt(np.mean(err[settle] ** 2, axis=0))
        bias_err = np.degrees(np.linalg.norm(r.bias[-1] - d.gyro_bias))
        results[name] = dict(roll_rmse_deg=rmse[0], pitch_rmse_deg=rmse[1], yaw_rmse_deg=rmse[2],
                             bias_err_deg_s=bias_err, bias_err_deg_h=bias_err * 3600,
                             samples_per_s=len(d.t) / elapsed, result=r)
    if not quiet:
        b = np.degrees(d.gyro_bias)
        print(f"quatnav demo: simulated rotation, {len(d.t)} samples at {1 / d.dt:.0f} Hz, gyro bias "
              f"[{' '.join(f'{x:+.2f}' for x in b)}] deg/s (|b| {np.linalg.norm(b):.2f} deg/s; RMSE after 5 s)")
        print(f"{'filter':<21}{'roll':>9}{'pitch':>9}{'yaw':>9}   {'|bias err|':>12}{'samples/s':>12}")
        print(f"{'':<21}{'[deg]':>9}{'[deg]':>9}{'[deg]':>9}   {'[deg/s]':>12}")
        for name, v in results.items():
            print(f"{name:<21}{v['roll_rmse_deg']:9.3f}{v['pitch_rmse_deg']:9.3f}{v['yaw_rmse_deg']:9.3f}   "
                  f"{v['bias_err_deg_s']:12.3f}{v['samples_per_s']:12.3g}")
    attitude = dict(results)
    nav_series = {} if plot else None
    nav = _navigation_demo(seed, quiet, series=nav_series)
    if nav:
        results["navigation"] = nav
    ins_series = {} if plot else None
    ins = _gpsins_demo(seed, quiet, series=ins_series)
    if ins:
        results["gpsins"] = ins
    if plot:
        written = _plot(d, attitude, nav_series, ins_series, plot)
        if not quiet:
            print()
            print(f"figure written to {written}")
    return results


def _navigation_demo(seed: int, quiet: bool, series: dict | None = None) -> dict:
    """NavFilter13 (paper 002) with its three time updates on the paper's simulated run; with
    ``series`` (a dict) also fills it with each time update's errors against time for the figure."""
    try:
        from .experiments import nav13 as X
        from .sim import make_scenario
        scn = make_scenario(X.SCENARIO, seed=seed)
    except ImportError as exc:  # quatnav.sim needs scipy (extra [sim])
        if not quiet:
            print(f"(navigation demo skipped: {exc})")
        return {}
    start = X.initial_state(scn, "paper", np.random.default_rng(seed))
    out = {}
    for tu in X.TIME_UPDATES:
        t0 = time.perf_counter()
        res = X.run_filter(scn, tu, start)
        elapsed = time.perf_counter() - t0
        err = X.errors(scn, res)
        late = err["t"] >= err["t"][0] + 100.0
        rpy = np.degrees(np.sqrt(np.mean(err["rpy"][late] ** 2, axis=0)))
        vel = np.sqrt(np.mean(np.sum(err["state"][late, 0:3] ** 2, axis=1)))
        out[tu] = dict(roll_rmse_deg=rpy[0], pitch_rmse_deg=rpy[1], yaw_rmse_deg=rpy[2],
                       vel_rmse_m_s=vel, samples_per_s=len(res.t) / elapsed)
        if series is not None:
            series[tu] = dict(t=err["t"], rpy_deg=np.degrees(err["rpy"]),
                              vel_m_s=np.linalg.norm(err["state"][:, 0:3], axis=1), window_s=(100.0, 200.0))
    if not quiet:
        print()
        print(f"NavFilter13 (paper 002): {X.SCENARIO}, seed {seed}, the paper's initial errors "
              f"(RMSE over 100-200 s)")
        print(f"{'time update':<21}{'roll':>9}{'pitch':>9}{'yaw':>9}   {'|v| err':>12}{'samples/s':>12}")
        print(f"{'':<21}{'[deg]':>9}{'[deg]':>9}{'[deg]':>9}   {'[m/s]':>12}")
        for name, v in out.items():
            print(f"{name:<21}{v['roll_rmse_deg']:9.3f}{v['pitch_rmse_deg']:9.3f}{v['yaw_rmse_deg']:9.3f}   "
                  f"{v['vel_rmse_m_s']:12.3f}{v['samples_per_s']:12.3g}")
    return out


def _gpsins_demo(seed: int, quiet: bool, series: dict | None = None) -> dict:
    """GpsInsFilter (paper 004) on its three simulated scenarios, with a 10 s GPS outage; with
    ``series`` (a dict) also fills it with each run's errors against time for the figure."""
    try:
        from .experiments import gpsins as G
        out = {name: G.run_scenario(name, seed=seed, keep_series=series is not None)
               for name in ("static", "turntable", "walk")}
        if series is not None:
            for name, r in out.items():
                o = r["outage"]
                series[name] = dict(r.pop("series"), outage_window_s=(o["start_s"], o["start_s"] + o["length_s"]))
    except ImportError as exc:  # quatnav.sim needs scipy (extra [sim])
        if not quiet:
            print(f"(GPS/INS demo skipped: {exc})")
        return {}
    if not quiet:
        print()
        print(f"GpsInsFilter (paper 004): simulated runs, seed {seed}; a 10 s GPS outage mid-run")
        print(f"{'scenario':<21}{'horiz RMS':>10}{'max':>8}{'roll':>8}{'pitch':>8}{'yaw':>8}"
              f"{'outage drift':>14}{'1-sigma':>9}")
        print(f"{'':<21}{'[m]':>10}{'[m]':>8}{'[deg]':>8}{'[deg]':>8}{'[deg]':>8}{'[m]':>14}{'[m]':>9}")
        for name, r in out.items():
            e, o = r["euler_deg"], r["outage"]
            print(f"{name:<21}{r['horizontal_m']['rms']:10.2f}{r['horizontal_m']['max']:8.2f}"
                  f"{e['roll']['rms']:8.2f}{e['pitch']['rms']:8.2f}{e['yaw']['rms']:8.2f}"
                  f"{o['horizontal_error_at_end_m']:14.2f}{o['horizontal_sigma_at_end_m']:9.2f}")
    return out


SETTLE_S = 5.0  # the attitude RMSE is taken after this time
_AXIS_COLORS = {"roll": "#1b9e77", "pitch": "#d95f02", "yaw": "#7570b3"}


def _plot(d: RotationData, attitude: dict, nav: dict | None, ins: dict | None, path: str):
    """The demo's figure: at the top the attitude filters on the simulated rotation (roll, pitch,
    yaw and gyro-bias errors), below NavFilter13's and GpsInsFilter's errors when those ran; the
    part of each run that the printed RMSE leaves out is shaded. One column, 11 in wide: on a
    documentation page (about 750 px wide) its 9-point text reads at 8.5 px, where two columns
    side by side (17 in) read at 5.4. Returns the path written."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from ._plotting import figure, legend_right, moving_rms, save

    right = bool(nav) or bool(ins)
    blocks = bool(nav) + bool(ins)
    fig = figure((11.0, 10.0 + 4.8 * blocks) if right else (11.0, 10.0))
    if right:
        left_fig, right_fig = fig.subfigures(2, 1, hspace=0.02, height_ratios=[10.0, 4.8 * blocks])
        rows = iter(right_fig.add_gridspec(2 * blocks, 1))
    else:
        left_fig = fig
    excluded = Patch(color="0.88", label=f"not in the RMSE (first {SETTLE_S:.0f} s)")

    # Attitude filters on the simulated rotation.
    ax0 = left_fig.add_subplot(4, 1, 1)
    axl = [ax0] + [left_fig.add_subplot(4, 1, i, sharex=ax0) for i in (2, 3, 4)]
    settle = d.t >= SETTLE_S
    handles = []
    for k, (name, v) in enumerate(attitude.items()):
        err = euler_errors_deg(v["result"].quat, d.q_nb)
        rmse = np.sqrt(np.mean(err[settle] ** 2, axis=0))
        for i in range(3):
            axl[i].plot(d.t, err[:, i], lw=0.6, color=f"C{k}")
        berr = np.degrees(np.linalg.norm(v["result"].bias - d.gyro_bias, axis=1))
        axl[3].plot(d.t, berr, lw=0.9, color=f"C{k}")
        handles.append(Line2D([], [], color=f"C{k}", lw=1.5,
                              label=f"{name}\n  RMSE {rmse[0]:.2f} / {rmse[1]:.2f} / {rmse[2]:.2f} deg"))
    b = np.degrees(np.linalg.norm(d.gyro_bias))
    axl[3].axhline(b, color="k", ls="--", lw=0.9)
    handles.append(Line2D([], [], color="k", ls="--", lw=0.9, label=f"|true bias| = {b:.2f} deg/s\n"
                                                                     "  (no bias estimate)"))
    for i, lab in enumerate(("roll", "pitch", "yaw")):
        axl[i].axhline(0.0, color="k", lw=0.5)
        axl[i].set_ylabel(f"{lab} error [deg]")
    axl[3].set_yscale("log")
    axl[3].set_ylabel("|gyro bias error| [deg/s]")
    axl[3].set_xlabel("time [s]")
    for ax in axl:
        ax.axvspan(d.t[0], SETTLE_S, color=excluded.get_facecolor(), lw=0, zorder=0)
        ax.grid(True, which="major", alpha=0.3)
        ax.set_xlim(d.t[0], d.t[-1])
    for ax in axl[:3]:
        ax.tick_params(labelbottom=False)
    axl[0].set_title(f"attitude filters, simulated rotation ({len(d.t)} samples at {1 / d.dt:.0f} Hz, "
                     f"constant gyro bias {b:.2f} deg/s)", fontsize=10, loc="left")
    legend_right(axl[0], handles + [excluded], [h.get_label() for h in handles + [excluded]],
                 title="roll / pitch / yaw RMSE after 5 s", title_fontsize=8)

    if nav:
        from .experiments.nav13 import LABELS, STYLES
        a1 = right_fig.add_subplot(next(rows))
        a2 = right_fig.add_subplot(next(rows), sharex=a1)
        for tu, s in nav.items():
            t = s["t"]
            n = max(1, int(round(1.0 / np.median(np.diff(t)))))  # samples in 1 s
            for i, lab in enumerate(("roll", "pitch", "yaw")):
                a1.plot(t, moving_rms(s["rpy_deg"][:, i], n), STYLES.get(tu, "-"), lw=1.0,
                        color=_AXIS_COLORS[lab])
            a2.plot(t, moving_rms(s["vel_m_s"], n), STYLES.get(tu, "-"), lw=1.0, color="0.2")
        w0 = next(iter(nav.values()))["window_s"][0]
        for ax in (a1, a2):
            ax.set_yscale("log")
            ax.axvspan(t[0], w0, color=excluded.get_facecolor(), lw=0, zorder=0)
            ax.grid(True, which="major", alpha=0.3)
            ax.set_xlim(0.0, t[-1])
        a1.tick_params(labelbottom=False)
        a1.set_ylabel("attitude error [deg]\n(1 s moving RMS)")
        a2.set_ylabel("|velocity error| [m/s]\n(1 s moving RMS)")
        a2.set_xlabel("time [s]")
        a1.set_title("NavFilter13 (paper 002), straight then circle, the paper's initial errors",
                     fontsize=10, loc="left")
        h = [Line2D([], [], color=c, lw=1.5, label=lab) for lab, c in _AXIS_COLORS.items()]
        h += [Line2D([], [], color="0.2", ls=STYLES.get(tu, "-"), lw=1.0, label=LABELS.get(tu, tu))
              for tu in nav]
        h.append(Patch(color=excluded.get_facecolor(), label=f"not in the RMSE (first {w0:.0f} s)"))
        legend_right(a1, h, [x.get_label() for x in h], title="axis (colour), time update (line)",
                     title_fontsize=8)

    if ins:
        g1 = right_fig.add_subplot(next(rows))
        g2 = right_fig.add_subplot(next(rows), sharex=g1)
        h = []
        for k, (name, s) in enumerate(ins.items()):
            e, (t0, t1) = s["outage"], s["outage_window_s"]
            c = f"C{k + 5}"
            x = e["t"] - t0
            g1.plot(x, e["horiz"], color=c, lw=1.0)
            g1.plot(x, e["sigma_h"], color=c, lw=0.8, ls="--")
            g2.plot(x, e["euler_deg"][:, 2], color=c, lw=0.8)
            g2.plot(x, 3 * e["sigma_psi_deg"][:, 2], color=c, lw=0.6, ls="--")
            g2.plot(x, -3 * e["sigma_psi_deg"][:, 2], color=c, lw=0.6, ls="--")
            h.append(Line2D([], [], color=c, lw=1.5, label=name))
        span = t1 - t0
        cb = {s.get("compass_bias_deg") for s in ins.values()}
        if len(cb) == 1 and next(iter(cb)):
            cb = next(iter(cb))
            g2.axhline(cb, color="k", ls=":", lw=1.0)
            h.append(Line2D([], [], color="k", ls=":", lw=1.0,
                            label=f"compass bias {cb:g} deg\n  (not a filter state)"))
        for ax in (g1, g2):
            ax.axvspan(0.0, span, color="#f4d6a0", lw=0, zorder=0)
            ax.grid(True, which="major", alpha=0.3)
        g2.axhline(0.0, color="k", lw=0.5)
        g1.tick_params(labelbottom=False)
        g1.set_ylim(bottom=0.0)
        g1.set_ylabel("horizontal position error [m]")
        g2.set_ylabel("yaw error [deg]")
        g2.set_xlabel("time from the start of the GPS outage [s]")
        g1.set_title("GpsInsFilter (paper 004), simulated runs with a GPS outage mid-run",
                     fontsize=10, loc="left")
        h += [Line2D([], [], color="0.3", lw=0.8, ls="--", label="filter's 1-sigma (position),\n"
                                                                   "3-sigma (yaw)"),
              Patch(color="#f4d6a0", label=f"GPS outage ({span:.0f} s)")]
        legend_right(g1, h, [x.get_label() for x in h], title="scenario", title_fontsize=8)
        g2.set_ylim(*_symmetric_limits([s["outage"]["euler_deg"][:, 2] for s in ins.values()]))

    fig.suptitle("quatnav demo: the filters on built-in simulated scenarios", fontsize=12)
    return save(fig, path, dpi=110)


def _symmetric_limits(series, pct: float = 99.5):
    """Symmetric y limits that hold ``pct`` percent of every series' samples (the start of a run,
    before the filter has converged, may leave the axis)."""
    m = max(np.percentile(np.abs(s[np.isfinite(s)]), pct) for s in series)
    return -1.3 * m, 1.3 * m


def add_parser(sub) -> None:
    p = sub.add_parser("demo", help="run the filters on built-in simulated scenarios and print a table")
    p.add_argument("--plot", metavar="FILE.png", help="write a figure of the errors")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", metavar="FILE", help="write the figures of the tables as JSON ('-': stdout)")
    p.set_defaults(func=_cmd)


def _cmd(args) -> int:
    res = run_demo(plot=args.plot, seed=args.seed)
    if args.json:
        from ._command import write_json

        def figures(d):
            return {k: figures(v) if isinstance(v, dict) else v for k, v in d.items() if k != "result"}
        write_json(figures(res), args)
    return 0
