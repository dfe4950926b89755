"""GpsInsFilter on the simulated car with RTK GNSS (``quatnav.sim.car``, scenario ``car_rtk``),
Monte Carlo over seeds: ``quatnav experiment gpsins-car [--seeds N] [--table perturbation]
[--json FILE]``.

Each seed is a new drive (sensor errors, vibration, timing, RTK stretches and jumps, mounting
error drawn anew) run three times with the filter's defaults and only the lever arm given: with
every fix, with the four 30 s outages and with the three 60 s outages of the scenario. Reported
over the seeds: the horizontal error while aided (RMS against the truth), the fixes gated out by
solution kind (RTK fixed / float / single), the drift at the end of each outage (mean, worst), the
heading error above 5 m/s, and the consistency: the mean over the navigating samples (every 1 s
after 40 s) of the squared errors of position, velocity and attitude over the filter's own
variances (per component, so the mean is 1 for a consistent filter whatever the correlations),
per run and over the runs.

As ``quatnav ins run`` does, the white-noise densities (``gyro_noise``, ``acc_noise``) given or
defaulted are raised to those the drive's IMU shows, vibration included
(:func:`quatnav.calibration.noise.noise_in_motion`), where they are more than 1.2x below them,
and lowered to 3x them where more than 3x above (``--noise-as-given``: neither).

``--table perturbation`` runs the settings of the robustness table (a 20 ms GNSS time sigma, a
5 cm position sigma floor, the learned non-holonomic constraint off, the lever arm off by 5 cm,
the IMU noise densities times 0.1 and times 10) and gives each one's 30 s drift against the
defaults'.
"""
from __future__ import annotations

import math

import numpy as np

SUMMARY = "GpsInsFilter on the simulated RTK car: Monte Carlo of outage drift, rejected fixes, NEES; robustness table"

NOISE_KEYS = ("gyro_noise", "acc_noise", "gyro_bias_noise", "acc_bias_noise")
#: The settings of the robustness table: name -> (parameters, lever-arm error in m).
PERTURBATIONS = {
    "defaults": ({}, None),
    "gps_time_sigma=0.02": (dict(gps_time_sigma=0.02), None),
    "gps_pos_sigma_min=0.05": (dict(gps_pos_sigma_min=0.05), None),
    "nhc_auto=false": (dict(nhc_auto=False), None),
    "lever arm +5 cm": ({}, (0.03, 0.03, 0.03)),
    "noise x0.1": ("x0.1", None),
    "noise x10": ("x10", None),
}
QUALITY_NAMES = {1: "fixed", 2: "float", 5: "single"}


def add_arguments(parser) -> None:
    parser.add_argument("--seeds", type=int, default=20, help="number of simulated drives (seeds 0..N-1; default 20)")
    parser.add_argument("--first-seed", type=int, default=0, help="first seed (default 0)")
    parser.add_argument("--table", choices=("defaults", "perturbation"), default="defaults",
                        help="defaults only, or every setting of the robustness table")
    parser.add_argument("--set", metavar="NAME=VALUE", action="append", default=[],
                        help="a filter parameter for every setting (repeatable), e.g. --set pseudo_interval=1.0")
    parser.add_argument("--noise-as-given", action="store_true",
                        help="the noise densities as given; by default raised to the log's (lowered to 3x it) as 'ins run' does")
    parser.add_argument("--json", metavar="FILE", help="write the results here ('-': stdout)")


def noise_scaled(factor: float) -> dict:
    """The IMU noise densities of the defaults times ``factor``."""
    from ..filters.tables import GPSINS_PARAMS
    d = {p.name: p.default for p in GPSINS_PARAMS}
    return {k: d[k] * factor for k in NOISE_KEYS}


def filter_params(s, setting="defaults", base=None, noise_from_log=True) -> dict:
    """The parameters a user gives for scenario ``s`` under ``setting`` (PERTURBATIONS), on top of
    ``base`` (parameters for every setting); with ``noise_from_log`` the white-noise densities
    raised to the log's (or lowered to 3x it) as ``ins run`` does
    (:func:`quatnav.calibration.noise.raised_noise`, :func:`~quatnav.calibration.noise.lowered_noise`)."""
    extra, lever_err = PERTURBATIONS[setting]
    if isinstance(extra, str):
        extra = noise_scaled(float(extra[1:]))
    lever = np.asarray(s.params["sensor_model"]["lever_arm_b_m"], float)
    if lever_err is not None:
        lever = lever + np.asarray(lever_err)
    p = {**(base or {}), "lever_arm_b": tuple(lever), **extra}
    if noise_from_log:
        from ..calibration.noise import lowered_noise, noise_in_motion, raised_noise
        from ..filters.tables import GPSINS_PARAMS
        given = {q.name: p.get(q.name, q.default) for q in GPSINS_PARAMS if q.name in ("gyro_noise", "acc_noise")}
        measured = noise_in_motion(s.imu.t, s.imu.gyro, s.imu.accel)
        p.update(raised_noise(given, measured), **lowered_noise(given, measured))
    return p


