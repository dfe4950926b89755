"""GPS/INS (paper 004) on a real pedestrian walk with RTK GNSS: ``quatnav experiment walk-rtk
[--data DIR] --json FILE [--plot FILE.png] [--seed N] [--noise-m S] [--sweep] [--perturbation]``.

Real-data evidence for :class:`quatnav.GpsInsFilter` on ``gnss_imu_walk`` (a 134 s walk, IMU
~166 Hz, RTKLIB solution 4 Hz; RTK-fixed epochs are cm-level and serve as the reference). The IMU
is rotated into a body FRD frame with the mounting found from the data
(:func:`quatnav.datasets.gnss_imu_walk.find_mounting`; docs/GPSINS_DATA.md); the lever arm is
unknown and taken as zero. Alignment is the filter's own: level from the accelerometer while the
walker stands still at the start, heading from the GNSS course once walking, position from the
fix.

Four runs, each scored against the RTK-fixed epochs (Q = 1), horizontal and vertical:

* ``rtk``: every RTK epoch as GNSS (fixed: its sigma with a 2 cm floor; float: 0.3 m);
* ``rtk_outages``: the same with GNSS outages of ``--outage-length`` (10) s every
  ``--outage-period`` (30) s from ``--outage-first`` (20) s after the start; the error during each
  outage (RMS, max, drift at its end, the filter's own one-sigma there);
* ``degraded``: positions with white noise of ``--noise-m`` (2.5) m added on each axis and that
  sigma given to the filter (velocity as RTKLIB gives it);
* ``degraded_outages``: both;
* ``rtk_noise_div10``: ``rtk`` with the noise densities of :data:`WALK_PARAMS` ten times too small
  (an over-confident configuration: the gating's inflation and the process-noise adaptation must
  keep the fixes in use).

Each run reports the decisions on the GNSS fixes (accepted, rejected, inflated, reset), the
largest process-noise scale of the adaptation and how the filter was aligned.

``--perturbation``: the robustness table of ``quatnav experiment gpsins-car`` on ``rtk_outages``
(:func:`perturbation_table`), the noise densities set as ``quatnav ins run`` sets them.
"""
from __future__ import annotations

import numpy as np

from .navego import ned_error

RUNS = ("rtk", "rtk_outages", "degraded", "degraded_outages", "rtk_noise_div10")
#: The noise densities scaled in ``rtk_noise_div10``.
NOISE_KEYS = ("gyro_noise", "acc_noise", "gyro_bias_noise", "acc_bias_noise")


#: One line for ``quatnav experiment -h``.
SUMMARY = "GpsInsFilter on a real walk with RTK GNSS and simulated GNSS outages (paper 004; gnss_imu_walk data)"


def add_arguments(parser) -> None:
    parser.add_argument("--data", default=None, metavar="DIR",
                        help="gnss_imu_walk folder (default $QUATNAV_DATA/gnss_imu_walk)")
    parser.add_argument("--json", metavar="FILE", help="write the results here ('-': stdout)")
    parser.add_argument("--plot", default=None, metavar="FILE.png", help="plot the errors here")
    parser.add_argument("--seed", type=int, default=0, help="seed of the added GNSS noise (default 0)")
    parser.add_argument("--noise-m", type=float, default=2.5, help="added GNSS position noise one-sigma, m (2.5)")
    parser.add_argument("--outage-first", type=float, default=20.0, help="first outage start after the IMU start, s")
    parser.add_argument("--outage-length", type=float, default=10.0, help="outage length, s (10)")
    parser.add_argument("--outage-period", type=float, default=30.0, help="outage period, s (30)")
    parser.add_argument("--sweep", action="store_true",
                        help="also repeat the outage runs with the first outage at 15, 20, ..., 45 s and "
                             "summarize the drift over every outage with >= 30 RTK-fixed epochs")
    parser.add_argument("--perturbation", action="store_true",
                        help="also the robustness table of 'experiment gpsins-car' on the RTK run with outages, "
                             "the noise set as 'ins run' does")


