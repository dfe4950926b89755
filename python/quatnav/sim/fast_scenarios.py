"""Fast-motion scenarios for attitude filters: what real fast motion brings.

Every scenario starts with 5 s at rest (the part a filter may use to settle, left out of the
score: ``params["scoring"]["from_s"]``), then moves, then rests 5 s. The sensor is a consumer
MEMS IMU at 200 Hz (:func:`consumer_imu`: gyro bias ~0.5 deg/s, accelerometer bias ~30 mg,
datasheet-typical noise, 2000 deg/s and 16 g ranges) with a magnetometer; the trajectory is
computed at 1 kHz and the IMU reports the mean over each 5 ms (as a real IMU's internal filter).

================================  ================================================================
scenario                          what it tests
================================  ================================================================
``fast_pendulum``                 a pendulum swing: centripetal acceleration along the string
``fast_limb_walk``                a forearm swinging while walking: 300 deg/s, 1-2 g centripetal
``fast_limb_run``                 the same while running: 500 deg/s, 3-4 g
``fast_running``                  torso while running: impacts of 3 g, sway, a weaving course
``fast_shaking``                  a hand shaking the sensor at 2-7 Hz: 1-2 g linear acceleration
``fast_gyro_saturation``          flips at up to 650 deg/s with a 500 deg/s gyro: clipped rates
``fast_scale_misalignment``       fast rotations with 2 % scale factors and 20 mrad misalignment
``fast_vibration``                slow hand-held motion with 8 m/s^2 vibration at 47-59 Hz
================================  ================================================================

:data:`FAST_MOTION` lists ``(name, seed)`` of the benchmark's simulated set
(``quatnav eval sim``).
"""
from __future__ import annotations

import numpy as np

from .motion import LimbSwing, Pendulum, Running, Shaking, Vibration
from .sensors import AccelSpec, GyroSpec, ImuSpec, MagSpec
from .trajectory import RandomMotion, Rest, Rotate, make_trajectory

__all__ = ["FAST_MOTION", "consumer_imu", "FAST_SCENARIOS"]

_TRAJ_RATE = 1000.0
_IMU_RATE = 200.0
_LAT0, _LON0, _H0 = np.radians(52.5), np.radians(13.4), 40.0
_REST = 5.0


def consumer_imu(gyro_range_dps=2000.0, scale_ppm=0.0, misalignment_mrad=0.0, seed_axes=0) -> ImuSpec:
    """A consumer MEMS IMU (typical datasheet values of a smartphone / wearable part) at 200 Hz."""
    rng = np.random.default_rng(1000 + seed_axes)
    gb = rng.choice([-1.0, 1.0], 3) * np.array([0.45, 0.6, 0.35]) * 3600.0  # deg/h
    ab = rng.choice([-1.0, 1.0], 3) * np.array([25e3, 30e3, 40e3])  # ug
    return ImuSpec(gyro=GyroSpec(bias_deg_per_h=tuple(gb), bias_instability_deg_per_h=20.0,
                                 noise_density_dps_per_sqrt_hz=0.008, range_deg_per_s=gyro_range_dps,
                                 scale_factor_ppm=scale_ppm, misalignment_mrad=misalignment_mrad,
                                 quantization_deg_per_s=0.061),
                   accel=AccelSpec(bias_ug=tuple(ab), bias_instability_ug=200.0, noise_density_ug_per_sqrt_hz=150.0,
                                   range_g=16.0, scale_factor_ppm=0.5 * np.asarray(scale_ppm, float),
                                   misalignment_mrad=misalignment_mrad, quantization_mg=0.5),
                   rate_hz=_IMU_RATE)


def _mag():
    return MagSpec(intensity_uT=49.0, inclination_deg=67.0, declination_deg=4.0, hard_iron_uT=(0.8, -0.5, 0.6),
                   noise_uT=0.4, rate_hz=100.0)


def _build(name, seed, description, motion, groups, imu=None, rpy0=(0.1, -0.05, 0.7)):
    from .scenarios import _assemble
    traj = make_trajectory([Rest(_REST), *motion, Rest(_REST)], _TRAJ_RATE, lat0=_LAT0, lon0=_LON0, h0=_H0,
                           rpy0=rpy0, earth_rate=False)
    return _assemble(name, seed, description, traj, imu=imu or consumer_imu(seed_axes=seed), mag=_mag(),
                     extra={"scoring": {"from_s": _REST}, "groups": list(groups),
                            "choices": {"trajectory_rate_hz": _TRAJ_RATE, "imu_rate_hz": _IMU_RATE}})


def fast_pendulum(seed=0, duration=60.0):
    """A sensor 0.8 m below a pivot swinging +-57 deg (elliptic, with a twist about the string)."""
    rng = np.random.default_rng(seed)
    m = Pendulum(duration, length=0.8, amplitude=1.0, cone=0.3 + 0.2 * rng.random(), twist=0.3,
                 axis_yaw=float(rng.uniform(-np.pi, np.pi)))
    return _build("fast_pendulum", seed, "pendulum: 0.8 m, +-57 deg swing", [m], ["swinging", "centripetal"])


