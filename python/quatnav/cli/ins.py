"""``quatnav ins run``: the GPS/INS filter of paper 004 (:class:`quatnav.GpsInsFilter`) on a user's logs:
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
(deg), ``h`` (m), ``v_n v_e v_d`` (m/s), ``roll pitch yaw`` (deg, ZYX), ``accel_bias_x_m_s2 ..z``,
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
import functools
import math
import sys
import warnings

import numpy as np

from .._command import InputError, UsageError, write_json
from ..io.table import CsvError, read_table
from ..plausibility import check_heading_aids, check_imu_times, check_overlap, plausibility_warnings
from ..plausibility.gnss import gnss_speed, gnss_velocity_ne
from .util import date_arg, declination_arg

IMU_COLUMNS = ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
IMU_INCREMENT_COLUMNS = ("time", "dtheta_x", "dtheta_y", "dtheta_z", "dvel_x", "dvel_y", "dvel_z")
MAG_COLUMNS = ("time", "mag_x", "mag_y", "mag_z")
ODOMETER_COLUMNS = ("time", "speed")
DIAGNOSTICS_COLUMNS = ("aid", "time", "innovation_0", "innovation_1", "innovation_2", "nis", "status", "decision",
                       "inflation", "q_scale")
GNSS_COLUMNS = ("time", "lat", "lon", "h")
GNSS_OPTIONAL = ("v_n", "v_e", "v_d", "sigma_n", "sigma_e", "sigma_d", "sigma_vn", "sigma_ve", "sigma_vd")
BARO_COLUMNS = ("time", "h")
COMPASS_COLUMNS = ("time", "heading")

_DEG_H = math.pi / 180.0 / 3600.0  # rad/s per deg/h
OUTPUT_COLUMNS = (
    ("time", "lat", "lon", "h", "v_n", "v_e", "v_d", "roll", "pitch", "yaw")
    + tuple(f"accel_bias_{a}_m_s2" for a in "xyz") + tuple(f"gyro_bias_{a}_deg_h" for a in "xyz")
    + ("sigma_n", "sigma_e", "sigma_d", "sigma_vn", "sigma_ve", "sigma_vd",
       "sigma_psi_n_deg", "sigma_psi_e_deg", "sigma_psi_d_deg")
    + tuple(f"sigma_accel_bias_{a}_m_s2" for a in "xyz") + tuple(f"sigma_gyro_bias_{a}_deg_h" for a in "xyz"))
#: Appended to OUTPUT_COLUMNS with scale_factors = true: the scale-factor estimates and one-sigmas, ppm.
SCALE_COLUMNS = (tuple(f"accel_scale_{a}_ppm" for a in "xyz") + tuple(f"gyro_scale_{a}_ppm" for a in "xyz")
                 + tuple(f"sigma_accel_scale_{a}_ppm" for a in "xyz")
                 + tuple(f"sigma_gyro_scale_{a}_ppm" for a in "xyz"))

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
  time, lat, lon (deg), h (m), v_n, v_e, v_d (m/s), roll, pitch, yaw (deg),
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
  stream; --format forces the format of the files.
--out OUT.parquet writes Parquet (pyarrow) instead of CSV; a long run shows a progress bar on a
  terminal
--kml FILE, --gpx FILE write the track; --plot FILE.png plots track with GNSS fixes, attitude
  with its 3-sigma band, biases, the difference to the log's own attitude estimate (e.g. PX4's)
  when it has one, the position one-sigma, and every aid's innovation NIS over time (x: not applied)
--declination auto: the World Magnetic Model (ahrs.utils.WMM, the [peers] extra) at the first GNSS
  fix on the day of the recording: --date YYYY-MM-DD (or a decimal year), else the GNSS's first UTC
  time (a ULog's time_utc_usec, a .pos or NMEA date, a utc column), else today's, with a note; the
  note names the model, the date and its source; a date after the model's five years is a warning,
  one before 2015 (no coefficients) an error
--json FILE writes a summary (rows, navigation start, alignment, gaps, decisions, warnings);
  --json - prints it
--diagnostics FILE.csv writes one row per aiding sample: aid, time (s), innovation_0..2 (INS
  minus aid), nis, status, decision (accepted, rejected, inflated, reset, skipped, aligned, none),
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


def read_csv(path, required, optional=(), what="file"):
    """Read a CSV with a header row; returns ({column: float array}, file line numbers).

    See :func:`quatnav.io.table.read_table`; raises :class:`InputError` naming the file, line, column.
    """
    try:
        tab = read_table(path, required, optional, what=what)
    except CsvError as e:
        raise InputError(str(e)) from None
    return tab.columns, tab.lines


def load_config(path, initial: dict | None = None) -> dict:
    """Parameters of :class:`quatnav.GpsInsFilter` from the ``[filter]`` table of a TOML file
    (the ``[parameters]`` and ``[allan]`` tables of a ``quatnav allan`` noise file are ignored).
    With a dict ``initial``, the ``[initial]`` table (a given initial state) is put in it."""
    try:
        import tomllib as toml  # Python 3.11+
    except ModuleNotFoundError:  # pragma: no cover - depends on the Python version
        try:
            import tomli as toml
        except ModuleNotFoundError:
            raise InputError(f"config {path}: reading TOML needs Python 3.11+ or the 'tomli' package") from None
    try:
        with open(path, "rb") as fh:
            doc = toml.load(fh)
    except OSError as e:
        raise InputError(f"config {path}: cannot open ({e.strerror})") from None
    except toml.TOMLDecodeError as e:
        raise InputError(f"config {path}: not valid TOML ({e})") from None
    from ..filters.gpsins import PARAM_NAMES
    from ..filters.tables import GPSINS_PARAMS
    kinds = {q.name: q.kind for q in GPSINS_PARAMS}
    # a noise file of 'quatnav allan' also holds [parameters.NAME] (other filters) and [allan] (read-outs)
    unknown = [k for k in doc if k not in ("filter", "initial", "parameters", "allan")]
    if unknown:
        raise InputError(f"config {path}: unknown table or key {unknown[0]!r} (expected a [filter] table)")
    params = doc.get("filter", {})
    if not isinstance(params, dict):
        raise InputError(f"config {path}: 'filter' must be a table")

    def numbers(v, n):
        return isinstance(v, list) and len(v) == n and all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                                           for x in v)
    for k, v in params.items():
        if k not in PARAM_NAMES:
            raise InputError(f"config {path}: [filter] unknown parameter {k!r} (known: {', '.join(PARAM_NAMES)})")
        kind = kinds[k]
        if kind == "vec3":
            if not numbers(v, 3):
                raise InputError(f"config {path}: [filter] {k} must be a list of 3 numbers (m)")
        elif kind == "mat3":
            if not (numbers(v, 3) or (isinstance(v, list) and len(v) == 3 and all(numbers(r, 3) for r in v))):
                raise InputError(f"config {path}: [filter] {k} must be [roll, pitch, yaw] (rad) or a 3x3 matrix "
                                 "(a list of 3 rows)")
            if numbers(v, 3):
                _check_radians(v, f"config {path}: [filter] {k}", pitch_limit=False)
        elif kind == "bool":
            if not isinstance(v, bool):
                raise InputError(f"config {path}: [filter] {k} must be true or false")
        elif kind in ("int1", "iter"):
            if isinstance(v, bool) or not isinstance(v, int):
                raise InputError(f"config {path}: [filter] {k} must be an integer")
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"config {path}: [filter] {k} must be a number")
    init = doc.get("initial", {})
    if not isinstance(init, dict):
        raise InputError(f"config {path}: 'initial' must be a table")
    sizes = {"euler": 3, "q_nb": 4, "v_n": 3, "acc_bias": 3, "gyro_bias": 3}
    for k, v in init.items():
        if k not in sizes:
            raise InputError(f"config {path}: [initial] unknown key {k!r} (known: {', '.join(sizes)})")
        if not numbers(v, sizes[k]):
            raise InputError(f"config {path}: [initial] {k} must be a list of {sizes[k]} numbers")
    if "euler" in init:
        _check_radians(init["euler"], f"config {path}: [initial] euler", pitch_limit=True)
    if init and ("euler" in init) == ("q_nb" in init):
        raise InputError(f"config {path}: [initial] needs exactly one of euler (rad) and q_nb")
    if initial is not None:
        initial.update(init)
    return dict(params)


def _check_radians(rpy, where, pitch_limit):
    """Refuse [roll, pitch, yaw] that cannot be radians (beyond 2 pi, or a pitch beyond pi/2 where
    ``pitch_limit``): most likely degrees, which the message converts."""
    bad = any(abs(float(x)) > 2 * math.pi + 1e-9 for x in rpy)
    if pitch_limit and abs(float(rpy[1])) > math.pi / 2 + 1e-9:
        bad = True
    if bad:
        rad = ", ".join(f"{math.radians(float(x)):.6g}" for x in rpy)
        raise InputError(f"{where} = {list(rpy)} is not [roll, pitch, yaw] in radians"
                         f"{' (pitch within +-pi/2)' if pitch_limit else ''}; if these are degrees: [{rad}]")


#: The most coasting steps inserted into one run (a longer gap is refused, not coasted).
MAX_COAST_STEPS = 5_000_000


def coast_gaps(t, gyro, accel, gaps, max_dt, lines=None, where="IMU"):
    """Insert coasting steps into gaps longer than ``max_dt``.

    Each gap (t[k-1], t[k]] is split into ``ceil(step / max_dt)`` equal steps, all with row k's
    rate and specific force (row k is the mean over the gap by the file's convention). ``lines``
    (file line of each row) and ``where`` only serve the message when the gaps are too long.

    Returns
    -------
    t, gyro, accel : ndarray
        The expanded record.
    original : (M,) bool ndarray
        True at the rows of the input (False at inserted steps).
    """
    if not gaps:
        return t, gyro, accel, np.ones(len(t), bool)
    reps = np.ones(len(t), dtype=np.int64)
    for k, step in gaps:
        reps[k] = int(math.ceil(step / (max_dt * (1 - 1e-9))))  # every sub-step strictly below max_dt
    total = int(reps.sum()) - len(t)
    if total > MAX_COAST_STEPS:
        k, step = max(gaps, key=lambda g: g[1])
        at = f"lines {lines[k - 1]}-{lines[k]}" if lines is not None else f"rows {k - 1}-{k}"
        raise InputError(f"{where}: gaps would need {total} coasting steps of max_dt = {max_dt:g} s (longest "
                         f"{step:g} s, {at}); split the log at the gap or raise max_dt")
    idx = np.repeat(np.arange(len(t)), reps)
    original = np.ones(len(idx), bool)
    tt = t[idx].copy()
    pos = np.cumsum(reps) - 1  # position of each original row in the expanded record
    for k, _ in gaps:
        m = reps[k]
        j = pos[k] - m + 1  # first inserted step
        frac = np.arange(1, m) / m
        tt[j:j + m - 1] = t[k - 1] + frac * (t[k] - t[k - 1])
        original[j:j + m - 1] = False
    return tt, gyro[idx], accel[idx], original


def _columns_of(log, what):
    """The column dicts ``run_files`` uses, from a :class:`quatnav.io.Log` stream (rows numbered
    from 1 as the 'lines' of messages)."""
    if what == "IMU":
        s = log.require("imu").imu
        d = {"time": s.t, **{f"gyro_{c}": s.gyr[:, i] for i, c in enumerate("xyz")},
             **{f"accel_{c}": s.acc[:, i] for i, c in enumerate("xyz")}}
    elif what == "GNSS":
        g = log.require("gnss").gnss
        nan = np.full((len(g.t), 3), np.nan)
        v, sg, sv = (x if x is not None else nan for x in (g.vel_n, g.sigma, g.sigma_vel))
        v = np.where(np.isnan(v).any(1, keepdims=True), np.nan, v)  # NMEA: no v_d -> no velocity
        sv = np.where(np.isnan(v).any(1, keepdims=True) | np.isnan(sv).any(1, keepdims=True), np.nan, sv)
        d = {"time": g.t, "lat": np.degrees(g.lat), "lon": np.degrees(g.lon), "h": g.h,
             **{k: v[:, i] for i, k in enumerate(("v_n", "v_e", "v_d"))},
             **{k: sg[:, i] for i, k in enumerate(("sigma_n", "sigma_e", "sigma_d"))},
             **{k: sv[:, i] for i, k in enumerate(("sigma_vn", "sigma_ve", "sigma_vd"))},
             "utc": g.utc if g.utc is not None else np.full(len(g.t), np.nan)}
    elif what == "BARO":
        b = log.require("baro").baro
        if b.altitude is None:
            raise InputError(f"{log.source}: the barometer gives pressure only, no altitude")
        d = {"time": b.t, "h": b.altitude}
    elif what == "MAG":
        m = log.require("mag").mag
        d = {"time": m.t, **{f"mag_{c}": m.values[:, i] for i, c in enumerate("xyz")}}
    else:
        c = log.require("compass").compass
        d = {"time": c.t, "heading": np.degrees(c.heading), "north": getattr(c, "north", "magnetic")}
    return d, np.arange(1, len(d["time"]) + 1)


def _reader(log, fmt):
    """A ``read_csv`` that takes any file :func:`quatnav.io.read` knows (CSV files keep the CSV
    reader and its messages); ``log`` (a Log) serves the files not given."""
    from .. import io

    def read(path, required, optional=(), what="file"):
        if path is None:
            return _columns_of(log, what)
        import os
        if not os.path.exists(path):
            kind = "csv"  # the CSV reader's message names the missing file
        else:
            kind = io.detect(path) if fmt == "auto" or log is not None else fmt
        if kind == "csv":
            return read_csv(path, required, optional, what=what)
        try:
            return _columns_of(io.read(path, format=kind), what)
        except ValueError as e:
            raise InputError(str(e)) from None
    return read


def _header_has(path, column) -> bool:
    """Whether a CSV file's header row (the first line that is not blank or a # comment) names
    ``column`` (case and surrounding spaces ignored)."""
    try:
        with open(path, encoding="utf-8-sig", errors="replace") as fh:
            for line in fh:
                if line.strip() and not line.lstrip().startswith("#"):
                    import re
                    return column in [c.strip().lower() for c in re.split(r"[,;\t]", line)]
    except OSError:
        return False
    return False


def mag_at_imu_rows(t_imu, t_mag, mag):
    """The magnetometer samples as (N, 3) rows of the IMU record: each sample at the first IMU time
    at or after its own (the last one when several fall on a row); NaN rows where none."""
    out = np.full((len(t_imu), 3), np.nan)
    k = np.searchsorted(t_imu, t_mag, side="left")
    ok = (k > 0) & (k < len(t_imu))
    out[k[ok]] = mag[ok]
    return out


def diagnostics_table(r) -> list:
    """One row per aiding sample of a run (see ``--diagnostics``)."""
    from ..filters.tables import GPSINS_DECISIONS, STATUS_NAMES
    rows = []
    qs = r.q_scale
    for name, a in r.aids.items():
        k = np.clip(np.searchsorted(r.t, a.t, side="left"), 0, len(r.t) - 1)
        inn = np.full((len(a.t), 3), np.nan)
        inn[:, :a.innovation.shape[1]] = a.innovation
        for i in range(len(a.t)):
            rows.append((name, float(a.t[i]), *inn[i], float(a.nis[i]), STATUS_NAMES[int(a.status[i])],
                         GPSINS_DECISIONS[int(a.decision[i])], float(a.inflation[i]), float(qs[k[i]])))
    rows.sort(key=lambda x: x[1])
    return rows


def write_diagnostics(path, r) -> int:
    """Write :func:`diagnostics_table` as CSV; returns the number of rows."""
    rows = diagnostics_table(r)
    try:
        with open(path, "w", encoding="utf-8") as fh:
            fh.write(",".join(DIAGNOSTICS_COLUMNS) + "\n")
            for row in rows:
                fh.write(",".join(x if isinstance(x, str) else repr(float(x)) for x in row) + "\n")
    except OSError as e:
        raise InputError(f"diagnostics {path}: cannot write ({e.strerror})") from None
    return len(rows)


def _quiet_navigation(fn):
    """Run ``fn`` with :class:`quatnav.NavigationWarning` silenced: its message reports the reason."""
    @functools.wraps(fn)
    def wrapped(*args, **kwargs):
        from ..filters.gpsins import NavigationWarning
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", NavigationWarning)
            return fn(*args, **kwargs)
    return wrapped


@_quiet_navigation
def run_files(imu, gnss, out, baro=None, compass=None, config=None, warn=None, log=None, fmt="auto", tracks=None,
              calibration=None, mag=None, odometer=None, diagnostics=None, smooth=False, time_offset=None,
              executor=None, no_mag=False, declination=False, mag_calibrate=False, date=None):
    """Run the filter on the files and write ``out``.

    Returns
    -------
    message : str
        One-line summary.
    ok : bool
        Whether navigation started (any output rows).
    summary : dict
        Rows, navigation start, coasted gaps, gate rejections, warnings (for ``--json``).

    ``warn(text)`` is called once per warning (default: collected in ``summary["warnings"]`` only).
    ``calibration``: a calibration TOML file (``quatnav calibrate``) applied to the gyro and
    accelerometer samples before the filter sees them. ``mag``, ``odometer``: CSV files of a raw
    magnetometer and an odometer (without ``mag``, the magnetometer of ``log`` when it has one, unless
    ``no_mag``); ``declination``: degrees east (replaces the configuration's), None for the
    World Magnetic Model at the first fix (``summary["declination_note"]``) on the date ``date`` (a
    decimal year), else the GNSS's (its ``utc`` column, a log's UTC time), else today's, False: as configured;
    ``mag_calibrate``: run once without the magnetometer, fit its offset and the Earth field to that
    run's attitude (:mod:`quatnav.calibration.mag_attitude`) and run with the corrected samples and
    the fitted declination (``summary["mag_calibration"]``);
    ``diagnostics``: a CSV file for the per-sample report of the aids. ``smooth``: write the Rauch-Tung-Striebel smoothed solution (``run(..., smooth=True)``).
    ``time_offset``: ``(low, high)`` s: estimate ``gps_time_offset`` over that interval first
    (:func:`quatnav.calibration.gps_time_offset`, its runs through ``executor``) and run with it;
    ``summary["gps_time_offset_estimate"]`` holds the estimate.
    """
    import quatnav

    warnings, note_info = [], []

    def note(text):
        warnings.append(text)
        if warn is not None:
            warn(text)

    from pathlib import Path
    parent = Path(out).resolve().parent
    if not parent.is_dir():
        raise InputError(f"output {out}: cannot write (no such directory: {parent})")
    initial = {}
    params = load_config(config, initial) if config else {}

    def make_filter():
        try:
            f = quatnav.GpsInsFilter(**params)
            if initial:
                f.set_initial(initial.get("q_nb"), euler=initial.get("euler"), v_n=initial.get("v_n"),
                              acc_bias=initial.get("acc_bias", (0.0, 0.0, 0.0)),
                              gyro_bias=initial.get("gyro_bias", (0.0, 0.0, 0.0)))
        except (TypeError, ValueError) as e:
            raise InputError(f"config {config}: {e}") from None
        return f

    if date is not None and declination is not None:
        raise InputError("--date dates the World Magnetic Model: it goes with --declination auto")
    if declination is not False and declination is not None:
        params["declination"] = math.radians(declination)
    f = make_filter()
    max_dt, align_time = float(f.params["max_dt"]), float(f.params["align_time"])
    read_csv = _reader(log, fmt)
    baro_from_log = log is not None and baro is None and log.baro is not None and log.baro.altitude is not None
    if log is None and (imu is None or gnss is None):
        raise InputError("give --imu and --gnss, or --log")
    increments = imu is not None and _header_has(imu, "dtheta_x")
    d_imu, lines_i = read_csv(imu, IMU_INCREMENT_COLUMNS if increments else IMU_COLUMNS, what="IMU")
    if increments:
        d_imu.update({f"gyro_{c}": d_imu[f"dtheta_{c}"] for c in "xyz"})
        d_imu.update({f"accel_{c}": d_imu[f"dvel_{c}"] for c in "xyz"})
    imu = imu or log.source
    if len(d_imu["time"]) < 2:
        raise InputError(f"IMU {imu}: needs at least two rows")
    try:  # utc (UTC s since 1970) dates the World Magnetic Model: read for --declination auto only
        d_g, lines_g = read_csv(gnss, GNSS_COLUMNS, GNSS_OPTIONAL + (("utc",) if declination is None else ()),
                                what="GNSS")
    except InputError as e:
        if "column 'utc'" not in str(e):
            raise
        raise InputError(f"{e} (utc: UTC seconds since 1970-01-01, Unix time; or give --date YYYY-MM-DD)") from None
    gnss = gnss or log.source
    for c, lim in (("lat", 90.0), ("lon", 360.0)):
        bad = np.flatnonzero(np.abs(d_g[c]) > lim)
        if len(bad):
            raise InputError(f"GNSS {gnss}: line {lines_g[bad[0]]}, column {c!r}: {float(d_g[c][bad[0]])!r} is not "
                             f"a {'latitude' if c == 'lat' else 'longitude'} in degrees")
    for cols in (("v_n", "v_e", "v_d"), ("sigma_n", "sigma_e", "sigma_d"), ("sigma_vn", "sigma_ve", "sigma_vd")):
        a = np.column_stack([d_g[c] for c in cols])
        part = np.isnan(a).any(axis=1) & ~np.isnan(a).all(axis=1)
        if part.any():
            i = int(np.argmax(part))
            c = cols[int(np.argmax(np.isnan(a[i])))]
            raise InputError(f"GNSS {gnss}: line {lines_g[i]}, column {c!r}: empty while "
                             f"{', '.join(x for x in cols if x != c)} are given (give all three or none)")
        if cols[0].startswith("sigma"):
            neg = np.flatnonzero((a <= 0).any(axis=1))
            if len(neg):
                raise InputError(f"GNSS {gnss}: line {lines_g[neg[0]]}: {'/'.join(cols)} must be positive")
    if declination is None:  # auto: the World Magnetic Model at the first fix
        from ..core.magnetic import first_fix_declination
        params["declination"], texts = first_fix_declination(np.radians(d_g["lat"]), np.radians(d_g["lon"]), d_g["h"],
                                                             f"GNSS {gnss}", utc=d_g.get("utc"), date=date, warn=note)
        f = make_filter()
        note_info.extend(texts)
    kw = dict(gps_pos=quatnav.Aid(d_g["time"], np.column_stack([np.radians(d_g["lat"]), np.radians(d_g["lon"]), d_g["h"]]),
                                  np.column_stack([d_g[c] for c in ("sigma_n", "sigma_e", "sigma_d")])),
              gps_vel=quatnav.Aid(d_g["time"], np.column_stack([d_g[c] for c in ("v_n", "v_e", "v_d")]),
                                  np.column_stack([d_g[c] for c in ("sigma_vn", "sigma_ve", "sigma_vd")])))
    if baro or baro_from_log:
        d_b, _ = read_csv(baro, BARO_COLUMNS, what="BARO")
        kw.update(baro=quatnav.Aid(d_b["time"], d_b["h"]))
    if compass or (log is not None and log.compass is not None):
        d_c, _ = read_csv(compass, COMPASS_COLUMNS, what="COMPASS")
        heading = np.radians(d_c["heading"])
        if d_c.get("north") == "true":  # a GNSS heading: the filter adds the declination to a magnetic one
            heading = heading - float(f.params["declination"])
        kw.update(compass=quatnav.Aid(d_c["time"], heading))
    if odometer:
        d_o, _ = read_csv(odometer, ODOMETER_COLUMNS, what="ODOMETER")
        kw.update(odometer=quatnav.Aid(d_o["time"], d_o["speed"]))
    d_m = None
    if mag or (log is not None and log.mag is not None and not no_mag):
        d_m, _ = read_csv(mag, MAG_COLUMNS, what="MAG")
    t = d_imu["time"]
    gyro = np.column_stack([d_imu[c] for c in ("gyro_x", "gyro_y", "gyro_z")])
    accel = np.column_stack([d_imu[c] for c in ("accel_x", "accel_y", "accel_z")])
    if calibration:
        from ..calibration import apply_calibration_args
        gyro, accel, _ = apply_calibration_args(argparse.Namespace(calibration=calibration), gyro, accel)
    gaps, wt = check_imu_times(t, lines_i, max_dt, where=f"IMU {imu}")
    for w in wt:
        note(str(w))
    step = np.diff(t)[:, None] if increments else 1.0
    rot = np.asarray(f.params["imu_rotation"], float)
    rates = np.vstack([gyro[:1] * 0, gyro[1:] / step]) if increments else gyro
    forces = np.vstack([accel[:1] * 0, accel[1:] / step]) if increments else accel
    if not np.array_equal(rot, np.eye(3)):  # the checks look at the body axes
        rates, forces = rates @ rot.T, forces @ rot.T
    for w in plausibility_warnings(t, rates, forces, d_g["time"], d_g["lat"], d_g["lon"], align_time,
                                   imu=f"IMU {imu}", gnss=f"GNSS {gnss}", gnss_speed=gnss_speed(d_g),
                                   gnss_vel=gnss_velocity_ne(d_g)):
        note(str(w))
    overlap = check_overlap(t, d_g["time"]) is None
    tt, gg, aa, original = coast_gaps(t, gyro, accel, gaps, max_dt, lines_i, where=f"IMU {imu}")
    if increments and not original.all():  # a coasted gap shares its increments between its steps
        row = np.cumsum(original) - original  # the input row each step belongs to (it ends the group)
        share = 1.0 / np.bincount(row)[row]
        gg, aa = gg * share[:, None], aa * share[:, None]
    if d_m is not None:
        kw["mag"] = mag_at_imu_rows(tt, d_m["time"], np.column_stack([d_m[f"mag_{c}"] for c in "xyz"]))
    imu_input = "increment" if increments else "rate"
    mag_fit = None
    if mag_calibrate:
        if "mag" not in kw:
            raise InputError("--mag-calibrate needs a magnetometer (--mag MAG.csv, or a log with one)")
        mag_fit = _calibrate_mag(make_filter(), gg, aa, tt, imu_input, kw)
        if mag_fit is None:
            note("--mag-calibrate: fewer than 100 magnetometer samples with a settled heading (yaw one-sigma "
                 "below 1 deg) in the run without it: the magnetometer is used as it is")
        else:
            b = np.asarray(f.params["imu_rotation"], float).T @ mag_fit.offset  # in the IMU axes of the samples
            kw["mag"] = kw["mag"] - b
            if declination is not False:
                note(f"--mag-calibrate: the magnetometer's fitted declination ({math.degrees(mag_fit.declination):+.2f} "
                     "deg) replaces the one given")
            params["declination"] = mag_fit.declination
            f = make_filter()
            note_info.append(f"magnetometer calibrated against the GNSS/INS attitude of a run without it: offset "
                             f"({b[0]:.4g}, {b[1]:.4g}, {b[2]:.4g}) in its axes, declination "
                             f"{math.degrees(mag_fit.declination):+.2f} deg, inclination "
                             f"{math.degrees(mag_fit.inclination):.2f} deg, residual {mag_fit.residual_rms:.3g} RMS "
                             f"({mag_fit.samples} samples)")
    estimate = None
    if time_offset is not None:
        import contextlib
        import os
        from concurrent.futures import ThreadPoolExecutor
        from ..calibration.time_offset import gps_time_offset
        # the runs release the GIL: without a given executor, threads keep every core busy
        pool = (contextlib.nullcontext(executor) if executor is not None
                else ThreadPoolExecutor(max_workers=os.cpu_count() or 1))
        with pool as ex:
            estimate = gps_time_offset(f, gg, aa, t=tt, imu_input=imu_input, bounds=time_offset, executor=ex, **kw)
        if "gps_time_offset" in params:
            note(f"the estimated gps_time_offset ({estimate.offset:+.4f} s) replaces the configured one "
                 f"({params['gps_time_offset']:+g} s)")
        state = f.get_state()
        f = quatnav.GpsInsFilter(**dict(params, gps_time_offset=estimate.offset))
        f.set_state(state)
        if estimate.at_bound:
            note(f"the estimated gps_time_offset is at the end of the searched {time_offset[0]:+g} .. "
                 f"{time_offset[1]:+g} s: widen --estimate-time-offset LOW,HIGH")
    from ..io.table import progress_bar, write_table
    bar = progress_bar(2 * len(tt), desc="ins run: filter", unit="row")  # a terminal and a long log only
    r = f.run(gg, aa, t=tt, imu_input=imu_input, smooth=smooth, **kw)
    bar.update(len(tt))
    bar.set_description("ins run: write")
    nav = r.navigating & original
    s = r.sigma[nav]
    cols = [r.t[nav], np.degrees(r.lat[nav]), np.degrees(r.lon[nav]), r.h[nav], *r.velocity[nav].T,
            *np.degrees(r.euler[nav]).T, *r.acc_bias[nav].T, *(r.bias[nav] / _DEG_H).T,
            *s[:, 0:6].T, *np.degrees(s[:, 6:9]).T, *s[:, 9:12].T, *(s[:, 12:15] / _DEG_H).T]
    names = OUTPUT_COLUMNS
    if r.acc_scale is not None:
        cols += [*(1e6 * r.acc_scale[nav]).T, *(1e6 * r.gyro_scale[nav]).T, *(1e6 * s[:, 16:22]).T]
        names = OUTPUT_COLUMNS + SCALE_COLUMNS
    fmt = ["%.6f", "%.10f", "%.10f"] + ["%.6g"] * (len(names) - 3)
    try:
        write_table(out, names, cols, fmt, progress=bar)
    except OSError as e:
        raise InputError(f"output {out}: cannot write ({e.strerror})") from None
    finally:
        bar.close()
    if tracks is not None:
        tracks.update(result=r, nav=nav, gnss=d_g)
    rej = {k: v for k, v in r.rejections.items() if v}
    for w in check_heading_aids(r):
        note(str(w))
    n_nav = int(nav.sum())
    n_diag = write_diagnostics(diagnostics, r) if diagnostics else None
    if nav.any():
        msg = f"wrote {out}: {n_nav} rows ({len(t)} IMU samples, navigation from t = {r.t[nav][0]:.3f} s)"
    elif not overlap:
        msg = f"wrote {out}: 0 rows (navigation never started: the GNSS and IMU times do not overlap)"
    else:
        a = r.alignment
        fix = ("; give --mag or --compass (or a log with a magnetometer), move faster than min_speed_for_heading, "
               "or the attitude as [initial] euler in --config" if a["method"] != "none" and a["heading"] == "none"
               else "")
        msg = f"wrote {out}: 0 rows (navigation never started: {a['reason']}{fix})"
    if gaps:
        msg += f"; {len(gaps)} IMU gap{'s' if len(gaps) > 1 else ''} coasted"
    if rej:
        msg += "; gated out: " + ", ".join(f"{k} {v}" for k, v in rej.items())
    if nav.any():
        msg += f"; alignment {r.alignment['method']}, heading from {r.alignment['heading']}"
    nhc_t = _nhc_start(r)
    if nhc_t is not None:
        msg += f"; non-holonomic constraint from t = {nhc_t:.1f} s"
    if smooth and nav.any():
        msg += "; smoothed"
    if estimate is not None:
        msg = f"estimated {estimate}\n" + msg
    summary = {"output": str(out), "rows": n_nav, "imu_samples": int(len(t)),
               "navigation_start_s": float(r.t[nav][0]) if nav.any() else None,
               "coasted_gaps": [{"lines": [int(lines_i[k - 1]), int(lines_i[k])], "seconds": step} for k, step in gaps],
               "gated_out": rej, "counters": r.counters, "alignment": r.alignment,
               "decisions": {k: a.decisions() for k, a in r.aids.items()}, "diagnostics_rows": n_diag,
               "warnings": warnings, "smoothed": bool(smooth), "nhc_start_s": nhc_t,
               "declination_rad": float(f.params["declination"])}
    if mag_fit is not None:
        summary["mag_calibration"] = {
            "offset_imu_axes": b.tolist(), "offset_sigma_body": mag_fit.offset_sigma.tolist(),
            "field_n": mag_fit.field_n.tolist(), "declination_rad": mag_fit.declination,
            "inclination_rad": mag_fit.inclination, "residual_rms": mag_fit.residual_rms, "samples": mag_fit.samples}
    for text in note_info:
        summary.setdefault("notes", []).append(text)
        if text.startswith("declination"):
            summary["declination_note"] = text
        msg += f"\nnote: {text}"
    if estimate is not None:
        summary["gps_time_offset_estimate"] = {
            "offset_s": estimate.offset, "sigma_s": estimate.sigma if np.isfinite(estimate.sigma) else None,
            "at_bound": estimate.at_bound, "bounds_s": list(estimate.bounds), "runs": estimate.runs}
    return msg, bool(nav.any()), summary


def _calibrate_mag(f, gyro, accel, t, imu_input, kw):
    """Run ``f`` without the magnetometer and fit its offset and the Earth field to the attitudes
    whose yaw one-sigma is below 1 deg (:func:`quatnav.calibration.mag_attitude_fit`), or None."""
    from ..calibration.mag_attitude import mag_attitude_fit
    r0 = f.run(gyro, accel, t=t, imu_input=imu_input, **{k: v for k, v in kw.items() if k != "mag"})
    settled = np.isfinite(r0.sigma[:, 8]) & (r0.sigma[:, 8] < math.radians(1.0))
    q = np.where(settled[:, None], r0.quat, np.nan)
    rot = np.asarray(f.params["imu_rotation"], float)
    return mag_attitude_fit(q, kw["mag"] @ rot.T)


def _nhc_start(r):
    """The time of the first accepted non-holonomic update (forced by nhc, or learned: nhc_auto)."""
    a = r.aids.get("nhc")
    ok = np.flatnonzero(a.accepted) if a is not None else []
    return float(a.t[ok[0]]) if len(ok) else None


def _run(args) -> int:
    prog = getattr(args, "_prog", "quatnav ins run")
    log = None
    if args.log:
        from .. import io
        log = io.read(args.log, format=args.format)
    elif not (args.imu and args.gnss):
        raise UsageError("give --imu IMU and --gnss GNSS, or --log FILE")
    tracks = {}
    msg, ok, summary = run_files(args.imu, args.gnss, args.out, baro=args.baro, compass=args.compass,
                                 config=args.config, warn=lambda w: print(f"{prog}: warning: {w}", file=sys.stderr),
                                 log=log, fmt=args.format, tracks=tracks,
                                 calibration=getattr(args, "calibration", None), mag=args.mag,
                                 odometer=args.odometer, diagnostics=args.diagnostics, smooth=args.smooth,
                                 time_offset=args.estimate_time_offset, no_mag=args.no_mag,
                                 declination=args.declination, mag_calibrate=args.mag_calibrate, date=args.date)
    print(msg)
    if ok:
        from ..io import tracks as track_files
        r, nav = tracks["result"], tracks["nav"]
        if args.kml:
            track_files.write_kml(args.kml, r.t[nav], r.lat[nav], r.lon[nav], r.h[nav])
            print(f"wrote {args.kml}")
        if args.gpx:
            track_files.write_gpx(args.gpx, r.t[nav], r.lat[nav], r.lon[nav], r.h[nav])
            print(f"wrote {args.gpx}")
        if args.plot:
            track_files.plot_nav(args.plot, r, nav, tracks["gnss"], log)
            print(f"wrote {args.plot}")
    if args.json:
        write_json(summary, args)
    return 0 if ok else 1


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
                              description="GPS/INS navigation (paper 004 filter) on CSV files or a PX4 ULog, "
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
    r.add_argument("--estimate-time-offset", nargs="?", const=(-0.5, 0.5), default=None, type=_offset_bounds,
                   metavar="LOW,HIGH",
                   help="estimate gps_time_offset (s, the GNSS clock to the IMU's; a receiver latency L is -L) "
                        "from the log first, searching LOW..HIGH s (default -0.5,0.5), and run with it: the "
                        "offset whose GNSS innovations are smallest (needs motion; prints the estimate and its "
                        "one-sigma); a negative LOW takes '=': --estimate-time-offset=-0.3,0.1")
    r.add_argument("--kml", metavar="FILE.kml", help="also write the track as KML (Google Earth)")
    r.add_argument("--gpx", metavar="FILE.gpx", help="also write the track as GPX")
    r.add_argument("--plot", metavar="FILE.png", help="also plot track with GNSS fixes, attitude, biases")
    r.set_defaults(func=_run)
    p.set_defaults(func=None)
    return p