#: Filter parameters for the walk (the measured sensor noise at rest is far lower, 5e-5 rad/s/sqrt(Hz)
#: and 9e-4 m/s^2/sqrt(Hz); the process noise also covers scale-factor and misalignment errors
#: at the walk's ~1 rad/s rates and the antenna swinging about the IMU).
WALK_PARAMS = dict(gyro_noise=2e-3, acc_noise=5e-2, gyro_bias_noise=1e-4, acc_bias_noise=1e-3,
                   init_gyro_bias_sigma=0.01, init_acc_bias_sigma=0.2, init_yaw_sigma=0.4,
                   gps_vel_sigma=0.1, align_time=5.0, min_speed_for_heading=0.8)


def outage_windows(t0, t_end, first=20.0, length=10.0, period=30.0):
    """[(start, end), ...] absolute times of the simulated outages."""
    out, s = [], t0 + first
    while s + length <= t_end:
        out.append((s, s + length))
        s += period
    return out


def gnss_inputs(w, noise_m=None, seed=0):
    """GNSS arrays for the filter: llh, velocity and per-epoch sigmas (see the module docstring)."""
    llh = w.gnss_llh.copy()
    ps = np.where(w.fixed[:, None], np.maximum(w.pos_sigma, 0.02), 0.3)
    if noise_m is not None:
        rng = np.random.default_rng(seed)
        d = rng.normal(0.0, noise_m, size=(len(llh), 3))
        lat, h = llh[:, 0], llh[:, 2]
        a, e2 = 6378137.0, 6.69437999014e-3
        sl2 = np.sin(lat) ** 2
        rm = a * (1 - e2) / (1 - e2 * sl2) ** 1.5
        rn = a / np.sqrt(1 - e2 * sl2)
        llh = llh + np.column_stack([d[:, 0] / (rm + h), d[:, 1] / ((rn + h) * np.cos(lat)), -d[:, 2]])
        ps = np.full_like(ps, noise_m)
    vs = np.maximum(w.vel_sigma, WALK_PARAMS["gps_vel_sigma"])  # floor: RTKLIB's 5 cm/s is optimistic
    return llh, w.vel_n, ps, vs


def _interp_llh(t, llh, tq):
    ok = np.isfinite(llh[:, 0])
    return np.column_stack([np.interp(tq, t[ok], llh[ok, c], left=np.nan, right=np.nan) for c in range(3)])


def score(w, r, outages=()):
    """Errors of a run at the RTK-fixed epochs: horizontal and down (m), and per outage."""
    ref = w.fixed & (w.gnss_t > r.t[0])
    est = _interp_llh(r.t, r.position, w.gnss_t[ref])
    sig = np.column_stack([np.interp(w.gnss_t[ref], r.t, r.sigma[:, c]) for c in range(3)])
    ok = np.isfinite(est[:, 0])
    tref = w.gnss_t[ref][ok]
    e = ned_error(est[ok], w.gnss_llh[ref][ok])
    hz = np.hypot(e[:, 0], e[:, 1])
    sh = np.hypot(sig[ok, 0], sig[ok, 1])
    st = lambda x: {"rms": float(np.sqrt(np.mean(x ** 2))), "max": float(np.max(np.abs(x))), "n": int(len(x))}  # noqa: E731
    out = {"all_fixed": {"horizontal_m": st(hz), "down_m": st(e[:, 2])}, "outages": []}
    inside = np.zeros(len(tref), bool)
    for a, b in outages:
        m = (tref >= a) & (tref < b)
        inside |= m
        o = {"start_s": float(a - w.imu_t[0]), "end_s": float(b - w.imu_t[0]), "fixed_epochs": int(m.sum())}
        if m.any():
            o.update({"horizontal_rms_m": float(np.sqrt(np.mean(hz[m] ** 2))), "horizontal_max_m": float(hz[m].max()),
                      "horizontal_at_start_m": float(hz[m][0]), "horizontal_at_end_m": float(hz[m][-1]),
                      "last_fixed_s": float(tref[m][-1] - w.imu_t[0]),
                      "sigma_h_at_end_m": float(sh[m][-1]), "down_max_m": float(np.abs(e[m, 2]).max())})
        out["outages"].append(o)
    if len(outages):
        out["during_outages"] = {"horizontal_m": st(hz[inside]), "down_m": st(e[inside, 2])} if inside.any() else None
        out["outside_outages"] = {"horizontal_m": st(hz[~inside]), "down_m": st(e[~inside, 2])}
    return out, dict(t=tref, hz=hz, sh=sh, down=e[:, 2])


