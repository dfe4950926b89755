"""``quatnav ahrs run``: an attitude filter (QuaternionEKF, EulerEKF or MargFilter) on a user's log.

::

    quatnav ahrs run --log FILE [--format FMT] [--topic KIND=TOPIC] | --imu IMU.csv [--mag MAG.csv]
                     [--filter qekf|euler-ekf|marg] [--declination DEG|auto [--date YYYY-MM-DD]]
                     [--rate HZ] [--no-mag]
                     [--smooth] --out OUT.csv|OUT.parquet [--plot FILE.png] [--json FILE|-]

The log is read by :func:`quatnav.io.read` (RTKLIB, ULog, ROS bag, NMEA or CSV). Magnetometer
samples go on the first IMU row at or after their time (other rows: no magnetometer update).
"""
from __future__ import annotations

import argparse
import math

from .._command import UsageError, write_json
from ..pipeline.ahrs import FILTERS
from .util import date_arg, declination_arg

EPILOG = """\
inputs: --log FILE is any format quatnav.io.read knows (RTKLIB .pos, PX4 .ulg, ROS 1 .bag or ROS 2
  bag folder, NMEA, CSV; --format to force one); it must hold IMU samples. --imu IMU.csv is a CSV
  with time, gyro_x, gyro_y, gyro_z (rad/s), accel_x, accel_y, accel_z (m/s^2), body
  forward-right-down (optional mag_x, mag_y, mag_z); --mag MAG.csv a CSV with time, mag_x, mag_y,
  mag_z (any unit, body frame).
--topic KIND=TOPIC (repeat): the topic of a stream instead of the first of its type: imu, mag in
  a ROS bag (e.g. --topic imu=/imu/data_raw); mag (vehicle_magnetometer, sensor_mag, ...) in a ULog.
--rate HZ: average the IMU over blocks to about HZ before filtering (default: every sample).
--declination DEG: east of true north; yaw is then relative to true north. --declination auto: the
  World Magnetic Model's at the log's first GNSS fix (ahrs.utils.WMM, the [peers] extra) on the day
  of the recording: --date YYYY-MM-DD (or a decimal year), else the GNSS's first UTC time (a ULog's
  time_utc_usec, a .pos or NMEA date, a CSV utc column), else today's, with a note.
--smooth: offline, the Rauch-Tung-Striebel smoothed attitude (every estimate uses the whole log;
  docs/SMOOTHING.md); qekf and euler-ekf.
output (CSV, or Parquet when OUT ends in .parquet; needs pyarrow): time (s), q_w, q_x, q_y, q_z
  (q_nb, body FRD to NED), roll, pitch, yaw (deg, ZYX), gyro_bias_x..z_deg_s, sigma_<state>
  (the filter's one-sigma values, rad or rad/s), flags (bits), flag_names ('|'-separated).
--plot FILE.png: attitude, biases and, when the log carries its own estimate (e.g. PX4's
  vehicle_attitude), the inclination and heading difference to it.
--json FILE writes a summary (rows, filter, magnetometer: whether any of its samples was used and
  magnetometer_rows: rows with a sample, used, rejected, skipped; declination, samples per flag,
  skipped rows, warnings, notes); --json - prints it
exit status: 0 on success, 2 on an input error (one line on stderr)."""


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav ahrs run``."""
    p = subparsers.add_parser("ahrs", help="attitude filters on your own logs (see 'quatnav ahrs run -h')",
                              description="Attitude and heading estimation on recorded logs.")
    sub = p.add_subparsers(dest="ahrs_command", metavar="COMMAND")
    r = sub.add_parser("run", help="run an attitude filter on a log and write the attitude",
                       description="Run QuaternionEKF, EulerEKF or MargFilter on a log and write the attitude.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    src = r.add_mutually_exclusive_group(required=True)
    src.add_argument("--log", metavar="FILE", help="a log file in any supported format")
    src.add_argument("--imu", metavar="IMU.csv", help="IMU samples as CSV")
    r.add_argument("--format", default="auto", help="format of --log: auto (default), rtklib, ulog, rosbag, nmea, csv")
    r.add_argument("--topic", action="append", default=[], metavar="KIND=TOPIC",
                   help="read stream KIND (imu, mag) of a bag or ULog from TOPIC (repeat)")
    r.add_argument("--mag", metavar="MAG.csv", help="magnetometer samples as CSV (with --imu)")
    r.add_argument("--filter", default="qekf", choices=list(FILTERS), help="qekf (default), euler-ekf or marg")
    r.add_argument("--declination", type=declination_arg, default=0.0, metavar="DEG|auto",
                   help="magnetic declination, deg east; auto: the World Magnetic Model at the log's first GNSS fix "
                        "(the ahrs package, [peers] extra)")
    r.add_argument("--date", type=date_arg, metavar="YYYY-MM-DD",
                   help="the day of the recording for --declination auto, YYYY-MM-DD or a decimal year; default: "
                        "the log's GNSS UTC time, else today, with a note")
    r.add_argument("--rate", type=float, metavar="HZ", help="average the IMU to this rate first")
    r.add_argument("--no-mag", action="store_true", help="ignore the magnetometer (6D: heading is free)")
    r.add_argument("--smooth", action="store_true", help="offline: the smoothed attitude (qekf, euler-ekf)")
    r.add_argument("--out", required=True, metavar="OUT.csv", help="output file (.csv or .parquet)")
    r.add_argument("--plot", metavar="FILE.png", help="also plot the result")
    r.add_argument("--json", metavar="FILE", help="also write a summary as JSON ('-': to stdout)")
    from ..calibration import add_calibration_argument
    add_calibration_argument(r)
    r.set_defaults(func=_run)
    p.set_defaults(func=None)
    return p


#: --topic KIND -> the reader option, per format
TOPIC_OPTIONS = {"rosbag": {"imu": "imu_topic", "mag": "mag_topic"}, "ulog": {"mag": "mag_topic"}}


def topic_options(topics, path, fmt="auto") -> dict:
    """Reader options of ``--topic KIND=TOPIC`` values for the log ``path``."""
    if not topics:
        return {}
    from .. import io
    kind = io.detect(path) if fmt == "auto" else fmt
    known = TOPIC_OPTIONS.get(kind, {})
    out = {}
    for text in topics:
        name, sep, topic = text.partition("=")
        name, topic = name.strip(), topic.strip()
        if not sep or not name or not topic:
            raise UsageError(f"--topic {text}: expected KIND=TOPIC (e.g. imu=/imu/data)")
        if name not in known:
            raise UsageError(f"--topic {text}: a {kind} log takes " + (", ".join(known) or "no topic options"))
        out[known[name]] = topic
    return out


def _run(args) -> int:
    if args.date is not None and args.declination is not None:
        raise UsageError("--date dates the World Magnetic Model: it goes with --declination auto")
    if args.rate is not None and not args.rate > 0:
        raise UsageError(f"--rate {args.rate:g}: must be > 0 Hz")
    from ..pipeline import run_ahrs
    from ..pipeline.outputs import ahrs_table, write_ahrs_table
    log = None
    if args.log:
        from .. import io
        log = io.read(args.log, format=args.format, **topic_options(getattr(args, "topic", []), args.log, args.format))
    run = run_ahrs(log, imu=args.imu, mag=args.mag, no_mag=args.no_mag, filter=args.filter,
                   declination="auto" if args.declination is None else math.radians(args.declination), date=args.date,
                   rate=args.rate, smooth=args.smooth, calibration=getattr(args, "calibration", None))
    write_ahrs_table(ahrs_table(run.result), args.out)
    m = run.magnetometer
    mag = (" (no magnetometer: heading free)" if run.log.mag is None else
           f" (magnetometer: {m['used']} of {m['rows']} rows with a sample used"
           + (f", {m['rejected']} rejected as disturbed" if m["rejected"] else "")
           + (f", {m['skipped']} skipped" if m["skipped"] else "")
           + ("; none used: heading free" if not m["used"] else "") + ")")
    print(f"wrote {args.out}: {len(run.result.t)} rows, {run.filter}{' smoothed' if args.smooth else ''}{mag}")
    for note in run.log.notes:
        print(f"note: {note}")
    if args.plot:
        from ..pipeline.figures import plot_attitude
        plot_attitude(run.result, run.log, args.plot)
        print(f"wrote {args.plot}")
    if args.json:
        write_json({"output": str(args.out), **run.summary()}, args)
    return 0
