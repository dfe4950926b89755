"""Datasheet units to SI: the one place where sensor parameters are converted.

Sensor specifications (:mod:`quatnav.sim.sensors`) are written in the units of datasheets and
papers; they are converted here, and nowhere else, to SI and radians.

=============================  ======================================  ===========================
datasheet quantity             datasheet unit                          SI unit used internally
=============================  ======================================  ===========================
gyro bias, bias instability    deg/h                                   rad/s
gyro angle random walk (ARW)   deg/sqrt(h)                             rad/s/sqrt(Hz) = rad/sqrt(s)
gyro rate random walk (RRW)    deg/h/sqrt(h)                           rad/s^2/sqrt(Hz)
gyro noise density             deg/s/sqrt(Hz)                          rad/s/sqrt(Hz)
gyro range, quantization       deg/s                                   rad/s
accel bias, bias instability   ug (micro standard gravity)             m/s^2
accel velocity random walk     m/s/sqrt(h)                             m/s^2/sqrt(Hz)
accel noise density            ug/sqrt(Hz)                             m/s^2/sqrt(Hz)
accel bias random walk         ug/sqrt(h)                              m/s^3/sqrt(Hz)
accel range                    g                                       m/s^2
accel quantization             mg                                      m/s^2
scale factor error             ppm                                     fraction
misalignment                   mrad                                    rad
magnetic field                 uT                                      T
speed                          ft/s                                    m/s
=============================  ======================================  ===========================

One "g" here is the conventional standard gravity 9.80665 m/s^2 (:data:`quatnav.core.earth.STANDARD_GRAVITY`),
not local gravity.

White noise given as a density ``N`` (per sqrt(Hz)) becomes a per-sample standard deviation
``N * sqrt(rate_hz)`` for a sensor that outputs the mean over each sample interval
(:func:`density_to_sample_sigma`); a per-sample standard deviation ``sigma`` at rate ``fs``
corresponds to the density ``sigma / sqrt(fs)`` (:func:`sample_sigma_to_density`).
"""

from __future__ import annotations

import math

from ..core.earth import STANDARD_GRAVITY

DEG = math.pi / 180.0  #: rad per degree
HOUR = 3600.0  #: s per hour
SQRT_HOUR = 60.0  #: sqrt(s) per sqrt(h)
UG = 1e-6 * STANDARD_GRAVITY  #: m/s^2 per micro-g
MG = 1e-3 * STANDARD_GRAVITY  #: m/s^2 per milli-g
G = STANDARD_GRAVITY  #: m/s^2 per g
FT = 0.3048  #: m per foot
UT = 1e-6  #: T per microtesla


def deg_per_h(x):
    """deg/h -> rad/s."""
    return x * DEG / HOUR


def to_deg_per_h(x):
    """rad/s -> deg/h."""
    return x / DEG * HOUR


def arw_deg_per_sqrt_h(x):
    """Angle random walk deg/sqrt(h) -> rad/s/sqrt(Hz) (= rad/sqrt(s))."""
    return x * DEG / SQRT_HOUR


def to_arw_deg_per_sqrt_h(x):
    """rad/s/sqrt(Hz) -> deg/sqrt(h)."""
    return x / DEG * SQRT_HOUR


def rrw_deg_per_h_per_sqrt_h(x):
    """Rate random walk deg/h/sqrt(h) -> rad/s^2/sqrt(Hz)."""
    return x * DEG / HOUR / SQRT_HOUR


def deg_per_s(x):
    """deg/s -> rad/s."""
    return x * DEG


def dps_per_sqrt_hz(x):
    """Gyro noise density deg/s/sqrt(Hz) -> rad/s/sqrt(Hz)."""
    return x * DEG


def ug(x):
    """micro-g -> m/s^2."""
    return x * UG


def to_ug(x):
    """m/s^2 -> micro-g."""
    return x / UG


def mg(x):
    """milli-g -> m/s^2."""
    return x * MG


def g_units(x):
    """g -> m/s^2."""
    return x * G


def vrw_m_per_s_per_sqrt_h(x):
    """Velocity random walk m/s/sqrt(h) -> m/s^2/sqrt(Hz)."""
    return x / SQRT_HOUR


def to_vrw_m_per_s_per_sqrt_h(x):
    """m/s^2/sqrt(Hz) -> m/s/sqrt(h)."""
    return x * SQRT_HOUR


def ug_per_sqrt_hz(x):
    """Accelerometer noise density ug/sqrt(Hz) -> m/s^2/sqrt(Hz)."""
    return x * UG


def ug_per_sqrt_h(x):
    """Accelerometer bias random walk ug/sqrt(h) -> m/s^3/sqrt(Hz) (= m/s^2/sqrt(s))."""
    return x * UG / SQRT_HOUR


def ppm(x):
    """ppm -> fraction."""
    return x * 1e-6


def mrad(x):
    """mrad -> rad."""
    return x * 1e-3


def microtesla(x):
    """uT -> T."""
    return x * UT


def ft_per_s(x):
    """ft/s -> m/s."""
    return x * FT


def density_to_sample_sigma(density, rate_hz):
    """White-noise density (unit/sqrt(Hz)) -> standard deviation of each interval-mean sample."""
    return density * math.sqrt(rate_hz)


def sample_sigma_to_density(sigma, rate_hz):
    """Per-sample standard deviation at ``rate_hz`` -> white-noise density (unit/sqrt(Hz))."""
    return sigma / math.sqrt(rate_hz)