def run_walk(directory=None, seed=0, noise_m=2.5, first=20.0, length=10.0, period=30.0, seconds=None,
             runs=RUNS, params=None, smooth=False):
    """The runs ``runs`` (default all four); returns (summary dict, per-run arrays).
    ``params`` overrides entries of :data:`WALK_PARAMS`. ``smooth``: the runs with outages also
    smoothed (``run(..., smooth=True)``), scored in ``summary[run]["smoothed"]``."""
    fp = dict(WALK_PARAMS, **(params or {}))
    import quatnav
    from ..datasets import gnss_imu_walk as W

    w = W.load(directory)
    mount = W.find_mounting(w)
    n = len(w.imu_t) if seconds is None else int(np.searchsorted(w.imu_t, w.imu_t[0] + seconds, "right"))
    t = w.imu_t[:n]
    gyro = W.to_body(w.gyro_s[:n])
    accel = W.to_body(w.accel_s[:n])
    g = (w.gnss_t > t[0]) & (w.gnss_t <= t[-1])
    windows = outage_windows(t[0], t[-1], first, length, period)
    summary = {"dataset": "gnss_imu_walk (rtklibexplorer GNSS_IMU, 2025-08-28, Boulder CO)",
               "duration_s": float(t[-1] - t[0]), "t0": float(t[0]), "mounting": mount,
               "C_bs": W.C_BS.tolist(), "lever_arm_b": [0.0, 0.0, 0.0],
               "fixed_epochs": int(np.sum(w.fixed & g)), "float_epochs": int(np.sum(~w.fixed & g)),
               "params": fp, "noise_m": noise_m, "seed": seed,
               "outage_windows_s": [[a - t[0], b - t[0]] for a, b in windows]}
    arrays = {}
    rng_gnss = {}
    for name in runs:
        noisy = name.startswith("degraded")
        if noisy not in rng_gnss:
            rng_gnss[noisy] = gnss_inputs(w, noise_m if noisy else None, seed)
        llh, vel, ps, vs = rng_gnss[noisy]
        outs = windows if name.endswith("outages") else ()
        run_p = dict(fp, **{k: fp[k] / 10 for k in NOISE_KEYS}) if name == "rtk_noise_div10" else fp
        f = quatnav.GpsInsFilter(**run_p)
        sm = smooth and bool(outs)
        r = f.run(gyro, accel, t=t, gps_pos=quatnav.Aid(w.gnss_t[g], llh[g], ps[g]),
                  gps_vel=quatnav.Aid(w.gnss_t[g], vel[g], vs[g]), outages=outs, smooth=sm)
        if sm:  # the smoothed run's score; the rest is the forward (causal) one's
            s_smoothed = score(w, r, outs)[0]
            r = r.forward
        s, a = score(w, r, outs)
        if sm:
            s["smoothed"] = s_smoothed
        nav = r.navigating
        s["navigating_from_s"] = float(r.t[nav][0] - t[0]) if nav.any() else None
        s["rejections"] = {k: int(v) for k, v in r.rejections.items()}
        s["gate_lockout_resets"] = {k: int(r.counters[k].get("resets", 0)) for k in ("gps_pos", "gps_vel")}
        s["decisions"] = {k: r.aids[k].decisions() for k in ("gps_pos", "gps_vel")}
        s["q_scale_max"] = float(np.max(r.q_scale))
        s["alignment"] = r.alignment
        nis = r.aids["gps_pos"].nis
        s["gps_pos_nis_mean"] = float(np.nanmean(nis)) if np.isfinite(nis).any() else None
        if noisy:
            e = ned_error(llh[g & w.fixed], w.gnss_llh[g & w.fixed])
            s["gnss_input_horizontal_rms_m"] = float(np.sqrt(np.mean(e[:, 0] ** 2 + e[:, 1] ** 2)))
        summary[name] = s
        arrays[name] = a
    return summary, arrays