def aids(s) -> dict:
    """The GNSS of scenario ``s`` as a user passes it: positions with the receiver's one-sigma and
    solution kind (RTKLIB's Q), velocities without a sigma (the filter's gps_vel_sigma)."""
    from .. import Aid
    from ..filters.gpsins import gnss_solution
    g = s.gps
    llh = np.column_stack([g.lat, g.lon, g.h])
    return dict(gps_pos=Aid(g.t_valid, llh, g.sigma), gps_vel=Aid(g.t_valid, g.v_n),
                gps_solution=gnss_solution(g.quality, "rtklib"))


def truth_at(s, r):
    """The truth at the times of result ``r``'s outputs, ``r.t`` on the GNSS clock: (lat, lon, h,
    v_n, q_nb of the IMU axes), interpolated on the trajectory (linear; attitude by the rotation
    vector between neighbours).

    The IMU stamps its samples late (``imu_delay_s``, 2-12 ms, which the filter is not told); the
    fixes, which hold the filter's position and velocity, carry their GPS time of validity. An
    output stamped ``t`` is what a user takes for the vehicle at GPS time ``t``, and that is
    what it is compared with: the truth at the sample's true time (``t`` less the delay) would
    count the vehicle's motion over the delay (up to 0.3 m at 25 m/s) as the filter's error."""
    from ..core import quaternion as Q
    tr = s.truth
    x = (np.asarray(r.t, float) - tr.t[0]) * tr.rate_hz
    i = np.clip(np.floor(x).astype(int), 0, len(tr.t) - 2)
    f = np.clip(x - i, 0.0, 1.0)

    def lin(a):
        a = np.asarray(a, float)
        ff = f if a.ndim == 1 else f[:, None]
        return a[i] * (1.0 - ff) + a[i + 1] * ff
    q0 = tr.q_nb[i]
    d = Q.to_rotvec(Q.mul(Q.conj(q0), tr.q_nb[i + 1]))
    q = Q.mul(q0, Q.from_rotvec(d * f[:, None]))
    q_b_imu = np.asarray(s.params["sensor_model"]["q_b_imu"])
    return lin(tr.lat), lin(tr.lon), lin(tr.h), lin(tr.v_n), Q.mul(q, q_b_imu)


def errors(s, r) -> dict:
    """Estimate minus truth at every IMU sample (NaN before navigation): ``dp`` NED m, ``dv``
    m/s, ``psi`` rad (the filter's phi-angle), ``yaw`` rad."""
    from ..core import earth
    from ..core import quaternion as Q
    lat, lon, h, v, q = truth_at(s, r)
    R_M, R_N = earth.radii(lat)
    p = r.position
    dp = np.column_stack([(p[:, 0] - lat) * (R_M + h), (p[:, 1] - lon) * (R_N + h) * np.cos(lat), -(p[:, 2] - h)])
    dv = r.velocity - v
    ok = np.isfinite(r.quat[:, 0])
    psi = np.full((len(q), 3), np.nan)
    psi[ok] = Q.to_rotvec(Q.mul(r.quat[ok], Q.conj(q[ok])))
    yaw = np.full(len(q), np.nan)
    yaw[ok] = np.angle(np.exp(1j * (Q.to_euler(r.quat[ok])[:, 2] - Q.to_euler(q[ok])[:, 2])))
    return {"dp": dp, "dv": dv, "psi": psi, "yaw": yaw}


def nees_per_run(r, e, t0=40.0, every=1.0):
    """Per block (position, velocity, attitude, all nine) the mean over the samples every
    ``every`` s after ``t0`` of the squared errors over the filter's variances, per component
    (1 for a consistent filter); ``heading`` the attitude's down component alone (tilt is
    north and east)."""
    t = r.t - r.t[0]
    k = np.searchsorted(t, np.arange(t0, t[-1], every))
    k = k[r.navigating[k]]
    z = np.column_stack([e["dp"][k], e["dv"][k], e["psi"][k]]) / r.sigma[k, :9]
    z2 = z ** 2
    return {"position": float(z2[:, 0:3].mean()), "velocity": float(z2[:, 3:6].mean()),
            "attitude": float(z2[:, 6:9].mean()), "heading": float(z2[:, 8].mean()), "all": float(z2.mean())}


