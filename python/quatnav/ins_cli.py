"""``quatnav ins run``: the GPS/INS filter of paper 004 (:class:`quatnav.GpsInsFilter`) on CSV logs.

::

    quatnav ins run --imu IMU.csv --gnss GNSS.csv [--baro BARO.csv] [--compass COMPASS.csv]
                    [--config CONFIG.toml] --out OUT.csv

Every input file is CSV with a header row of named columns (any order; extra columns are
ignored; blank lines and lines starting with ``#`` are skipped). Times are in seconds on one
clock shared by all files and strictly increasing within each file.

=============  ===========================================================================
file           columns
=============  ===========================================================================
IMU            ``time`` (s), ``gyro_x gyro_y gyro_z`` (rad/s), ``accel_x accel_y accel_z``
               (m/s^2): body frame forward-right-down; row k holds the mean rate and specific
               force over (time[k-1], time[k]]; the first row only fixes the start time.
GNSS           ``time`` (s), ``lat lon`` (deg), ``h`` (m, ellipsoidal) of the antenna; optional
               ``v_n v_e v_d`` (NED velocity, m/s), ``sigma_n sigma_e sigma_d`` (position
               one-sigma, m), ``sigma_vn sigma_ve sigma_vd`` (velocity one-sigma, m/s). An
               empty optional cell means "not given" (no velocity / the configured sigma).
BARO           ``time`` (s), ``h`` (altimeter height, m; its offset is tied to the GNSS height)
COMPASS        ``time`` (s), ``heading`` (magnetic heading, deg; ``declination`` is added)
=============  ===========================================================================

The TOML configuration has one table, ``[filter]``, whose keys are the parameters of
:class:`quatnav.GpsInsFilter` (``quatnav::GpsInsParams``) in their units (SI, radians), e.g.::

    [filter]
    gyro_noise = 8.7e-4          # rad/s/sqrt(Hz)
    accel_noise = 2.0e-3         # m/s^2/sqrt(Hz)
    lever_arm_b = [0.1, 0.0, -0.1]   # m, antenna in the body frame
    gps_pos_sigma_h = 2.5        # m, when a fix gives none
    gate_gps_pos = 21.108        # chi-square gate (3 dof); 0 switches it off
    align_time = 2.0             # s at rest for levelling

The output has one row per IMU sample from the start of navigation: ``time`` (s), ``lat lon``
(deg), ``h`` (m), ``v_n v_e v_d`` (m/s), ``roll pitch yaw`` (deg, ZYX), ``accel_bias_x_m_s2 ..z``,
``gyro_bias_x_deg_h ..z``, then the one-sigma columns ``sigma_n sigma_e sigma_d`` (m),
``sigma_vn sigma_ve sigma_vd`` (m/s), ``sigma_psi_n_deg sigma_psi_e_deg sigma_psi_d_deg``
(attitude error about the NED axes), ``sigma_accel_bias_x_m_s2 ..z``, ``sigma_gyro_bias_x_deg_h
..z``. Errors in the input end the command with exit status 2 and a one-line message naming the
file, the line and the column; exit status 1 means navigation never started (no output rows).
"""
from __future__ import annotations

import argparse
import csv
import math
import sys

import numpy as np

IMU_COLUMNS = ("time", "gyro_x", "gyro_y", "gyro_z", "accel_x", "accel_y", "accel_z")
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

EPILOG = """\
input files: CSV, a header row of named columns in any order (extra columns ignored; lines
starting with # skipped); times in s on one clock, strictly increasing in each file.
  IMU      time, gyro_x, gyro_y, gyro_z (rad/s), accel_x, accel_y, accel_z (m/s^2); body
           forward-right-down; row k = mean over (time[k-1], time[k]]
  GNSS     time, lat, lon (deg), h (m, antenna); optional v_n, v_e, v_d (m/s),
           sigma_n, sigma_e, sigma_d (m), sigma_vn, sigma_ve, sigma_vd (m/s); empty cell = not given
  BARO     time, h (m)
  COMPASS  time, heading (deg, magnetic; the declination parameter is added)
config (TOML): a [filter] table of quatnav.GpsInsFilter parameters in SI units and radians,
  e.g. lever_arm_b = [0.1, 0.0, -0.1], gps_pos_sigma_h = 2.5, gate_gps_pos = 21.108
output (CSV), one row per IMU sample once navigating:
  time, lat, lon (deg), h (m), v_n, v_e, v_d (m/s), roll, pitch, yaw (deg),
  accel_bias_{x,y,z}_m_s2, gyro_bias_{x,y,z}_deg_h, sigma_n, sigma_e, sigma_d (m),
  sigma_vn, sigma_ve, sigma_vd (m/s), sigma_psi_{n,e,d}_deg,
  sigma_accel_bias_{x,y,z}_m_s2, sigma_gyro_bias_{x,y,z}_deg_h
exit status: 0 on success, 1 when navigation never started (no output rows), 2 on an input
error (one line on stderr naming the file, line and column)."""


