"""The Earth's magnetic field: the declination of the World Magnetic Model at a place and a date
(:func:`wmm_declination`), at the first fix of a GNSS record (:func:`first_fix_declination`),
and the decimal year that dates it (:func:`decimal_year`).

The model is ``ahrs.utils.WMM`` (the ``[peers]`` extra), imported when first used: this module
imports without it.
"""
from __future__ import annotations

__all__ = ["decimal_year", "wmm_declination", "first_fix_declination"]


def decimal_year(when) -> float:
    """A date or a UTC datetime as a decimal year: the year plus the fraction of it gone by
    (a date: at its start), the World Magnetic Model's time argument."""
    import calendar
    import datetime
    t = when.replace(tzinfo=None) if isinstance(when, datetime.datetime) else \
        datetime.datetime(when.year, when.month, when.day)
    days = 366 if calendar.isleap(t.year) else 365
    return t.year + (t - datetime.datetime(t.year, 1, 1)).total_seconds() / (86400.0 * days)


def _date_text(year: float) -> str:
    """A decimal year as its day, ``YYYY-MM-DD``."""
    import calendar
    import datetime
    import math
    y = int(year)
    day = math.floor((year - y) * (366 if calendar.isleap(y) else 365) + 1e-6)
    return (datetime.date(y, 1, 1) + datetime.timedelta(days=day)).isoformat()


def wmm_declination(lat_rad: float, lon_rad: float, h_m: float, year: float | None = None, *,
                    source: str = "", warn=None) -> tuple:
    """The magnetic declination (rad, east of true north) of the World Magnetic Model at a place
    and a decimal year (default: today), with a one-line note naming the model, place and date
    (and ``source``, where the date comes from).

    The model is ``ahrs.utils.WMM`` (the ``[peers]`` extra): a maintained implementation of the
    NOAA/BGS model with its coefficient files (WMM2015, WMM2020 and WMM2025 in ahrs 0.4, each
    valid for five years from its epoch), used here rather than a copy of the coefficients in this
    package, which would age with each five-year release. A date before its first model is a
    ``ValueError``; a date after its last model's five years is evaluated (the model's
    secular change extrapolated) and ``warn(text)`` says so."""
    import datetime
    import math
    try:
        from ahrs.utils import WMM
    except ImportError:
        raise ImportError("--declination auto needs the ahrs package (pip install 'quatnav[peers]')",
                          name="ahrs") from None
    if year is None:
        year = decimal_year(datetime.datetime.now(datetime.timezone.utc))
        source = source or "today"
    lat, lon = math.degrees(lat_rad), math.degrees(lon_rad)
    when = f"{_date_text(year)} ({year:.2f}{', ' + source if source else ''})"
    try:
        w = WMM(latitude=lat, longitude=lon, height=h_m / 1000.0, date=year)
        if w.D is None:  # ahrs evaluates in its constructor only where latitude and longitude are both non-zero
            w.magnetic_field(lat, lon, h_m / 1000.0, date=year)
    except ValueError as e:  # ahrs: no coefficients before its first model
        raise ValueError(f"--declination auto: ahrs.utils.WMM cannot give the World Magnetic Model on {when}: "
                         f"{str(e).rstrip('.')}; give another --date or the declination in degrees "
                         "(--declination DEG)") from None
    dec = float(w.D) if w.D is not None else math.nan
    if not math.isfinite(dec):
        raise ValueError(f"--declination auto: the World Magnetic Model gives no declination at {lat:.5f}, {lon:.5f}")
    epoch = float(w.epoch)
    if warn is not None and not epoch <= year < epoch + 5.0:
        warn(f"--declination auto: {when} is outside {w.model}'s validity ({epoch:.0f}.0 to {epoch + 5:.0f}.0), the "
             "newest model ahrs.utils.WMM has: its secular change is extrapolated (a newer ahrs may carry the next "
             "model)")
    note = (f"declination {dec:+.2f} deg from the World Magnetic Model ({w.model}, ahrs.utils.WMM) at {lat:.5f}, "
            f"{lon:.5f} on {when}")
    return math.radians(dec), note


def first_fix_declination(lat_rad, lon_rad, h_m, where: str, utc=None, date: float | None = None,
                          warn=None) -> tuple:
    """:func:`wmm_declination` at the first fix with a finite latitude and longitude (its height,
    or 0 m when that is not finite); a ValueError naming ``where`` when there is none.

    The date is ``date`` (a decimal year: ``--date``), else that of the first finite ``utc`` (UTC
    s since 1970, per fix: :attr:`quatnav.io.Gnss.utc`), else today's, with a note that the log
    has none. Returns ``(declination_rad, notes)``: the note of :func:`wmm_declination` first.
    ``warn``: see :func:`wmm_declination`."""
    import datetime
    import numpy as np
    lat, lon, h = (np.asarray(x, float) for x in (lat_rad, lon_rad, h_m))
    ok = np.isfinite(lat) & np.isfinite(lon)
    if not ok.any():
        raise ValueError(f"--declination auto: {where} has no GNSS position; give the declination in degrees")
    i = int(np.argmax(ok))
    notes, source = [], "from --date"
    if date is None:
        u = np.asarray(utc, float).ravel() if utc is not None else np.empty(0)
        u = u[np.isfinite(u)]
        if u.size:
            try:
                date = decimal_year(datetime.datetime.fromtimestamp(float(u[0]), datetime.timezone.utc))
            except (OverflowError, OSError, ValueError):
                raise ValueError(f"--declination auto: {where}: UTC time {float(u[0]):g} s is not a date (expected "
                                 "seconds since 1970-01-01); give --date YYYY-MM-DD") from None
            source = "from the log's GNSS UTC time"
        else:
            source = "today"
            notes.append(f"{where}: no recording date in the log (no UTC time with its GNSS fixes): the World "
                         "Magnetic Model at today's date; give --date YYYY-MM-DD (the day of the recording) "
                         "for its own")
    d, text = wmm_declination(float(lat[i]), float(lon[i]), float(h[i]) if np.isfinite(h[i]) else 0.0, date,
                              source=source, warn=warn)
    return d, [text] + notes
