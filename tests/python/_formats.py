"""Writers of the log formats quatnav.io reads, for round-trip tests: RTKLIB .pos (lat/lon,
ECEF and ENU baseline), NMEA (GGA, RMC, HDT), PX4 ULog (the integral sensor_combined layout,
vehicle_magnetometer, vehicle_attitude) and ROS 1 / ROS 2 bags (rosbags). Each writer returns
the arrays as the file holds them (after the format's rounding), so a test can give the Python
API exactly what the command reads."""
from __future__ import annotations

import calendar
import math
import struct
import time as time_mod
from functools import reduce
from pathlib import Path

import numpy as np

from quatnav.core import earth as E
from quatnav.core import quaternion as Q

#: simulated times (0 s ...) become calendar seconds from this date in formats that need a date
EPOCH = calendar.timegm((2026, 1, 1, 0, 0, 0, 0, 0, 0))
_GPS_EPOCH = calendar.timegm((1980, 1, 6, 0, 0, 0, 0, 0, 0))


def _date_time(t):
    ts = time_mod.gmtime(int(t))
    return (f"{ts.tm_year:04d}/{ts.tm_mon:02d}/{ts.tm_mday:02d} {ts.tm_hour:02d}:{ts.tm_min:02d}:"
            f"{ts.tm_sec + (t - int(t)):06.3f}")


def write_pos(path, t, lat, lon, h, sigma, vel=None, mode="deg", q=1):
    """An RTKLIB .pos file of fixes at times ``t`` (s from EPOCH) in the layout rtkpost writes.

    mode: "deg" (lat/lon deg), "ecef" (x/y/z m), "enu" (baseline e/n/u m from a '% ref pos'
    header line at the first fix). Returns (t_abs, lat, lon, h) as the file holds them (rad, m)."""
    lab = {"deg": "latitude(deg) longitude(deg)  height(m)", "ecef": "x-ecef(m)      y-ecef(m)      z-ecef(m)",
           "enu": "e-baseline(m)  n-baseline(m)  u-baseline(m)"}[mode]
    sd = "sdx(m)   sdy(m)   sdz(m)  sdxy(m)  sdyz(m)  sdzx(m)" if mode == "ecef" else \
        ("sde(m)   sdn(m)   sdu(m)  sden(m)  sdnu(m)  sdue(m)" if mode == "enu" else
         "sdn(m)   sde(m)   sdu(m)  sdne(m)  sdeu(m)  sdun(m)")
    lines = ["% program   : RTKPOST ver.2.4.3 (written by quatnav's tests)"]
    lat0, lon0, h0 = lat[0], lon[0], h[0]
    if mode == "enu":
        lines.append(f"% ref pos   :{math.degrees(lat0):14.9f} {math.degrees(lon0):14.9f} {h0:10.4f}")
        lat0, lon0, h0 = math.radians(round(math.degrees(lat0), 9)), math.radians(round(math.degrees(lon0), 9)), \
            round(h0, 4)
    lines.append(f"%  GPST                  {lab}   Q  ns   {sd} age(s)  ratio"
                 + ("  vn(m/s)  ve(m/s)  vu(m/s)   sdvn   sdve   sdvu  sdvne  sdveu  sdvun" if vel is not None else ""))
    out = {"lat": [], "lon": [], "h": [], "t": []}
    for k in range(len(t)):
        tt = EPOCH + t[k]
        s3 = sigma[k] if np.ndim(sigma) == 2 else sigma
        if mode == "deg":
            p = f"{math.degrees(lat[k]):14.9f} {math.degrees(lon[k]):14.9f} {h[k]:10.4f}"
            sds = f"{s3[0]:.4f} {s3[1]:.4f} {s3[2]:.4f}"
        elif mode == "ecef":
            xyz = np.ravel(E.geodetic_to_ecef(lat[k], lon[k], h[k]))
            p = " ".join(f"{v:14.4f}" for v in xyz)
            m = max(s3)
            sds = f"{m:.4f} {m:.4f} {m:.4f}"
        else:
            ned = np.ravel(E.geodetic_to_ned(lat[k], lon[k], h[k], lat0, lon0, h0))
            p = f"{ned[1]:14.4f} {ned[0]:14.4f} {-ned[2]:14.4f}"
            sds = f"{s3[1]:.4f} {s3[0]:.4f} {s3[2]:.4f}"
        row = f"{_date_time(tt)} {p} {q:3d} 12 {sds} 0.0000 0.0000 0.0000 0.00 999.9"
        if vel is not None:
            row += f" {vel[k, 0]:.6f} {vel[k, 1]:.6f} {-vel[k, 2]:.6f} 0.05 0.05 0.05 0 0 0"
        lines.append(row)
    Path(path).write_text("\n".join(lines) + "\n")
    from quatnav import io
    g = io.read(path).gnss  # the file's values as any reader of the format gets them
    return g