def perturbation_table(directory=None, first=20.0, length=10.0, period=30.0) -> dict:
    """The robustness table of the simulated car (``gpsins_car.PERTURBATIONS``) on the walk: the
    RTK run with its outages, the noise densities as ``quatnav ins run`` sets them (the filter's
    defaults, or the setting's, raised to the log's and lowered to 3x it; the other entries of
    :data:`WALK_PARAMS` kept: the walk's alignment and priors), each setting changing one thing.
    Per setting: the drift at the end of each outage with RTK-fixed epochs, their mean and its
    ratio to the defaults', the horizontal RMS against the fixed epochs and the positions gated
    out."""
    from ..calibration.noise import lowered_noise, noise_in_motion, raised_noise
    from ..datasets import gnss_imu_walk as W
    from ..filters.tables import GPSINS_PARAMS
    from .gpsins_car import PERTURBATIONS, noise_scaled
    defaults = {q.name: q.default for q in GPSINS_PARAMS}
    w = W.load(directory)
    measured = noise_in_motion(w.imu_t, W.to_body(w.gyro_s), W.to_body(w.accel_s))
    out = {}
    for name, (extra, lever_err) in PERTURBATIONS.items():
        p = {k: defaults[k] for k in NOISE_KEYS}
        p.update(noise_scaled(float(extra[1:])) if isinstance(extra, str) else extra)
        given = {k: p[k] for k in ("gyro_noise", "acc_noise")}
        p.update(raised_noise(given, measured), **lowered_noise(given, measured))
        if lever_err is not None:
            p["lever_arm_b"] = tuple(float(x) for x in lever_err)
        summary, _ = run_walk(directory, first=first, length=length, period=period, runs=("rtk_outages",), params=p)
        s = summary["rtk_outages"]
        drift = [o["horizontal_at_end_m"] for o in s["outages"] if o["fixed_epochs"]]
        out[name] = {"drift_m": drift, "drift_mean_m": float(np.mean(drift)),
                     "horizontal_rms_m": s["outside_outages"]["horizontal_m"]["rms"],
                     "gps_pos": s["decisions"]["gps_pos"],
                     "noise": {k: float(summary["params"][k]) for k in NOISE_KEYS}}
    base = out["defaults"]["drift_mean_m"]
    for v in out.values():
        v["ratio"] = v["drift_mean_m"] / base
    return out


def outage_sweep(directory=None, firsts=range(15, 46, 5), seed=0, noise_m=2.5, length=10.0, period=30.0) -> dict:
    """Drift at the end of each outage over several outage phases (outages with >= 30 RTK-fixed
    epochs): median, 90th percentile, max, and the error over the filter's own one-sigma."""
    out = {"firsts_s": [float(f) for f in firsts]}
    for run in ("rtk_outages", "degraded_outages"):
        ends, sig, starts = [], [], []
        for first in firsts:
            s, _ = run_walk(directory, seed, noise_m, float(first), length, period, runs=(run,))
            for o in s[run]["outages"]:
                if o["fixed_epochs"] >= 30:
                    ends.append(o["horizontal_at_end_m"])
                    sig.append(o["sigma_h_at_end_m"])
                    starts.append(o["start_s"])
        e, sg = np.array(ends), np.array(sig)
        out[run] = {"n": int(len(e)), "starts_s": starts, "drift_at_end_m": e.tolist(),
                    "median_m": float(np.median(e)), "p90_m": float(np.percentile(e, 90)), "max_m": float(e.max()),
                    "min_m": float(e.min()), "error_over_sigma_median": float(np.median(e / sg)),
                    "error_over_sigma_max": float(np.max(e / sg)), "within_2_sigma": float(np.mean(e < 2 * sg))}
    return out


