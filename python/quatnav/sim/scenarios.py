"""Named simulation scenarios: truth, sensor outputs and the parameters used.

``make_scenario(name, seed)`` builds one; ``list_scenarios()`` names them all (also
``quatnav simulate --list``). Random draws come from ``numpy.random.default_rng(seed)``,
split with ``Generator.spawn`` into one stream per sensor in a fixed order (IMU, GPS,
magnetometer, altimeter, compass, odometer), so a scenario is reproducible from its seed.

Choices that the papers leave open are stated in each scenario's docstring and in its
``params["choices"]``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Callable, Dict, Optional

import numpy as np

from . import units
from .sensors import (AccelSpec, BaroSpec, BaroData, CompassData, CompassSpec, GpsData, GpsSpec,
                      GyroSpec, ImuData, ImuSpec, MagData, MagDisturbance, MagSpec, OdometerData,
                      OdometerSpec, mounting_quaternion, simulate_baro, simulate_compass,
                      simulate_gps, simulate_imu, simulate_mag, simulate_odometer)
from .trajectory import (Accelerate, Climb, Cruise, RandomMotion, Rest, Rotate, Trajectory, Turn,
                         WaypointPath, make_trajectory)

__all__ = ["Scenario", "make_scenario", "list_scenarios", "scenario_description",
           "PAPER002_NOISE_RATE_HZ"]

#: Paper 002 gives white-noise *variances* of the accelerometer (30 ug)^2 and the gyro
#: (0.3 deg/h)^2 without a rate. They are taken as the variance of each IMU sample at this rate
#: (the scenario's IMU rate); the noise density is sigma / sqrt(rate).
PAPER002_NOISE_RATE_HZ = 100.0

_LAT0 = np.radians(36.37)  # Daejeon, Korea
_LON0 = np.radians(127.36)
_H0 = 50.0


@dataclass
class Scenario:
    """A simulated run.

    Attributes
    ----------
    name, description : str
    seed : int
    truth : Trajectory
        Truth at every trajectory sample.
    imu : ImuData
    gps, mag, baro, compass, odometer : optional sensor outputs
    params : dict
        JSON-serializable: the sensor specifications (datasheet units), trajectory settings and
        the scenario's stated choices; paper scenarios also hold ``initial_errors``.
    """

    name: str
    seed: int
    description: str
    truth: Trajectory
    imu: ImuData
    gps: Optional[GpsData] = None
    mag: Optional[MagData] = None
    baro: Optional[BaroData] = None
    compass: Optional[CompassData] = None
    odometer: Optional[OdometerData] = None
    params: dict = field(default_factory=dict)

    SENSORS = ("imu", "gps", "mag", "baro", "compass", "odometer")


def _spec_dict(spec):
    d = dataclasses.asdict(spec)
    d["type"] = type(spec).__name__
    return d


def _assemble(name, seed, description, traj, imu=None, gps=None, mag=None, baro=None,
              compass=None, extra=None, odometer=None) -> Scenario:
    rng = np.random.default_rng(seed)
    # spawn(6) gives the same first five streams as spawn(5) did: older scenarios are unchanged
    r_imu, r_gps, r_mag, r_baro, r_cmp, r_odo = rng.spawn(6)
    params = {"trajectory": {"rate_hz": traj.rate_hz, "earth_rate": traj.earth_rate,
                             "lat0": float(traj.lat[0]), "lon0": float(traj.lon[0]),
                             "h0": float(traj.h[0]), "duration_s": float(traj.t[-1])}}
    out = dict(imu=simulate_imu(traj, imu, r_imu))
    params["imu"] = _spec_dict(imu)
    for key, spec, fn, r in (("gps", gps, simulate_gps, r_gps), ("mag", mag, simulate_mag, r_mag),
                             ("baro", baro, simulate_baro, r_baro),
                             ("compass", compass, simulate_compass, r_cmp),
                             ("odometer", odometer, simulate_odometer, r_odo)):
        if spec is not None:
            out[key] = fn(traj, spec, r)
            params[key] = _spec_dict(spec)
    params.update(extra or {})
    return Scenario(name=name, seed=int(seed), description=description, truth=traj,
                    params=params, **out)


# ----------------------------------------------------------------------------------------------
# Scenarios
# ----------------------------------------------------------------------------------------------
def paper002_straight_then_circle(seed=0, speed=2.0, radius=20.0, rate_hz=100.0):
    """Paper 002, section IV: 200 s, straight at constant velocity, then a circle from 100 s.

    Sensor errors of the paper: accelerometer bias 1000 ug and white-noise variance (30 ug)^2,
    gyro bias 1 deg/h and white-noise variance (0.3 deg/h)^2 (per sample at
    :data:`PAPER002_NOISE_RATE_HZ`), NED velocity measurement variance (0.1 ft/s)^2 and yaw
    measurement variance (2 deg)^2. The paper gives neither the speed nor the radius: 2 m/s and
    20 m are chosen (a small robot; yaw rate 0.1 rad/s), the yaw rate ramps up over 1 s at 100 s.
    The velocity and yaw aids run at 10 Hz (GPS record: only its velocity is the paper's
    measurement). ``params["initial_errors"]`` holds the paper's initial filter errors.
    """
    if rate_hz != PAPER002_NOISE_RATE_HZ:
        raise ValueError(f"rate_hz must be {PAPER002_NOISE_RATE_HZ} (the rate at which the paper's "
                         "noise variances are taken)")
    traj = make_trajectory([Cruise(100.0), Turn(110.0, rate=speed / radius, ramp=1.0)], rate_hz,
                           lat0=_LAT0, lon0=_LON0, h0=_H0, rpy0=(0.0, 0.0, np.radians(30.0)),
                           speed0=speed, t_end=200.0)
    gyro_density = units.deg_per_h(0.3) / np.sqrt(PAPER002_NOISE_RATE_HZ)  # rad/s/sqrt(Hz)
    accel_density_ug = 30.0 / np.sqrt(PAPER002_NOISE_RATE_HZ)  # ug/sqrt(Hz)
    imu = ImuSpec(gyro=GyroSpec(bias_deg_per_h=1.0,
                                noise_density_dps_per_sqrt_hz=np.degrees(gyro_density)),
                  accel=AccelSpec(bias_ug=1000.0, noise_density_ug_per_sqrt_hz=accel_density_ug))
    gps = GpsSpec(rate_hz=10.0, pos_sigma_h_m=3.0, pos_sigma_v_m=5.0,
                  vel_sigma_m_s=units.ft_per_s(0.1))
    compass = CompassSpec(rate_hz=10.0, noise_deg=2.0)
    init = {"roll_deg": 10.0, "pitch_deg": 10.0, "yaw_deg": 20.0, "velocity_ft_s": 1.0,
            "accel_bias_ug": 2000.0, "gyro_bias_deg_h": 2.0,
            "si": {"roll": np.radians(10.0), "pitch": np.radians(10.0), "yaw": np.radians(20.0),
                   "velocity": units.ft_per_s(1.0), "accel_bias": units.ug(2000.0),
                   "gyro_bias": units.deg_per_h(2.0)}}
    choices = {"speed_m_s": speed, "radius_m": radius, "noise_rate_hz": PAPER002_NOISE_RATE_HZ,
               "aid_rate_hz": 10.0, "bias_sign": "+ on every axis"}
    return _assemble("paper002_straight_then_circle", seed,
                     "paper 002: 200 s straight then circle from 100 s; velocity + yaw aiding",
                     traj, imu=imu, gps=gps, compass=compass,
                     extra={"initial_errors": init, "choices": choices})


def _paper004_imu():
    """MEMS IMU of paper 004: ADXRS150-class gyros (+/-150 deg/s) and a Kionix +/-2 g
    accelerometer, 12-bit conversion, 50 Hz. Noise and bias values are typical datasheet
    figures for these parts (the paper does not list them)."""
    return ImuSpec(
        gyro=GyroSpec(bias_deg_per_h=(300.0, -200.0, 150.0), bias_instability_deg_per_h=30.0,
                      bias_corr_time_s=100.0, noise_density_dps_per_sqrt_hz=0.05,
                      scale_factor_ppm=(2000.0, -1500.0, 1000.0), misalignment_mrad=2.0,
                      range_deg_per_s=150.0, quantization_deg_per_s=300.0 / 4096),
        accel=AccelSpec(bias_ug=(5000.0, -8000.0, 10000.0), bias_instability_ug=500.0,
                        bias_corr_time_s=100.0, noise_density_ug_per_sqrt_hz=200.0,
                        scale_factor_ppm=(3000.0, -2000.0, 2500.0), misalignment_mrad=3.0,
                        range_g=2.0, quantization_mg=4000.0 / 4096),
        rate_hz=50.0)


def _paper004_aids(gps_rate_hz=5.0):
    return dict(gps=GpsSpec(rate_hz=gps_rate_hz, pos_sigma_h_m=2.5, pos_sigma_v_m=5.0,
                            vel_sigma_m_s=0.1, lever_arm_b_m=(0.1, 0.0, -0.1), latency_s=0.1),
                baro=BaroSpec(rate_hz=10.0, noise_m=0.5, drift_m_per_sqrt_h=2.0),
                compass=CompassSpec(rate_hz=10.0, noise_deg=2.0, bias_deg=1.0))


_P004_CHOICES = {"imu": "ADXRS150-class gyro, Kionix +/-2 g accelerometer, 12-bit, typical "
                        "datasheet noise and bias", "gps_rate_hz": 5.0, "gps_latency_s": 0.1}


def paper004_static(seed=0, duration=120.0, gps_rate_hz=5.0):
    """Paper 004, ground static test: the IMU at rest (slightly tilted) for ``duration`` s.

    ``gps_rate_hz`` (1, 2 or 5 Hz; the paper's GPS gives 1 to a few Hz) applies to all three
    paper 004 scenarios."""
    traj = make_trajectory([Rest(duration)], 50.0, lat0=_LAT0, lon0=_LON0, h0=_H0,
                           rpy0=np.radians([2.0, -1.0, 30.0]))
    return _assemble("paper004_static", seed, "paper 004: ground static test, 50 Hz MEMS IMU",
                     traj, imu=_paper004_imu(), **_paper004_aids(gps_rate_hz),
                     extra={"choices": dict(_P004_CHOICES, gps_rate_hz=gps_rate_hz)})


def paper004_turntable(seed=0, gps_rate_hz=5.0):
    """Paper 004, turntable test: rotations about the roll axis (+30, -60, +30 deg), then about
    the pitch axis, at up to about 15 deg/s, with rests in between."""
    a = np.radians(30.0)
    segs = [Rest(10.0)]
    for axis in ("roll", "pitch"):
        segs += [Rotate(axis, 4.0, angle=a, ramp=1.0), Rest(5.0),
                 Rotate(axis, 6.0, angle=-2 * a, ramp=1.0), Rest(5.0),
                 Rotate(axis, 4.0, angle=a, ramp=1.0), Rest(10.0)]
    traj = make_trajectory(segs, 50.0, lat0=_LAT0, lon0=_LON0, h0=_H0,
                           rpy0=(0.0, 0.0, np.radians(90.0)))
    return _assemble("paper004_turntable", seed,
                     "paper 004: turntable, rotation about roll then about pitch", traj,
                     imu=_paper004_imu(), **_paper004_aids(gps_rate_hz),
                     extra={"choices": dict(_P004_CHOICES, gps_rate_hz=gps_rate_hz)})


def paper004_walk(seed=0, speed=1.4, gps_rate_hz=5.0):
    """Paper 004, walking test: a quarter of a sports field at about 1.4 m/s.

    The path (chosen): 40 m north, a quarter circle of radius 20 m turning east, 30 m east;
    about 100 m, with 10 s rests at both ends.
    """
    arc = np.radians(np.arange(5.0, 90.1, 5.0))
    pts = [[40.0, 0.0]]
    pts += [[40.0 + 20.0 * np.sin(a), 20.0 - 20.0 * np.cos(a)] for a in arc]
    pts += [[60.0, 50.0]]
    pts = np.array(pts)
    run = 0.5 * speed * 4.0  # distance of the 4 s raised-cosine acceleration
    segs = [Rest(10.0), Accelerate(4.0, to_speed=speed),
            WaypointPath(np.column_stack([pts[:, 0] - run, pts[:, 1], np.zeros(len(pts))]), speed),
            Accelerate(4.0, to_speed=0.0), Rest(10.0)]
    traj = make_trajectory(segs, 50.0, lat0=_LAT0, lon0=_LON0, h0=_H0)
    ch = dict(_P004_CHOICES, path="40 m N, quarter circle r=20 m, 30 m E", speed_m_s=speed,
              gps_rate_hz=gps_rate_hz)
    return _assemble("paper004_walk", seed, "paper 004: walking a quarter of a sports field",
                     traj, imu=_paper004_imu(), **_paper004_aids(gps_rate_hz), extra={"choices": ch})


def paper001_constant_turn(seed=0, speed=10.0, rate_deg_s=12.0, lever_arm_b_m=(0.8, 0.3, -0.9)):
    """Paper 001: a vehicle in a steady turn with the IMU offset from the GPS antenna.

    Rest 10 s, accelerate to ``speed`` in 8 s, straight 10 s, then a level turn at
    ``rate_deg_s`` for 60 s (radius ~48 m, centripetal ~2.1 m/s^2), straight 10 s. Sensors
    after Table 1: +/-200 deg/s gyro, +/-4 g accelerometer, 10-bit conversion, magnetometer,
    RTK-DGPS at 20 Hz (1 cm). The antenna sits at ``lever_arm_b_m`` (body frame) from the IMU,
    so the GPS acceleration differs from the IMU's by the lever-arm terms of eq. (7).
    IMU and magnetometer at 100 Hz (chosen).
    """
    rate = np.radians(rate_deg_s)
    segs = [Rest(10.0), Accelerate(8.0, to_speed=speed), Cruise(10.0),
            Turn(60.0, rate=rate, ramp=2.0), Cruise(10.0)]
    traj = make_trajectory(segs, 100.0, lat0=_LAT0, lon0=_LON0, h0=_H0)
    imu = ImuSpec(gyro=GyroSpec(bias_deg_per_h=(200.0, -150.0, 100.0),
                                bias_instability_deg_per_h=20.0, noise_density_dps_per_sqrt_hz=0.03,
                                range_deg_per_s=200.0, quantization_deg_per_s=400.0 / 1024),
                  accel=AccelSpec(bias_ug=(3000.0, -2000.0, 4000.0), bias_instability_ug=300.0,
                                  noise_density_ug_per_sqrt_hz=150.0, range_g=4.0,
                                  quantization_mg=8000.0 / 1024))
    gps = GpsSpec(rate_hz=20.0, pos_sigma_h_m=0.01, pos_sigma_v_m=0.02, vel_sigma_m_s=0.02,
                  lever_arm_b_m=lever_arm_b_m)
    mag = MagSpec(noise_uT=0.5)
    ch = {"speed_m_s": speed, "turn_rate_deg_s": rate_deg_s, "lever_arm_b_m": list(lever_arm_b_m),
          "imu_rate_hz": 100.0}
    return _assemble("paper001_constant_turn", seed,
                     "paper 001: steady turn, IMU offset from the GPS antenna", traj, imu=imu,
                     gps=gps, mag=mag, extra={"choices": ch})


def handheld_marg(seed=0, rate_hz=200.0, duration=60.0, mag_disturbance=False,
                  linear_accel=False):
    """Smooth random hand-held rotations with a magnetometer (MARG), for attitude filters.

    Rest 5 s, then ``duration`` s of random rotation (roll/pitch/yaw amplitudes about
    30/25/60 deg, tones up to 0.3 Hz), rest 5 s. ``linear_accel`` adds 5 cm translations
    (accelerations up to about 1.5 m/s^2); ``mag_disturbance`` adds two magnet-near events.
    Consumer MEMS noise (typical datasheet values). No Earth rate (a consumer gyro cannot
    see it).
    """
    motion = RandomMotion(duration, amplitude=np.radians([30.0, 25.0, 60.0]).tolist(),
                          max_freq=0.3, translation=0.05 if linear_accel else 0.0,
                          ramp=2.0, seed=int(seed))
    traj = make_trajectory([Rest(5.0), motion, Rest(5.0)], rate_hz, lat0=_LAT0, lon0=_LON0,
                           h0=_H0, earth_rate=False)
    imu = ImuSpec(gyro=GyroSpec(bias_deg_per_h=(360.0, -540.0, 200.0), bias_instability_deg_per_h=10.0,
                                noise_density_dps_per_sqrt_hz=0.007, range_deg_per_s=2000.0),
                  accel=AccelSpec(bias_ug=(2000.0, -3000.0, 1500.0), bias_instability_ug=100.0,
                                  noise_density_ug_per_sqrt_hz=120.0, range_g=16.0))
    dist = ()
    if mag_disturbance:
        t_mid = 5.0 + duration
        dist = (MagDisturbance(0.3 * t_mid, 0.3 * t_mid + 5.0, (25.0, -15.0, 10.0)),
                MagDisturbance(0.7 * t_mid, 0.7 * t_mid + 3.0, (-10.0, 30.0, -20.0)))
    mag = MagSpec(hard_iron_uT=(5.0, -3.0, 2.0), noise_uT=0.4, disturbances=dist)
    name = "handheld_marg_disturbed" if (mag_disturbance and linear_accel) else "handheld_marg"
    ch = {"mag_disturbance": mag_disturbance, "linear_accel": linear_accel, "rate_hz": rate_hz}
    return _assemble(name, seed, "hand-held MARG: smooth random rotations", traj, imu=imu,
                     mag=mag, extra={"choices": ch})


def _handheld_disturbed(seed=0, **kw):
    kw.setdefault("mag_disturbance", True)
    kw.setdefault("linear_accel", True)
    return handheld_marg(seed, **kw)


# ----------------------------------------------------------------------------------------------
# Car
# ----------------------------------------------------------------------------------------------
#: ZYX Euler angles (deg) of the IMU of ``car_city`` relative to the body: turned 90 deg (its x
#: axis points to the car's right) and tilted by a few degrees, as an IMU screwed to a bracket.
CAR_MOUNTING_RPY_DEG = (2.0, -3.0, 90.0)
#: The upside-down variant: the IMU's z axis points up, its axes are forward-left-up.
CAR_UPSIDE_DOWN_RPY_DEG = (180.0, 0.0, 0.0)


def _car_segments():
    """(segments, labels): the city drive, about 204 s."""
    r = np.radians
    segs = [
        ("launch", Accelerate(3.5, delta_speed=9.0, from_peak=True)),   # 2 -> 11 m/s, 4.04 m/s^2 at t = 0
        ("cruise", Cruise(15.0)),
        ("turn right", Turn(7.0, angle=r(90.0), ramp=1.5)),
        ("cruise", Cruise(10.0)),
        ("brake", Accelerate(5.0, to_speed=0.0)),
        ("stop", Rest(8.0)),
        ("pull away", Accelerate(6.0, to_speed=13.0)),
        ("cruise", Cruise(5.0)),
        ("uphill", Climb(15.0, angle=r(4.0), ramp=4.0)),
        ("turn left", Turn(8.0, angle=r(-90.0), ramp=2.0)),
        ("cruise", Cruise(40.0)),
        ("turn right", Turn(6.0, angle=r(90.0), ramp=1.5)),
        ("cruise", Cruise(15.0)),
        ("brake", Accelerate(5.0, to_speed=0.0)),
        ("stop", Rest(10.0)),
        ("pull away", Accelerate(5.0, to_speed=9.0)),
        ("roundabout", Turn(10.0, angle=r(180.0), ramp=2.0)),
        ("cruise", Cruise(20.0)),
        ("brake", Accelerate(4.0, to_speed=0.0)),
        ("stop", Rest(6.0)),
    ]
    return [s for _, s in segs], [n for n, _ in segs]


def car_city(seed=0, rate_hz=200.0, mounting_rpy_deg=CAR_MOUNTING_RPY_DEG, latency_s=0.125,
             lever_arm_b_m=(-0.4, 0.2, -1.4), outage_s=30.0, imu_errors=True, gyro_scale_ppm=0.0,
             accel_scale_ppm=0.0, name="car_city"):
    """A car in town: a moving start, turns, a hill, three stops and a GNSS outage, with the IMU
    mounted rotated, a late-stamped GNSS and a lever arm; wheel odometer and magnetometer.

    * The log starts while the car accelerates: 2 m/s at t = 0 with 4.04 m/s^2 (easing to zero
      over 3.5 s, reaching 11 m/s): levelling from the accelerometer at t = 0 is 22 deg off.
    * Turns of 90 deg right and left at 11-13 m/s (lateral acceleration up to 3.5 m/s^2), a 4 deg
      climb, a half-circle roundabout at 9 m/s; stops of 8, 10 and 6 s standing still
      (``params["events"]["stops"]``, the car exactly at rest).
    * GNSS (10 Hz; 0.3 m horizontal, 0.6 m vertical, 0.05 m/s) of an antenna at
      ``lever_arm_b_m`` (body, m), with a ``latency_s`` latency and **time stamps on delivery**
      (late by the latency), and an outage of ``outage_s`` s during the long cruise and the
      right turn after it (``params["events"]["gnss_outages"]``).
    * IMU (200 Hz, automotive MEMS: 0.1 deg/s-class gyro bias, 0.005 deg/s/sqrt(Hz), mg-class
      accelerometer bias, 60 ug/sqrt(Hz)) mounted at ``mounting_rpy_deg`` (ZYX, deg) relative to
      the body: its samples are in the IMU frame. ``imu_errors=False`` gives an ideal IMU (no
      noise, bias or quantization) for round-trip tests. ``gyro_scale_ppm``, ``accel_scale_ppm``
      (a scalar or 3 values, IMU axes): scale-factor errors (the sensor reads (1 + s) x + b).
    * Magnetometer (50 Hz, in the IMU's package: the same mounting; 8/-5/3 uT hard iron of the
      car body) and a wheel odometer (20 Hz forward speed, 0.3 % scale error, 0.03 m/s noise,
      0.01 m/s steps).

    ``params["sensor_model"]`` states what a filter must be given: the mounting (``rpy_deg``,
    ``q_b_imu`` and ``C_b_imu``, body from IMU), the GNSS latency and how fixes are stamped, and
    the lever arm.
    """
    segs, labels = _car_segments()
    traj = make_trajectory(segs, rate_hz, lat0=_LAT0, lon0=_LON0, h0=_H0,
                           rpy0=(0.0, 0.0, np.radians(60.0)), speed0=2.0)
    if imu_errors:
        imu = ImuSpec(gyro=GyroSpec(bias_deg_per_h=(300.0, -250.0, 400.0), bias_instability_deg_per_h=10.0,
                                    noise_density_dps_per_sqrt_hz=0.005, range_deg_per_s=300.0,
                                    quantization_deg_per_s=0.004, scale_factor_ppm=gyro_scale_ppm),
                      accel=AccelSpec(bias_ug=(3000.0, -2000.0, 4000.0), bias_instability_ug=100.0,
                                      noise_density_ug_per_sqrt_hz=60.0, range_g=8.0, quantization_mg=0.25,
                                      scale_factor_ppm=accel_scale_ppm),
                      mounting_rpy_deg=tuple(float(x) for x in mounting_rpy_deg))
    else:
        imu = ImuSpec(mounting_rpy_deg=tuple(float(x) for x in mounting_rpy_deg))
    # segment start times (durations are whole samples at rate_hz)
    starts = np.concatenate([[0.0], np.cumsum([sg.duration for sg in segs])])
    stops = [[float(starts[i]), float(starts[i + 1])] for i, n in enumerate(labels) if n == "stop"]
    i_long = labels.index("cruise", labels.index("turn left"))
    t_out = float(starts[i_long] + 20.0)
    outages = ((t_out, t_out + float(outage_s)),) if outage_s > 0 else ()
    gps = GpsSpec(rate_hz=10.0, pos_sigma_h_m=0.3, pos_sigma_v_m=0.6, vel_sigma_m_s=0.05,
                  lever_arm_b_m=tuple(float(x) for x in lever_arm_b_m), latency_s=float(latency_s),
                  outages=outages, time_stamp="delivery")
    mag = MagSpec(hard_iron_uT=(8.0, -5.0, 3.0), noise_uT=0.3, rate_hz=50.0,
                  mounting_rpy_deg=tuple(float(x) for x in mounting_rpy_deg))
    odo = OdometerSpec(rate_hz=20.0, noise_m_s=0.03, scale_factor_ppm=3000.0, quantization_m_s=0.01)
    q = mounting_quaternion(mounting_rpy_deg)
    from ..core import quaternion as quat
    sensor_model = {"imu_mounting_rpy_deg": [float(x) for x in mounting_rpy_deg], "q_b_imu": q.tolist(),
                    "C_b_imu": quat.to_rotmat(q).tolist(), "mag_in_imu_frame": True,
                    "gnss_latency_s": float(latency_s), "gnss_time_stamp": "delivery",
                    "lever_arm_b_m": [float(x) for x in lever_arm_b_m]}
    a0 = float(traj.a_n[0] @ traj.v_n[0] / np.linalg.norm(traj.v_n[0]))
    events = {"stops": stops, "gnss_outages": [list(o) for o in outages],
              "moving_start": {"speed_m_s": 2.0, "accel_m_s2": a0},
              "segments": [[n, float(starts[i]), float(starts[i + 1])] for i, n in enumerate(labels)]}
    choices = {"imu": "automotive MEMS, typical datasheet values", "imu_errors": bool(imu_errors),
               "gyro_scale_ppm": gyro_scale_ppm, "accel_scale_ppm": accel_scale_ppm,
               "rate_hz": rate_hz, "gnss": "10 Hz, 0.3 m / 0.6 m, stamped on delivery"}
    return _assemble(name, seed, "car in town: moving start, stops, turns, GNSS outage; IMU mounted "
                     "rotated, late GNSS stamps, lever arm", traj, imu=imu, gps=gps, mag=mag, odometer=odo,
                     extra={"sensor_model": sensor_model, "events": events, "choices": choices})


def _car_upside_down(seed=0, **kw):
    kw.setdefault("mounting_rpy_deg", CAR_UPSIDE_DOWN_RPY_DEG)
    kw.setdefault("name", "car_city_upside_down")
    return car_city(seed, **kw)


_REGISTRY: Dict[str, Callable[..., Scenario]] = {
    "paper002_straight_then_circle": paper002_straight_then_circle,
    "paper004_static": paper004_static,
    "paper004_turntable": paper004_turntable,
    "paper004_walk": paper004_walk,
    "paper001_constant_turn": paper001_constant_turn,
    "handheld_marg": handheld_marg,
    "handheld_marg_disturbed": _handheld_disturbed,
    "car_city": car_city,
    "car_city_upside_down": _car_upside_down,
}

_DESCRIPTIONS = {
    "paper002_straight_then_circle": "200 s straight then circle from 100 s; IMU 100 Hz, velocity + yaw (paper 002)",
    "paper004_static": "ground static test; 50 Hz MEMS IMU, GPS 5 Hz, altimeter, compass (paper 004)",
    "paper004_turntable": "turntable: rotation about roll, then about pitch (paper 004)",
    "paper004_walk": "walking a quarter of a sports field at 1.4 m/s (paper 004)",
    "paper001_constant_turn": "steady turn, IMU offset from the GPS antenna by a lever arm (paper 001)",
    "handheld_marg": "smooth random hand-held rotations, 200 Hz IMU + magnetometer",
    "handheld_marg_disturbed": "handheld_marg with magnet-near events and linear accelerations",
    "car_city": "car in town: moving start, stops, turns, 30 s GNSS outage; IMU mounted rotated, GNSS 0.125 s late",
    "car_city_upside_down": "car_city with the IMU mounted upside down (axes forward-left-up)",
}


def _register_fast_motion():
    from .fast_scenarios import FAST_SCENARIOS
    for name, (fn, text) in FAST_SCENARIOS.items():
        _REGISTRY[name] = fn
        _DESCRIPTIONS[name] = text


_register_fast_motion()


def list_scenarios():
    """Names of the registered scenarios, sorted."""
    return sorted(_REGISTRY)


def scenario_description(name):
    """One-line description of a scenario."""
    _check_name(name)
    return _DESCRIPTIONS[name]


def _check_name(name):
    if name not in _REGISTRY:
        raise ValueError(f"unknown scenario name {name!r}; known: {', '.join(list_scenarios())}")


def make_scenario(name, seed=0, **options) -> Scenario:
    """Build a named scenario.

    Parameters
    ----------
    name : str
        One of :func:`list_scenarios`.
    seed : int
        Seed of every random draw.
    **options
        Passed to the scenario function (see its docstring).
    """
    _check_name(name)
    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise ValueError(f"seed must be a non-negative integer, got {seed!r}")
    return _REGISTRY[name](seed=int(seed), **options)
