"""ROS 1 (``.bag``) and ROS 2 (bag folder: sqlite3 or mcap) recordings, read with ``rosbags``
(pure Python, no ROS installation; ``pip install 'quatnav[logs]'``).

Messages read, one topic each, chosen by the options ``imu_topic``, ``mag_topic``,
``gnss_topic``, ``baro_topic``, ``vel_topic`` or, when not given, the first topic of the type:

* ``sensor_msgs/Imu``: ``angular_velocity`` rad/s, ``linear_acceleration`` m/s^2; its
  ``orientation`` (unless ``orientation_covariance[0] == -1``) becomes the reference track.
* ``sensor_msgs/MagneticField``: ``magnetic_field``, tesla.
* ``sensor_msgs/NavSatFix``: ``latitude longitude`` deg, ``altitude`` m (ellipsoidal per the
  message definition); sigmas from the diagonal of ``position_covariance`` (ENU); fixes with
  ``status.status == -1`` (no fix) dropped; ``status.status`` kept as quality.
* ``sensor_msgs/FluidPressure``: ``fluid_pressure`` Pa, and the standard-atmosphere altitude.
* ``geometry_msgs/TwistWithCovarianceStamped``: ``twist.twist.linear``, the GNSS velocity,
  interpolated onto the fixes' times.

Frames: ROS uses REP-103/105, ENU navigation frame and FLU body frame; they are converted to NED
and FRD (``v_frd = (x, -y, -z)``, ``v_ned = (e_y, e_x, -e_z)``, ``q_ned_frd = q_ned_enu * q_enu_flu
* q_flu_frd``). ``frames="ned"`` reads data that are NED/FRD already. Times are the message
header stamps in seconds (the recording time where a stamp is zero).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from ..core import quaternion as Q
from .log import Baro, Gnss, Imu, Log, Mag, Reference

__all__ = ["read_bag", "FLU_TO_FRD", "Q_NED_ENU", "Q_FLU_FRD"]

TYPES = {"imu": ("sensor_msgs/msg/Imu", "sensor_msgs/Imu"),
         "mag": ("sensor_msgs/msg/MagneticField", "sensor_msgs/MagneticField"),
         "gnss": ("sensor_msgs/msg/NavSatFix", "sensor_msgs/NavSatFix"),
         "baro": ("sensor_msgs/msg/FluidPressure", "sensor_msgs/FluidPressure"),
         "vel": ("geometry_msgs/msg/TwistWithCovarianceStamped", "geometry_msgs/TwistWithCovarianceStamped")}
FLU_TO_FRD = np.array([1.0, -1.0, -1.0])
Q_NED_ENU = Q.Q_NED_ENU  #: rotates ENU vectors into NED: (e, n, u) -> (n, e, -u)
Q_FLU_FRD = np.array([0.0, 1.0, 0.0, 0.0])  #: 180 deg about x


def _vec3(v):
    return [v.x, v.y, v.z]


def _stamp(msg, t_ns):
    h = getattr(msg, "header", None)
    if h is not None:
        s = h.stamp.sec + h.stamp.nanosec * 1e-9
        if s > 0:
            return s
    return t_ns * 1e-9


def read_bag(path, *, imu_topic=None, mag_topic=None, gnss_topic=None, baro_topic=None, vel_topic=None,
             frames: str = "ros") -> Log:
    """Read a ROS 1 or ROS 2 bag into a :class:`~quatnav.io.Log` (see the module text)."""
    try:
        from rosbags.highlevel import AnyReader
        from rosbags.typesys import Stores, get_typestore
    except ImportError as e:
        raise ImportError("reading ROS bags needs rosbags: pip install 'quatnav[logs]'", name="rosbags") from e
    if frames not in ("ros", "ned"):
        raise ValueError(f"frames={frames!r}: expected 'ros' (ENU/FLU) or 'ned' (NED/FRD)")
    chosen = {"imu": imu_topic, "mag": mag_topic, "gnss": gnss_topic, "baro": baro_topic, "vel": vel_topic}
    try:
        reader = AnyReader([Path(path)], default_typestore=get_typestore(Stores.ROS2_HUMBLE))
        reader.open()
    except Exception as e:  # rosbags raises its own error types for damaged or unknown files
        raise ValueError(f"{path}: not a readable ROS bag ({type(e).__name__}: {e})") from None
    try:
        topics = {c.topic: c.msgtype for c in reader.connections}
        conns = {}
        for kind, topic in chosen.items():
            if topic is not None:
                if topic not in topics:
                    raise ValueError(f"{path}: no topic {topic!r} (topics: {', '.join(sorted(topics))})")
                if topics[topic] not in TYPES[kind]:
                    raise ValueError(f"{path}: topic {topic!r} is {topics[topic]}, not {TYPES[kind][0]}")
                conns[kind] = topic
            else:
                found = sorted(t for t, m in topics.items() if m in TYPES[kind])
                if found:
                    conns[kind] = found[0]
        data = {k: [] for k in conns}
        by_topic = {v: k for k, v in conns.items()}
        sel = [c for c in reader.connections if c.topic in by_topic]
        for c, t_ns, raw in reader.messages(connections=sel):
            msg = reader.deserialize(raw, c.msgtype)
            data[by_topic[c.topic]].append((_stamp(msg, t_ns), msg))
    finally:
        reader.close()
    log = Log(source=str(path), format="rosbag")
    b = FLU_TO_FRD if frames == "ros" else np.ones(3)

    def nav(v):  # (K, 3) ENU -> NED
        v = np.asarray(v, float)
        return v[:, [1, 0, 2]] * [1, 1, -1] if frames == "ros" else v

    def sort(rows):
        rows.sort(key=lambda r: r[0])
        t = np.array([r[0] for r in rows])
        keep = np.concatenate([[True], np.diff(t) > 0]) if len(t) else np.zeros(0, bool)
        return t[keep], [r[1] for r, k in zip(rows, keep) if k]

    if data.get("imu"):
        t, ms = sort(data["imu"])
        log.imu = Imu(t=t, gyr=np.array([_vec3(m.angular_velocity) for m in ms]) * b,
                      acc=np.array([_vec3(m.linear_acceleration) for m in ms]) * b)
        has_q = np.array([m.orientation_covariance[0] != -1 for m in ms])
        if has_q.any():
            q = np.array([[m.orientation.w, m.orientation.x, m.orientation.y, m.orientation.z] for m in ms])[has_q]
            if frames == "ros":
                q = Q.mul(Q.mul(Q_NED_ENU, q), Q_FLU_FRD)
            log.reference = Reference(t=t[has_q], quat=Q.normalize(q), name=f"{conns['imu']} orientation")
    if data.get("mag"):
        t, ms = sort(data["mag"])
        log.mag = Mag(t=t, values=np.array([_vec3(m.magnetic_field) for m in ms]) * b, unit="tesla")
    if data.get("gnss"):
        t, ms = sort(data["gnss"])
        st = np.array([m.status.status for m in ms], int)
        ok = st >= 0
        if (~ok).any():
            log.notes.append(f"{conns['gnss']}: {int((~ok).sum())} messages without a fix dropped")
        cov = np.array([np.asarray(m.position_covariance, float) for m in ms])
        sd = np.sqrt(np.abs(cov[:, [4, 0, 8]] if frames == "ros" else cov[:, [0, 4, 8]]))
        sd[~(sd > 0)] = np.nan
        if ok.any():
            log.gnss = Gnss(t=t[ok], lat=np.radians([m.latitude for m in ms])[ok],
                            lon=np.radians([m.longitude for m in ms])[ok], h=np.array([m.altitude for m in ms])[ok],
                            sigma=sd[ok] if np.isfinite(sd).any() else None, quality=st[ok],
                            weight=np.select([st[ok] >= 2, st[ok] == 1], [0.5, 0.3], 0.1), quality_kind="navsatstatus")
    if data.get("vel") and log.gnss is not None:
        t, ms = sort(data["vel"])
        v = nav([_vec3(m.twist.twist.linear) for m in ms])
        g = log.gnss
        inside = (g.t >= t[0]) & (g.t <= t[-1])
        g.vel_n = np.full((len(g.t), 3), np.nan)
        for j in range(3):
            g.vel_n[inside, j] = np.interp(g.t[inside], t, v[:, j])
    if data.get("baro"):
        t, ms = sort(data["baro"])
        p = np.array([m.fluid_pressure for m in ms], float)
        log.baro = Baro(t=t, pressure=p, altitude=44330.0 * (1.0 - (p / 101325.0) ** (1 / 5.255)))
    if not conns:
        raise ValueError(f"{path}: no topic of a known type (topics: {', '.join(f'{k} [{v}]' for k, v in topics.items())})")
    log.notes.append("topics: " + ", ".join(f"{k}={v}" for k, v in conns.items()))
    return log
