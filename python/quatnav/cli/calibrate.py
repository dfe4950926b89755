"""``quatnav calibrate mag|acc|gyro LOG --out cal.toml``: fit a sensor calibration from an IMU
CSV log and write (or update) a calibration TOML file that ``--calibration FILE`` applies."""
from __future__ import annotations

import argparse
import sys
import warnings
from pathlib import Path

import numpy as np

from .._command import UsageError, write_json

__all__ = ["add_parser", "read_log"]

IMU = ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
MAG = ("mag_x", "mag_y", "mag_z")

EPILOG = """\
LOG: a CSV with a header row: time (s), gyro_x..z (rad/s), accel_x..z (m/s^2) and, for 'mag',
mag_x..z (any unit; rows with an empty mag are skipped); or any log 'ahrs run --log' reads (a PX4
ULog, a ROS bag: its IMU and magnetometer). The fitted sensor's table is written to --out; the
other tables of an existing file are kept, so one file collects all three.
rest: 'gyro' takes the bias over the longest rest and 'acc' finds its static poses with one rest
detector, the one of 'allan --rest-only' (quatnav.calibration.rest_segments: windows of 0.5 s
whose deviation is below 1.5 times that of the log's quietest 1 %, thresholds scaled to the
sensor's own noise); 'acc' rejects a pose whose per-axis std exceeds --still-std.

calibrated = matrix @ (raw - offset); see docs/CALIBRATION.md.
examples:
  quatnav calibrate mag rotations.csv --out cal.toml --model full --plot mag.png
  quatnav calibrate acc six_poses.csv --out cal.toml
  quatnav calibrate gyro rest.csv --out cal.toml            (or --rest T0 T1: the interval, s)
  quatnav calibrate mag flight.ulg --out cal.toml
  quatnav ins run --imu imu.csv --gnss gnss.csv --calibration cal.toml --out nav.csv"""


def read_log(path, mag=False, fmt="auto"):
    """(t, gyr, acc, mag or None) of a log: an IMU CSV (its errors name the line and column), or
    any file ``quatnav.io.read`` knows (PX4 ULog, ROS bag, ...: what ``ahrs run --log`` reads;
    the magnetometer then at its own times, ``t`` the IMU's); a bad file raises UsageError."""
    from .. import io
    from ..io.table import CsvError, read_table
    kind = io.detect(path) if fmt == "auto" and Path(path).exists() else ("csv" if fmt == "auto" else fmt)
    if kind != "csv":
        log = io.read(path, format=kind)
        log.require("imu")
        m = None
        if mag:
            if log.mag is None:
                raise UsageError(f"LOG {path}: no magnetometer in this {log.format} log (needed by 'calibrate mag'; it "
                                 f"has: {', '.join(log.streams())})")
            m = np.asarray(log.mag.values, float)
        return log.imu.t, log.imu.gyr, log.imu.acc, m
    try:
        tab = read_table(path, IMU, MAG, what="LOG", min_rows=2)
    except CsvError as e:
        raise UsageError(str(e)) from None
    m = tab.stack(MAG)
    if mag:
        missing = [c for c in MAG if c not in tab.header]
        if missing:
            word = "column" if len(missing) == 1 else "columns"
            raise UsageError(f"LOG {path}: no {', '.join(missing)} {word} (needed by 'calibrate mag'; "
                             f"found {', '.join(h for h in tab.header if h)})")
        if not np.isfinite(m).all(axis=1).any():
            raise UsageError(f"LOG {path}: no row has all of mag_x, mag_y, mag_z (needed by 'calibrate mag')")
    return tab["time"], tab.stack(IMU[1:4]), tab.stack(IMU[4:7]), m


def _fit(args):
    from .. import calibration as cal
    t, gyr, acc, mag = read_log(args.log, mag=args.sensor == "mag", fmt=args.format)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        try:
            if args.sensor == "mag":
                rows = np.isfinite(mag).all(axis=1)
                res = cal.magnetometer(mag[rows], model=args.model or "full")
                raw = mag[rows]
            elif args.sensor == "acc":
                res = cal.accelerometer(acc=acc, t=t, gyr=gyr, g=args.g, model=args.model,
                                        still_std=args.still_std)
                raw = acc
            else:
                rest = tuple(args.rest) if args.rest else None
                res = cal.gyroscope(gyr, t, acc=acc, rest=rest)
                raw = gyr
        except ValueError as e:  # the library's hint in the command's syntax
            raise UsageError(f"LOG {args.log}: {str(e).replace('give rest=(t0, t1)', 'give --rest T0 T1 (s)')}") \
                from None
    return res, raw, [str(w.message) for w in caught]


def _summary(res) -> str:
    if res.sensor == "mag":
        return (f"mag ({res.model}): offset {np.array2string(res.offset, precision=4)}, field strength "
                f"{res.field_strength:.4g}, residual {res.residual:.3g}, coverage {res.coverage:.0%}, "
                f"{res.info['outliers']} outliers")
    if res.sensor == "acc":
        rej = res.info["rejected"]
        return (f"acc ({res.model}): bias {np.array2string(res.offset, precision=4)} m/s^2, scale "
                f"{np.array2string(np.diag(res.matrix), precision=5)}, residual {res.residual:.3g} m/s^2, "
                f"{res.info['poses']} poses" + (f", {len(rej)} rejected as moving" if rej else ""))
    return (f"gyro: bias {np.array2string(res.offset, precision=6)} rad/s from rest "
            f"{res.info['rest'][0]:.2f}-{res.info['rest'][1]:.2f} s")


