"""Track outputs of navigation runs: KML (Google Earth), GPX 1.1, and a summary plot."""
from __future__ import annotations

import datetime as _dt
from xml.sax.saxutils import escape

import numpy as np

__all__ = ["write_kml", "write_gpx", "plot_nav"]


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


def plot_nav(path, r, nav, gnss, log=None):
    """Track (north/east m about the first GNSS fix) with the fixes; attitude with its three-sigma
    band; biases; the difference to the log's own attitude estimate when it has one (else the
    accelerometer bias); the horizontal and vertical position one-sigma; and the innovations of
    every aid over time as their NIS (its chi-square gate is the filter's), rejected samples
    marked."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from ..core import earth as E
    lat0, lon0, h0 = np.radians(gnss["lat"][0]), np.radians(gnss["lon"][0]), gnss["h"][0]
    p = E.geodetic_to_ned(r.lat[nav], r.lon[nav], r.h[nav], lat0, lon0, h0)
    g = E.geodetic_to_ned(np.radians(gnss["lat"]), np.radians(gnss["lon"]), gnss["h"], lat0, lon0, h0)
    ref = log.reference if log is not None and log.reference is not None and log.reference.quat is not None else None
    fig, ax = plt.subplots(3, 2, figsize=(11, 10))
    ax[0, 0].plot(p[:, 1], p[:, 0], label="INS")
    ax[0, 0].plot(g[:, 1], g[:, 0], ".", ms=3, label="GNSS fixes")
    ax[0, 0].set_xlabel("east, m")
    ax[0, 0].set_ylabel("north, m")
    ax[0, 0].axis("equal")
    ax[0, 0].legend(fontsize=7)
    t = r.t[nav]
    e = np.degrees(r.euler[nav])
    s_att = None
    if r.sigma is not None and r.sigma.shape[1] >= 9:  # tilt errors about north and east, heading about down
        psi = np.degrees(r.sigma[nav][:, 6:9])
        tilt = np.maximum(psi[:, 0], psi[:, 1])  # roll and pitch: the larger tilt sigma (heading-independent)
        s_att = np.column_stack([tilt, tilt, psi[:, 2]])
    for i, c in enumerate(("roll", "pitch", "yaw")):
        ax[0, 1].plot(t, e[:, i], label=c, color=f"C{i}")
        if s_att is not None:
            ax[0, 1].fill_between(t, e[:, i] - 3 * s_att[:, i], e[:, i] + 3 * s_att[:, i], color=f"C{i}",
                                  alpha=0.2, lw=0)
    ax[0, 1].set_ylabel("deg (band: 3 sigma)")
    ax[0, 1].legend(fontsize=7)
    ax[1, 0].plot(t, np.degrees(r.bias[nav]) * 3600)
    ax[1, 0].set_ylabel("gyro bias, deg/h")
    if ref is not None:
        from ..evaluation.track_difference import attitude_difference
        d = attitude_difference(t, r.quat[nav], ref.t, ref.quat)
        ax[1, 1].plot(d["t"], d["inclination_deg"], label="inclination")
        ax[1, 1].plot(d["t"], d["heading_deg"], label="heading")
        ax[1, 1].set_ylabel(f"difference to {ref.name}, deg")
        ax[1, 1].legend(fontsize=7)
    else:
        ax[1, 1].plot(t, r.acc_bias[nav])
        ax[1, 1].set_ylabel("accelerometer bias, m/s^2")
    if r.sigma is not None:
        ax[2, 0].plot(t, np.hypot(r.sigma[nav][:, 0], r.sigma[nav][:, 1]), label="horizontal")
        ax[2, 0].plot(t, r.sigma[nav][:, 2], label="vertical")
        ax[2, 0].set_yscale("log")
        ax[2, 0].set_ylabel("position one-sigma, m")
        ax[2, 0].legend(fontsize=7)
    for i, (name, a) in enumerate(sorted((getattr(r, "aids", None) or {}).items())):
        if a.nis is None or not len(a.t):
            continue
        ok = np.isfinite(a.nis)
        if not ok.any():
            continue
        ax[2, 1].plot(a.t[ok], a.nis[ok], ".", ms=2, color=f"C{i % 10}", label=name)
        bad = ok & (np.asarray(a.status) != 0)
        if bad.any():
            ax[2, 1].plot(a.t[bad], a.nis[bad], "x", ms=4, color=f"C{i % 10}")
    if ax[2, 1].lines:
        ax[2, 1].set_yscale("log")
        ax[2, 1].legend(fontsize=7, ncol=2, title="x: not applied", title_fontsize=7)
    ax[2, 1].set_ylabel("innovation NIS")
    for a in (ax[0, 1], ax[1, 0], ax[1, 1], ax[2, 0], ax[2, 1]):
        a.set_xlabel("t, s")
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)