class InputError(Exception):
    """A problem with an input file or the configuration (its message is the one-line report)."""


def read_csv(path, required, optional=(), what="file"):
    """Read a CSV with a header row; returns ({column: float array}, line numbers).

    Required columns must be present with a number in every row; optional columns may be absent
    (all NaN) or empty in a row (NaN). Raises :class:`InputError` naming the file, line, column.
    """
    try:
        fh = open(path, newline="")
    except OSError as e:
        raise InputError(f"{what} {path}: cannot open ({e.strerror})") from None
    with fh:
        rows = []
        header = None
        for lineno, row in enumerate(csv.reader(fh), start=1):
            if not row or all(not c.strip() for c in row) or row[0].lstrip().startswith("#"):
                continue
            if header is None:
                header = [c.strip() for c in row]
                header_line = lineno
                dup = sorted({c for c in header if header.count(c) > 1 and c})
                if dup:
                    raise InputError(f"{what} {path}: line {lineno}: column {dup[0]!r} appears twice in the header")
                continue
            rows.append((lineno, row))
    if header is None:
        raise InputError(f"{what} {path}: empty file (no header row)")
    missing = [c for c in required if c not in header]
    if missing:
        raise InputError(f"{what} {path}: line {header_line}: missing column {missing[0]!r} "
                         f"(needs {', '.join(required)}; found {', '.join(header)})")
    if not rows:
        raise InputError(f"{what} {path}: no data rows")
    idx = {c: header.index(c) for c in tuple(required) + tuple(optional) if c in header}
    n = len(rows)
    out = {c: np.full(n, np.nan) for c in tuple(required) + tuple(optional)}
    lines = np.empty(n, dtype=np.int64)
    for i, (lineno, row) in enumerate(rows):
        lines[i] = lineno
        if len(row) < len(header) and any(idx[c] >= len(row) for c in required):
            raise InputError(f"{what} {path}: line {lineno}: {len(row)} fields, the header has {len(header)}")
        for c, j in idx.items():
            raw = row[j].strip() if j < len(row) else ""
            if raw == "" and c not in required:
                continue
            try:
                x = float(raw)
            except ValueError:
                x = math.nan
            if not math.isfinite(x):
                if c in required or raw != "":
                    kind = "empty" if raw == "" else f"not a finite number ({raw!r})"
                    raise InputError(f"{what} {path}: line {lineno}, column {c!r}: {kind}")
            out[c][i] = x
    t = out["time"]
    d = np.diff(t)
    bad = np.flatnonzero(d <= 0)
    if len(bad):
        k = bad[0] + 1
        word = "duplicate time" if d[bad[0]] == 0 else "time goes backwards"
        raise InputError(f"{what} {path}: line {lines[k]}, column 'time': {word} ({t[k]!r} after {t[k - 1]!r} "
                         f"on line {lines[k - 1]}); times must be strictly increasing")
    return out, lines


def load_config(path) -> dict:
    """Parameters of :class:`quatnav.GpsInsFilter` from the ``[filter]`` table of a TOML file."""
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
    from .gpsins import PARAM_NAMES
    unknown = [k for k in doc if k != "filter"]
    if unknown:
        raise InputError(f"config {path}: unknown table or key {unknown[0]!r} (expected a [filter] table)")
    params = doc.get("filter", {})
    if not isinstance(params, dict):
        raise InputError(f"config {path}: 'filter' must be a table")
    for k, v in params.items():
        if k not in PARAM_NAMES:
            raise InputError(f"config {path}: [filter] unknown parameter {k!r} (known: {', '.join(PARAM_NAMES)})")
        if k == "lever_arm_b":
            if not (isinstance(v, list) and len(v) == 3 and all(isinstance(x, (int, float)) for x in v)):
                raise InputError(f"config {path}: [filter] lever_arm_b must be a list of 3 numbers (m)")
        elif k in ("heading_from_gps", "earth_rotation"):
            if not isinstance(v, bool):
                raise InputError(f"config {path}: [filter] {k} must be true or false")
        elif isinstance(v, bool) or not isinstance(v, (int, float)):
            raise InputError(f"config {path}: [filter] {k} must be a number")
    return dict(params)