def _nmea(body):
    return f"${body}*{reduce(lambda a, c: a ^ ord(c), body, 0):02X}"


def _dm(x, deg_digits):
    a = abs(math.degrees(x))
    d = int(a)
    m = (a - d) * 60.0
    return f"{d:0{deg_digits}d}{m:011.8f}"


def write_nmea(path, t, lat, lon, h, speed=None, course=None, heading=None, hdop=1.0, quality=4):
    """GGA (+ RMC with speed/course when given, + HDT true heading when given) at times ``t``
    (s from EPOCH, UTC). Positions to 1e-8 minutes (~0.02 mm), heights to 1 mm."""
    lines = []
    for k in range(len(t)):
        tt = EPOCH + t[k]
        ts = time_mod.gmtime(int(tt))
        hms = f"{ts.tm_hour:02d}{ts.tm_min:02d}{ts.tm_sec + (tt - int(tt)):05.2f}"
        la = _dm(lat[k], 2) + ("," + ("N" if lat[k] >= 0 else "S"))
        lo = _dm(lon[k], 3) + ("," + ("E" if lon[k] >= 0 else "W"))
        lines.append(_nmea(f"GNGGA,{hms},{la},{lo},{quality},12,{hdop:.1f},{h[k]:.3f},M,0.000,M,,"))
        if speed is not None:
            date = f"{ts.tm_mday:02d}{ts.tm_mon:02d}{ts.tm_year % 100:02d}"
            lines.append(_nmea(f"GNRMC,{hms},A,{la},{lo},{speed[k] / (1852 / 3600):.4f},"
                               f"{math.degrees(course[k]) % 360:.3f},{date},,,R"))
        if heading is not None:
            lines.append(_nmea(f"GNHDT,{math.degrees(heading[k]) % 360:.3f},T"))
    Path(path).write_text("\r\n".join(lines) + "\r\n")


# ----------------------------------------------------------------------------------------------
# PX4 ULog
# ----------------------------------------------------------------------------------------------
_ULOG_TYPES = {"uint64_t": "Q", "uint32_t": "I", "float": "f", "uint8_t": "B", "int32_t": "i"}


def _ulog_msg(kind, payload):
    return struct.pack("<HB", len(payload), ord(kind)) + payload


def write_ulog(path, topics):
    """A ULog file (version 1) of ``topics``: {name: (fields, rows)} with fields a list of
    (type, name) (``float[3] x`` as ("float[3]", "x")), the first ("uint64_t", "timestamp"), and
    rows a list of tuples of values in field order (arrays for array fields)."""
    out = bytearray(b"ULog\x01\x12\x35" + bytes([1]) + struct.pack("<Q", 0))
    out += _ulog_msg("B", bytes(16) + bytes(24))  # flag bits: no compat/incompat flags, no appended data
    for name, (fields, _) in topics.items():
        out += _ulog_msg("F", (name + ":" + "".join(f"{t} {n};" for t, n in fields)).encode())
    for i, name in enumerate(topics):
        out += _ulog_msg("A", struct.pack("<BH", 0, i) + name.encode())
    rows = []
    for i, (name, (fields, data)) in enumerate(topics.items()):
        fmt = "<"
        for t, _ in fields:
            base, _, n = t.partition("[")
            fmt += (n.rstrip("]") if n else "") + _ULOG_TYPES[base]
        for r in data:
            flat = []
            for v in r:
                flat += list(np.ravel(v)) if np.ndim(v) else [v]
            rows.append((int(r[0]), i, struct.pack(fmt, *flat)))
    rows.sort(key=lambda r: (r[0], r[1]))
    for _, i, payload in rows:
        out += _ulog_msg("D", struct.pack("<H", i) + payload)
    Path(path).write_bytes(bytes(out))