def nees_per_axis(r, e, outages, inside=True, t0=40.0, every=1.0):
    """Per block (position, velocity, attitude) the mean of the squared error over the filter's
    variance for each NED axis (attitude: north and east are tilt, down the heading), over the
    samples every ``every`` s after ``t0`` inside the outage windows (``inside``) or outside them
    (while aided)."""
    t = r.t - r.t[0]
    k = np.searchsorted(t, np.arange(t0, t[-1], every))
    k = k[r.navigating[k]]
    w = np.zeros(len(k), bool)
    for a, b in outages:
        w |= (r.t[k] >= a) & (r.t[k] < b)
    k = k[w] if inside else k[~w]
    z2 = (np.column_stack([e["dp"][k], e["dv"][k], e["psi"][k]]) / r.sigma[k, :9]) ** 2
    m = z2.mean(axis=0)
    return {"position": m[0:3].tolist(), "velocity": m[3:6].tolist(), "attitude": m[6:9].tolist()}


def outage_drift(s, r, e, outages):
    """Horizontal error (m) at the end of each outage: the last IMU sample before the first fix
    after it (the outage windows on the GNSS clock, put on the IMU's by gps_time_offset)."""
    out = []
    for a, b in outages:
        k = int(np.searchsorted(r.t, b)) - 1
        out.append(float(np.hypot(*e["dp"][k, :2])))
    return out


def rejected_by_quality(s, r) -> dict:
    """Position and velocity fixes gated out (or reset) per solution kind."""
    g = r.aids["gps_pos"]
    q = s.gps.quality
    out = {}
    for code, name in QUALITY_NAMES.items():
        m = q == code
        d = r.aids["gps_pos"].decision_names
        dv = r.aids["gps_vel"].decision_names if "gps_vel" in r.aids else np.array([])
        out[name] = {"fixes": int(m.sum()), "pos_rejected": int(np.isin(d[m], ("rejected", "reset")).sum()),
                     "vel_rejected": int(np.isin(dv[m], ("rejected", "reset")).sum()) if len(dv) else 0}
    del g
    return out


def run_seed(seed: int, settings=("defaults",), base=None, noise_from_log=True) -> dict:
    """Every setting on the drive of ``seed``: with every fix, the 30 s and the 60 s outages."""
    import quatnav
    from ..sim.car import car_rtk
    s = car_rtk(seed=seed)
    ev = s.params["events"]
    a = aids(s)
    res = {}
    for setting in settings:
        p = filter_params(s, setting, base, noise_from_log)
        row = {}
        for kind, outages in (("all", ()), ("30", ev["outages_30"]), ("60", ev["outages_60"])):
            if kind != "30" and setting != "defaults":
                continue  # the robustness table judges the 30 s drift
            r = quatnav.GpsInsFilter(**p).run(s.imu.gyro, s.imu.accel, t=s.imu.t, outages=outages, **a)
            e = errors(s, r)
            t = r.t - r.t[0]
            if kind == "all":
                aided = r.navigating & (t > 40.0)
                speed = np.linalg.norm(s.truth.v_n[s.imu.index], axis=1)
                fast = aided & (speed > 5.0)
                row["all"] = {"horizontal_rms_m": float(np.sqrt(np.nanmean(np.sum(e["dp"][aided, :2] ** 2, axis=1)))),
                              "heading_rms_deg": float(np.degrees(np.sqrt(np.nanmean(e["yaw"][fast] ** 2)))),
                              "rejected": rejected_by_quality(s, r), "nees": nees_per_run(r, e),
                              "navigating_from_s": float(t[np.argmax(r.navigating)])}
            else:
                row[kind] = {"drift_m": outage_drift(s, r, e, outages), "nees": nees_per_run(r, e),
                             "nees_outage": nees_per_axis(r, e, outages),
                             "nees_aided": nees_per_axis(r, e, outages, inside=False)}
        res[setting] = row
    return res


