"""Paper 004 on the simulated scenarios: ``quatnav experiment gpsins --scenario static|turntable|walk
--json FILE [--seed N] [--outage-start S] [--outage-length S]``.

Runs :class:`quatnav.GpsInsFilter` (GPS with lever arm, altimeter and its vertical velocity,
compass) on the simulator's paper-004 scenario, once with every GPS fix and once with a GPS
outage, and reports against the truth: horizontal and vertical position error (RMS, max), Euler
angle errors (RMS, max, deg), the chi-square rejections, and the horizontal drift during the
outage with the filter's own one-sigma at its end.
"""
from __future__ import annotations

import json

import numpy as np

from ..sim.scenarios import make_scenario

SCENARIOS = ("static", "turntable", "walk")
_A, _E2 = 6378137.0, 6.69437999014e-3  # WGS-84


def add_arguments(parser) -> None:
    parser.add_argument("--scenario", choices=SCENARIOS, default="walk", help="paper 004 scenario (default walk)")
    parser.add_argument("--json", required=True, metavar="FILE", help="write the results here")
    parser.add_argument("--seed", type=int, default=0, help="simulation seed (default 0)")
    parser.add_argument("--outage-start", type=float, default=None,
                        help="GPS outage start (s); default: the middle of the run")
    parser.add_argument("--outage-length", type=float, default=10.0, help="GPS outage length (s), default 10")


def _aids(s):
    return dict(gps_t=s.gps.t_valid, gps_llh=np.column_stack([s.gps.lat, s.gps.lon, s.gps.h]),
                gps_vel=s.gps.v_n, baro_t=s.baro.t, baro_h=s.baro.h, compass_t=s.compass.t,
                compass_yaw=s.compass.yaw)


def errors(s, r) -> dict:
    """Errors of a run against the truth at the IMU times where the filter navigates."""
    nav = r.navigating
    i = np.searchsorted(s.truth.t, r.t[nav])
    lat, h = s.truth.lat[i], s.truth.h[i]
    sl2 = np.sin(lat) ** 2
    rm = _A * (1 - _E2) / (1 - _E2 * sl2) ** 1.5
    rn = _A / np.sqrt(1 - _E2 * sl2)
    dn = (r.llh[nav, 0] - lat) * (rm + h)
    de = (r.llh[nav, 1] - s.truth.lon[i]) * (rn + h) * np.cos(lat)
    dd = -(r.llh[nav, 2] - h)
    deul = r.euler[nav] - s.truth.rpy[i]
    deul = np.angle(np.exp(1j * deul))
    return dict(t=r.t[nav], horiz=np.hypot(dn, de), down=dd, euler_deg=np.degrees(deul),
                sigma_h=np.hypot(r.sigma[nav, 0], r.sigma[nav, 1]))


def _stats(x):
    x = np.abs(np.asarray(x))
    return {"rms": float(np.sqrt(np.mean(x ** 2))), "max": float(np.max(x))}


def run_scenario(name: str, seed: int = 0, outage_start=None, outage_length: float = 10.0) -> dict:
    import quatnav

    s = make_scenario(f"paper004_{name}", seed=seed)
    lever = tuple(s.params.get("gps", {}).get("lever_arm_b_m", (0.1, 0.0, -0.1))) \
        if isinstance(s.params.get("gps"), dict) else (0.1, 0.0, -0.1)
    f = quatnav.GpsInsFilter(lever_arm_b=lever)
    r = f.run(s.imu.t, s.imu.gyro, s.imu.accel, **_aids(s))
    e = errors(s, r)
    out = {"scenario": s.name, "seed": seed, "duration_s": float(s.imu.t[-1] - s.imu.t[0]),
           "navigating_from_s": float(e["t"][0]),
           "horizontal_m": _stats(e["horiz"]), "down_m": _stats(e["down"]),
           "euler_deg": {k: _stats(e["euler_deg"][:, j]) for j, k in enumerate(("roll", "pitch", "yaw"))},
           "rejections": r.rejections}
    t0 = float(s.imu.t[0] + 0.5 * (s.imu.t[-1] - s.imu.t[0])) if outage_start is None else float(outage_start)
    t1 = t0 + outage_length
    r2 = quatnav.GpsInsFilter(lever_arm_b=lever).run(s.imu.t, s.imu.gyro, s.imu.accel,
                                                     outages=[(t0, t1)], **_aids(s))
    e2 = errors(s, r2)
    m = (e2["t"] >= t0) & (e2["t"] < t1)
    out["outage"] = {"start_s": t0, "length_s": outage_length,
                     "horizontal_error_at_start_m": float(e2["horiz"][m][0]),
                     "horizontal_error_max_m": float(e2["horiz"][m].max()),
                     "horizontal_error_at_end_m": float(e2["horiz"][m][-1]),
                     "horizontal_sigma_at_end_m": float(e2["sigma_h"][m][-1]),
                     "horizontal_rms_whole_run_m": _stats(e2["horiz"])["rms"]}
    return out


def run(args) -> int:
    res = run_scenario(args.scenario, args.seed, args.outage_start, args.outage_length)
    with open(args.json, "w") as fh:
        json.dump(res, fh, indent=2)
    h, o = res["horizontal_m"], res["outage"]
    print(f"{res['scenario']} seed {res['seed']}: horizontal RMS {h['rms']:.2f} m, max {h['max']:.2f} m; "
          f"Euler RMS (deg) " + ", ".join(f"{k} {v['rms']:.2f}" for k, v in res["euler_deg"].items()))
    print(f"GPS outage {o['length_s']:.0f} s from {o['start_s']:.1f} s: horizontal error "
          f"{o['horizontal_error_at_start_m']:.2f} -> {o['horizontal_error_at_end_m']:.2f} m "
          f"(max {o['horizontal_error_max_m']:.2f} m, filter 1-sigma {o['horizontal_sigma_at_end_m']:.2f} m)")
    return 0
