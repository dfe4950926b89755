"""``quatnav experiment marg-broad``: MargFilter (paper 001) against the QuaternionEKF (paper
000) on the BROAD trials (real IMU data with optical ground truth; no GPS, so the correction of
eq. 7 is off).

    quatnav experiment marg-broad [--data DIR] [--json FILE] [--gain 1.0]

BROAD: D. Laidig, M. Caruso, A. Cereatti, T. Seel, "BROAD - A Benchmark for Robust Inertial
Orientation Estimation", Data 6(7), 2021, doi:10.3390/data6070072 (CC BY 4.0).

Metric as in the benchmark: q_err = q_est * conj(q_ref) in the (ENU) earth frame; inclination
error 2 acos(sqrt(w^2 + z^2)), heading error 2 atan(|z / w|); RMSE in degrees over the samples
with ``movement`` set and a valid reference. The filters' heading is referred to magnetic north
and the optical frame's to its own x axis, so a constant heading offset per trial (the circular
mean over those samples) is removed before the heading error is taken; the inclination error
does not depend on it. One parameter set for all trials.

The trials are read with :mod:`quatnav.datasets.broad`; ``quatnav eval broad`` gives the
benchmark's own figures (no heading-offset removal) for every filter and the peers.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core import quaternion as Q

FILTERS = ("marg", "marg_6d", "qekf")


#: One line for ``quatnav experiment -h``.
SUMMARY = "MargFilter against the QuaternionEKF on the BROAD real-data trials (paper 001; broad data)"


def add_arguments(parser) -> None:
    parser.add_argument("--data", metavar="DIR", help="folder of the BROAD .mat files "
                        "(default: $QUATNAV_DATA/broad or ../shared/data/broad next to the repository)")
    parser.add_argument("--json", metavar="FILE", help="write the figures to this JSON file ('-': stdout)")
    parser.add_argument("--gain", type=float, default=1.0, help="MargFilter gain k of eq. (6), 1/s (default 1)")


def default_dir() -> Path:
    """``<shared data>/broad`` (see :func:`quatnav.datasets.broad.default_dir`)."""
    from ..datasets import broad
    return broad.default_dir()


def load_trial(path) -> dict:
    """One BROAD trial through :func:`quatnav.datasets.broad.load_trial`, as a dict (the
    reference kept in the dataset's ENU frame for :func:`errors_deg`)."""
    from ..datasets import broad
    t = broad.load_trial(path)
    return dict(name=t.name, gyr=t.gyr, acc=t.acc, mag=t.mag, quat_ref_enu=t.quat_ref_enu,
                movement=t.movement, rate_hz=t.rate)


def errors_deg(q_est_ned, q_ref_enu, mask):
    """Inclination and heading RMSE (deg) of estimates (NED) against the reference (ENU)."""
    q_est = Q.ned_to_enu(q_est_ned)
    ok = mask & np.all(np.isfinite(q_ref_enu), axis=1)
    e = Q.mul(q_est[ok], Q.conj(q_ref_enu[ok]))
    w, z = e[:, 0], e[:, 3]
    incl = 2 * np.arccos(np.clip(np.sqrt(w**2 + z**2), 0, 1))
    # Heading part of the error quaternion; remove its circular mean (constant frame offset).
    psi = 2 * np.arctan2(z, w)
    psi = Q.wrap_pi(psi - np.angle(np.mean(np.exp(1j * psi))))
    return float(np.degrees(np.sqrt(np.mean(incl**2)))), float(np.degrees(np.sqrt(np.mean(psi**2))))


def run_trial(tr: dict, gain: float = 1.0) -> dict:
    import warnings

    from .. import AxesWarning, MargFilter, QuaternionEKF
    dt = 1.0 / tr["rate_hz"]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", AxesWarning)  # BROAD's body frame is its sensor's own, z up
        est = {
            "marg": MargFilter(gain=gain).run(tr["gyr"], tr["acc"], tr["mag"], dt=dt).quat,
            "marg_6d": MargFilter(gain=gain).run(tr["gyr"], tr["acc"], None, dt=dt).quat,
            "qekf": QuaternionEKF().run(tr["gyr"], tr["acc"], tr["mag"], dt=dt).quat,
        }
    out = {}
    for name, q in est.items():
        inc, head = errors_deg(q, tr["quat_ref_enu"], tr["movement"])
        out[name] = {"inclination_rmse_deg": inc, "heading_rmse_deg": None if name == "marg_6d" else head}
    return out


def run(args) -> int:
    from .._command import UsageError, write_json
    d = Path(args.data) if args.data else default_dir()
    files = sorted(d.glob("*.mat"))
    if not files:
        raise UsageError(f"no BROAD .mat files in {d}: give --data DIR or set QUATNAV_DATA to the folder that "
                         "holds broad/")
    trials = {}
    for f in files:
        trials[f.stem] = run_trial(load_trial(f), args.gain)
    mean = {k: {"inclination_rmse_deg": float(np.mean([t[k]["inclination_rmse_deg"] for t in trials.values()]))}
            for k in FILTERS}
    for k in ("marg", "qekf"):
        mean[k]["heading_rmse_deg"] = float(np.mean([t[k]["heading_rmse_deg"] for t in trials.values()]))
    print(f"BROAD ({len(trials)} trials), RMSE [deg] during movement; MargFilter gain k = {args.gain} 1/s")
    print(f"{'trial':38s} " + " ".join(f"{k + ' incl':>11s}" for k in FILTERS) +
          " " + " ".join(f"{k + ' head':>11s}" for k in ("marg", "qekf")))
    for name, t in list(trials.items()) + [("mean", mean)]:
        print(f"{name:38s} " + " ".join(f"{t[k]['inclination_rmse_deg']:11.2f}" for k in FILTERS) + " " +
              " ".join(f"{t[k]['heading_rmse_deg']:11.2f}" for k in ("marg", "qekf")))
    write_json({"data": str(d), "gain_per_s": args.gain, "trials": trials, "mean": mean}, args)
    return 0
