"""``quatnav compare RUN REF``: differences between two tracks aligned in time.

Each file is read by :func:`quatnav.io.read`: the output of ``quatnav ahrs run`` / ``ins run``
(CSV or Parquet), a log with its own estimate (PX4 ``vehicle_attitude`` and local/global
position), a truth CSV, or a GNSS solution (RTKLIB, NMEA: position and velocity only). REF is
interpolated onto RUN's times inside their common span: quaternions by slerp, the rest
linearly. The attitude error ``q_err = q_run * conj(q_ref)`` is split as in
:mod:`quatnav.evaluation.metrics` into heading and inclination; positions into horizontal and
vertical (NED about REF's first point); velocities when both have them. For each: RMS, max,
median (p50), p95.
"""
from __future__ import annotations

import argparse

from .._command import write_json
from ..evaluation.track_difference import compare_tracks

EPILOG = """\
inputs: any file quatnav.io.read knows; a CSV track has time and q_w..q_z (ahrs run output) or
  roll, pitch, yaw (deg), and/or lat, lon (deg), h (m), v_n, v_e, v_d (m/s) (ins run output);
  a ULog gives PX4's own estimate (vehicle_attitude, vehicle_local/global_position); an RTKLIB
  or NMEA file gives positions. Both on one clock (seconds).
output: a table of RMS, max, p50, p95 of: attitude total, heading, inclination (deg);
  horizontal and vertical position (m) and velocity (m/s) when both tracks have them.
--ref-frame enu, --ref-body flu: REF's attitude is body to east-north-up (most motion-capture
  systems, BROAD's opt_quat), its body forward-left-up (ROS); quatnav's is forward-right-down to
  north-east-down. An attitude difference near 180 deg that one of them removes gets a warning
  naming the options.
--json FILE writes the figures; --plot FILE.png plots the differences over time (attitude,
  position, velocity: the panels of what both tracks have).
exit status: 0 on success, 2 on an input error (no common time span, no common quantity)."""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav compare``."""
    p = subparsers.add_parser("compare", help="differences between two tracks (attitude, position, velocity)",
                              description="Compare RUN with REF, aligned in time (REF interpolated, slerp for "
                                          "quaternions): RMS, max, p50, p95 of the differences.",
                              epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", metavar="RUN", help="the track to judge (e.g. the output of 'ahrs run')")
    p.add_argument("ref", metavar="REF", help="the reference (truth, or a log with its own estimate)")
    p.add_argument("--run-format", default="auto", help="format of RUN (default: detected)")
    p.add_argument("--ref-frame", choices=("ned", "enu"), default="ned",
                   help="navigation frame of REF's attitude, velocity and position: ned (default; quatnav's, PX4's) "
                        "or enu (east-north-up: most motion-capture systems, BROAD's opt_quat, ROS)")
    p.add_argument("--ref-body", choices=("frd", "flu"), default="frd",
                   help="body axes of REF's attitude: frd (forward-right-down, default) or flu (forward-left-up, ROS)")
    p.add_argument("--ref-format", default="auto", help="format of REF (default: detected)")
    p.add_argument("--plot", metavar="FILE.png", help="plot the differences over time")
    p.add_argument("--json", metavar="FILE", help="write the figures as JSON ('-': to stdout)")
    p.set_defaults(func=_run)
    return p


def _run(args) -> int:
    from ..pipeline.recording import issue, recorded
    from .. import io
    a = io.read(args.run, format=args.run_format)
    b = io.read(args.ref, format=args.ref_format)
    with recorded() as kept:
        res = compare_tracks(a, b, ref_frame=args.ref_frame, ref_body=args.ref_body)
    issue(kept)
    series = res.pop("_series")
    frames = "" if (args.ref_frame, args.ref_body) == ("ned", "frd") else \
        f" (read as {args.ref_frame.upper()}, body {args.ref_body.upper()})"
    print(f"{args.run} against {args.ref}{frames}, common span {res['span'][0]:.3f} .. {res['span'][1]:.3f} s")
    print(f"{'quantity':28s} {'rms':>10s} {'max':>10s} {'p50':>10s} {'p95':>10s} {'n':>8s}")
    for k, s in res.items():
        if not isinstance(s, dict):
            continue
        print(f"{k:28s} {s['rms']:10.4g} {s['max']:10.4g} {s['p50']:10.4g} {s['p95']:10.4g} {s['n']:8d}")
    res["warnings"] = [str(w) for w in kept]
    write_json(res, args)
    if args.plot:
        from ..pipeline.figures import plot_differences
        plot_differences(series, args.plot)
        print(f"wrote {args.plot}")
    return 0