def ulog_integral(path, t, gyr, acc, mag_gauss=None, q_nb=None, dt_us=None):
    """A ULog with the older integral ``sensor_combined`` layout (integrals over
    ``*_integral_dt`` microseconds), ``vehicle_magnetometer`` (gauss) and ``vehicle_attitude``.
    Returns the rates as the file holds them (float32 integrals / integer dt)."""
    ts = np.round(t * 1e6).astype(np.int64) + 1_000_000
    dt = np.diff(ts, prepend=ts[0] - (ts[1] - ts[0])) if dt_us is None else np.full(len(t), dt_us)
    gi = (gyr * dt[:, None] * 1e-6).astype(np.float32)
    ai = (acc * dt[:, None] * 1e-6).astype(np.float32)
    topics = {"sensor_combined": ([("uint64_t", "timestamp"), ("float[3]", "gyro_integral_rad"),
                                   ("uint32_t", "gyro_integral_dt"), ("float[3]", "accelerometer_integral_m_s"),
                                   ("uint32_t", "accelerometer_integral_dt")],
                                  [(ts[k], gi[k], dt[k], ai[k], dt[k]) for k in range(len(t))])}
    if mag_gauss is not None:
        topics["vehicle_magnetometer"] = ([("uint64_t", "timestamp"), ("float[3]", "magnetometer_ga")],
                                          [(ts[k], mag_gauss[k].astype(np.float32)) for k in range(len(t))])
    if q_nb is not None:
        topics["vehicle_attitude"] = ([("uint64_t", "timestamp"), ("float[4]", "q")],
                                      [(ts[k], q_nb[k].astype(np.float32)) for k in range(len(t))])
    write_ulog(path, topics)
    return (ts * 1e-6, gi.astype(float) / (dt[:, None] * 1e-6), ai.astype(float) / (dt[:, None] * 1e-6))


