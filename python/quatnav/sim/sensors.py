"""Sensor models: IMU (gyro + accelerometer), magnetometer, GPS, barometric altimeter, compass.

Specifications are frozen dataclasses whose fields are in datasheet units (the unit is in each
field's name); they are converted to SI only in :mod:`quatnav.sim.units`. Bad values raise a
``ValueError`` naming the field. Every random draw comes from the ``numpy.random.Generator``
passed in.

Inertial sensor error model (per axis triad, all in SI)::

    y = Q(sat((I + diag(s)) M x + b_c + b_gm(t) + b_rw(t) + w))

* ``x``: the true mean rate / specific force over each output interval
  (:attr:`Trajectory.omega_mean_b`, :attr:`Trajectory.f_mean_b`);
* ``M``: axis misalignment, ``I`` plus the six small off-diagonal angles
  ``[xy, xz, yx, yz, zx, zy]``; ``s``: scale-factor errors;
* ``b_c``: constant bias; ``b_gm``: bias instability, a first-order Gauss-Markov process with
  correlation time ``bias_corr_time_s``, started from its stationary distribution. Its
  stationary standard deviation is ``0.664 B / 0.6174``, which puts the peak of its Allan
  deviation (0.6174 sigma at tau = 1.89 T) at the flicker floor ``0.664 B`` that the datasheet
  bias instability ``B`` denotes (IEEE Std 952-1997, annex C);
* ``b_rw``: rate random walk, ``b_rw[k] = b_rw[k-1] + K sqrt(dt) n``, starting at zero;
* ``w``: white noise of density ``N`` (ARW, VRW or a density), standard deviation
  ``N / sqrt(dt)`` per interval-mean sample;
* ``sat``: clipping to +/-range; ``Q``: rounding to the quantization step.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Optional, Sequence, Tuple

import numpy as np

from ..core import earth
from ..core import quaternion as quat
from . import units
from .trajectory import Trajectory

__all__ = [
    "GyroSpec", "AccelSpec", "ImuSpec", "ImuData", "simulate_imu",
    "MagDisturbance", "MagSpec", "MagData", "simulate_mag", "earth_field_n",
    "GpsSpec", "GpsData", "simulate_gps",
    "BaroSpec", "BaroData", "simulate_baro",
    "CompassSpec", "CompassData", "simulate_compass",
    "OdometerSpec", "OdometerData", "simulate_odometer", "mounting_quaternion",
    "GM_ALLAN_PEAK", "FLICKER_FLOOR",
]

#: Peak of the Allan deviation of a unit-variance first-order Gauss-Markov process (at 1.89 T).
GM_ALLAN_PEAK = 0.6174
#: Allan-deviation floor of flicker noise per unit bias instability (IEEE Std 952).
FLICKER_FLOOR = 0.664


# ----------------------------------------------------------------------------------------------
# validation helpers
# ----------------------------------------------------------------------------------------------
def _nonneg(obj, name, allow_inf=False):
    v = np.asarray(getattr(obj, name), dtype=float)
    bad = np.isnan(v) | (v < 0) | (np.isinf(v) & (not allow_inf))
    if np.any(bad):
        raise ValueError(f"{type(obj).__name__}.{name} must be non-negative"
                         f"{'' if allow_inf else ' and finite'}, got {getattr(obj, name)!r}")
    return v


def _finite(obj, name):
    v = getattr(obj, name)
    if not np.isfinite(v):
        raise ValueError(f"{type(obj).__name__}.{name} must be finite, got {v!r}")


def _positive(obj, name, allow_inf=False, allow_none=False):
    raw = getattr(obj, name)
    if raw is None and allow_none:
        return None
    v = np.asarray(raw, dtype=float)
    if np.any(np.isnan(v) | (v <= 0) | (np.isinf(v) & (not allow_inf))):
        raise ValueError(f"{type(obj).__name__}.{name} must be positive, got {raw!r}")
    return v


def _vec(obj, name, n):
    raw = getattr(obj, name)
    v = np.asarray(raw, dtype=float)
    if v.ndim == 0:
        v = np.full(n, float(v))
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{type(obj).__name__}.{name} must be a finite scalar or {n} numbers, "
                         f"got {raw!r}")
    return v


def _misalignment_matrix(m6):
    xy, xz, yx, yz, zx, zy = m6
    return np.array([[1.0, xy, xz], [yx, 1.0, yz], [zx, zy, 1.0]])


def mounting_quaternion(rpy_deg):
    """``q_b_s`` (body from sensor, [w, x, y, z]) of a sensor mounted at ZYX Euler angles
    ``rpy_deg`` = [roll, pitch, yaw] (deg) relative to the body: a vector in the sensor frame
    is ``v_b = q_b_s * v_s * conj(q_b_s)``, so the sensor measures ``v_s = C_b_s^T v_b``."""
    return quat.from_euler(np.radians(np.asarray(rpy_deg, float)))


def _mounted(spec, name="mounting_rpy_deg"):
    """``(q_b_s, rotated)``: the mounting quaternion and whether it differs from identity."""
    rpy = _vec(spec, name, 3)
    return mounting_quaternion(rpy), bool(np.any(rpy != 0.0))


def _decimation(traj_rate, rate_hz, what):
    if rate_hz is None:
        return 1
    m = traj_rate / float(rate_hz)
    k = int(round(m))
    if k < 1 or abs(m - k) > 1e-9:
        raise ValueError(f"{what}.rate_hz={rate_hz} must divide the trajectory rate {traj_rate} Hz")
    return k


# ----------------------------------------------------------------------------------------------
# IMU
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class GyroSpec:
    """Gyroscope triad specification (datasheet units in the field names).

    White noise: give ``arw_deg_per_sqrt_h`` or ``noise_density_dps_per_sqrt_hz`` (not both).
    Vector fields accept a scalar (all axes) or 3 values; ``misalignment_mrad`` 6 values
    ``[xy, xz, yx, yz, zx, zy]`` or a scalar.
    """

    bias_deg_per_h: object = 0.0
    bias_instability_deg_per_h: float = 0.0
    bias_corr_time_s: float = 100.0
    arw_deg_per_sqrt_h: Optional[float] = None
    noise_density_dps_per_sqrt_hz: Optional[float] = None
    rrw_deg_per_h_per_sqrt_h: float = 0.0
    scale_factor_ppm: object = 0.0
    misalignment_mrad: object = 0.0
    range_deg_per_s: float = np.inf
    quantization_deg_per_s: float = 0.0

    def __post_init__(self):
        self.si()

    def si(self):
        """Parameters in SI (rad/s, rad/s/sqrt(Hz), ...), as a dict."""
        if self.arw_deg_per_sqrt_h is not None and self.noise_density_dps_per_sqrt_hz is not None:
            raise ValueError("GyroSpec: give arw_deg_per_sqrt_h or noise_density_dps_per_sqrt_hz, "
                             "not both")
        if self.noise_density_dps_per_sqrt_hz is not None:
            white = units.dps_per_sqrt_hz(float(_nonneg(self, "noise_density_dps_per_sqrt_hz")))
        elif self.arw_deg_per_sqrt_h is not None:
            white = units.arw_deg_per_sqrt_h(float(_nonneg(self, "arw_deg_per_sqrt_h")))
        else:
            white = 0.0
        return dict(
            bias=units.deg_per_h(_vec(self, "bias_deg_per_h", 3)),
            bias_instability=units.deg_per_h(float(_nonneg(self, "bias_instability_deg_per_h"))),
            bias_corr_time=float(_positive(self, "bias_corr_time_s")),
            white_density=white,
            rrw_density=units.rrw_deg_per_h_per_sqrt_h(float(_nonneg(self, "rrw_deg_per_h_per_sqrt_h"))),
            scale_factor=units.ppm(_vec(self, "scale_factor_ppm", 3)),
            misalignment=units.mrad(_vec(self, "misalignment_mrad", 6)),
            range=units.deg_per_s(float(_positive(self, "range_deg_per_s", allow_inf=True))),
            quantization=units.deg_per_s(float(_nonneg(self, "quantization_deg_per_s"))),
        )


@dataclass(frozen=True)
class AccelSpec:
    """Accelerometer triad specification (datasheet units in the field names).

    White noise: give ``vrw_m_per_s_per_sqrt_h`` or ``noise_density_ug_per_sqrt_hz`` (not both).
    """

    bias_ug: object = 0.0
    bias_instability_ug: float = 0.0
    bias_corr_time_s: float = 100.0
    vrw_m_per_s_per_sqrt_h: Optional[float] = None
    noise_density_ug_per_sqrt_hz: Optional[float] = None
    bias_rw_ug_per_sqrt_h: float = 0.0
    scale_factor_ppm: object = 0.0
    misalignment_mrad: object = 0.0
    range_g: float = np.inf
    quantization_mg: float = 0.0

    def __post_init__(self):
        self.si()

    def si(self):
        """Parameters in SI (m/s^2, m/s^2/sqrt(Hz), ...), as a dict."""
        if self.vrw_m_per_s_per_sqrt_h is not None and self.noise_density_ug_per_sqrt_hz is not None:
            raise ValueError("AccelSpec: give vrw_m_per_s_per_sqrt_h or "
                             "noise_density_ug_per_sqrt_hz, not both")
        if self.noise_density_ug_per_sqrt_hz is not None:
            white = units.ug_per_sqrt_hz(float(_nonneg(self, "noise_density_ug_per_sqrt_hz")))
        elif self.vrw_m_per_s_per_sqrt_h is not None:
            white = units.vrw_m_per_s_per_sqrt_h(float(_nonneg(self, "vrw_m_per_s_per_sqrt_h")))
        else:
            white = 0.0
        return dict(
            bias=units.ug(_vec(self, "bias_ug", 3)),
            bias_instability=units.ug(float(_nonneg(self, "bias_instability_ug"))),
            bias_corr_time=float(_positive(self, "bias_corr_time_s")),
            white_density=white,
            rrw_density=units.ug_per_sqrt_h(float(_nonneg(self, "bias_rw_ug_per_sqrt_h"))),
            scale_factor=units.ppm(_vec(self, "scale_factor_ppm", 3)),
            misalignment=units.mrad(_vec(self, "misalignment_mrad", 6)),
            range=units.g_units(float(_positive(self, "range_g", allow_inf=True))),
            quantization=units.mg(float(_nonneg(self, "quantization_mg"))),
        )


@dataclass(frozen=True)
class ImuSpec:
    """An IMU: gyro and accelerometer triads and an output rate (Hz; ``None`` = trajectory rate,
    otherwise it must divide the trajectory rate; samples are means over the output interval).

    ``mounting_rpy_deg``: the IMU's axes relative to the body, ZYX Euler angles [roll, pitch,
    yaw] in degrees (:func:`mounting_quaternion` gives ``q_b_imu``, body from IMU). The IMU
    sits at the body origin; its samples, and its errors, are in the IMU frame:
    ``omega_imu = C_b_imu^T omega_b``. ``(180, 0, 0)`` is an IMU mounted upside down (its axes
    forward-left-up); ``(0, 0, 90)`` one whose x axis points to the body's right.
    """

    gyro: GyroSpec = field(default_factory=GyroSpec)
    accel: AccelSpec = field(default_factory=AccelSpec)
    rate_hz: Optional[float] = None
    mounting_rpy_deg: object = (0.0, 0.0, 0.0)

    def __post_init__(self):
        if not isinstance(self.gyro, GyroSpec):
            raise ValueError(f"ImuSpec.gyro must be a GyroSpec, got {self.gyro!r}")
        if not isinstance(self.accel, AccelSpec):
            raise ValueError(f"ImuSpec.accel must be an AccelSpec, got {self.accel!r}")
        _positive(self, "rate_hz", allow_none=True)
        _vec(self, "mounting_rpy_deg", 3)


@dataclass
class ImuData:
    """Simulated IMU output (K samples).

    Attributes
    ----------
    t : (K,) s, end of each output interval
    index : (K,) int, trajectory sample of each output
    gyro : (K, 3) rad/s, measured mean body rate over the interval (row 0: instantaneous)
    accel : (K, 3) m/s^2, measured mean specific force
    gyro_bias, accel_bias : (K, 3) total additive error from biases (constant + instability +
        random walk), in rad/s and m/s^2
    saturated : (K,) bool, any axis clipped at the range
    rate_hz : float
    q_b_imu : (4,) the mounting, body from IMU ([w, x, y, z]; identity for an IMU aligned with
        the body). ``gyro``, ``accel`` and the biases are in the IMU frame.
    """

    t: np.ndarray
    index: np.ndarray
    gyro: np.ndarray
    accel: np.ndarray
    gyro_bias: np.ndarray
    accel_bias: np.ndarray
    saturated: np.ndarray
    rate_hz: float
    q_b_imu: np.ndarray = field(default_factory=lambda: np.array([1.0, 0.0, 0.0, 0.0]))

    @property
    def C_b_imu(self):
        """(3, 3) rotation matrix body from IMU."""
        return quat.to_rotmat(self.q_b_imu)

    @property
    def dt(self):
        return 1.0 / self.rate_hz


def gauss_markov(n, sigma, corr_time, dt, rng, dim=3):
    """First-order Gauss-Markov samples, shape (n, dim), stationary with standard deviation
    ``sigma`` and correlation time ``corr_time`` (s)."""
    from .._optional import require
    lfilter = require("scipy.signal", "quatnav.sim Gauss-Markov noise").lfilter
    e = rng.standard_normal((n, dim))
    if sigma == 0:
        return np.zeros((n, dim))
    phi = np.exp(-dt / corr_time)
    drive = sigma * np.sqrt(1.0 - phi**2) * e
    drive[0] = sigma * e[0]
    return lfilter([1.0], [1.0, -phi], drive, axis=0)


def _triad(x, p, dt, rng):
    n = x.shape[0]
    M = _misalignment_matrix(p["misalignment"])
    y = (x @ M.T) * (1.0 + p["scale_factor"])
    white = rng.standard_normal((n, 3)) * (p["white_density"] / np.sqrt(dt))
    gm = gauss_markov(n, FLICKER_FLOOR * p["bias_instability"] / GM_ALLAN_PEAK,
                      p["bias_corr_time"], dt, rng)
    steps = rng.standard_normal((n, 3)) * (p["rrw_density"] * np.sqrt(dt))
    steps[0] = 0.0
    rw = np.cumsum(steps, axis=0)
    bias = p["bias"] + gm + rw
    y = y + bias + white
    sat = np.any(np.abs(y) >= p["range"], axis=1)
    y = np.clip(y, -p["range"], p["range"])
    if p["quantization"] > 0:
        y = np.round(y / p["quantization"]) * p["quantization"]
    return y, bias, sat


def simulate_imu(traj: Trajectory, spec: ImuSpec, rng: np.random.Generator) -> ImuData:
    """Simulate an IMU on a trajectory.

    Parameters
    ----------
    traj : Trajectory
    spec : ImuSpec
    rng : numpy.random.Generator

    Returns
    -------
    ImuData
    """
    m = _decimation(traj.rate_hz, spec.rate_hz, "ImuSpec")
    idx = np.arange(0, len(traj), m)
    dt = m * traj.dt
    # mean over each output interval = sum of the trajectory increments / interval
    cth = np.concatenate([np.zeros((1, 3)), np.cumsum(traj.dtheta_b[1:], axis=0)])
    cv = np.concatenate([np.zeros((1, 3)), np.cumsum(traj.dv_b[1:], axis=0)])
    w = np.empty((len(idx), 3))
    f = np.empty((len(idx), 3))
    w[1:] = (cth[idx[1:]] - cth[idx[:-1]]) / dt
    f[1:] = (cv[idx[1:]] - cv[idx[:-1]]) / dt
    w[0] = traj.omega_ib_b[0]
    f[0] = traj.f_ib_b[0]
    q_b_imu, rotated = _mounted(spec)
    if rotated:  # into the IMU frame: x_imu = C_b_imu^T x_b
        C = quat.to_rotmat(q_b_imu)
        w, f = w @ C, f @ C
    gyro, gb, gs = _triad(w, spec.gyro.si(), dt, rng)
    accel, ab, as_ = _triad(f, spec.accel.si(), dt, rng)
    return ImuData(t=traj.t[idx], index=idx, gyro=gyro, accel=accel, gyro_bias=gb,
                   accel_bias=ab, saturated=gs | as_, rate_hz=traj.rate_hz / m, q_b_imu=q_b_imu)


# ----------------------------------------------------------------------------------------------
# Magnetometer
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MagDisturbance:
    """A magnet near the sensor: an extra body-frame field (uT) from ``t_start`` to ``t_end`` (s),
    faded in and out over ``ramp_s`` seconds."""

    t_start: float
    t_end: float
    field_b_uT: Sequence[float] = (20.0, -10.0, 15.0)
    ramp_s: float = 0.5

    def __post_init__(self):
        if not (np.isfinite(self.t_start) and np.isfinite(self.t_end) and self.t_end > self.t_start):
            raise ValueError(f"MagDisturbance: need t_end > t_start, got {self.t_start}, {self.t_end}")
        _vec(self, "field_b_uT", 3)
        _nonneg(self, "ramp_s")


@dataclass(frozen=True)
class MagSpec:
    """Three-axis magnetometer.

    The Earth field has ``intensity_uT``, ``inclination_deg`` (dip, positive down) and
    ``declination_deg`` (east of true north); defaults are about right for central Korea.
    Output ``m_s = S C_sn m_n + hard_iron + disturbance + noise`` in the sensor frame, which is
    the body frame rotated by ``mounting_rpy_deg`` (as :attr:`ImuSpec.mounting_rpy_deg`; a
    magnetometer in the IMU's package has the IMU's mounting). Disturbance fields are given in
    the sensor frame.
    """

    intensity_uT: float = 50.0
    inclination_deg: float = 53.0
    declination_deg: float = -8.5
    hard_iron_uT: object = 0.0
    soft_iron: object = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    noise_uT: float = 0.3
    rate_hz: Optional[float] = None
    disturbances: Tuple[MagDisturbance, ...] = ()
    mounting_rpy_deg: object = (0.0, 0.0, 0.0)

    def __post_init__(self):
        _positive(self, "intensity_uT")
        _vec(self, "mounting_rpy_deg", 3)
        if not (np.isfinite(self.inclination_deg) and abs(self.inclination_deg) <= 90):
            raise ValueError(f"MagSpec.inclination_deg must be in [-90, 90], got {self.inclination_deg!r}")
        if not np.isfinite(self.declination_deg):
            raise ValueError(f"MagSpec.declination_deg must be finite, got {self.declination_deg!r}")
        _vec(self, "hard_iron_uT", 3)
        S = np.asarray(self.soft_iron, float)
        if S.shape != (3, 3) or not np.all(np.isfinite(S)) or abs(np.linalg.det(S)) < 1e-6:
            raise ValueError(f"MagSpec.soft_iron must be an invertible 3x3 matrix, got {self.soft_iron!r}")
        _nonneg(self, "noise_uT")
        _positive(self, "rate_hz", allow_none=True)
        for d in self.disturbances:
            if not isinstance(d, MagDisturbance):
                raise ValueError(f"MagSpec.disturbances must hold MagDisturbance, got {d!r}")


def earth_field_n(spec: MagSpec):
    """Earth magnetic field in NED (T), shape (3,)."""
    B = units.microtesla(spec.intensity_uT)
    inc = np.radians(spec.inclination_deg)
    dec = np.radians(spec.declination_deg)
    return B * np.array([np.cos(inc) * np.cos(dec), np.cos(inc) * np.sin(dec), np.sin(inc)])


@dataclass
class MagData:
    """Magnetometer output: ``t`` (K,) s, ``index`` (K,), ``mag`` (K, 3) T, ``disturbed`` (K,)
    bool (a disturbance is active), ``field_n`` (3,) T the undisturbed Earth field."""

    t: np.ndarray
    index: np.ndarray
    mag: np.ndarray
    disturbed: np.ndarray
    field_n: np.ndarray


def simulate_mag(traj: Trajectory, spec: MagSpec, rng: np.random.Generator) -> MagData:
    """Simulate a magnetometer on a trajectory (sampled at the trajectory sample times)."""
    m = _decimation(traj.rate_hz, spec.rate_hz, "MagSpec")
    idx = np.arange(0, len(traj), m)
    t = traj.t[idx]
    m_n = earth_field_n(spec)
    m_b = quat.rotate_inv(traj.q_nb[idx], np.broadcast_to(m_n, (len(idx), 3)))
    q_b_s, rotated = _mounted(spec)
    if rotated:
        m_b = m_b @ quat.to_rotmat(q_b_s)
    out = m_b @ np.asarray(spec.soft_iron, float).T + units.microtesla(_vec(spec, "hard_iron_uT", 3))
    disturbed = np.zeros(len(idx), bool)
    for d in spec.disturbances:
        r = max(d.ramp_s, 1e-12)
        w = np.clip(np.minimum(t - d.t_start, d.t_end - t) / r, 0.0, 1.0)
        w = 0.5 * (1 - np.cos(np.pi * w))
        out += w[:, None] * units.microtesla(np.asarray(d.field_b_uT, float))
        disturbed |= w > 0
    out += rng.standard_normal(out.shape) * units.microtesla(spec.noise_uT)
    return MagData(t=t, index=idx, mag=out, disturbed=disturbed, field_n=m_n)


# ----------------------------------------------------------------------------------------------
# GPS
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class GpsSpec:
    """GPS receiver: position and velocity of the antenna.

    ``lever_arm_b_m`` is the antenna position in the body frame relative to the IMU (m).
    A fix measured at ``t`` is delivered at ``t + latency_s`` (latency rounded to whole
    trajectory samples). ``time_stamp`` says which time the receiver writes on a fix:
    ``"valid"`` (the time of validity; the latency only delays delivery) or ``"delivery"`` (the
    fix is stamped on arrival, late by ``latency_s``: a filter must be told the latency, as
    with a receiver whose messages are time-stamped by the logger). No fix is measured inside
    an outage ``(t_start, t_end)``.
    Noise is white per fix with standard deviations in m (horizontal per axis, vertical) and
    m/s (per axis).
    """

    rate_hz: float = 5.0
    pos_sigma_h_m: float = 2.0
    pos_sigma_v_m: float = 4.0
    vel_sigma_m_s: float = 0.1
    lever_arm_b_m: object = 0.0
    latency_s: float = 0.0
    outages: Tuple[Tuple[float, float], ...] = ()
    time_stamp: str = "valid"

    def __post_init__(self):
        if self.time_stamp not in ("valid", "delivery"):
            raise ValueError(f"GpsSpec.time_stamp must be 'valid' or 'delivery', got {self.time_stamp!r}")
        _positive(self, "rate_hz")
        _nonneg(self, "pos_sigma_h_m")
        _nonneg(self, "pos_sigma_v_m")
        _nonneg(self, "vel_sigma_m_s")
        _vec(self, "lever_arm_b_m", 3)
        _nonneg(self, "latency_s")
        for o in self.outages:
            if len(o) != 2 or not (o[1] > o[0]):
                raise ValueError(f"GpsSpec.outages must be (t_start, t_end) pairs, got {o!r}")


@dataclass
class GpsData:
    """GPS fixes (K): ``t`` delivery time (s), ``t_valid`` time of validity (s), ``index`` and
    ``index_valid`` trajectory samples, ``lat``, ``lon`` (rad), ``h`` (m), ``pos_n`` (K, 3) m local
    NED, ``v_n`` (K, 3) m/s, all of the antenna. ``t_stamp`` (property): the time the receiver
    writes on each fix (``t_valid`` or ``t`` as :attr:`GpsSpec.time_stamp` says)."""

    t: np.ndarray
    t_valid: np.ndarray
    index: np.ndarray
    index_valid: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    h: np.ndarray
    pos_n: np.ndarray
    v_n: np.ndarray
    stamped_on_delivery: bool = False

    @property
    def t_stamp(self):
        """(K,) s: the time stamp of each fix as the receiver writes it."""
        return self.t if self.stamped_on_delivery else self.t_valid


def simulate_gps(traj: Trajectory, spec: GpsSpec, rng: np.random.Generator) -> GpsData:
    """Simulate GPS fixes of the antenna on a trajectory."""
    m = _decimation(traj.rate_hz, spec.rate_hz, "GpsSpec")
    lag = int(round(spec.latency_s * traj.rate_hz))
    iv = np.arange(0, len(traj) - lag, m)
    tv = traj.t[iv]
    keep = np.ones(len(iv), bool)
    for t0, t1 in spec.outages:
        keep &= ~((tv >= t0) & (tv < t1))
    iv = iv[keep]
    n = len(iv)
    lever = _vec(spec, "lever_arm_b_m", 3)
    q = traj.q_nb[iv]
    w_eb_b = traj.omega_ib_b[iv]
    if traj.earth_rate:
        w_eb_b = w_eb_b - quat.rotate_inv(q, earth.earth_rate_n(traj.lat[iv]))
    pos = traj.pos_n[iv] + quat.rotate(q, np.broadcast_to(lever, (n, 3)))
    vel = traj.v_n[iv] + quat.rotate(q, np.cross(w_eb_b, lever))
    sig = np.array([spec.pos_sigma_h_m, spec.pos_sigma_h_m, spec.pos_sigma_v_m])
    pos = pos + rng.standard_normal((n, 3)) * sig
    vel = vel + rng.standard_normal((n, 3)) * spec.vel_sigma_m_s
    lat, lon, h = earth.ned_to_geodetic(pos, traj.lat[0], traj.lon[0], traj.h[0])
    return GpsData(t=traj.t[iv + lag], t_valid=tv[keep], index=iv + lag, index_valid=iv,
                   lat=lat, lon=lon, h=h, pos_n=pos, v_n=vel,
                   stamped_on_delivery=spec.time_stamp == "delivery")


# ----------------------------------------------------------------------------------------------
# Barometric altimeter and compass
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BaroSpec:
    """Barometric altimeter: height (m) with white noise, a constant bias and a slow drift
    (random walk of ``drift_m_per_sqrt_h``, i.e. its standard deviation after one hour)."""

    rate_hz: float = 10.0
    noise_m: float = 0.5
    bias_m: float = 0.0
    drift_m_per_sqrt_h: float = 1.0

    def __post_init__(self):
        _positive(self, "rate_hz")
        _nonneg(self, "noise_m")
        _finite(self, "bias_m")
        _nonneg(self, "drift_m_per_sqrt_h")


@dataclass
class BaroData:
    """Altimeter output: ``t`` (K,) s, ``index`` (K,), ``h`` (K,) m, ``drift`` (K,) m (bias +
    drift, truth)."""

    t: np.ndarray
    index: np.ndarray
    h: np.ndarray
    drift: np.ndarray


def simulate_baro(traj: Trajectory, spec: BaroSpec, rng: np.random.Generator) -> BaroData:
    """Simulate a barometric altimeter."""
    m = _decimation(traj.rate_hz, spec.rate_hz, "BaroSpec")
    idx = np.arange(0, len(traj), m)
    dt = m * traj.dt
    steps = rng.standard_normal(len(idx)) * spec.drift_m_per_sqrt_h / units.SQRT_HOUR * np.sqrt(dt)
    steps[0] = 0.0
    drift = spec.bias_m + np.cumsum(steps)
    h = traj.h[idx] + drift + rng.standard_normal(len(idx)) * spec.noise_m
    return BaroData(t=traj.t[idx], index=idx, h=h, drift=drift)


@dataclass(frozen=True)
class CompassSpec:
    """Magnetic compass giving true heading (declination already applied): yaw + bias + noise."""

    rate_hz: float = 10.0
    noise_deg: float = 2.0
    bias_deg: float = 0.0

    def __post_init__(self):
        _positive(self, "rate_hz")
        _nonneg(self, "noise_deg")
        _finite(self, "bias_deg")


@dataclass
class CompassData:
    """Compass output: ``t`` (K,) s, ``index`` (K,), ``yaw`` (K,) rad in (-pi, pi]."""

    t: np.ndarray
    index: np.ndarray
    yaw: np.ndarray


def simulate_compass(traj: Trajectory, spec: CompassSpec, rng: np.random.Generator) -> CompassData:
    """Simulate a heading sensor."""
    m = _decimation(traj.rate_hz, spec.rate_hz, "CompassSpec")
    idx = np.arange(0, len(traj), m)
    yaw = traj.rpy[idx, 2] + np.radians(spec.bias_deg) + \
        rng.standard_normal(len(idx)) * np.radians(spec.noise_deg)
    return CompassData(t=traj.t[idx], index=idx, yaw=np.angle(np.exp(1j * yaw)))


# ----------------------------------------------------------------------------------------------
# Wheel odometer
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class OdometerSpec:
    """Wheel odometer: the forward speed of the body (m/s, along body x; negative when
    reversing), as a car's wheel-speed or transmission sensor gives it:
    ``speed = (1 + scale) v_bx + noise``, rounded to ``quantization_m_s``."""

    rate_hz: float = 10.0
    noise_m_s: float = 0.05
    scale_factor_ppm: float = 0.0
    quantization_m_s: float = 0.0

    def __post_init__(self):
        _positive(self, "rate_hz")
        _nonneg(self, "noise_m_s")
        _finite(self, "scale_factor_ppm")
        _nonneg(self, "quantization_m_s")


@dataclass
class OdometerData:
    """Odometer output: ``t`` (K,) s, ``index`` (K,), ``speed`` (K,) m/s forward (body x)."""

    t: np.ndarray
    index: np.ndarray
    speed: np.ndarray


def simulate_odometer(traj: Trajectory, spec: OdometerSpec, rng: np.random.Generator) -> OdometerData:
    """Simulate a wheel odometer (forward speed of the body)."""
    m = _decimation(traj.rate_hz, spec.rate_hz, "OdometerSpec")
    idx = np.arange(0, len(traj), m)
    v_b = quat.rotate_inv(traj.q_nb[idx], traj.v_n[idx])
    y = v_b[:, 0] * (1.0 + units.ppm(spec.scale_factor_ppm)) + rng.standard_normal(len(idx)) * spec.noise_m_s
    if spec.quantization_m_s > 0:
        y = np.round(y / spec.quantization_m_s) * spec.quantization_m_s
    return OdometerData(t=traj.t[idx], index=idx, speed=y)
