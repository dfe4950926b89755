"""What the command line and its subcommand modules share: :class:`UsageError` (a user mistake:
one line on stderr, exit status 2), :func:`write_json` (the ``--json FILE`` of every command) and
the table of optional packages and the extras that provide them. A module of its own, so that
:mod:`quatnav.cli` imports the subcommands and they import this, without a cycle."""
from __future__ import annotations

import json
import sys
from pathlib import Path

__all__ = ["UsageError", "write_json", "missing_extra", "declination_arg", "wmm_declination",
           "first_fix_declination"]

#: optional package -> extra of ``pip install 'quatnav[EXTRA]'`` that provides it, per command
#: (``None``: any command). scipy is in both [sim] and [eval]; the command decides which to name.
_EXTRAS = {
    "scipy": {"simulate": "sim", "bench": "sim", None: "eval"},
    "matplotlib": {None: "eval"}, "h5py": {None: "eval"}, "tqdm": {None: "eval"},
    "pandas": {None: "io"}, "distributed": {None: "cluster"}, "dask": {None: "cluster"},
    "pyulog": {None: "logs"}, "rosbags": {None: "logs"}, "pyarrow": {None: "logs"},
    "vqf": {None: "peers"}, "imufusion": {None: "peers"}, "ahrs": {None: "peers"}, "filterpy": {None: "peers"},
}


class UsageError(Exception):
    """A mistake of the user (bad argument, bad input file): :func:`main` prints its message as
    one line and exits with status 2."""


def missing_extra(module: str, command: str | None = None) -> str | None:
    """The extra that provides ``module`` (top-level name), for ``command``; None if not optional."""
    table = _EXTRAS.get(module.split(".")[0])
    if table is None:
        return None
    return table.get(command, table[None])


def write_json(obj, args, path: str | None = None) -> None:
    """Write ``obj`` as JSON to ``path`` (default ``args.json``); ``-`` is standard output.

    With ``--json -`` :func:`main` sends the command's human-readable output to stderr, so that
    stdout holds only the JSON document.
    """
    dest = path if path is not None else getattr(args, "json", None)
    if not dest:
        return
    text = json.dumps(obj, indent=1, default=_json_default, allow_nan=True)
    if dest == "-":
        out = getattr(args, "_json_stdout", None) or sys.stdout
        out.write(text + "\n")
        out.flush()
        return
    with open(dest, "w") as fh:
        fh.write(text + "\n")
    print(f"wrote {dest}")


def _json_default(o):
    import numpy as np
    if isinstance(o, np.ndarray):
        return o.tolist()
    if isinstance(o, np.generic):
        return o.item()
    if isinstance(o, Path):
        return str(o)
    raise TypeError(f"cannot write {type(o).__name__} as JSON")


def declination_arg(text: str):
    """``--declination``: degrees east of true north (a float) or ``auto`` (None: from the World
    Magnetic Model at the log's first GNSS fix, :func:`wmm_declination`)."""
    import argparse
    import math
    if text.strip().lower() == "auto":
        return None
    try:
        v = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r}: expected degrees east (e.g. 3.2) or auto") from None
    if not math.isfinite(v) or abs(v) > 180.0:
        raise argparse.ArgumentTypeError(f"{text!r}: expected degrees east within +-180, or auto")
    return v


def wmm_declination(lat_rad: float, lon_rad: float, h_m: float, year: float | None = None) -> tuple:
    """The magnetic declination (rad, east of true north) of the World Magnetic Model at a place
    and a decimal year (default: today), with a one-line note naming the model, place and date.

    The model is ``ahrs.utils.WMM`` (the ``[peers]`` extra): a maintained implementation of the
    NOAA/BGS model with its coefficient files (WMM2025 from ahrs 0.4), used here rather than a
    copy of the coefficients in this package, which would age with each five-year release."""
    import datetime
    import math
    try:
        from ahrs.utils import WMM
    except ImportError:
        raise UsageError("--declination auto needs the ahrs package (pip install 'quatnav[peers]')") from None
    if year is None:
        d = datetime.date.today()
        year = d.year + (d.timetuple().tm_yday - 0.5) / 365.25
    lat, lon = math.degrees(lat_rad), math.degrees(lon_rad)
    w = WMM(latitude=lat, longitude=lon, height=h_m / 1000.0, date=year)
    dec = float(w.D)
    if not math.isfinite(dec):
        raise UsageError(f"--declination auto: the World Magnetic Model gives no declination at {lat:.5f}, {lon:.5f}")
    note = f"declination {dec:+.2f} deg from the World Magnetic Model at {lat:.5f}, {lon:.5f}, {year:.1f} (ahrs.utils.WMM)"
    return math.radians(dec), note


def first_fix_declination(lat_rad, lon_rad, h_m, where: str) -> tuple:
    """:func:`wmm_declination` at the first fix with a finite latitude and longitude (its height,
    or 0 m when that is not finite); a UsageError naming ``where`` when there is none."""
    import numpy as np
    lat, lon, h = (np.asarray(x, float) for x in (lat_rad, lon_rad, h_m))
    ok = np.isfinite(lat) & np.isfinite(lon)
    if not ok.any():
        raise UsageError(f"--declination auto: {where} has no GNSS position; give the declination in degrees")
    i = int(np.argmax(ok))
    return wmm_declination(float(lat[i]), float(lon[i]), float(h[i]) if np.isfinite(h[i]) else 0.0)