def _spans(t, gap: float = 1.0):
    """[(start, end), ...] of the runs of ``t`` (sorted) with no step longer than ``gap``."""
    if len(t) == 0:
        return []
    cut = np.flatnonzero(np.diff(t) > gap)
    return list(zip(t[np.r_[0, cut + 1]], t[np.r_[cut, len(t) - 1]]))


def plot(summary, arrays, path):
    """Horizontal error at the RTK-fixed epochs (log axis) of the runs with outages, beside the
    same GNSS without outages, with the filter's one-sigma; each outage is shaded only where
    RTK-fixed epochs exist to score it."""
    from matplotlib.lines import Line2D
    from matplotlib.patches import Patch

    from .._plotting import figure, legend_right, save
    t0 = summary["t0"]
    panels = [(n, n.replace("_outages", "")) for n in ("rtk_outages", "degraded_outages") if n in arrays]
    fig = figure((11.0, 3.6 * len(panels) + 0.8))
    ax = []
    for k, (name, base) in enumerate(panels):
        a = fig.add_subplot(len(panels), 1, k + 1, sharex=ax[0] if ax else None)
        ax.append(a)
        r = arrays[name]
        tr = r["t"] - t0
        if base in arrays:
            b = arrays[base]
            a.plot(b["t"] - t0, b["hz"], ".", ms=1.5, color="0.6")
        a.plot(tr, r["hz"], ".", ms=2.0, color="C0")
        a.plot(tr, r["sh"], "-", lw=0.9, color="C1")
        spans = _spans(tr)
        for s0, s1 in summary["outage_windows_s"]:
            for g0, g1 in spans:
                lo, hi = max(s0, g0), min(s1, g1)
                if hi > lo:
                    a.axvspan(lo, hi, color="#f4d6a0", lw=0, zorder=0)
        a.set_yscale("log")
        a.set_ylabel("horizontal error [m]")
        a.grid(True, which="major", alpha=0.35)
        a.grid(True, which="minor", alpha=0.12)
        what = "RTK GNSS" if base == "rtk" else f"GNSS with {summary['noise_m']:g} m noise added"
        a.set_title(f"{what}, outages of {summary['outage_windows_s'][0][1] - summary['outage_windows_s'][0][0]:.0f} s"
                    if summary["outage_windows_s"] else what, fontsize=9, loc="left")
        h = [Line2D([], [], ls="", marker=".", color="C0", label="with outages"),
             Line2D([], [], lw=0.9, color="C1", label="filter's 1-sigma"),
             Line2D([], [], ls="", marker=".", color="0.6", label="without outages"),
             Patch(color="#f4d6a0", label="GNSS outage (where\nRTK-fixed epochs exist)")]
        legend_right(a, h, [x.get_label() for x in h], markerscale=3)
    ends = [arrays[n]["t"] for n, _ in panels if len(arrays[n]["t"])]
    if ends:
        lo, hi = min(e[0] for e in ends) - t0, max(e[-1] for e in ends) - t0
        ax[0].set_xlim(lo - 2.0, hi + 2.0)
    ax[-1].set_xlabel(f"time from the IMU start [s] (RTK-fixed reference epochs only; the walk lasts "
                      f"{summary['duration_s']:.0f} s)")
    for a in ax[:-1]:
        a.tick_params(labelbottom=False)
    fig.suptitle("GpsInsFilter on the gnss_imu_walk data: horizontal error at the RTK-fixed epochs", fontsize=11)
    save(fig, path)
    return fig


