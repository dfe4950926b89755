"""``quatnav ins run``: the GPS/INS filter :class:`quatnav.GpsInsFilter` (paper 004) on a user's logs:
CSV files, or a PX4 ULog, ROS bag, RTKLIB ``.pos`` or NMEA file read by :mod:`quatnav.io`.

::

    quatnav ins run --imu IMU.csv --gnss GNSS.csv [--baro BARO.csv] [--compass COMPASS.csv]
                    [--mag MAG.csv] [--odometer ODO.csv] [--config CONFIG.toml]
                    [--diagnostics DIAG.csv] --out OUT.csv

Every input file is CSV with a header row of named columns (any order, matched without regard to
case or surrounding spaces; extra columns are ignored; blank lines and lines starting with ``#``
are skipped), read by :func:`quatnav.io.table.read_table` (pandas: ``pip install 'quatnav[io]'``):
``,``, ``;`` or tab delimiters, UTF-8 with or without a byte-order mark. Times are in seconds on
one clock shared by all files and strictly increasing within each file.

=============  ===========================================================================
file           columns
=============  ===========================================================================
IMU            ``time`` (s), ``gyro_x gyro_y gyro_z`` (rad/s), ``accel_x accel_y accel_z``
               (m/s^2); or increments ``dtheta_x dtheta_y dtheta_z`` (rad), ``dvel_x dvel_y
               dvel_z`` (m/s): IMU axes (``imu_rotation`` turns them into the body's,
               forward-right-down); row k holds the mean rate and specific force (or the
               increments) over (time[k-1], time[k]]; the first row only fixes the start time.
GNSS           ``time`` (s), ``lat lon`` (deg), ``h`` (m, ellipsoidal) of the antenna; optional
               ``v_n v_e v_d`` (NED velocity, m/s), ``sigma_n sigma_e sigma_d`` (position
               one-sigma, m), ``sigma_vn sigma_ve sigma_vd`` (velocity one-sigma, m/s), ``utc``
               (UTC time of the fix, s since 1970-01-01, Unix time: the date of the recording
               for ``--declination auto``, read with it only). An empty optional cell means
               "not given" (no velocity / the configured sigma).
BARO           ``time`` (s), ``h`` (altimeter height, m; its offset is tied to the GNSS height)
COMPASS        ``time`` (s), ``heading`` (magnetic heading, deg; ``declination`` is added)
MAG            ``time`` (s), ``mag_x mag_y mag_z`` (raw magnetometer, IMU axes, any unit; each
               sample is used at the first IMU row at or after its time). With ``--log``, the
               log's magnetometer unless ``--mag`` replaces it or ``--no-mag`` drops it
ODOMETER       ``time`` (s), ``speed`` (m/s along the body x axis)
=============  ===========================================================================

The TOML configuration has a table ``[filter]``, whose keys are the parameters of
:class:`quatnav.GpsInsFilter` (``quatnav::GpsInsParams``) in their units (SI, radians; every key
with its unit and default in ``quatnav ins run -h``), and optionally ``[initial]``, a given initial
state instead of the alignment (:meth:`quatnav.GpsInsFilter.set_initial`): ``euler`` (roll,
pitch, yaw, rad) or ``q_nb``, ``v_n`` (m/s), ``acc_bias`` (m/s^2), ``gyro_bias`` (rad/s), e.g.::

    [filter]
    gyro_noise = 8.7e-4          # rad/s/sqrt(Hz)
    acc_noise = 2.0e-3           # m/s^2/sqrt(Hz)
    lever_arm_b = [0.1, 0.0, -0.1]   # m, antenna in the body frame
    gps_pos_sigma_h = 2.5        # m, when a fix gives none
    gate_gps_pos = 21.108        # chi-square gate (3 dof); 0 switches it off
    align_time = 2.0             # s at rest for levelling
    imu_rotation = [3.141592653589793, 0.0, 0.0]   # the IMU upside down (roll pi); or a 3x3 matrix
    gps_time_offset = -0.11      # s: the receiver's latency

    [initial]
    euler = [0.0, 0.0, 1.2]      # rad
    v_n = [10.0, 3.0, 0.0]       # m/s

The output has one row per IMU sample from the start of navigation: ``time`` (s), ``lat lon``
(deg), ``h`` (m), ``v_n v_e v_d`` (m/s) of the IMU (not of the antenna, which is ``lever_arm_b``
from it), ``roll pitch yaw`` (deg, ZYX), ``accel_bias_x_m_s2 ..z``,
``gyro_bias_x_deg_h ..z``, then the one-sigma columns ``sigma_n sigma_e sigma_d`` (m),
``sigma_vn sigma_ve sigma_vd`` (m/s), ``sigma_psi_n_deg sigma_psi_e_deg sigma_psi_d_deg``
(attitude error about the NED axes), ``sigma_accel_bias_x_m_s2 ..z``, ``sigma_gyro_bias_x_deg_h
..z``. Errors in the input end the command with exit status 2 and a one-line message naming the
file, the line and the column; exit status 1 means navigation never started (no output rows).

An IMU gap longer than ``max_dt`` is coasted: the INS is propagated across it in equal steps of
at most ``max_dt`` with the sample that ends the gap (by the file's convention the mean over the
gap), without output rows for the inserted steps, and a warning names the file lines. IMU times
whose median step exceeds ``max_dt`` are refused as a wrong unit (ms, us or ns are named when the
step fits one). Inputs that look like the wrong unit or axes give one warning each on stderr
(:mod:`quatnav.plausibility`): gyro in deg/s, accelerometer in g or mg, gravity not on -z at
rest, latitude/longitude in radians, GNSS and IMU time ranges that do not overlap.
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from .._command import UsageError, write_json
from .util import date_arg, declination_arg


EPILOG = """\
input files: CSV, a header row of named columns in any order (case and surrounding spaces do
not matter; extra columns ignored; lines starting with # skipped); delimiter , ; or tab; UTF-8
(a byte-order mark is fine); times in s on one clock, strictly increasing in each file. Read
with pandas: pip install 'quatnav[io]'.
  IMU      time, gyro_x, gyro_y, gyro_z (rad/s), accel_x, accel_y, accel_z (m/s^2); body
           forward-right-down; row k = mean over (time[k-1], time[k]]
  GNSS     time, lat, lon (deg), h (m, antenna); optional v_n, v_e, v_d (m/s),
           sigma_n, sigma_e, sigma_d (m), sigma_vn, sigma_ve, sigma_vd (m/s); empty cell = not given;
           utc (UTC s since 1970, Unix time: the recording's date for --declination auto)
  BARO     time, h (m)
  COMPASS  time, heading (deg, magnetic; the declination parameter is added)
  MAG      time, mag_x, mag_y, mag_z (raw magnetometer, IMU axes, any unit; optional)
  ODOMETER time, speed (m/s along the body x axis; optional)
  IMU increments instead of rates: time, dtheta_x, dtheta_y, dtheta_z (rad), dvel_x, dvel_y,
           dvel_z (m/s) over (time[k-1], time[k]]
config (TOML): a [filter] table of quatnav.GpsInsFilter parameters in SI units and radians,
  e.g. lever_arm_b = [0.1, 0.0, -0.1], gps_pos_sigma_h = 2.5, imu_rotation = [3.141593, 0, 0]
  (every key below), and optionally [initial], a given initial state
output (CSV), one row per IMU sample once navigating:
  time, lat, lon (deg), h (m), v_n, v_e, v_d (m/s): the IMU's position and velocity, not the
  antenna's (the antenna is lever_arm_b from the IMU, in the body frame); roll, pitch, yaw (deg),
  accel_bias_{x,y,z}_m_s2, gyro_bias_{x,y,z}_deg_h, sigma_n, sigma_e, sigma_d (m),
  sigma_vn, sigma_ve, sigma_vd (m/s), sigma_psi_{n,e,d}_deg,
  sigma_accel_bias_{x,y,z}_m_s2, sigma_gyro_bias_{x,y,z}_deg_h; with scale_factors = true also
  accel_scale_{x,y,z}_ppm, gyro_scale_{x,y,z}_ppm and their sigma_..._ppm (the sensor reads
  (1 + scale) * x + bias per axis)
gaps: an IMU gap longer than max_dt is coasted (propagated in steps of at most max_dt with the
  sample that ends it) and reported as a warning with the file lines; IMU times whose median
  step exceeds max_dt are refused as a wrong unit (ms, us, ns)
warnings (stderr, once each): gyro in deg/s, accelerometer in g or mg, gravity not on -z at rest
  (forward-right-down sees (0, 0, -9.8) m/s^2), lat/lon in radians, GNSS and IMU times that do
  not overlap
other inputs: --log FILE (PX4 .ulg, ROS 1 .bag / ROS 2 bag folder, CSV; read by quatnav.io.read)
  gives the IMU, GNSS, barometer and compass it holds; --imu, --gnss, --baro, --compass take any
  supported file instead of CSV (e.g. --gnss solution.pos from RTKLIB, or an NMEA log whose
  HDT/THS sentences give a true heading, used without the declination) and replace the log's
  stream; --format forces the format of the files. Where the GNSS source reports its solution
  quality (RTKLIB's Q, NMEA GGA's fix quality, PX4's fix_type), each fix's kind (RTK fixed or
  float, DGNSS, single) sets its position sigma floor (GpsInsFilter.run(gps_solution=)); the
  run's notes count the kinds
--out OUT.parquet writes Parquet (pyarrow) instead of CSV; a long run shows a progress bar on a
  terminal
--kml FILE, --gpx FILE write the track at the GNSS's rate (--track-rate HZ: another); the GPX
  times are UTC: the IMU's clock plus the offset the GNSS fixes' UTC times give (an RTKLIB .pos
  in GPST: less the leap seconds; a ULog's time_utc_usec; a CSV utc column), else the clock taken
  for Unix time when it is one (> 1e8 s), else none
--plot FILE.png plots track with GNSS fixes, attitude with its 3-sigma band, biases, the
  difference to the log's own attitude estimate (e.g. PX4's) when it has one, the position
  one-sigma, and every aid's innovation NIS over time (x: not applied)
--declination auto: the World Magnetic Model (ahrs.utils.WMM, the [peers] extra) at the first GNSS
  fix on the day of the recording: --date YYYY-MM-DD (or a decimal year), else the GNSS's first UTC
  time (a ULog's time_utc_usec, a .pos or NMEA date, a utc column), else today's, with a note; the
  note names the model, the date and its source; a date after the model's five years is a warning,
  one before 2015 (no coefficients) an error
--json FILE writes a summary (rows, navigation start, alignment, gaps, decisions, warnings);
  --json - prints it
--diagnostics FILE.csv writes one row per aiding sample: aid, time (s), innovation_0..2 (INS
  minus aid), nis, status, decision (accepted, weighted, rejected, inflated, reset, skipped, aligned, none),
  inflation, q_scale (the process-noise scale at that sample)
alignment: at rest (the IMU still for align_time) roll and pitch from the accelerometer, heading
  from the compass, the magnetometer or, once moving, the GNSS course; started while moving, the
  roll, pitch and heading from the GNSS velocity change against the specific force over
  align_motion_time with the body x axis along the velocity (no side slip), or with positions
  only from the course between fixes align_course_distance apart and the mean specific force
  (roll/pitch one-sigma align_level_sigma); or given in the config's [initial] table
non-holonomic constraint (no lateral or vertical body velocity): nhc = true applies it whenever
  moving; by default (nhc_auto) it applies once the log has shown a wheeled vehicle (nhc_auto_time
  of GNSS-aided motion above nhc_auto_speed within nhc_auto_limit across); the summary line says
  from when
exit status: 0 on success, 1 when navigation never started (no output rows), 2 on an input
error (one line on stderr naming the file, line and column)."""


def _run(args) -> int:
    log = None
    if args.log:
        from .. import io
        log = io.read(args.log, format=args.format)
    elif not (args.imu and args.gnss):
        raise UsageError("give --imu IMU and --gnss GNSS, or --log FILE")
    if args.date is not None and args.declination is not None:
        raise UsageError("--date dates the World Magnetic Model: it goes with --declination auto")
    from ..io.table import progress_bar
    from ..pipeline import run_ins, write_diagnostics, write_ins_table
    bar = []

    def progress(done, total):  # a bar on a terminal for a long log only
        if not bar:
            bar.append(progress_bar(total, desc="ins run: filter", unit="row"))
        bar[0].update(done)
    declination = ("auto" if args.declination is None else None if args.declination is False
                   else math.radians(args.declination))
    run = run_ins(log, imu=args.imu, gnss=args.gnss, baro=args.baro, compass=args.compass, mag=args.mag,
                  odometer=args.odometer, no_mag=args.no_mag, fmt=args.format, config=args.config,
                  declination=declination, date=args.date, calibration=getattr(args, "calibration", None),
                  mag_calibrate=args.mag_calibrate, time_offset=args.estimate_time_offset, smooth=args.smooth,
                  progress=progress, utc=bool(args.gpx), noise_from_log=not args.noise_as_given)
    try:
        if bar:
            bar[0].set_description("ins run: write")
        write_ins_table(run, args.out, progress=bar[0] if bar else None)
    finally:
        if bar:
            bar[0].close()
    n_diag = write_diagnostics(args.diagnostics, run.result) if args.diagnostics else None
    if run.time_offset is not None:
        print(f"estimated {run.time_offset}")
    print(f"wrote {args.out}: {run.summary_line()}")
    for text in run.notes:
        print(f"note: {text}")
    if run.navigated:
        from ..io import tracks as track_files
        r, nav = run.result, run.rows
        rate = args.track_rate or run.gnss_rate
        each = f"{rate:g} Hz" if rate else "every sample"
        if args.kml:
            n = track_files.write_kml(args.kml, r.t[nav], r.lat[nav], r.lon[nav], r.h[nav], rate=rate)
            print(f"wrote {args.kml}: {n} points ({each})")
        if args.gpx:
            utc, clock = _gpx_times(run, r.t[nav])
            n = track_files.write_gpx(args.gpx, r.t[nav], r.lat[nav], r.lon[nav], r.h[nav], rate=rate, utc=utc)
            print(f"wrote {args.gpx}: {n} points ({each}); {clock}")
        if args.plot:
            from ..pipeline.figures import plot_nav
            plot_nav(args.plot, r, nav, run.inputs.gnss, log)
            print(f"wrote {args.plot}")
    if args.json:
        summary = {"output": str(args.out)}
        for key, value in run.summary().items():
            summary[key] = value
            if key == "decisions":
                summary["diagnostics_rows"] = n_diag
        write_json(summary, args)
    return 0 if run.navigated else 1



def _gpx_times(run, t):
    """The UTC times of the GPX points, and a sentence on where they come from."""
    if run.utc_offset is not None:
        return run.utc(t), (f"times in UTC: the IMU's clock {run.utc_offset:+.3f} s (from the GNSS fixes' UTC times, "
                            "leap seconds included)")
    if len(t) and t[0] > 1e8:
        return t, ("times in UTC taking the IMU's clock for Unix time (the GNSS gives no UTC time: if the clock is GPS "
                   "time, give the GNSS's utc column, UTC s since 1970)")
    return None, "no times (the log's clock has no date, and the GNSS gives no UTC time: a utc column, UTC s since 1970)"


def config_keys_text(width: int = 100) -> str:
    """Every ``[filter]`` key of the config with its unit, default and meaning (for ``-h``), from
    the parameter table of :class:`quatnav.GpsInsFilter`."""
    import textwrap

    from ..filters.tables import GPSINS_PARAMS
    lines = ["[filter] keys (quatnav.GpsInsFilter parameters; unit, default):"]
    for q in GPSINS_PARAMS:
        d = q.default
        if q.kind == "mat3":
            default = "identity ([roll, pitch, yaw] rad or a 3x3 matrix)"
        elif isinstance(d, tuple):
            default = "[" + ", ".join(f"{x:g}" for x in d) + "]"
        elif isinstance(d, bool):
            default = "true" if d else "false"
        else:
            default = f"{d:g}" if isinstance(d, float) else str(d)
        unit = "" if q.unit in ("-",) else f" [{q.unit}]"
        head = f"  {q.name} = {default}{unit}: "
        lines += textwrap.wrap(q.doc, width=width, initial_indent=head, subsequent_indent="      ")
    lines.append("[initial] keys (a given initial state instead of the alignment): euler = [roll, pitch, yaw] (rad) "
                 "or q_nb = [w, x, y, z]; v_n = [n, e, d] (m/s); acc_bias (m/s^2); gyro_bias (rad/s)")
    return "\n".join(lines)


def _positive_hz(text: str) -> float:
    """A rate in Hz above 0 (argparse type of --track-rate)."""
    try:
        v = float(text)
    except ValueError:
        v = float("nan")
    if not (np.isfinite(v) and v > 0):
        raise argparse.ArgumentTypeError(f"expected a rate in Hz above 0, got {text!r}")
    return v


def _offset_bounds(text: str) -> tuple:
    """``LOW,HIGH`` in seconds (argparse type of --estimate-time-offset)."""
    try:
        lo, hi = (float(x) for x in text.split(","))
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected LOW,HIGH in seconds (e.g. -0.5,0.5), got {text!r}") from None
    if not (np.isfinite(lo) and np.isfinite(hi) and lo < hi):
        raise argparse.ArgumentTypeError(f"expected finite LOW < HIGH, got {text!r}")
    return lo, hi


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav ins run`` on an argparse subparsers object."""
    p = subparsers.add_parser("ins", help="GPS/INS navigation on your logs: CSV, ULog, ROS bag, .pos, NMEA "
                                   "(see 'quatnav ins run -h')",
                              description="GPS/INS navigation (GpsInsFilter, paper 004) on CSV files or a PX4 ULog, "
                                          "ROS bag, RTKLIB .pos or NMEA log.")
    sub = p.add_subparsers(dest="ins_command", metavar="COMMAND")
    r = sub.add_parser("run", help="run the GPS/INS filter on a log, or on IMU and GNSS (and altimeter, compass, "
                            "magnetometer, odometer) files",
                       description="Run quatnav.GpsInsFilter (16-state loosely coupled GPS/INS with altimeter, "
                                   "compass, magnetometer and motion constraints, paper 004) on a log or on "
                                   "CSV files and write the navigation solution.",
                       epilog=EPILOG + "\n" + config_keys_text(), formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("--log", metavar="FILE", help="one log with IMU and GNSS (ULog, ROS bag, CSV, ...); "
                   "--imu/--gnss/--baro then replace its streams")
    r.add_argument("--format", default="auto", help="format of --log and the other files: auto (default), "
                   "rtklib, ulog, rosbag, nmea, csv")
    r.add_argument("--imu", metavar="IMU.csv", help="IMU samples (CSV, or any log with IMU)")
    r.add_argument("--gnss", metavar="GNSS.csv", help="GNSS fixes of the antenna (CSV, RTKLIB .pos, NMEA, ULog, bag)")
    r.add_argument("--baro", metavar="BARO.csv", help="altimeter heights (optional; CSV or a log with a barometer)")
    r.add_argument("--compass", metavar="COMPASS.csv", help="compass headings (optional)")
    r.add_argument("--mag", metavar="MAG.csv", help="raw magnetometer: time, mag_x, mag_y, mag_z (optional; IMU axes; "
                   "default: the magnetometer of --log, if it has one)")
    r.add_argument("--no-mag", action="store_true", help="ignore the magnetometer of --log (heading from a compass or "
                   "the GNSS course; for a magnetometer disturbed by the vehicle)")
    r.add_argument("--odometer", metavar="ODO.csv", help="odometer: time, speed (m/s, optional)")
    r.add_argument("--mag-calibrate", action="store_true",
                   help="calibrate the magnetometer on this log first: run without it, fit its hard-iron offset "
                        "and the Earth field (hence the declination) to that run's attitude, whose heading the "
                        "GNSS gives, then run with the corrected samples (needs turns; a drive will do)")
    r.add_argument("--declination", type=declination_arg, default=False, metavar="DEG|auto",
                   help="magnetic declination, deg east of true north (replaces the config's), or auto: the World "
                        "Magnetic Model at the first GNSS fix (the ahrs package, [peers] extra); the compass and "
                        "magnetometer headings then turn into true ones")
    r.add_argument("--date", type=date_arg, metavar="YYYY-MM-DD",
                   help="the day of the recording for --declination auto (the World Magnetic Model's date), "
                        "YYYY-MM-DD or a decimal year; default: the GNSS's UTC time (a ULog's time_utc_usec, a utc "
                        "column, a .pos or NMEA date), else today, with a note")
    r.add_argument("--config", metavar="CONFIG.toml", help="filter parameters ([filter] table)")
    from ..calibration import add_calibration_argument
    add_calibration_argument(r)
    r.add_argument("--out", required=True, metavar="OUT.csv", help="output CSV")
    r.add_argument("--json", metavar="FILE", help="also write a summary as JSON ('-': to stdout)")
    r.add_argument("--diagnostics", metavar="DIAG.csv",
                   help="also write one row per aiding sample: innovation, NIS, status, decision, inflation")
    r.add_argument("--smooth", action="store_true",
                   help="write the smoothed solution: a Rauch-Tung-Striebel backward pass after the filter, so that "
                        "every row uses the whole log (post-processing; bridges GNSS outages); the gating "
                        "decisions and the diagnostics are the filter's")
    r.add_argument("--noise-as-given", action="store_true",
                   help="use gyro_noise and acc_noise as given; by default each is raised to the white noise the "
                        "log's IMU shows (vibration included) where it is below it, and lowered to 3x it where more than 3x "
                        "above it (the summary's notes say which)")
    r.add_argument("--estimate-time-offset", nargs="?", const=(-0.5, 0.5), default=None, type=_offset_bounds,
                   metavar="LOW,HIGH",
                   help="estimate gps_time_offset (s, the GNSS clock to the IMU's; a receiver latency L is -L) "
                        "from the log first, searching LOW..HIGH s (default -0.5,0.5), and run with it: the "
                        "offset whose GNSS innovations are smallest (needs motion; prints the estimate and its "
                        "one-sigma); a negative LOW takes '=': --estimate-time-offset=-0.3,0.1")
    r.add_argument("--kml", metavar="FILE.kml", help="also write the track as KML (Google Earth)")
    r.add_argument("--gpx", metavar="FILE.gpx", help="also write the track as GPX (times in UTC: from the GNSS fixes' "
                   "UTC times, leap seconds included)")
    r.add_argument("--track-rate", type=_positive_hz, metavar="HZ",
                   help="points per second of --kml and --gpx (default: the GNSS's rate)")
    r.add_argument("--plot", metavar="FILE.png", help="also plot track with GNSS fixes, attitude, biases")
    r.set_defaults(func=_run)
    p.set_defaults(func=None)
    return p
