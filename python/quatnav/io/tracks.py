"""Track outputs of navigation runs: KML (Google Earth) and GPX 1.1."""
from __future__ import annotations

import datetime as _dt
from xml.sax.saxutils import escape

import numpy as np

__all__ = ["write_kml", "write_gpx", "track_rows"]


def track_rows(t, rate=None, max_points=20000) -> np.ndarray:
    """The rows of a track to write: the first row in each interval of ``1 / rate`` s (every row
    without ``rate``), the last row, and at most ``max_points`` rows in all (a map needs no
    more). A navigation solution at the IMU's rate (200 Hz: 2 MB of GPX for two minutes) is
    written at the GNSS's (5 Hz) this way."""
    t = np.asarray(t, dtype=float)
    n = len(t)
    if not n:
        return np.arange(0)
    k = np.arange(n)
    if rate:
        slot = np.floor((t - t[0]) * float(rate) + 1e-9)
        k = np.flatnonzero(np.r_[True, np.diff(slot) > 0])
    k = k[::max(1, -(-len(k) // max_points))]
    return k if k[-1] == n - 1 else np.r_[k, n - 1]


def write_kml(path, t, lat, lon, h, name="quatnav track", rate=None):
    """A KML LineString of lat/lon (rad) and ellipsoidal height h (m; absolute altitude mode), at
    most ``rate`` points per second (:func:`track_rows`); returns the number of points."""
    k = track_rows(t, rate)
    coords = "\n".join(f"{np.degrees(lon[i]):.9f},{np.degrees(lat[i]):.9f},{h[i]:.3f}" for i in k)
    with open(path, "w") as fh:
        fh.write('<?xml version="1.0" encoding="UTF-8"?>\n<kml xmlns="http://www.opengis.net/kml/2.2">\n'
                 f"<Document><name>{escape(name)}</name><Placemark><name>{escape(name)}</name>\n"
                 "<LineString><altitudeMode>absolute</altitudeMode><coordinates>\n"
                 f"{coords}\n</coordinates></LineString></Placemark></Document></kml>\n")
    return len(k)


def write_gpx(path, t, lat, lon, h, name="quatnav track", rate=None, utc=None):
    """A GPX 1.1 track at most ``rate`` points per second (:func:`track_rows`); returns the
    number of points. Each point's ``time`` is its UTC time ``utc`` (s since 1970, ISO 8601 with
    Z), given, since the log's own clock may be GPS time (18 s ahead of UTC) or the time since
    boot (no date); without ``utc`` the points have no time."""
    k = track_rows(t, rate)
    pts = []
    for i in k:
        tt = ""
        if utc is not None and np.isfinite(utc[i]):
            iso = _dt.datetime.fromtimestamp(round(float(utc[i]), 3), _dt.timezone.utc).isoformat(
                timespec="milliseconds").replace("+00:00", "Z")
            tt = f"<time>{iso}</time>"
        pts.append(f'<trkpt lat="{np.degrees(lat[i]):.9f}" lon="{np.degrees(lon[i]):.9f}"><ele>{h[i]:.3f}</ele>{tt}</trkpt>')
    with open(path, "w") as fh:
        fh.write('<?xml version="1.0" encoding="UTF-8"?>\n<gpx version="1.1" creator="quatnav" '
                 'xmlns="http://www.topografix.com/GPX/1/1">\n'
                 f"<trk><name>{escape(name)}</name><trkseg>\n" + "\n".join(pts) + "\n</trkseg></trk></gpx>\n")
    return len(k)