# ----------------------------------------------------------------------------------------------
# ROS bags
# ----------------------------------------------------------------------------------------------
def write_bag(path, version, t0, imu=None, mag=None, fix=None, twist=None, pressure=None, q_nb=None,
              imu_topic="/imu/data"):
    """A ROS 1 (.bag) or ROS 2 (folder) bag with sensor_msgs/Imu (``imu`` = (t, gyr_frd, acc_frd),
    orientation from ``q_nb`` when given), MagneticField (``mag`` = (t, tesla_frd)), NavSatFix
    (``fix`` = (t, lat, lon, h, sigma_ned)), TwistWithCovarianceStamped (``twist`` = (t, v_ned))
    and FluidPressure (``pressure`` = (t, Pa)); ENU/FLU as REP-103 says. Times ``t0 + t``."""
    from rosbags.typesys import Stores, get_typestore
    from quatnav.io.rosbag import FLU_TO_FRD, Q_FLU_FRD
    ts = get_typestore(Stores.ROS2_HUMBLE if version == 2 else Stores.ROS1_NOETIC)
    T = ts.types
    Header, Time = T["std_msgs/msg/Header"], T["builtin_interfaces/msg/Time"]
    V3, Qm = T["geometry_msgs/msg/Vector3"], T["geometry_msgs/msg/Quaternion"]
    if version == 2:
        from rosbags.rosbag2 import Writer
        w = Writer(path, version=8)
        ser = ts.serialize_cdr
    else:
        from rosbags.rosbag1 import Writer
        w = Writer(path)
        ser = ts.serialize_ros1

    def hdr(t):
        sec = int(t)
        kw = dict(stamp=Time(sec=sec, nanosec=int(round((t - sec) * 1e9))), frame_id="base")
        return Header(seq=0, **kw) if version == 1 else Header(**kw)

    def enu(v):
        v = np.asarray(v, float)
        return np.column_stack([v[:, 1], v[:, 0], -v[:, 2]])

    msgs = []
    with w:
        if imu is not None:
            c = w.add_connection(imu_topic, "sensor_msgs/msg/Imu", typestore=ts)
            ti, g, a = imu
            g, a = g * FLU_TO_FRD, a * FLU_TO_FRD
            q = None if q_nb is None else Q.mul(Q.mul(Q.conj(Q.Q_NED_ENU), q_nb), Q.conj(Q_FLU_FRD))
            for k in range(len(ti)):
                o = Qm(x=q[k, 1], y=q[k, 2], z=q[k, 3], w=q[k, 0]) if q is not None else Qm(x=0.0, y=0.0, z=0.0, w=1.0)
                oc = np.zeros(9) if q is not None else np.r_[-1.0, np.zeros(8)]
                m = T["sensor_msgs/msg/Imu"](header=hdr(t0 + ti[k]), orientation=o, orientation_covariance=oc,
                                             angular_velocity=V3(*g[k]), angular_velocity_covariance=np.zeros(9),
                                             linear_acceleration=V3(*a[k]), linear_acceleration_covariance=np.zeros(9))
                msgs.append((t0 + ti[k], c, ser(m, "sensor_msgs/msg/Imu")))
        if mag is not None:
            c = w.add_connection("/imu/mag", "sensor_msgs/msg/MagneticField", typestore=ts)
            tm, mv = mag
            mv = mv * FLU_TO_FRD
            for k in range(len(tm)):
                m = T["sensor_msgs/msg/MagneticField"](header=hdr(t0 + tm[k]), magnetic_field=V3(*mv[k]),
                                                       magnetic_field_covariance=np.zeros(9))
                msgs.append((t0 + tm[k], c, ser(m, "sensor_msgs/msg/MagneticField")))
        if fix is not None:
            c = w.add_connection("/fix", "sensor_msgs/msg/NavSatFix", typestore=ts)
            tf, la, lo, hh, sg = fix
            for k in range(len(tf)):
                st = T["sensor_msgs/msg/NavSatStatus"](status=2, service=1)
                cov = np.diag(np.asarray(sg[k], float)[[1, 0, 2]] ** 2).ravel()  # E, N, U variances
                m = T["sensor_msgs/msg/NavSatFix"](header=hdr(t0 + tf[k]), status=st, latitude=math.degrees(la[k]),
                                                   longitude=math.degrees(lo[k]), altitude=float(hh[k]),
                                                   position_covariance=cov, position_covariance_type=2)
                msgs.append((t0 + tf[k], c, ser(m, "sensor_msgs/msg/NavSatFix")))
        if twist is not None:
            c = w.add_connection("/fix_velocity", "geometry_msgs/msg/TwistWithCovarianceStamped", typestore=ts)
            tv, v = twist
            ve = enu(v)
            for k in range(len(tv)):
                tw = T["geometry_msgs/msg/Twist"](linear=V3(*ve[k]), angular=V3(0.0, 0.0, 0.0))
                twc = T["geometry_msgs/msg/TwistWithCovariance"](twist=tw, covariance=np.zeros(36))
                m = T["geometry_msgs/msg/TwistWithCovarianceStamped"](header=hdr(t0 + tv[k]), twist=twc)
                msgs.append((t0 + tv[k], c, ser(m, "geometry_msgs/msg/TwistWithCovarianceStamped")))
        if pressure is not None:
            c = w.add_connection("/pressure", "sensor_msgs/msg/FluidPressure", typestore=ts)
            tp, pv = pressure
            for k in range(len(tp)):
                m = T["sensor_msgs/msg/FluidPressure"](header=hdr(t0 + tp[k]), fluid_pressure=float(pv[k]), variance=0.0)
                msgs.append((t0 + tp[k], c, ser(m, "sensor_msgs/msg/FluidPressure")))
        msgs.sort(key=lambda m: m[0])
        for tt, c, raw in msgs:
            w.write(c, int(round(tt * 1e9)), raw)


def pressure_of_altitude(h):
    """The standard-atmosphere pressure (Pa) whose altitude quatnav.io.rosbag computes as ``h``."""
    return 101325.0 * (1.0 - np.asarray(h, float) / 44330.0) ** 5.255