def run(args) -> int:
    from .._command import UsageError, write_json
    for opt, v in (("--outage-length", args.outage_length), ("--outage-period", args.outage_period)):
        if not v > 0:
            raise UsageError(f"{opt}: expected a positive number of seconds, got {v:g}")
    try:
        summary, arrays = run_walk(args.data, args.seed, args.noise_m, args.outage_first, args.outage_length,
                                   args.outage_period, smooth=True)
    except FileNotFoundError as exc:
        raise UsageError(f"{exc} (use --data DIR or set QUATNAV_DATA to the folder that holds gnss_imu_walk/)") \
            from None
    if args.sweep:
        summary["outage_sweep"] = outage_sweep(args.data, seed=args.seed, noise_m=args.noise_m,
                                               length=args.outage_length, period=args.outage_period)
    if args.perturbation:
        summary["perturbation"] = perturbation_table(args.data, args.outage_first, args.outage_length,
                                                     args.outage_period)
    write_json(summary, args)
    if args.plot:
        plot(summary, arrays, args.plot)
    m = summary["mounting"]
    print(f"mounting: up axis {m['up_axis']} ({m['rest_accel_norm_g']:.4f} g at rest), yaw rate about down = "
          f"{m['yaw_rate_sign']:+d} x gyro_{m['up_axis'][1]}, forward at {m['forward_yaw_deg']:.1f} deg from x "
          f"(spread {m['forward_spread_deg']:.1f} deg; other sign {m['spread_other_sign_deg']:.1f} deg)")
    for name in RUNS:
        s = summary[name]
        a = s["all_fixed"]["horizontal_m"]
        line = (f"{name}: horizontal vs RTK-fixed RMS {a['rms']:.3f} m, max {a['max']:.3f} m; GNSS position "
                f"{s['decisions']['gps_pos']}")
        if s.get("during_outages"):
            d = s["during_outages"]["horizontal_m"]
            line += f"; during outages RMS {d['rms']:.3f} m, max {d['max']:.3f} m; drift at end " + ", ".join(
                f"{o['horizontal_at_end_m']:.2f}" for o in s["outages"] if o["fixed_epochs"]) + " m"
        if "gnss_input_horizontal_rms_m" in s:
            line += f" (noisy GNSS input RMS {s['gnss_input_horizontal_rms_m']:.2f} m)"
        print(line)
        if s.get("smoothed", {}).get("during_outages"):
            z = s["smoothed"]
            worst = [(o["horizontal_max_m"], q["horizontal_max_m"]) for o, q in zip(s["outages"], z["outages"])
                     if o["fixed_epochs"]]
            print(f"{name} smoothed: during outages RMS {z['during_outages']['horizontal_m']['rms']:.3f} m, max "
                  f"{z['during_outages']['horizontal_m']['max']:.3f} m; worst per outage smoothed/forward "
                  + ", ".join(f"{b:.2f}/{a:.2f}" for a, b in worst) + " m")
    if args.sweep:
        for run in ("rtk_outages", "degraded_outages"):
            w = summary["outage_sweep"][run]
            print(f"sweep {run}: {w['n']} outages, drift at end median {w['median_m']:.2f} m, 90% {w['p90_m']:.2f} m, "
                  f"max {w['max_m']:.2f} m; error/sigma median {w['error_over_sigma_median']:.2f}, "
                  f"max {w['error_over_sigma_max']:.2f}")
    if args.perturbation:
        print("robustness (RTK with outages, noise as 'ins run' sets it): drift at the end of each outage with "
              "RTK-fixed epochs (m), their mean and its ratio to the defaults'")
        for name, v in summary["perturbation"].items():
            print(f"  {name:24s} " + ", ".join(f"{x:6.2f}" for x in v["drift_m"])
                  + f"   mean {v['drift_mean_m']:6.2f}   ratio {v['ratio']:.2f}")
    return 0
