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
import sys

import numpy as np

from .._command import UsageError, write_json
from ..core.magnetic import first_fix_declination
from .util import date_arg, declination_arg

FILTERS = {"qekf": "QuaternionEKF", "euler-ekf": "EulerEKF", "marg": "MargFilter"}

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
--json FILE writes a summary (rows, filter, magnetometer used, declination, samples per flag,
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


def load_inputs(args):
    from .. import io
    if args.log:
        log = io.read(args.log, format=args.format, **topic_options(getattr(args, "topic", []), args.log, args.format))
    else:
        log = io.read(args.imu, format="csv", kind="imu")
        if args.mag:
            from ..io.csvfile import read_csv
            from ..io.table import read_table, CsvError
            try:
                c = read_table(args.mag, ("time", "mag_x", "mag_y", "mag_z"), what="MAG").columns
            except CsvError as e:
                raise UsageError(str(e)) from None
            log.mag = io.Mag(t=c["time"], values=np.column_stack([c["mag_x"], c["mag_y"], c["mag_z"]]),
                             unit="as in the file")
    log.require("imu")
    if args.no_mag:
        # nor say where the magnetometer was read from (ULog: "magnetometer from vehicle_magnetometer")
        log.mag = None
        log.notes = [n for n in log.notes if not n.startswith("magnetometer")]
    return log


def decimate(t, gyr, acc, rate):
    """Block means of the IMU to about ``rate`` Hz: (t_end, gyr_mean, acc_mean, block index of rows)."""
    med = float(np.median(np.diff(t)))
    k = max(1, int(round(1.0 / (rate * med))))
    n = (len(t) // k) * k
    if k == 1:
        return t, gyr, acc, k
    tb = t[k - 1:n:k]
    return tb, gyr[:n].reshape(-1, k, 3).mean(1), acc[:n].reshape(-1, k, 3).mean(1), k


def run_filter(log, name="qekf", declination_deg=0.0, rate=None, smooth=False):
    """Run the attitude filter ``name`` on ``log`` (IMU averaged to ``rate`` Hz when given;
    ``smooth``: the smoothed result); returns its result."""
    import quatnav
    from ..io import mag_on_imu_times
    t, gyr, acc = log.imu.t, log.imu.gyr, log.imu.acc
    mag = mag_on_imu_times(log)
    if rate:
        t, gyr, acc, k = decimate(t, gyr, acc, rate)
        if mag is not None and k > 1:
            n = len(t) * k
            m = mag[:n].reshape(-1, k, 3)
            with np.errstate(all="ignore"):
                mag = np.nanmean(m, axis=1) if np.isfinite(m).any() else None
    cls = getattr(quatnav, FILTERS[name])
    # QuaternionEKF refers its yaw to true north given the declination; MargFilter's declination
    # only turns GPS velocities into its magnetic frame and EulerEKF has none: their yaw is magnetic
    takes_decl = FILTERS[name] == "QuaternionEKF"
    f = cls(declination=math.radians(declination_deg)) if takes_decl else cls()
    if mag is not None and not np.isfinite(mag[0]).all():
        first = np.flatnonzero(np.isfinite(mag).all(1))
        if first.size == 0:
            mag = None
        else:
            mag[0] = mag[first[0]]  # the initial heading from the first magnetometer sample
    res = f.run(gyr, acc, mag, t=t, on_invalid="skip", **({"smooth": True} if smooth else {}))
    if not takes_decl and declination_deg and mag is not None:
        # a filter whose yaw is magnetic (EulerEKF, MargFilter): turn the navigation frame about
        # down by the declination (q_true_nb = q_z(decl) * q_mag_nb)
        from ..core import quaternion as Q
        d = math.radians(declination_deg)
        res.quat[:] = Q.mul(np.array([math.cos(d / 2), 0.0, 0.0, math.sin(d / 2)]), res.quat)
    return res


def result_table(res) -> dict:
    """The output columns of ``ahrs run`` as {name: array}."""
    e = np.degrees(res.euler)
    cols = {"time": res.t}
    for i, c in enumerate("wxyz"):
        cols[f"q_{c}"] = res.quat[:, i]
    for i, c in enumerate(("roll", "pitch", "yaw")):
        cols[c] = e[:, i]
    for i, c in enumerate("xyz"):
        cols[f"gyro_bias_{c}_deg_s"] = np.degrees(res.bias[:, i])
    if res.sigma is not None:
        for i, n in enumerate(res.sigma_names):
            cols[f"sigma_{n}"] = res.sigma[:, i]
    cols["flags"] = res.flags.astype(np.int64)
    names = [n for n in res.FLAGS]
    bits = [res.FLAGS[n] for n in names]
    uniq, inv = np.unique(res.flags, return_inverse=True)
    text = np.array(["|".join(n for n, b in zip(names, bits) if int(u) & b) for u in uniq], dtype=object)
    cols["flag_names"] = text[inv]
    return cols


def write_table(cols: dict, path: str) -> None:
    """CSV, or Parquet for a ``.parquet`` path (pyarrow)."""
    import pandas as pd
    df = pd.DataFrame(cols)
    if str(path).lower().endswith(".parquet"):
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise UsageError(f"{path}: writing Parquet needs pyarrow: pip install 'quatnav[logs]'") from None
        df.to_parquet(path, index=False)
    else:
        if "time" in df:  # absolute times (GPS, UNIX: ~1e9 s) keep nanoseconds
            df["time"] = np.char.mod("%.9f", df["time"].to_numpy(np.float64))
        df.to_csv(path, index=False, float_format="%.10g")


def plot_attitude(res, log, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ref = log.reference if log is not None and log.reference is not None and log.reference.quat is not None else None
    n = 3 if ref is not None else 2
    fig, ax = plt.subplots(n, 1, figsize=(9, 2.6 * n), sharex=True)
    e = np.degrees(res.euler)
    for i, c in enumerate(("roll", "pitch", "yaw")):
        ax[0].plot(res.t, e[:, i], label=c)
    if ref is not None:
        from ..core import quaternion as Q
        er = np.degrees(Q.to_euler(ref.quat))
        for i in range(3):
            ax[0].plot(ref.t, er[:, i], "k:", lw=0.8, label=ref.name if i == 0 else None)
    ax[0].set_ylabel("deg")
    ax[0].legend(fontsize=7)
    ax[1].plot(res.t, np.degrees(res.bias))
    ax[1].set_ylabel("gyro bias, deg/s")
    if ref is not None:
        from ..evaluation.track_difference import attitude_difference
        d = attitude_difference(res.t, res.quat, ref.t, ref.quat)
        ax[2].plot(d["t"], d["inclination_deg"], label="inclination")
        ax[2].plot(d["t"], d["heading_deg"], label="heading")
        ax[2].set_ylabel(f"difference to\n{ref.name}, deg")
        ax[2].legend(fontsize=7)
    ax[-1].set_xlabel("t, s")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def run_summary(res, log, args, declination_deg, warnings) -> dict:
    """The ``--json`` summary of ``ahrs run`` (keys and units in the manner of ``ins run``'s)."""
    summary = {"output": str(args.out), "rows": int(len(res.t)), "imu_samples": int(len(log.imu.t)),
               "filter": FILTERS[args.filter], "smoothed": bool(args.smooth), "magnetometer": log.mag is not None,
               "declination_rad": math.radians(declination_deg), "rate_hz": args.rate,
               "flags": {n: int(np.count_nonzero(res.flag(n))) for n in res.flags_seen()},
               "skipped_rows": {k: int(len(v)) for k, v in res.skipped_rows.items()},
               "warnings": warnings}
    for text in log.notes:
        summary.setdefault("notes", []).append(text)
        if text.startswith("declination"):
            summary["declination_note"] = text
    return summary


def _run(args) -> int:
    if args.date is not None and args.declination is not None:
        raise UsageError("--date dates the World Magnetic Model: it goes with --declination auto")
    prog = getattr(args, "_prog", "quatnav ahrs run")
    warnings = []

    def warn(text):
        warnings.append(text)
        print(f"{prog}: warning: {text}", file=sys.stderr)

    log = load_inputs(args)
    if getattr(args, "calibration", None):
        from ..calibration import apply_calibration_args
        mag = log.mag.values if log.mag is not None else None
        log.imu.gyr, log.imu.acc, mag = apply_calibration_args(args, log.imu.gyr, log.imu.acc, mag)
        if log.mag is not None:
            log.mag.values = mag
    if args.rate is not None and not args.rate > 0:
        raise UsageError(f"--rate {args.rate:g}: must be > 0 Hz")
    if len(log.imu.t) < 2:
        raise UsageError(f"{log.source}: fewer than 2 IMU samples")
    # times in ms, us or ns are refused as ins run refuses them (the filters' max_dt is 1 s)
    from ..plausibility import GapWarning, check_imu_times
    _, warns = check_imu_times(log.imu.t, np.arange(1, len(log.imu.t) + 1), 1.0, where=f"IMU {log.source}")
    for w in warns:
        if not isinstance(w, GapWarning):
            warn(str(w))
    if args.smooth and args.filter == "marg":
        raise UsageError("--smooth: marg has no smoother; use --filter qekf or euler-ekf")
    decl = args.declination
    if decl is None:  # auto
        g = log.gnss
        d, texts = first_fix_declination(*((g.lat, g.lon, g.h) if g is not None else ([], [], [])), log.source,
                                         utc=g.utc if g is not None else None, date=args.date,
                                         warn=warn)
        decl = math.degrees(d)
        log.notes.extend(texts)
    res = run_filter(log, args.filter, decl, args.rate, args.smooth)
    write_table(result_table(res), args.out)
    print(f"wrote {args.out}: {len(res.t)} rows, {FILTERS[args.filter]}{' smoothed' if args.smooth else ''}"
          f"{'' if log.mag is not None else ' (no magnetometer: heading free)'}")
    for note in log.notes:
        print(f"note: {note}")
    if args.plot:
        plot_attitude(res, log, args.plot)
        print(f"wrote {args.plot}")
    if args.json:
        write_json(run_summary(res, log, args, decl, warnings), args)
    return 0
