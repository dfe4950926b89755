"""PX4 ULog files, read with ``pyulog`` (the PX4 project's own parser: pure Python, reads every
ULog version and appended data; ``pip install 'quatnav[logs]'``).

Topics read (the first instance, ``multi_id`` 0, unless a topic option names another):

* IMU: ``sensor_combined``, rate layout ``gyro_rad[0..2]`` / ``accelerometer_m_s2[0..2]``
  (accelerometer time = ``timestamp + accelerometer_timestamp_relative``), or the older integral
  layout ``gyro_integral_rad`` / ``accelerometer_integral_m_s`` divided by ``gyro_integral_dt`` /
  ``accelerometer_integral_dt`` (microseconds when integer, else seconds).
* magnetometer: ``vehicle_magnetometer`` (``magnetometer_ga``), else ``magnetometer_ga`` of
  ``sensor_combined``, else ``sensor_mag`` (``x y z``); gauss, body FRD.
* GNSS: ``vehicle_gps_position`` or ``sensor_gps``: ``lat lon`` as int 1e-7 deg or ``latitude_deg
  longitude_deg``; ``alt_ellipsoid`` in mm or ``altitude_ellipsoid_m`` (else the MSL altitude, noted);
  ``eph``/``epv`` as sigmas, ``vel_n_m_s vel_e_m_s vel_d_m_s`` when ``vel_ned_valid``,
  ``s_variance_m_s`` as velocity sigma, ``fix_type`` as quality (rows below a 3-D fix dropped);
  ``time_utc_usec`` (UTC microseconds since 1970, 0 when the receiver has no time) as ``utc``;
  ``heading`` (rad, NaN when the receiver has none; a two-antenna GPS yaw) as the ``compass``
  stream with ``north="true"``.
* barometer: ``vehicle_air_data`` (``baro_alt_meter``, ``baro_pressure_pa``), else ``baro_alt_meter``
  of ``sensor_combined``.
* reference: PX4's own estimate, ``vehicle_attitude`` ``q[0..3]`` ([w, x, y, z], FRD to NED as
  quatnav's ``q_nb``), with ``vehicle_local_position`` (``x y z vx vy vz``, NED m from PX4's
  origin) and ``vehicle_global_position`` (``lat lon`` deg, ``alt`` m) interpolated onto its times.

Times are seconds since boot (``timestamp`` is in microseconds).
"""
from __future__ import annotations

import numpy as np

from .log import Baro, Compass, Gnss, Imu, Log, Mag, Reference

__all__ = ["read_ulog", "looks_like_ulog"]

MAGIC = b"ULog\x01\x12\x35"


def looks_like_ulog(head: bytes) -> bool:
    return head.startswith(MAGIC)


def _topic(ulog, name, multi_id=0):
    for d in ulog.data_list:
        if d.name == name and d.multi_id == multi_id:
            return d.data
    return None


def _vec(d, stem, n=3):
    keys = [f"{stem}[{i}]" for i in range(n)]
    if all(k in d for k in keys):
        return np.column_stack([np.asarray(d[k], float) for k in keys])
    return None


def _interp(t, tt, x):
    out = np.full((len(t),) + x.shape[1:], np.nan)
    ok = (t >= tt[0]) & (t <= tt[-1])
    if x.ndim == 1:
        out[ok] = np.interp(t[ok], tt, x)
    else:
        for j in range(x.shape[1]):
            out[ok, j] = np.interp(t[ok], tt, x[:, j])
    return out


