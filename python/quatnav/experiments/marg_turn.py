"""``quatnav experiment marg-turn``: paper 001's constant-rate turn, before and after the GPS
acceleration correction (eq. 7), Monte Carlo over seeds.

    quatnav experiment marg-turn --json FILE [--plot FILE.png] [--seeds 20] [--gain 1.0]

Scenario ``paper001_constant_turn`` (:mod:`quatnav.sim`): rest, accelerate, straight, a 60 s
level turn at 12 deg/s and 10 m/s (centripetal ~2.1 m/s^2), straight; the GPS antenna is offset
from the IMU by a lever arm. Truth roll and pitch are zero throughout the turn, so every degree
of roll or pitch the filter reports there is error.

Variants, all on the same sensor data of each seed:

* ``uncorrected``: MargFilter without GPS (the accelerometer taken as gravity);
* ``gps_no_lever``: GPS antenna acceleration removed, lever-arm terms left out (d = 0);
* ``corrected``: the full correction of eq. (7) (GPS acceleration and lever-arm terms);
* ``corrected_no_declination``: as ``corrected`` but with the GPS acceleration taken as if true
  north were magnetic north (the scenario's declination is -8.5 deg): the filter's frame is
  magnetic NED, so the turn acceleration is misplaced by sin(8.5 deg) of itself;
* ``qekf``: the QuaternionEKF of paper 000 on the accelerometer and magnetometer (no GPS).

Reported also: a diagnosis of the lever-arm terms (see :func:`diagnose_lever_arm`).

Reported: roll and pitch RMSE (deg) in the turn and over the whole run, per seed and as
mean/std over seeds; the figure shows roll and pitch of one seed, before (dotted) and after
(solid) the correction, like the paper's Fig. 4.
"""
from __future__ import annotations


import numpy as np

from ..core import quaternion as Q

SCENARIO = "paper001_constant_turn"
VARIANTS = ("uncorrected", "gps_no_lever", "corrected", "corrected_no_declination", "qekf")


#: One line for ``quatnav experiment -h``.
SUMMARY = ("MargFilter roll/pitch in a constant-rate turn before and after the GPS-acceleration correction, "
           "over seeds (paper 001)")


def add_arguments(parser) -> None:
    parser.add_argument("--json", metavar="FILE", help="write the figures to this JSON file ('-': stdout)")
    parser.add_argument("--plot", metavar="FILE.png", help="write a figure like the paper's Fig. 4")
    parser.add_argument("--seeds", type=int, default=20, help="Monte Carlo runs, seeds 0..N-1 (default 20)")
    parser.add_argument("--gain", type=float, default=1.0, help="MargFilter gain k of eq. (6), 1/s (default 1)")
    parser.add_argument("--gps-tau", type=float, default=0.05,
                        help="low-pass time constant of the GPS acceleration, s (default 0.05)")


def _inputs(s):
    """IMU, magnetometer (aligned to the IMU samples) and GPS arrays of a scenario."""
    imu = s.imu
    n = len(imu.t)
    mag = np.full((n, 3), np.nan)
    pos = np.searchsorted(imu.index, s.mag.index)
    ok = (pos < n) & (imu.index[np.minimum(pos, n - 1)] == s.mag.index)
    mag[pos[ok]] = s.mag.mag[ok]
    truth_q = s.truth.q_nb[imu.index]
    return dict(t=imu.t, gyr=imu.gyro, acc=imu.accel, mag=mag, gps_t=s.gps.t_valid, gps_vel_n=s.gps.v_n,
                q_true=truth_q, rate_z=s.truth.omega_nb_b[imu.index, 2],
                lever=np.asarray(s.params["gps"]["lever_arm_b_m"], float),
                declination=float(np.radians(s.params["mag"]["declination_deg"])))


def _tilt_errors(quat, q_true):
    """Roll and pitch errors (rad) of estimates against truth, as (N, 2)."""
    e = Q.to_euler(quat)[:, :2] - Q.to_euler(q_true)[:, :2]
    return np.vstack([Q.wrap_pi(e[:, 0]), e[:, 1]]).T


