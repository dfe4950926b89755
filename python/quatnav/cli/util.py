"""The argument types the commands of :mod:`quatnav.cli` share (``--declination``, ``--date``).
What every command shares wherever it lives (:class:`UsageError`, :func:`write_json`) is
:mod:`quatnav._command`; the World Magnetic Model, :mod:`quatnav.core.magnetic`."""
from __future__ import annotations

from ..core.magnetic import decimal_year

__all__ = ["declination_arg", "date_arg"]


def declination_arg(text: str):
    """``--declination``: degrees east of true north (a float) or ``auto`` (None: from the World
    Magnetic Model at the log's first GNSS fix, :func:`quatnav.core.magnetic.wmm_declination`)."""
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


def date_arg(text: str) -> float:
    """``--date``: the day of the recording, ``YYYY-MM-DD`` or a decimal year (``2027.5``), as a
    decimal year (:func:`decimal_year`)."""
    import argparse
    import datetime
    import math
    import re
    s = text.strip()
    if re.fullmatch(r"\d{4}-\d{2}-\d{2}", s):
        try:
            return decimal_year(datetime.date.fromisoformat(s))
        except ValueError as e:
            raise argparse.ArgumentTypeError(f"{text!r}: not a date ({e})") from None
    try:
        v = float(s)
    except ValueError:
        v = math.nan
    if not (math.isfinite(v) and 1.0 <= v < 10000.0):
        raise argparse.ArgumentTypeError(f"{text!r}: expected a date YYYY-MM-DD (e.g. 2022-04-29) or a decimal "
                                         "year (e.g. 2022.3)")
    return v