def fast_limb_walk(seed=0, duration=60.0):
    """A forearm swinging at 0.9 Hz while walking at 1.4 m/s."""
    rng = np.random.default_rng(seed)
    m = LimbSwing(duration, freq=0.9, speed=1.4, heading=float(rng.uniform(-np.pi, np.pi)))
    return _build("fast_limb_walk", seed, "forearm swinging while walking", [m], ["swinging", "centripetal"])


def fast_limb_run(seed=0, duration=60.0):
    """A forearm swinging at 1.3 Hz while running at 3.5 m/s (larger swing, more bend)."""
    rng = np.random.default_rng(seed)
    m = LimbSwing(duration, freq=1.3, shoulder=0.7, elbow=0.4, bend=1.2, twist=0.7, speed=3.5, bounce=0.07,
                  heading=float(rng.uniform(-np.pi, np.pi)))
    return _build("fast_limb_run", seed, "forearm swinging while running", [m], ["swinging", "centripetal"])


def fast_running(seed=0, duration=90.0):
    """A torso-mounted sensor running at 3 m/s with foot-strike impacts and a weaving course."""
    m = Running(duration, speed=3.0, cadence=2.8, impact=20.0, weave=1.2, weave_period=30.0)
    return _build("fast_running", seed, "torso while running: impacts, sway, weaving", [m], ["impacts", "centripetal"])


def fast_shaking(seed=0, duration=40.0):
    """Slow hand-held rotations with fast shaking on top (2-7 Hz, 1.5 cm)."""
    m = Shaking(duration, rotation=(0.05, 0.05, 0.06), translation=0.006, seed=seed)
    return _build("fast_shaking", seed, "hand-held shaking at 2-7 Hz", [m], ["shaking"])


def fast_gyro_saturation(seed=0):
    """Flips about each axis at up to 650 deg/s, read by a gyro with a 500 deg/s range: the rates
    are clipped (``imu.saturated`` marks the samples), between slow hand-held motion."""
    segs = []
    for i, axis in enumerate(("roll", "pitch", "yaw", [1.0, 1.0, 0.0])):
        segs += [RandomMotion(8.0, amplitude=np.radians([15.0, 15.0, 30.0]).tolist(), max_freq=0.3, seed=seed + i),
                 Rotate(axis, 1.0, angle=2 * np.pi * (1 if i % 2 == 0 else -1), ramp=0.45), Rest(2.0)]
    return _build("fast_gyro_saturation", seed, "flips at 650 deg/s, gyro range 500 deg/s", segs, ["sensor errors"],
                  imu=consumer_imu(gyro_range_dps=500.0, seed_axes=seed))


def fast_scale_misalignment(seed=0, duration=60.0):
    """Large fast rotations (tones up to 0.8 Hz) seen by an IMU with 2 % scale factors and 20 mrad
    axis misalignment (gyro and accelerometer; the accelerometer half the scale error)."""
    m = RandomMotion(duration, amplitude=np.radians([40.0, 30.0, 80.0]).tolist(), max_freq=0.8, seed=seed)
    imu = consumer_imu(scale_ppm=(20000.0, -15000.0, 18000.0), misalignment_mrad=20.0, seed_axes=seed)
    return _build("fast_scale_misalignment", seed, "fast rotations, 2 % scale factors, 20 mrad misalignment", [m],
                  ["sensor errors"], imu=imu)


def fast_vibration(seed=0, duration=60.0):
    """Slow hand-held motion on a vibrating mount (8 m/s^2 at 47-59 Hz, 0.1 deg angular)."""
    m = Vibration(RandomMotion(duration, amplitude=np.radians([20.0, 15.0, 60.0]).tolist(), max_freq=0.2, seed=seed),
                  accel=8.0, angular=0.002)
    return _build("fast_vibration", seed, "slow motion with 8 m/s^2 vibration at 47-59 Hz", [m], ["vibration"])


#: name -> (function, one-line description)
FAST_SCENARIOS = {
    "fast_pendulum": (fast_pendulum, "pendulum swing, 0.8 m, +-57 deg: centripetal acceleration along the string"),
    "fast_limb_walk": (fast_limb_walk, "forearm swinging while walking: 300 deg/s, 1-2 g centripetal"),
    "fast_limb_run": (fast_limb_run, "forearm swinging while running: 500 deg/s, 3-4 g centripetal"),
    "fast_running": (fast_running, "torso while running: 3 g impacts, trunk sway, weaving course"),
    "fast_shaking": (fast_shaking, "hand-held shaking at 2-7 Hz: 1-2 g linear accelerations"),
    "fast_gyro_saturation": (fast_gyro_saturation, "flips at 650 deg/s with a 500 deg/s gyro: clipped rates"),
    "fast_scale_misalignment": (fast_scale_misalignment, "fast rotations, 2 % gyro scale factors, 20 mrad misalignment"),
    "fast_vibration": (fast_vibration, "slow hand-held motion with 8 m/s^2 vibration at 47-59 Hz"),
}

#: The simulated set of the attitude benchmark (``quatnav eval sim``): (scenario, seed).
FAST_MOTION = tuple((name, 0) for name in FAST_SCENARIOS)
