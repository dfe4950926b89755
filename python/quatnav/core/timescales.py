"""GPS time and UTC: the leap seconds between them.

GPS time runs without leap seconds from its epoch, 1980-01-06 00:00:00 UTC; UTC inserts one now
and then, so that GPS time is ahead of UTC by the leap seconds inserted since (18 s since
2017-01-01). Logs often count GPS time from 1970 as Unix time counts UTC ("GPS seconds since
1970": UTC + 18 s today); :func:`gps_to_utc` and :func:`utc_to_gps` convert such times.
"""
from __future__ import annotations

import calendar

import numpy as np

__all__ = ["LEAP_SECONDS", "gps_minus_utc", "gps_to_utc", "utc_to_gps"]

#: (UTC date from which it holds, GPS - UTC in seconds): every leap second since the GPS epoch
#: (IERS Bulletin C; none announced after 2017-01-01 up to this release).
LEAP_SECONDS = tuple((calendar.timegm((y, m, 1, 0, 0, 0, 0, 0, 0)), n) for (y, m), n in (
    ((1981, 7), 1), ((1982, 7), 2), ((1983, 7), 3), ((1985, 7), 4), ((1988, 1), 5), ((1990, 1), 6),
    ((1991, 1), 7), ((1992, 7), 8), ((1993, 7), 9), ((1994, 7), 10), ((1996, 1), 11), ((1997, 7), 12),
    ((1999, 1), 13), ((2006, 1), 14), ((2009, 1), 15), ((2012, 7), 16), ((2015, 7), 17), ((2017, 1), 18)))
_STARTS = np.array([s for s, _ in LEAP_SECONDS], dtype=float)
_COUNTS = np.array([0] + [n for _, n in LEAP_SECONDS], dtype=float)


def gps_minus_utc(utc):
    """GPS time minus UTC, s (0 before 1981-07-01), at UTC times ``utc`` (s since 1970)."""
    return _COUNTS[np.searchsorted(_STARTS, np.asarray(utc, dtype=float), side="right")]


def gps_to_utc(gps):
    """UTC (s since 1970) of GPS times counted from 1970 like Unix time (s): less the leap
    seconds inserted by then."""
    g = np.asarray(gps, dtype=float)
    # the offset at the UTC time, which is the GPS time less at most 18 s: look up both sides of
    # a leap second, keep the one that is consistent
    u = g - gps_minus_utc(g)
    return g - gps_minus_utc(u)


def utc_to_gps(utc):
    """GPS time counted from 1970 (s) of UTC times (s since 1970)."""
    u = np.asarray(utc, dtype=float)
    return u + gps_minus_utc(u)