def run_files(imu, gnss, out, baro=None, compass=None, config=None):
    """Run the filter on the files and write ``out``; returns a one-line summary."""
    import quatnav

    params = load_config(config) if config else {}
    d_imu, _ = read_csv(imu, IMU_COLUMNS, what="IMU")
    if len(d_imu["time"]) < 2:
        raise InputError(f"IMU {imu}: needs at least two rows")
    d_g, lines_g = read_csv(gnss, GNSS_COLUMNS, GNSS_OPTIONAL, what="GNSS")
    for c, lim in (("lat", 90.0), ("lon", 360.0)):
        bad = np.flatnonzero(np.abs(d_g[c]) > lim)
        if len(bad):
            raise InputError(f"GNSS {gnss}: line {lines_g[bad[0]]}, column {c!r}: {d_g[c][bad[0]]!r} is not "
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
    kw = dict(gps_t=d_g["time"], gps_llh=np.column_stack([np.radians(d_g["lat"]), np.radians(d_g["lon"]), d_g["h"]]),
              gps_vel=np.column_stack([d_g[c] for c in ("v_n", "v_e", "v_d")]),
              gps_pos_sigma=np.column_stack([d_g[c] for c in ("sigma_n", "sigma_e", "sigma_d")]),
              gps_vel_sigma=np.column_stack([d_g[c] for c in ("sigma_vn", "sigma_ve", "sigma_vd")]))
    if baro:
        d_b, _ = read_csv(baro, BARO_COLUMNS, what="BARO")
        kw.update(baro_t=d_b["time"], baro_h=d_b["h"])
    if compass:
        d_c, _ = read_csv(compass, COMPASS_COLUMNS, what="COMPASS")
        kw.update(compass_t=d_c["time"], compass_yaw=np.radians(d_c["heading"]))
    try:
        f = quatnav.GpsInsFilter(**params)
    except (TypeError, ValueError) as e:
        raise InputError(f"config {config}: {e}") from None
    t = d_imu["time"]
    gyro = np.column_stack([d_imu[c] for c in ("gyro_x", "gyro_y", "gyro_z")])
    accel = np.column_stack([d_imu[c] for c in ("accel_x", "accel_y", "accel_z")])
    r = f.run(t, gyro, accel, **kw)
    nav = r.navigating
    s = r.sigma[nav]
    cols = [r.t[nav], np.degrees(r.llh[nav, 0]), np.degrees(r.llh[nav, 1]), r.llh[nav, 2], *r.v_n[nav].T,
            *np.degrees(r.euler[nav]).T, *r.accel_bias[nav].T, *(r.gyro_bias[nav] / _DEG_H).T,
            *s[:, 0:6].T, *np.degrees(s[:, 6:9]).T, *s[:, 9:12].T, *(s[:, 12:15] / _DEG_H).T]
    table = np.column_stack(cols) if nav.any() else np.zeros((0, len(OUTPUT_COLUMNS)))
    fmt = ["%.6f", "%.10f", "%.10f"] + ["%.6g"] * (len(OUTPUT_COLUMNS) - 3)
    try:
        np.savetxt(out, table, delimiter=",", header=",".join(OUTPUT_COLUMNS), comments="", fmt=fmt)
    except OSError as e:
        raise InputError(f"output {out}: cannot write ({e.strerror})") from None
    rej = {k: v for k, v in r.rejections.items() if v}
    msg = (f"wrote {out}: {int(nav.sum())} rows ({len(t)} IMU samples, navigation from t = "
           f"{r.t[nav][0]:.3f} s)" if nav.any() else f"wrote {out}: 0 rows (navigation never started: "
           "no GNSS fix after levelling, or no heading)")
    if rej:
        msg += "; gated out: " + ", ".join(f"{k} {v}" for k, v in rej.items())
    return msg, bool(nav.any())


def _run(args) -> int:
    try:
        msg, ok = run_files(args.imu, args.gnss, args.out, baro=args.baro, compass=args.compass, config=args.config)
    except InputError as e:
        print(f"quatnav ins run: error: {e}", file=sys.stderr)
        return 2
    print(msg)
    return 0 if ok else 1


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav ins run`` on an argparse subparsers object."""
    p = subparsers.add_parser("ins", help="GPS/INS navigation on CSV logs (see 'quatnav ins run -h')",
                              description="GPS/INS navigation (paper 004 filter) on CSV logs.")
    sub = p.add_subparsers(dest="ins_command", metavar="COMMAND")
    r = sub.add_parser("run", help="run the GPS/INS filter on IMU and GNSS (and altimeter, compass) CSV files",
                       description="Run quatnav.GpsInsFilter (15-state loosely coupled GPS/INS with altimeter "
                                   "and compass, paper 004) on CSV logs and write the navigation solution.",
                       epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    r.add_argument("--imu", required=True, metavar="IMU.csv", help="IMU samples (required)")
    r.add_argument("--gnss", required=True, metavar="GNSS.csv", help="GNSS fixes of the antenna (required)")
    r.add_argument("--baro", metavar="BARO.csv", help="altimeter heights (optional)")
    r.add_argument("--compass", metavar="COMPASS.csv", help="compass headings (optional)")
    r.add_argument("--config", metavar="CONFIG.toml", help="filter parameters ([filter] table)")
    r.add_argument("--out", required=True, metavar="OUT.csv", help="output CSV")
    r.set_defaults(func=_run)
    p.set_defaults(func=lambda args: (p.print_help(), 2)[1])
    return p
