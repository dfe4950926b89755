"""Offline smoothing against the causal filters: ``quatnav experiment smoothing [--parts LIST]
[--data DIR] --json FILE``.

The Rauch-Tung-Striebel backward pass of every filter (``run(..., smooth=True)``,
docs/SMOOTHING.md) beside the forward (causal) results of the same runs:

* ``broad``: BROAD (the trials in ``$QUATNAV_DATA/broad``, one parameter set for all, the
  defaults): the total / heading / inclination RMSE over the movement phases of QuaternionEKF
  smoothed and causal and of VQF causal and offline (``vqf.offlineVQF``; when installed), per
  trial, per group and on average;
* ``nav13``: paper 002's straight-then-circle simulation (NavFilter13, every time update,
  ``--runs`` Monte Carlo seeds with Gaussian initial errors): the roll / pitch / yaw and gyro-bias
  RMSE after the first 5 s and the average NEES of the 12-dimensional error state, smoothed and
  forward.

BROAD: D. Laidig, M. Caruso, A. Cereatti, T. Seel, Data 6(7), 2021, doi:10.3390/data6070072,
CC BY 4.0.
"""
from __future__ import annotations

import numpy as np

PARTS = ("broad", "nav13")

#: One line for ``quatnav experiment -h``.
SUMMARY = "offline smoothing (smooth=True) against the causal filters: BROAD, NavFilter13 Monte Carlo (paper 002)"


def add_arguments(parser) -> None:
    parser.add_argument("--parts", default=",".join(PARTS), help=f"comma list of {', '.join(PARTS)} (default: all)")
    parser.add_argument("--data", default=None, metavar="DIR",
                        help="folder of the shared datasets (default $QUATNAV_DATA); BROAD is DIR/broad")
    parser.add_argument("--runs", type=int, default=8, help="nav13: Monte Carlo runs (default 8)")
    parser.add_argument("--json", metavar="FILE", help="write the results here ('-': stdout)")


def broad_part(directory=None) -> dict:
    """QuaternionEKF smoothed and causal, VQF causal and offline, on the BROAD trials."""
    from ..evaluation import evaluate as E
    peers = tuple(p for p in ("vqf", "vqf-offline") if E.available(p)[0])
    res = E.evaluate(directory, filters=("qekf", "qekf-smoothed"), peers=peers)
    keys = ("total", "heading", "inclination")
    out = {"algorithms": res["algorithms"], "notes": res["notes"],
           "mean": {a: {k: res["mean"][a][k] for k in keys} for a in res["algorithms"]},
           "groups": {g: {a: d[a]["total"] for a in res["algorithms"]} for g, d in res["groups"].items()},
           "trials": {t: {a: d["results"][a]["total"] for a in res["algorithms"]} for t, d in res["trials"].items()}}
    return out


def nav13_part(runs: int = 8, seed: int = 100) -> dict:
    """NavFilter13 on paper 002's scenario, smoothed and forward, every time update."""
    from ..sim import make_scenario
    from . import nav13 as X
    out = {}
    for tu in X.TIME_UPDATES:
        acc = {"smoothed": {"rpy": [], "gyro_bias": [], "nees": []}, "forward": {"rpy": [], "gyro_bias": [], "nees": []}}
        for r in range(runs):
            scn = make_scenario(X.SCENARIO, seed=seed + r)
            start = X.initial_state(scn, "gaussian", np.random.default_rng([seed + r, 2]))
            res = X.run_filter(scn, tu, start, return_covariance=True, accel_noise_scale=5.0, smooth=True)
            for name, rr in (("smoothed", res), ("forward", res.forward)):
                err = X.errors(scn, rr)
                keep = err["t"] >= err["t"][0] + X.TRANSIENT_S
                acc[name]["rpy"].append(err["rpy"][keep])
                acc[name]["gyro_bias"].append(err["gyro_bias"][keep])
                sel = slice(499, None, 500)
                sub = type(rr)(**{**rr.__dict__, "x": rr.x[sel], "P": rr.P[sel], "quat": rr.quat[sel]})
                acc[name]["nees"].append(X.nees(sub, {"state": err["state"][sel]}))
        out[tu] = {}
        for name, d in acc.items():
            rpy = np.degrees(np.sqrt(np.mean(np.concatenate(d["rpy"]) ** 2, axis=0)))
            bg = np.sqrt(np.mean(np.concatenate(d["gyro_bias"]) ** 2, axis=0)) / X.DEG_H
            out[tu][name] = {"rpy_rmse_deg": dict(zip(("roll", "pitch", "yaw"), map(float, rpy))),
                             "gyro_bias_rmse_deg_h": list(map(float, bg)),
                             "anees": float(np.mean(d["nees"]))}
    out["runs"] = runs
    out["setting"] = (f"{X.SCENARIO}, seeds {seed}..{seed + runs - 1}, Gaussian initial errors, accelerometer noise "
                      "5x the paper's (the setting of the NEES tests); RMSE after the first 5 s")
    return out


def run(args) -> int:
    from pathlib import Path

    from .._command import UsageError, write_json
    parts = [p.strip() for p in args.parts.split(",") if p.strip()]
    for p in parts:
        if p not in PARTS:
            raise UsageError(f"--parts: unknown part {p!r}; known: {', '.join(PARTS)}")
    if args.runs < 1:
        raise UsageError(f"--runs: expected a positive integer, got {args.runs}")
    out = {}
    if "broad" in parts:
        from ..datasets import broad
        d = Path(args.data) / "broad" if args.data else broad.default_dir()
        if not d.is_dir() or not broad.list_trials(d):
            raise UsageError(f"no BROAD trials in {d}: give --data DIR (the folder that holds broad/) or set "
                             "QUATNAV_DATA")
        out["broad"] = b = broad_part(d)
        algs = b["algorithms"]
        print("BROAD total RMSE over the movement phases (deg): " + ", ".join(algs))
        for g, v in b["groups"].items():
            print(f"  {g:20s}" + "".join(f"{v[a]:8.2f}" for a in algs))
        for k in ("total", "heading", "inclination"):
            print(f"  {'mean ' + k:20s}" + "".join(f"{b['mean'][a][k]:8.2f}" for a in algs))
    if "nav13" in parts:
        out["nav13"] = n = nav13_part(args.runs)
        print(f"paper 002 ({n['runs']} runs): yaw RMSE (deg) and ANEES (12 states), smoothed / forward")
        for tu in ("ekf", "second_order", "ukf"):
            s, f = n[tu]["smoothed"], n[tu]["forward"]
            print(f"  {tu:13s} yaw {s['rpy_rmse_deg']['yaw']:.4f} / {f['rpy_rmse_deg']['yaw']:.4f}; "
                  f"ANEES {s['anees']:.2f} / {f['anees']:.2f}")
    write_json(out, args)
    return 0