def _plot(res, raw, path):
    from .. import _plotting
    fig = _plotting.figure((9, 3.2))
    cal = res.apply(raw)
    pairs = ((0, 1), (0, 2), (1, 2))
    for k, (i, j) in enumerate(pairs):
        ax = fig.add_subplot(1, 3, k + 1)
        ax.plot(raw[:, i], raw[:, j], ".", ms=1, alpha=0.4, label="raw")
        ax.plot(cal[:, i], cal[:, j], ".", ms=1, alpha=0.4, label="calibrated")
        ax.set_aspect("equal", adjustable="datalim")
        ax.set_xlabel("xyz"[i])
        ax.set_ylabel("xyz"[j])
    ax.legend(fontsize=7, markerscale=8)
    fig.suptitle(_summary(res), fontsize=8)
    _plotting.save(fig, path)
    print(f"wrote {path}")


def _run(args) -> int:
    from .. import calibration as cal
    prog = getattr(args, "_prog", "quatnav calibrate")
    if args.model and args.sensor == "gyro":
        raise UsageError("--model is for mag and acc (the gyro model follows from the data)")
    allowed = {"mag": ("offset", "diagonal", "full"), "acc": ("diagonal", "triangular", "six_position")}
    if args.model and args.model not in allowed[args.sensor]:
        raise UsageError(f"--model {args.model}: {args.sensor} models are {', '.join(allowed[args.sensor])}")
    res, raw, warned = _fit(args)
    for w in warned:
        print(f"{prog}: warning: {w}", file=__import__("sys").stderr)
    try:
        cal.save_calibration(args.out, **{res.sensor: res})
    except OSError as e:
        raise UsageError(f"--out {args.out}: cannot write ({e.strerror})") from None
    print(_summary(res))
    print(f"wrote {args.out}")
    if args.plot:
        _plot(res, raw, args.plot)
    if args.json:
        write_json({"sensor": res.sensor, **res.to_dict(), "warnings": warned}, args)
    return 0


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav calibrate`` on an argparse subparsers object."""
    p = subparsers.add_parser("calibrate", help="fit a magnetometer, accelerometer or gyro calibration from a log",
                              description="Fit a sensor calibration (calibrated = matrix @ (raw - offset)) from "
                                          "an IMU CSV log and write it to a TOML file.",
                              epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("sensor", choices=("mag", "acc", "gyro"),
                   help="mag: ellipsoid fit of a log of rotations; acc: static poses (found in the log); "
                        "gyro: bias from the longest rest")
    p.add_argument("log", metavar="LOG", help="IMU log: CSV, or any format 'ahrs run --log' reads (PX4 ULog, ROS bag)")
    p.add_argument("--format", default="auto", help="format of LOG: auto (default), csv, ulog, rosbag")
    p.add_argument("--out", required=True, metavar="CAL.toml", help="calibration file to write or update")
    p.add_argument("--model", help="mag: offset, diagonal, full (default); acc: diagonal, triangular, six_position "
                                   "(default: triangular with 9 or more poses, else diagonal)")
    p.add_argument("--g", type=float, default=9.80665, help="acc: local gravity, m/s^2 (default 9.80665)")
    p.add_argument("--still-std", type=float, default=None,
                   help="acc: a pose whose per-axis std exceeds this (m/s^2) is rejected as moving (default: four "
                        "times the poses' median, at least 0.05: a real IMU's noise)")
    p.add_argument("--rest", type=float, nargs=2, metavar=("T0", "T1"),
                   help="gyro: rest interval (s) instead of the automatic rest detection")
    p.add_argument("--plot", metavar="PNG", help="also draw raw and calibrated samples (matplotlib)")
    p.add_argument("--json", metavar="FILE", help="also write the result as JSON ('-': to stdout)")
    p.set_defaults(func=_run)
    return p


ALLAN_EPILOG = """\
LOG: an IMU CSV log (time, gyro_x..z, accel_x..z) recorded at rest, as long as possible (the
rate random walk shows only at taus of a tenth of the log and beyond). --rest-only: use the
longest rest segment found in the log instead of the whole log (windows of 0.5 s whose deviation
is below 1.5 times that of the log's quietest 1 %: thresholds scaled to the sensor's own noise,
quatnav.calibration.rest_segments with acc_std=None, gyr_std=None). A log that is evidently not
static (a 1 s mean of the gyro or the accelerometer changing from one second to the next by more
than 10 times what its white noise allows and more than a still sensor's bias ever moves in a
second: 0.01 rad/s, 1 % of gravity; quatnav.calibration.noise.motion_evidence) gets a warning:
its Allan deviation would read the motion as noise.

