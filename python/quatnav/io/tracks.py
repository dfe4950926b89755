"""Track outputs of navigation runs: KML (Google Earth) and GPX 1.1."""
from __future__ import annotations

import datetime as _dt
from xml.sax.saxutils import escape

import numpy as np

__all__ = ["write_kml", "write_gpx"]


def _decimate(n, max_points=20000):
    return np.arange(0, n, max(1, n // max_points)) if n else np.arange(0)


def write_kml(path, t, lat, lon, h, name="quatnav track"):
    """A KML LineString of lat/lon (rad) and ellipsoidal height h (m; absolute altitude mode)."""
    k = _decimate(len(t))
    coords = "\n".join(f"{np.degrees(lon[i]):.9f},{np.degrees(lat[i]):.9f},{h[i]:.3f}" for i in k)
    with open(path, "w") as fh:
        fh.write('<?xml version="1.0" encoding="UTF-8"?>\n<kml xmlns="http://www.opengis.net/kml/2.2">\n'
                 f"<Document><name>{escape(name)}</name><Placemark><name>{escape(name)}</name>\n"
                 "<LineString><altitudeMode>absolute</altitudeMode><coordinates>\n"
                 f"{coords}\n</coordinates></LineString></Placemark></Document></kml>\n")


def write_gpx(path, t, lat, lon, h, name="quatnav track"):
    """A GPX 1.1 track; times as UTC ISO 8601 when they look like seconds since 1970 (> 1e8 s),
    else omitted (times since boot have no date)."""
    k = _decimate(len(t))
    absolute = len(t) and t[0] > 1e8
    pts = []
    for i in k:
        tt = ""
        if absolute:
            iso = _dt.datetime.fromtimestamp(float(t[i]), _dt.timezone.utc).isoformat().replace("+00:00", "Z")
            tt = f"<time>{iso}</time>"
        pts.append(f'<trkpt lat="{np.degrees(lat[i]):.9f}" lon="{np.degrees(lon[i]):.9f}"><ele>{h[i]:.3f}</ele>{tt}</trkpt>')
    with open(path, "w") as fh:
        fh.write('<?xml version="1.0" encoding="UTF-8"?>\n<gpx version="1.1" creator="quatnav" '
                 'xmlns="http://www.topografix.com/GPX/1/1">\n'
                 f"<trk><name>{escape(name)}</name><trkseg>\n" + "\n".join(pts) + "\n</trkseg></trk></gpx>\n")