def summarize(runs: list, settings) -> dict:
    """Over the seeds: means and worst cases (see the module docstring)."""
    out = {}
    for setting in settings:
        rows = [r[setting] for r in runs]
        d = {}
        if "all" in rows[0]:
            rej = {q: {k: int(sum(r["all"]["rejected"][q][k] for r in rows)) for k in ("fixes", "pos_rejected",
                                                                                     "vel_rejected")}
                   for q in QUALITY_NAMES.values()}
            d["all"] = {"horizontal_rms_m": float(np.mean([r["all"]["horizontal_rms_m"] for r in rows])),
                        "heading_rms_deg": float(np.mean([r["all"]["heading_rms_deg"] for r in rows])),
                        "rejected": rej,
                        "nees": {b: _mean_se([r["all"]["nees"][b] for r in rows]) for b in rows[0]["all"]["nees"]}}
        for kind in ("30", "60"):
            if kind in rows[0]:
                drift = np.array([r[kind]["drift_m"] for r in rows])
                d[kind] = {"drift_mean_m": float(drift.mean()), "drift_worst_m": float(drift.max()),
                           "drift_median_m": float(np.median(drift)),
                           "drift_mean_per_outage_m": drift.mean(axis=0).tolist(),
                           "nees": {b: _mean_se([r[kind]["nees"][b] for r in rows]) for b in rows[0][kind]["nees"]}}
                for part in ("nees_outage", "nees_aided"):
                    if part in rows[0][kind]:
                        d[kind][part] = {b: np.mean([r[kind][part][b] for r in rows], axis=0).tolist()
                                         for b in rows[0][kind][part]}
        out[setting] = d
    return out


def _mean_se(x):
    x = np.asarray(x, float)
    return {"mean": float(x.mean()), "se": float(x.std(ddof=1) / math.sqrt(len(x))) if len(x) > 1 else float("nan"),
            "min": float(x.min()), "max": float(x.max())}


def monte_carlo(seeds, settings=("defaults",), base=None, noise_from_log=True) -> dict:
    """:func:`run_seed` over ``seeds``: ``{"seeds", "summary", "runs", "base", "noise_from_log"}``."""
    runs = [run_seed(int(k), settings, base, noise_from_log) for k in seeds]
    return {"seeds": [int(k) for k in seeds], "base": dict(base or {}), "noise_from_log": bool(noise_from_log),
            "summary": summarize(runs, settings), "runs": runs}


def table(res) -> str:
    sm = res["summary"]
    lines = []
    d = sm.get("defaults", {})
    if "all" in d:
        a = d["all"]
        lines.append(f"seeds {res['seeds'][0]}..{res['seeds'][-1]} ({len(res['seeds'])} drives), defaults with the lever arm:")
        lines.append(f"  horizontal RMS aided {a['horizontal_rms_m']:.3f} m, heading RMS above 5 m/s {a['heading_rms_deg']:.2f} deg")
        for q, v in a["rejected"].items():
            lines.append(f"  {q:6s} fixes {v['fixes']:6d}: positions gated out {v['pos_rejected']:5d}, "
                         f"velocities {v['vel_rejected']:5d}")
        lines.append("  NEES per component (1 = consistent), mean +- se over the runs: " + ", ".join(
            f"{b} {v['mean']:.2f}+-{v['se']:.2f}" for b, v in a["nees"].items()))
    for kind in ("30", "60"):
        if kind in d:
            k = d[kind]
            lines.append(f"  {kind} s outages: drift mean {k['drift_mean_m']:.2f} m, median {k['drift_median_m']:.2f}, "
                         f"worst {k['drift_worst_m']:.2f}; per outage " + ", ".join(f"{x:.2f}" for x in
                                                                                  k["drift_mean_per_outage_m"])
                         + "; NEES all " + f"{k['nees']['all']['mean']:.2f}")
            for part, label in (("nees_outage", "inside the outages"), ("nees_aided", "while aided")):
                if part in k:
                    lines.append(f"    NEES per axis N/E/D {label}: " + "; ".join(
                        f"{b} " + "/".join(f"{x:.2f}" for x in v) for b, v in k[part].items()))
    if len(sm) > 1:
        base = sm["defaults"]["30"]["drift_mean_m"]
        lines.append("robustness, 30 s drift mean / worst (m) and the mean's ratio to the defaults':")
        for name, v in sm.items():
            lines.append(f"  {name:24s} {v['30']['drift_mean_m']:8.2f} {v['30']['drift_worst_m']:8.2f} "
                         f"{v['30']['drift_mean_m'] / base:6.2f}")
    return "\n".join(lines)


def run(args) -> int:
    import json
    import sys
    import ast
    settings = tuple(PERTURBATIONS) if args.table == "perturbation" else ("defaults",)
    base = {}
    for item in args.set:
        name, _, value = item.partition("=")
        try:
            base[name.strip()] = ast.literal_eval(value.strip())
        except (ValueError, SyntaxError):
            base[name.strip()] = value.strip()
    res = monte_carlo(range(args.first_seed, args.first_seed + args.seeds), settings, base,
                      noise_from_log=not args.noise_as_given)
    text = table(res)
    if args.json:
        doc = json.dumps(res, indent=1)
        if args.json == "-":
            print(doc)
            print(text, file=sys.stderr)
            return 0
        with open(args.json, "w") as fh:
            fh.write(doc)
    print(text)
    return 0