def run_seed(s, gain: float = 1.0, gps_tau: float = 0.05, keep_series: bool = False) -> dict:
    """Run every variant on one scenario; return the RMSE figures (deg) and optionally series."""
    from .. import Aid, MargFilter, QuaternionEKF
    d = _inputs(s)
    t = d["t"]
    est = {}
    est["uncorrected"] = MargFilter(gain=gain).run(d["gyr"], d["acc"], d["mag"], t=t).quat
    gps = dict(gps_vel=Aid(d["gps_t"], d["gps_vel_n"]))
    mf = dict(gain=gain, gps_acc_tau=gps_tau)
    est["gps_no_lever"] = MargFilter(declination=d["declination"], **mf).run(
        d["gyr"], d["acc"], d["mag"], t=t, **gps).quat
    est["corrected"] = MargFilter(declination=d["declination"], lever_arm_b=d["lever"], **mf).run(
        d["gyr"], d["acc"], d["mag"], t=t, **gps).quat
    est["corrected_no_declination"] = MargFilter(lever_arm_b=d["lever"], **mf).run(
        d["gyr"], d["acc"], d["mag"], t=t, **gps).quat
    est["qekf"] = QuaternionEKF().run(d["gyr"], d["acc"], d["mag"], t=t).quat
    rate = np.abs(d["rate_z"])
    turn = rate > 0.5 * rate.max()
    settled = t >= t[0] + 1.0
    out = {"seed": int(s.seed), "turn_s": [float(t[turn][0]), float(t[turn][-1])], "rmse_deg": {}}
    series = {}
    for name, q in est.items():
        e = np.degrees(_tilt_errors(q, d["q_true"]))
        series[name] = e
        r_turn = np.sqrt(np.mean(e[turn] ** 2, axis=0))
        r_all = np.sqrt(np.mean(e[settled] ** 2, axis=0))
        out["rmse_deg"][name] = {
            "roll_turn": float(r_turn[0]), "pitch_turn": float(r_turn[1]),
            "turn": float(np.sqrt(np.mean(np.sum(e[turn] ** 2, axis=1)))),
            "roll_all": float(r_all[0]), "pitch_all": float(r_all[1]),
        }
    if keep_series:
        out["series"] = dict(t=t, truth=np.degrees(Q.to_euler(d["q_true"])[:, :2]),
                             est={k: np.degrees(Q.to_euler(v)[:, :2]) for k, v in est.items()}, turn=turn)
    return out


def diagnose_lever_arm(s, gps_taus=(0.02, 0.05, 0.1, 0.2), gain: float = 1.0) -> dict:
    """Why the lever-arm terms gain little here.

    * ``exact``: sensors without errors (truth specific force and rate, the antenna velocity of
      the truth at every IMU sample, no low-pass): the tilt RMSE (deg) in the turn without and
      with the lever-arm terms. It isolates eq. (7')'s lever-arm part.
    * ``lag``: the mean pitch error (deg) in the turn, on the simulated sensors, for several
      GPS-acceleration time constants, without and with the lever-arm terms. The GPS
      acceleration lags by about half the fix interval plus the time constant; in the turn the
      lagged vector points behind the true one, an along-track error of a_c * yaw_rate * lag of
      opposite sign to the neglected lever-arm term, so the two partly cancel.
    """
    from .. import Aid, MargFilter
    tr = s.truth
    lever = np.asarray(s.params["gps"]["lever_arm_b_m"], float)
    dec = float(np.radians(s.params["mag"]["declination_deg"]))
    w = tr.omega_ib_b
    v_ant = tr.v_n + Q.rotate(tr.q_nb, np.cross(w, lever))
    mag = Q.rotate_inv(tr.q_nb, np.broadcast_to(s.mag.field_n, (len(tr.t), 3)))
    turn = np.abs(tr.omega_nb_b[:, 2]) > 0.5 * np.abs(tr.omega_nb_b[:, 2]).max()
    out = {"exact": {}, "lag": {}}
    for lev in (False, True):
        kw = dict(gain=gain, declination=dec, gps_acc_tau=0.0, gn_max_iter=10, gn_tol=1e-12)
        if lev:
            kw["lever_arm_b"] = lever
        q = MargFilter(**kw).run(w, tr.f_ib_b, mag, t=tr.t, gps_vel=Aid(tr.t, v_ant)).quat
        e = np.degrees(_tilt_errors(q, tr.q_nb))[turn]
        out["exact"]["with_lever" if lev else "without_lever"] = float(np.sqrt(np.mean(np.sum(e**2, axis=1))))
    d = _inputs(s)
    gps = dict(gps_vel=Aid(d["gps_t"], d["gps_vel_n"]))
    turn_imu = np.abs(d["rate_z"]) > 0.5 * np.abs(d["rate_z"]).max()
    for tau in gps_taus:
        row = {}
        for lev in (False, True):
            kw = dict(gain=gain, declination=d["declination"], gps_acc_tau=tau)
            if lev:
                kw["lever_arm_b"] = d["lever"]
            q = MargFilter(**kw).run(d["gyr"], d["acc"], d["mag"], t=d["t"], **gps).quat
            e = np.degrees(_tilt_errors(q, d["q_true"]))[turn_imu]
            row["with_lever" if lev else "without_lever"] = float(e[:, 1].mean())
        out["lag"][str(tau)] = row
    return out


