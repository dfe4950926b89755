"""A real pedestrian walk with an IMU and an RTK GNSS solution (rtklibexplorer's GNSS_IMU
example, BSD-3-Clause): 134 s recorded 2025-08-28 near Boulder, CO.

Files in ``<shared data>/gnss_imu_walk``:

* ``imu_1730_sf.csv`` (no header): GPS time (s, the GPST calendar counted from 1970-01-01 like a
  Unix time), accelerometer x, y, z (g), gyro x, y, z (rad/s), four unused columns; ~166 Hz.
* ``gnss_1730_sf.pos``: RTKLIB solution, 4 Hz: GPST date and time, latitude and longitude (deg),
  ellipsoidal height (m), Q (1 fixed, 2 float, ...), number of satellites, sdn/sde/sdu (m),
  sdne/sdeu/sdun, age (s), ratio, then velocity **north, east, up** (m/s) and its sigmas.

:func:`load` returns the raw sensor axes in SI units (accelerometer times :data:`G0`) and the
GNSS velocity converted to NED (``v_D = -v_U``). The IMU mounting (which sensor axis is down and
which is forward) is not documented; :data:`C_BS` is the one found from the data
(``docs/GPSINS_DATA.md``) and :func:`to_body` applies it.
"""
from __future__ import annotations

import calendar
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["Walk", "load", "default_dir", "to_body", "find_mounting", "mounting_matrix", "C_BS",
           "FORWARD_YAW_DEG", "G0", "IMU_FILE", "POS_FILE"]

#: Standard gravity used to convert the accelerometer from g to m/s^2.
G0 = 9.80665
IMU_FILE = "imu_1730_sf.csv"
POS_FILE = "gnss_1730_sf.pos"

#: Mounting found from the data by :func:`find_mounting` (docs/GPSINS_DATA.md): the sensor's z
#: axis points up (+1.01 g at rest) and the gyro is right-handed about it (the yaw rate about
#: down is -gyro_z), so (x, -y, -z) is a forward-right-down-like frame; the walking direction is
#: at FORWARD_YAW_DEG about down from the sensor's x axis (between -x and -y).
FORWARD_YAW_DEG = 140.0


def _rz(psi):
    c, s = np.cos(psi), np.sin(psi)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def mounting_matrix(forward_yaw_deg: float = FORWARD_YAW_DEG) -> np.ndarray:
    """Sensor -> body rotation: flip to (x, -y, -z), then turn by ``forward_yaw_deg`` about
    down so that body x is the walking direction."""
    return _rz(np.radians(forward_yaw_deg)).T @ np.diag([1.0, -1.0, -1.0])


#: Sensor -> body FRD rotation (body x along the walk): ``v_b = C_BS v_s``.
C_BS = mounting_matrix()


def default_dir() -> Path:
    """``<shared data>/gnss_imu_walk`` (see :func:`quatnav.datasets.data_dir`)."""
    from . import data_dir
    return data_dir() / "gnss_imu_walk"


@dataclass
class Walk:
    """The walk record in SI units (sensor axes for the IMU, NED for the GNSS velocity).

    Attributes
    ----------
    imu_t : (N,) ndarray
        GPS time, s (strictly increasing).
    accel_s : (N, 3) ndarray
        Accelerometer in the sensor axes, m/s^2 (specific force; ~ +g on the up axis at rest).
    gyro_s : (N, 3) ndarray
        Gyro in the sensor axes, rad/s.
    gnss_t : (K,) ndarray
        GPS time of the solutions, s (same scale as ``imu_t``).
    gnss_llh : (K, 3) ndarray
        [lat (rad), lon (rad), h (m)] of the antenna.
    q : (K,) int ndarray
        RTKLIB quality flag (1 fixed, 2 float).
    ns : (K,) int ndarray
        Number of satellites.
    pos_sigma : (K, 3) ndarray
        One-sigma north, east, down (m) (RTKLIB sdn, sde, sdu).
    vel_n : (K, 3) ndarray
        NED velocity (m/s), converted from RTKLIB's north, east, up.
    vel_sigma : (K, 3) ndarray
        One-sigma of ``vel_n`` (m/s).
    """

    imu_t: np.ndarray
    accel_s: np.ndarray
    gyro_s: np.ndarray
    gnss_t: np.ndarray
    gnss_llh: np.ndarray
    q: np.ndarray
    ns: np.ndarray
    pos_sigma: np.ndarray
    vel_n: np.ndarray
    vel_sigma: np.ndarray
    path: Path = field(default_factory=Path)

    @property
    def fixed(self) -> np.ndarray:
        """(K,) bool: RTK-fixed epochs (Q = 1)."""
        return self.q == 1


def _gpst_seconds(date: str, time: str) -> float:
    y, mo, d = (int(x) for x in date.split("/"))
    hh, mm, ss = time.split(":")
    return calendar.timegm((y, mo, d, int(hh), int(mm), 0, 0, 0, 0)) + float(ss)


def read_pos(path) -> dict:
    """Read an RTKLIB ``.pos`` file (GPST time, lat/lon in degrees, velocity columns)."""
    t, rows = [], []
    with open(path) as fh:
        for line in fh:
            if line.startswith("%") or not line.strip():
                continue
            p = line.split()
            if len(p) < 21:
                raise ValueError(f"{path}: expected >= 21 columns (with velocity), got {len(p)}: {line!r}")
            t.append(_gpst_seconds(p[0], p[1]))
            rows.append([float(x) for x in p[2:21]])
    a = np.array(rows, dtype=np.float64)
    return dict(t=np.array(t), lat=np.radians(a[:, 0]), lon=np.radians(a[:, 1]), h=a[:, 2], q=a[:, 3].astype(int),
                ns=a[:, 4].astype(int), sd_neu=a[:, 5:8], vel_neu=a[:, 13:16], sdv_neu=a[:, 16:19])