def read_ulog(path, *, mag_topic=None, gnss_topic=None, multi_id: int = 0) -> Log:
    """Read a PX4 ULog into a :class:`~quatnav.io.Log` (see the module text for the topics)."""
    try:
        import pyulog
    except ImportError as e:
        raise ImportError("reading ULog files needs pyulog: pip install 'quatnav[logs]'", name="pyulog") from e
    try:
        u = pyulog.ULog(str(path))
    except Exception as e:  # pyulog raises plain Exceptions on a damaged file
        raise ValueError(f"{path}: not a readable ULog file ({type(e).__name__}: {e})") from None
    log = Log(source=str(path), format="ulog")
    names = sorted({d.name for d in u.data_list})
    for topic in (mag_topic, gnss_topic):
        if topic is not None and topic not in names:
            raise ValueError(f"{path}: no topic {topic!r} (topics: {', '.join(names)})")
    us = 1e-6
    sc = _topic(u, "sensor_combined", multi_id)
    if sc is not None:
        t = np.asarray(sc["timestamp"], float) * us
        gyr, acc = _vec(sc, "gyro_rad"), _vec(sc, "accelerometer_m_s2")
        if gyr is None and _vec(sc, "gyro_integral_rad") is not None:
            def per_s(key):
                dt = np.asarray(sc[key], float)
                return dt * us if np.issubdtype(np.asarray(sc[key]).dtype, np.integer) or np.median(dt) > 1.0 else dt
            gyr = _vec(sc, "gyro_integral_rad") / per_s("gyro_integral_dt")[:, None]
            acc = _vec(sc, "accelerometer_integral_m_s") / per_s("accelerometer_integral_dt")[:, None]
            log.notes.append("sensor_combined integral layout: rates = integrals / integral_dt")
        if gyr is not None and acc is not None:
            keep = np.concatenate([[True], np.diff(t) > 0])
            log.imu = Imu(t=t[keep], gyr=gyr[keep], acc=acc[keep])
            if (~keep).any():
                log.notes.append(f"sensor_combined: {int((~keep).sum())} rows with a repeated timestamp dropped")
    # magnetometer
    for name in ([mag_topic] if mag_topic else ["vehicle_magnetometer", "sensor_combined", "sensor_mag"]):
        d = _topic(u, name, multi_id)
        if d is None:
            continue
        v = _vec(d, "magnetometer_ga")
        if v is None and all(k in d for k in "xyz"):
            v = np.column_stack([np.asarray(d[k], float) for k in "xyz"])
        if v is not None:
            tm = np.asarray(d["timestamp"], float) * us
            if "magnetometer_timestamp_relative" in d:
                tm = tm + np.asarray(d["magnetometer_timestamp_relative"], float) * us
                ok = np.concatenate([[True], np.diff(tm) > 0]) & np.isfinite(v).all(1)
                tm, v = tm[ok], v[ok]
            log.mag = Mag(t=tm, values=v, unit="gauss")
            log.notes.append(f"magnetometer from {name}")
            break
    if mag_topic is not None and log.mag is None:
        raise ValueError(f"{path}: topic {mag_topic!r} has no magnetometer fields (magnetometer_ga, or x, y, z)")
    # GNSS
    for name in ([gnss_topic] if gnss_topic else ["vehicle_gps_position", "sensor_gps"]):
        d = _topic(u, name, multi_id)
        if d is None:
            continue
        tg = np.asarray(d["timestamp"], float) * us
        if "latitude_deg" in d:
            lat, lon = np.asarray(d["latitude_deg"], float), np.asarray(d["longitude_deg"], float)
        else:
            la = np.asarray(d["lat"])
            f = 1e-7 if np.issubdtype(la.dtype, np.integer) else 1.0
            lat, lon = la.astype(float) * f, np.asarray(d["lon"]).astype(float) * f
        if "altitude_ellipsoid_m" in d:
            h = np.asarray(d["altitude_ellipsoid_m"], float)
        elif "alt_ellipsoid" in d:
            a = np.asarray(d["alt_ellipsoid"])
            h = a.astype(float) * (1e-3 if np.issubdtype(a.dtype, np.integer) else 1.0)
        else:
            a = np.asarray(d.get("altitude_msl_m", d.get("alt")))
            h = a.astype(float) * (1e-3 if np.issubdtype(a.dtype, np.integer) else 1.0)
            log.notes.append(f"{name}: no ellipsoidal altitude, MSL altitude used")
        fix = np.asarray(d.get("fix_type", np.full(len(tg), 3)), int)
        vel = None
        if "vel_n_m_s" in d:
            vel = np.column_stack([np.asarray(d[k], float) for k in ("vel_n_m_s", "vel_e_m_s", "vel_d_m_s")])
            if "vel_ned_valid" in d:
                vel[~np.asarray(d["vel_ned_valid"], bool)] = np.nan
        eph = np.asarray(d.get("eph", np.full(len(tg), 5.0)), float)
        epv = np.asarray(d.get("epv", np.full(len(tg), 10.0)), float)
        sv = np.asarray(d["s_variance_m_s"], float) if "s_variance_m_s" in d else None
        utc = None
        if "time_utc_usec" in d:
            u_us = np.asarray(d["time_utc_usec"])
            utc = np.where(u_us > 0, u_us.astype(float) * us, np.nan)
        ok = (fix >= 3) & np.isfinite(lat) & np.concatenate([[True], np.diff(tg) > 0])
        if (~ok).any():
            log.notes.append(f"{name}: {int((~ok).sum())} rows without a 3-D fix dropped")
        if ok.any():
            w = np.select([fix >= 6, fix == 5, fix == 4], [1.0, 0.5, 0.3], 0.1)
            log.gnss = Gnss(t=tg[ok], lat=np.radians(lat[ok]), lon=np.radians(lon[ok]), h=h[ok],
                            vel_n=None if vel is None else vel[ok],
                            sigma=np.column_stack([eph, eph, epv])[ok],
                            sigma_vel=None if sv is None else np.column_stack([sv, sv, sv])[ok],
                            quality=fix[ok], weight=w[ok], quality_kind="px4-fix_type",
                            utc=None if utc is None else utc[ok])
            if "heading" in d:
                hd = np.asarray(d["heading"], float)
                hk = ok & np.isfinite(hd)
                if hk.any():
                    log.compass = Compass(t=tg[hk], heading=np.angle(np.exp(1j * hd[hk])), north="true")
                    log.notes.append(f"{name}: {int(hk.sum())} GPS headings (true north)")
            break
    # barometer
    d = _topic(u, "vehicle_air_data", multi_id)
    if d is not None:
        log.baro = Baro(t=np.asarray(d["timestamp"], float) * us, altitude=np.asarray(d["baro_alt_meter"], float),
                        pressure=np.asarray(d["baro_pressure_pa"], float) if "baro_pressure_pa" in d else None)
    elif sc is not None and "baro_alt_meter" in sc:
        tb = np.asarray(sc["timestamp"], float) * us + np.asarray(sc.get("baro_timestamp_relative", 0), float) * us
        ok = np.concatenate([[True], np.diff(tb) > 0]) & np.isfinite(np.asarray(sc["baro_alt_meter"], float))
        log.baro = Baro(t=tb[ok], altitude=np.asarray(sc["baro_alt_meter"], float)[ok])
    # reference: PX4's estimate
    d = _topic(u, "vehicle_attitude", multi_id)
    if d is not None and _vec(d, "q", 4) is not None:
        tr = np.asarray(d["timestamp"], float) * us
        q = _vec(d, "q", 4)
        ok = np.concatenate([[True], np.diff(tr) > 0])
        tr, q = tr[ok], q[ok]
        ref = Reference(t=tr, quat=q / np.linalg.norm(q, axis=1, keepdims=True), name="PX4 vehicle_attitude")
        lp = _topic(u, "vehicle_local_position", multi_id)
        if lp is not None and len(lp["timestamp"]) > 1:
            tl = np.asarray(lp["timestamp"], float) * us
            ref.p_n = _interp(tr, tl, np.column_stack([np.asarray(lp[k], float) for k in "xyz"]))
            ref.vel_n = _interp(tr, tl, np.column_stack([np.asarray(lp[k], float) for k in ("vx", "vy", "vz")]))
        gp = _topic(u, "vehicle_global_position", multi_id)
        if gp is not None and len(gp["timestamp"]) > 1:
            tl = np.asarray(gp["timestamp"], float) * us
            ref.lat = np.radians(_interp(tr, tl, np.asarray(gp["lat"], float)))
            ref.lon = np.radians(_interp(tr, tl, np.asarray(gp["lon"], float)))
            ref.h = _interp(tr, tl, np.asarray(gp["alt"], float))
        log.reference = ref
    return log