def monte_carlo(seeds: int = 20, gain: float = 1.0, gps_tau: float = 0.05, keep_first: bool = False):
    from ..sim import make_scenario
    runs = []
    first = None
    for seed in range(seeds):
        r = run_seed(make_scenario(SCENARIO, seed=seed), gain=gain, gps_tau=gps_tau, keep_series=keep_first and seed == 0)
        if "series" in r:
            first = r.pop("series")
        runs.append(r)
    summary = {}
    for v in VARIANTS:
        summary[v] = {}
        for key in runs[0]["rmse_deg"][v]:
            x = np.array([r["rmse_deg"][v][key] for r in runs])
            summary[v][key] = {"mean": float(x.mean()), "std": float(x.std(ddof=1)) if len(x) > 1 else 0.0}
    res = {"scenario": SCENARIO, "seeds": seeds, "gain_per_s": gain, "gps_acc_tau_s": gps_tau, "summary_rmse_deg": summary, "runs": runs}
    res["diagnosis_seed0"] = diagnose_lever_arm(make_scenario(SCENARIO, seed=0), gain=gain)
    u, c = summary["uncorrected"]["turn"]["mean"], summary["corrected"]["turn"]["mean"]
    res["turn_tilt_rmse_reduction"] = float(1 - c / u) if u > 0 else None
    return res, first


def plot(series, path):
    from matplotlib.patches import Patch

    from .._plotting import figure, legend_right, save
    t = series["t"]
    fig = figure((10.5, 6.5))
    a0 = fig.add_subplot(2, 1, 1)
    axes = [a0, fig.add_subplot(2, 1, 2, sharex=a0)]
    turn_t = t[series["turn"]]
    for i, name in enumerate(("roll", "pitch")):
        ax = axes[i]
        ax.plot(t, series["est"]["uncorrected"][:, i], ":", color="tab:red", label="before correction")
        ax.plot(t, series["est"]["corrected"][:, i], "-", color="tab:blue", lw=1.0, label="after correction (eq. 7)")
        ax.plot(t, series["truth"][:, i], "-", color="k", lw=0.8, label="truth")
        ax.set_ylabel(f"{name} [deg]")
        ax.grid(True, alpha=0.3)
        ax.axvspan(turn_t[0], turn_t[-1], color="0.9", lw=0, zorder=0)
        ax.set_xlim(t[0], t[-1])
    axes[0].tick_params(labelbottom=False)
    h, lab = axes[0].get_legend_handles_labels()
    h.append(Patch(color="0.9"))
    lab.append("constant-rate turn")
    legend_right(axes[0], h, lab)
    axes[1].set_xlabel("time [s]")
    fig.suptitle("paper 001 constant-rate turn (seed 0): attitude before (dotted) and after (solid) the GPS "
                 "correction", fontsize=11)
    save(fig, path, dpi=120)
    return fig


def run(args) -> int:
    from .._command import UsageError, write_json
    if args.seeds < 1:
        raise UsageError(f"--seeds: expected a positive integer, got {args.seeds}")
    res, first = monte_carlo(args.seeds, args.gain, args.gps_tau, keep_first=bool(args.plot))
    s = res["summary_rmse_deg"]
    print(f"{SCENARIO}: {args.seeds} seeds, gain k = {args.gain} 1/s; roll/pitch RMSE [deg], mean over seeds")
    print(f"{'variant':25s} {'roll(turn)':>11s} {'pitch(turn)':>12s} {'tilt(turn)':>11s} {'roll(all)':>10s} {'pitch(all)':>11s}")
    for v in VARIANTS:
        r = s[v]
        print(f"{v:25s} {r['roll_turn']['mean']:11.3f} {r['pitch_turn']['mean']:12.3f} {r['turn']['mean']:11.3f} "
              f"{r['roll_all']['mean']:10.3f} {r['pitch_all']['mean']:11.3f}")
    print(f"tilt RMSE in the turn reduced by {100 * res['turn_tilt_rmse_reduction']:.1f} % by the correction")
    dg = res["diagnosis_seed0"]
    print(f"seed 0, exact sensors, tilt RMSE in the turn [deg]: without lever-arm terms "
          f"{dg['exact']['without_lever']:.3f}, with {dg['exact']['with_lever']:.3f}")
    print("seed 0, mean pitch error in the turn [deg] vs GPS-acceleration time constant (lag):")
    for tau, row in dg["lag"].items():
        print(f"  tau {float(tau):5.2f} s: without lever-arm terms {row['without_lever']:+.3f}, "
              f"with {row['with_lever']:+.3f}")
    write_json(res, args)
    if args.plot:
        plot(first, args.plot)
    return 0