def load(directory=None) -> Walk:
    """Load both files of ``directory`` (default :func:`default_dir`)."""
    d = Path(directory) if directory is not None else default_dir()
    fi, fp = d / IMU_FILE, d / POS_FILE
    for f in (fi, fp):
        if not f.is_file():
            raise FileNotFoundError(f"gnss_imu_walk data: {f} not found")
    a = np.loadtxt(fi, delimiter=",", ndmin=2)
    if a.shape[1] < 7:
        raise ValueError(f"{fi}: expected >= 7 columns, got {a.shape[1]}")
    t = a[:, 0]
    if not np.all(np.diff(t) > 0):
        raise ValueError(f"{fi}: times are not strictly increasing")
    p = read_pos(fp)
    if not np.all(np.diff(p["t"]) > 0):
        raise ValueError(f"{fp}: times are not strictly increasing")
    neu2ned = np.array([1.0, 1.0, -1.0])
    return Walk(imu_t=t, accel_s=a[:, 1:4] * G0, gyro_s=a[:, 4:7].copy(), gnss_t=p["t"],
                gnss_llh=np.column_stack([p["lat"], p["lon"], p["h"]]), q=p["q"], ns=p["ns"],
                pos_sigma=p["sd_neu"].copy(), vel_n=p["vel_neu"] * neu2ned, vel_sigma=p["sdv_neu"].copy(), path=d)


def to_body(v_s, C_bs=C_BS) -> np.ndarray:
    """Sensor-axis vectors (N, 3) rotated into the body FRD frame: ``v_b = C_bs v_s``."""
    return np.asarray(v_s, dtype=float) @ np.asarray(C_bs).T


def find_mounting(w: Walk, rest_s: float = 8.0, min_speed: float = 0.8) -> dict:
    """Measure the IMU mounting from the data.

    * Down axis: the mean accelerometer over the first ``rest_s`` seconds (the walker stands
      still): the axis with the largest magnitude, and its sign (specific force at rest points up).
    * Gyro handedness: the yaw rate about down is +/- that axis' gyro; integrate both (gyro bias
      from the rest period removed) and keep the sign for which GNSS course minus integrated yaw
      stays constant (smallest circular spread) over the epochs faster than ``min_speed`` m/s.
    * Forward axis: that constant (circular mean), the yaw of the walking direction from the
      sensor's x axis (about down), with its spread and its mean over each 10 s.

    Returns
    -------
    dict with ``rest_accel_g`` (3,), ``rest_accel_norm_g``, ``rest_gyro_rad_s`` (3,),
    ``up_axis`` (e.g. ``"+z"``), ``yaw_rate_sign`` (-1: yaw rate about down = -gyro),
    ``forward_yaw_deg``, ``forward_spread_deg``, ``spread_other_sign_deg``, ``forward_yaw_10s_deg``
    (list), ``level_roll_pitch_deg`` (2,) in the (x, -y, -z) frame.
    """
    t = w.imu_t
    rest = (t - t[0]) < rest_s
    fm = w.accel_s[rest].mean(axis=0)
    k = int(np.argmax(np.abs(fm)))
    up = ("+" if fm[k] > 0 else "-") + "xyz"[k]
    bg = w.gyro_s[rest].mean(axis=0)
    g_up = (w.gyro_s[:, k] - bg[k]) * np.sign(fm[k])  # rate about the up axis
    sp = np.hypot(w.vel_n[:, 0], w.vel_n[:, 1])
    mv = sp > min_speed
    course = np.arctan2(w.vel_n[mv, 1], w.vel_n[mv, 0])
    res = {}
    for sgn in (-1, 1):
        yaw = np.concatenate([[0.0], np.cumsum(sgn * g_up[1:] * np.diff(t))])
        off = np.angle(np.exp(1j * (course - np.interp(w.gnss_t[mv], t, yaw))))
        z = np.mean(np.exp(1j * off))
        res[sgn] = (off, float(np.degrees(np.angle(z))), float(np.degrees(np.sqrt(-2 * np.log(abs(z))))))
    sgn = min(res, key=lambda s_: res[s_][2])
    off, mean_deg, spread = res[sgn]
    tt = w.gnss_t[mv] - t[0]
    bins = []
    for a in np.arange(np.floor(tt.min() / 10) * 10, tt.max(), 10):
        m = (tt >= a) & (tt < a + 10)
        if m.sum() >= 8:
            bins.append(float(np.degrees(np.angle(np.mean(np.exp(1j * off[m]))))))
    f1 = fm * np.array([1.0, -1.0, -1.0])
    roll = np.degrees(np.arctan2(-f1[1], -f1[2]))
    pitch = np.degrees(np.arctan2(f1[0], np.hypot(f1[1], f1[2])))
    return {"rest_accel_g": (fm / G0).tolist(), "rest_accel_norm_g": float(np.linalg.norm(fm) / G0),
            "rest_gyro_rad_s": bg.tolist(), "up_axis": up, "yaw_rate_sign": int(sgn),
            "forward_yaw_deg": mean_deg, "forward_spread_deg": spread,
            "spread_other_sign_deg": res[-sgn][2], "forward_yaw_10s_deg": bins,
            "level_roll_pitch_deg": [float(roll), float(pitch)]}