The noise file holds [filter] (GpsInsFilter parameters: 'quatnav ins run --config noise.toml'),
[parameters.NAME] (QuaternionEKF, EulerEKF, NavFilter13, GpsInsFilter under their own parameter
names; all continuous-time densities) and [allan.gyro], [allan.acc] (per-axis read-outs with
their relative standard errors). See docs/CALIBRATION.md."""


def _allan(args) -> int:
    from .. import calibration as cal
    from ..calibration.noise import motion_evidence, noise_parameters, plot_allan
    prog = getattr(args, "_prog", "quatnav allan")
    t, gyr, acc, _ = read_log(args.log, fmt=args.format)
    dt = np.diff(t)
    if np.max(dt) > 1.5 * np.median(dt):
        i = int(np.argmax(dt))
        raise UsageError(f"LOG {args.log}: time step of {dt[i]:.4g} s after t = {t[i]:.4f} s (median "
                         f"{np.median(dt):.4g} s): the Allan deviation needs uniform samples; cut the log there")
    if args.rest_only:
        segs = cal.rest_segments(t, acc, gyr, acc_std=None, gyr_std=None)  # thresholds from the sensor's noise
        if not segs:
            raise UsageError(f"LOG {args.log}: no rest segment found")
        a, b = max(segs, key=lambda s: s[1] - s[0])
        t, gyr, acc = t[a:b], gyr[a:b], acc[a:b]
    rate = 1.0 / float(np.median(np.diff(t)))
    warned = []
    moving = motion_evidence(t, gyr, acc)
    if moving:
        warned.append(f"LOG {args.log} is not static: {moving}; an Allan deviation describes a sensor's noise at "
                      "rest, and motion, being signal, would be read as noise, bias instability and random walk "
                      "far above the sensor's own: record the IMU held still"
                      + ("" if args.rest_only else ", or take the longest rest of this log with --rest-only"))
        print(f"{prog}: warning: {warned[-1]}", file=sys.stderr)
    try:
        model = noise_parameters(rate, gyr=gyr, acc=acc)
    except ValueError as e:
        raise UsageError(f"LOG {args.log}: {e}") from None
    try:
        with open(args.out, "w") as fh:
            fh.write(model.to_toml())
    except OSError as e:
        raise UsageError(f"--out {args.out}: cannot write ({e.strerror})") from None
    short = []
    for s, unit in (("gyro", "rad/s"), ("acc", "m/s^2")):
        for axis, a in zip("xyz", getattr(model, s)):
            bi = (f"bias instability {a.bias_instability:.3g} {unit} at {a.tau_bias_instability:.3g} s" if a.floor_reached
                  else f"bias instability <= {a.bias_instability:.3g} {unit} (no floor up to {a.tau_bias_instability:.3g} s)")
            print(f"{s} {axis}: white {a.white:.3g} {unit}/sqrt(Hz) (+-{a.white_rel_err:.0%}), {bi}, rate random walk "
                  f"{a.rate_random_walk:.3g} {unit}/s/sqrt(Hz)")
            if not a.floor_reached:
                short.append((f"{s} {axis}", a.tau_bias_instability))
    if short and not moving:  # (a moving log's figures mean nothing: its warning says so)
        warned.append(f"LOG {args.log}: the Allan deviation of {', '.join(n for n, _ in short)} still falls at the "
                      f"longest tau ({max(tau for _, tau in short):.3g} s of a {model.duration:.3g} s log): the "
                      "bias-instability "
                      "floor was not reached, and the figure given is only an upper bound; record at rest for longer "
                      "(the floor of a MEMS gyro is typically at 10-1000 s)")
        print(f"{prog}: warning: {warned[-1]}", file=sys.stderr)
    print(f"{len(t)} samples, {model.duration:.1f} s at {rate:.4g} Hz; wrote {args.out}")
    if args.plot:
        print(f"wrote {plot_allan(model, args.plot)}")
    if args.json:
        write_json({"filters": model.filter_params(),
                    "gyro": [vars(a) for a in model.gyro], "acc": [vars(a) for a in model.acc],
                    "warnings": warned}, args)
    return 0


def add_allan_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav allan`` on an argparse subparsers object."""
    p = subparsers.add_parser("allan", help="noise parameters of a static IMU log from its Allan deviation",
                              description="Overlapping Allan deviation per axis of a static IMU log; fits of the "
                                          "white noise (ARW/VRW), bias instability and rate random walk; the "
                                          "filter noise parameters they give, written as TOML.",
                              epilog=ALLAN_EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("log", metavar="LOG", help="IMU log at rest: CSV, or any format 'ahrs run --log' reads")
    p.add_argument("--format", default="auto", help="format of LOG: auto (default), csv, ulog, rosbag")
    p.add_argument("--out", required=True, metavar="NOISE.toml", help="noise parameter file to write")
    p.add_argument("--rest-only", action="store_true", help="use the longest rest segment of the log only")
    p.add_argument("--plot", metavar="PNG", help="also draw the Allan deviation with the fitted lines")
    p.add_argument("--json", metavar="FILE", help="also write the read-outs as JSON ('-': to stdout)")
    p.set_defaults(func=_allan)
    return p
