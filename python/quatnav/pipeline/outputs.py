"""The tables the pipelines write: a GNSS/INS run's navigation solution (one row per IMU sample
once navigating, in the units of the columns' names) and diagnostics (one row per aiding sample);
an attitude run's attitude (one row per sample)."""
from __future__ import annotations

import math

import numpy as np

from .._command import InputError

__all__ = ["OUTPUT_COLUMNS", "SCALE_COLUMNS", "DIAGNOSTICS_COLUMNS", "ins_table", "write_ins_table",
           "diagnostics_table", "write_diagnostics", "ahrs_table", "write_ahrs_table"]

_DEG_H = math.pi / 180.0 / 3600.0  # rad/s per deg/h
#: The columns of the output table of a GNSS/INS run, one row per IMU sample once navigating.
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
#: The columns of the diagnostics table, one row per aiding sample.
DIAGNOSTICS_COLUMNS = ("aid", "time", "innovation_0", "innovation_1", "innovation_2", "nis", "status", "decision",
                       "inflation", "q_scale")


def ins_table(run) -> tuple:
    """The output table of an :class:`~quatnav.pipeline.InsRun`: ``(names, columns, formats)``,
    one row per sample of ``run.rows`` (the navigating IMU samples of the input: coasting steps
    inserted into gaps left out); with scale factors estimated, :data:`SCALE_COLUMNS` appended."""
    r, nav = run.result, run.rows
    s = r.sigma[nav]
    cols = [r.t[nav], np.degrees(r.lat[nav]), np.degrees(r.lon[nav]), r.h[nav], *r.velocity[nav].T,
            *np.degrees(r.euler[nav]).T, *r.acc_bias[nav].T, *(r.bias[nav] / _DEG_H).T,
            *s[:, 0:6].T, *np.degrees(s[:, 6:9]).T, *s[:, 9:12].T, *(s[:, 12:15] / _DEG_H).T]
    names = OUTPUT_COLUMNS
    if r.acc_scale is not None:
        cols += [*(1e6 * r.acc_scale[nav]).T, *(1e6 * r.gyro_scale[nav]).T, *(1e6 * s[:, 16:22]).T]
        names = OUTPUT_COLUMNS + SCALE_COLUMNS
    fmt = ["%.6f", "%.10f", "%.10f"] + ["%.6g"] * (len(names) - 3)
    return names, cols, fmt


def write_ins_table(run, path, progress=None) -> int:
    """Write :func:`ins_table` as CSV (Parquet for a path ending in ``.parquet``,
    :func:`quatnav.io.table.write_table`); returns the number of rows. ``progress``: a bar
    (``update(n)``) advanced as the rows are written."""
    from ..io.table import write_table
    names, cols, fmt = ins_table(run)
    try:
        write_table(path, names, cols, fmt, progress=progress)
    except OSError as e:
        raise InputError(f"output {path}: cannot write ({e.strerror})") from None
    return int(run.rows.sum())


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


def ahrs_table(res) -> dict:
    """The output columns of an attitude run (``quatnav ahrs run``) as {name: array}: time, the
    quaternion, roll/pitch/yaw (deg), the gyro bias (deg/s), the one-sigmas, the flags (bits and
    names)."""
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


def write_ahrs_table(cols: dict, path) -> None:
    """Write :func:`ahrs_table` as CSV, or Parquet for a ``.parquet`` path (pyarrow)."""
    import pandas as pd
    df = pd.DataFrame(cols)
    if str(path).lower().endswith(".parquet"):
        try:
            import pyarrow  # noqa: F401
        except ImportError:
            raise InputError(f"{path}: writing Parquet needs pyarrow: pip install 'quatnav[logs]'") from None
        df.to_parquet(path, index=False)
    else:
        if "time" in df:  # absolute times (GPS, UNIX: ~1e9 s) keep nanoseconds
            df["time"] = np.char.mod("%.9f", df["time"].to_numpy(np.float64))
        df.to_csv(path, index=False, float_format="%.10g")
