"""A car as a GNSS/INS filter meets it on the road: ``car_rtk``, a 486 s drive through town, an
arterial road and a highway with a roof MEMS IMU at 100 Hz and an RTK receiver at 4 Hz.

What a real car brings and a smooth simulated trajectory does not, each a separate piece here
(each stated in ``params["choices"]`` and ``params["car"]``):

* **Car kinematics** (:class:`CarTurn`): the body rolls outward in a turn (``roll_per_accel``
  rad per m/s^2 of lateral acceleration) and the IMU, ``imu_ahead_m`` ahead of the rear axle,
  moves sideways at ``imu_ahead_m`` times the yaw rate (the rear axle does not slide): the
  non-holonomic constraint holds at the axle, not at the IMU.
* **Vibration** (:func:`vibration`): the road through the suspension (a 12 Hz wheel-hop mode,
  amplitude growing with speed) and the engine (a tone at twice the crankshaft rate, 25 Hz at
  idle to 80 Hz), on the accelerometer and the gyro, generated at 1 kHz and added to each IMU
  sample as the value at its time: an IMU whose output filter does not remove them aliases
  them into its band, where they act as noise far above the datasheet's while driving. (The
  slow body motion on the springs is real motion of the IMU, which it measures as such: not an
  error, not simulated.)
* **Mounting** the filter is not told: the IMU is tilted and turned by about a degree relative to
  the car body (``mount_error_deg``, drawn per seed).
* **Timing**: the IMU stamps its samples late by a constant ``imu_delay_s`` (its digital filter's
  group delay and the logger's latency, drawn per seed) plus a white jitter; a few samples are
  lost. The GNSS fixes carry their GPS time of validity. A filter that takes both stamps as
  one clock sees the fixes early by ``imu_delay_s``.
* **RTK** (:func:`simulate_rtk`): fixed, float and single solutions in stretches (a Markov chain
  at the fix rate: float under trees and bridges, single where the corrections drop), each with
  its own error process (fixed: cm white noise; float: a decimetre-level Gauss-Markov wander;
  single: a metre-level one) and the optimistic one-sigma a receiver reports for it; multipath
  jumps of about a metre lasting seconds in float and single stretches; Doppler velocities.
  ``quality`` holds RTKLIB's Q (1 fixed, 2 float, 5 single).

Outages are not cut into the data: ``params["events"]["outages_30"]`` and ``["outages_60"]``
name windows (on the GNSS clock) where a filter run drops the fixes (``run(..., outages=...)``),
so one simulated drive serves every outage placement.
"""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from ..core import earth
from ..core import quaternion as quat
from .sensors import AccelSpec, GpsData, GyroSpec, ImuSpec, mounting_quaternion, simulate_imu
from .trajectory import Accelerate, Climb, Cruise, Rest, Turn, make_trajectory

__all__ = ["CarTurn", "VibrationSpec", "vibration", "RtkSpec", "simulate_rtk", "car_rtk", "car_rtk_segments"]


@dataclass(frozen=True)
class CarTurn(Turn):
    """A car's turn at a constant yaw rate (``rate`` or ``angle``, ramps as :class:`Turn`): the body
    rolls outward by ``roll_per_accel`` rad per m/s^2 of lateral acceleration (speed times yaw
    rate), and the point the trajectory follows (the IMU), ``imu_ahead_m`` ahead of the rear axle,
    moves sideways at ``imu_ahead_m`` times the yaw rate."""

    roll_per_accel: float = 0.006
    imu_ahead_m: float = 1.2

    def _profile(self, tau, s0):
        d = np.zeros((tau.shape[0], 3))
        d[:, 2], r = self._yaw(tau)
        d[:, 0] = -self.roll_per_accel * s0.speed * r
        course = s0.course + d[:, 2]
        right = np.column_stack([-np.sin(course), np.cos(course), np.zeros_like(course)])
        return d, np.full(tau.shape[0], s0.speed), (self.imu_ahead_m * r)[:, None] * right


def car_rtk_segments(imu_ahead_m=1.2, roll_per_accel=0.006):
    """(segments, labels) of the ``car_rtk`` drive: 486 s from a standstill."""
    r = np.radians

    def turn(duration, angle, ramp):
        return CarTurn(duration, angle=r(angle), ramp=ramp, roll_per_accel=roll_per_accel, imu_ahead_m=imu_ahead_m)
    segs = [
        ("standstill", Rest(20.0)),
        ("pull away", Accelerate(6.0, to_speed=10.0)),
        ("cruise", Cruise(10.0)),
        ("turn right", turn(7.0, 90.0, 1.5)),
        ("accelerate", Accelerate(5.0, to_speed=14.0)),
        ("cruise", Cruise(12.0)),
        ("brake", Accelerate(6.0, to_speed=0.0)),
        ("traffic light", Rest(12.0)),
        ("pull away", Accelerate(6.0, to_speed=12.0)),
        ("turn left", turn(8.0, -90.0, 2.0)),
        ("accelerate", Accelerate(6.0, to_speed=17.0)),
        ("arterial", Cruise(15.0)),
        ("curve right", turn(12.0, 35.0, 3.0)),
        ("arterial", Cruise(10.0)),
        ("uphill", Climb(14.0, angle=r(3.0), ramp=3.0)),
        ("curve left", turn(10.0, -25.0, 3.0)),
        ("slow down", Accelerate(5.0, to_speed=11.0)),
        ("on-ramp loop", turn(22.0, 270.0, 3.0)),
        ("merge", Accelerate(12.0, to_speed=25.0)),
        ("highway", Cruise(25.0)),
        ("highway curve", turn(20.0, -30.0, 4.0)),
        ("highway", Cruise(15.0)),
        ("lane change", turn(4.0, 4.0, 1.5)),
        ("lane change", turn(4.0, -4.0, 1.5)),
        ("highway", Cruise(20.0)),
        ("highway curve", turn(18.0, 40.0, 4.0)),
        ("highway", Cruise(20.0)),
        ("exit", Accelerate(10.0, to_speed=14.0)),
        ("exit ramp", turn(12.0, 120.0, 3.0)),
        ("brake", Accelerate(5.0, to_speed=0.0)),
        ("traffic light", Rest(15.0)),
        ("pull away", Accelerate(7.0, to_speed=13.0)),
        ("cruise", Cruise(15.0)),
        ("roundabout", turn(12.0, 200.0, 2.5)),
        ("accelerate", Accelerate(5.0, to_speed=16.0)),
        ("curve right", turn(10.0, 60.0, 2.5)),
        ("cruise", Cruise(25.0)),
        ("turn left", turn(8.0, -90.0, 2.0)),
        ("cruise", Cruise(20.0)),
        ("brake", Accelerate(6.0, to_speed=0.0)),
        ("parked", Rest(12.0)),
    ]
    return [s for _, s in segs], [n for n, _ in segs]


# ----------------------------------------------------------------------------------------------
# Vibration
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class VibrationSpec:
    """A car's vibration at the IMU, body axes (forward, right, down).

    Road: white noise through the 12 Hz wheel-hop mode (damping 0.2), with the RMS
    ``road_acc_m_s2`` (x, y, z) and ``road_gyro_deg_s`` (roll, pitch, yaw rate) at
    ``ref_speed_m_s``, proportional to the speed. Engine: a tone at twice the crankshaft rate,
    ``engine_hz`` at idle rising by ``engine_hz_per_m_s`` with speed up to ``engine_hz_max``,
    with the amplitudes ``engine_acc_m_s2`` and ``engine_gyro_deg_s`` (per axis, random phases),
    whenever the engine runs. Generated at ``rate_hz``.
    """

    road_acc_m_s2: tuple = (0.2, 0.25, 0.5)
    road_gyro_deg_s: tuple = (0.5, 0.4, 0.2)
    ref_speed_m_s: float = 20.0
    engine_hz: float = 25.0
    engine_hz_per_m_s: float = 2.0
    engine_hz_max: float = 80.0
    engine_acc_m_s2: float = 0.15
    engine_gyro_deg_s: float = 0.1
    rate_hz: float = 1000.0


def _resonator(x, f0, zeta, fs):
    """x through a second-order band-pass at f0 (Hz, damping zeta; bilinear, unit peak gain)."""
    from scipy.signal import bilinear, lfilter
    w0 = 2 * np.pi * f0
    b, a = bilinear([2 * zeta * w0, 0.0], [1.0, 2 * zeta * w0, w0 * w0], fs)
    return lfilter(b, a, x, axis=0)


def vibration(t_end, speed_of_t, spec: VibrationSpec, rng):
    """Vibration of the car at ``spec.rate_hz`` from 0 to ``t_end`` s: ``(t, acc (n, 3) m/s^2,
    gyro (n, 3) rad/s)``, zero mean, for the speed profile ``speed_of_t(t)`` (m/s)."""
    fs = spec.rate_hz
    t = np.arange(0.0, t_end + 2.0 / fs, 1.0 / fs)
    n = len(t)
    speed = np.abs(speed_of_t(t))
    scale = (speed / spec.ref_speed_m_s)[:, None]

    def road(rms):
        x = _resonator(rng.standard_normal((n, 3)), 12.0, 0.2, fs)
        x /= np.std(x[n // 10:], axis=0)
        return x * np.asarray(rms, float) * scale

    acc = road(spec.road_acc_m_s2)
    gyro = road(np.radians(spec.road_gyro_deg_s))
    f_e = np.minimum(spec.engine_hz + spec.engine_hz_per_m_s * speed, spec.engine_hz_max)
    phase = 2 * np.pi * np.cumsum(f_e) / fs
    for out, amp in ((acc, spec.engine_acc_m_s2), (gyro, np.radians(spec.engine_gyro_deg_s))):
        out += amp * np.sin(phase[:, None] + rng.uniform(0, 2 * np.pi, 3))
    return t, acc, gyro


# ----------------------------------------------------------------------------------------------
# RTK receiver
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RtkSpec:
    """An RTK receiver at ``rate_hz`` (the antenna at ``lever_arm_b_m``, body axes).

    Solution kinds by RTKLIB's Q: 1 fixed, 2 float, 5 single. Stretches of float and single
    start at the rates ``float_per_min`` and ``single_per_min`` while fixed and last an
    exponential time with the means ``float_mean_s`` and ``single_mean_s``. Errors, horizontal
    per axis and vertical (m): fixed white ``fixed_sigma``; float a Gauss-Markov wander
    ``float_sigma`` (time constant ``wander_tau_s``) plus 3 cm white; single likewise
    ``single_sigma``. The reported one-sigma is ``reported_ratio`` times the true one (receivers
    are optimistic). Multipath: in float and single stretches a jump of ``jump_sigma_m`` per
    axis starts at the rate ``jumps_per_min`` and lasts an exponential time of mean
    ``jump_mean_s``. Velocity: white ``vel_sigma_m_s`` (three times it in single), no sigma
    reported.
    """

    rate_hz: float = 4.0
    lever_arm_b_m: tuple = (0.3, 0.0, -0.4)
    float_per_min: float = 0.8
    float_mean_s: float = 12.0
    single_per_min: float = 0.15
    single_mean_s: float = 8.0
    fixed_sigma: tuple = (0.012, 0.025)
    float_sigma: tuple = (0.25, 0.4)
    single_sigma: tuple = (1.2, 2.5)
    wander_tau_s: float = 20.0
    reported_ratio: float = 0.5
    jumps_per_min: float = 2.0
    jump_sigma_m: float = 1.0
    jump_mean_s: float = 4.0
    vel_sigma_m_s: float = 0.03


@dataclass
class RtkData(GpsData):
    """GpsData with the receiver's view: ``quality`` (K,) RTKLIB's Q, ``sigma`` (K, 3) the reported
    position one-sigma NED (m), ``error_n`` (K, 3) the true position error NED (m)."""

    quality: np.ndarray = None
    sigma: np.ndarray = None
    error_n: np.ndarray = None


def _gauss_markov(n, sigma, tau, dt, rng):
    from .sensors import gauss_markov
    return gauss_markov(n, 1.0, tau, dt, rng) * np.asarray(sigma, float)


def simulate_rtk(traj, spec: RtkSpec, rng) -> RtkData:
    """Fixes of the antenna at the rate of ``spec``, with the solution kinds and errors it
    describes; times are the times of validity (``t == t_valid``)."""
    m = int(round(traj.rate_hz / spec.rate_hz))
    iv = np.arange(0, len(traj), m)
    n = len(iv)
    dt = 1.0 / spec.rate_hz
    # the solution kind: a Markov chain at the fix rate
    q = np.ones(n, int)
    k = 0
    while k < n:
        u = rng.uniform()
        p_float, p_single = spec.float_per_min * dt / 60.0, spec.single_per_min * dt / 60.0
        if u < p_float + p_single:
            kind, mean = (2, spec.float_mean_s) if u < p_float else (5, spec.single_mean_s)
            length = max(1, int(round(rng.exponential(mean) / dt)))
            q[k:k + length] = kind
            k += length
        k += 1
    # errors per kind (horizontal per axis, vertical)
    e = np.zeros((n, 3))
    rep = np.zeros((n, 3))
    hv = lambda s: np.array([s[0], s[0], s[1]])  # noqa: E731
    white = rng.standard_normal((n, 3))
    e_fixed = white * hv(spec.fixed_sigma)
    e_float = _gauss_markov(n, hv(spec.float_sigma), spec.wander_tau_s, dt, rng) + 0.03 * rng.standard_normal((n, 3))
    e_single = _gauss_markov(n, hv(spec.single_sigma), 3 * spec.wander_tau_s, dt, rng) + 0.3 * white
    for kind, err, sig in ((1, e_fixed, spec.fixed_sigma), (2, e_float, spec.float_sigma), (5, e_single, spec.single_sigma)):
        sel = q == kind
        e[sel] = err[sel]
        rep[sel] = spec.reported_ratio * hv(sig) * rng.uniform(0.8, 1.25, (sel.sum(), 1))
    # multipath jumps in float and single stretches
    jump = np.zeros((n, 3))
    k = 0
    while k < n:
        if q[k] != 1 and rng.uniform() < spec.jumps_per_min * dt / 60.0:
            length = max(1, int(round(rng.exponential(spec.jump_mean_s) / dt)))
            d = rng.standard_normal(3) * spec.jump_sigma_m * np.array([1.0, 1.0, 1.5])
            end = k + length
            while k < min(end, n) and q[k] != 1:
                jump[k] = d
                k += 1
        k += 1
    e += jump
    lever = np.asarray(spec.lever_arm_b_m, float)
    qn = traj.q_nb[iv]
    w_eb_b = traj.omega_ib_b[iv]
    if traj.earth_rate:
        w_eb_b = w_eb_b - quat.rotate_inv(qn, earth.earth_rate_n(traj.lat[iv]))
    ant = traj.pos_n[iv] + quat.rotate(qn, np.broadcast_to(lever, (n, 3)))
    v = traj.v_n[iv] + quat.rotate(qn, np.cross(w_eb_b, lever))
    vs = np.where(q == 5, 3.0, 1.0)[:, None] * spec.vel_sigma_m_s
    v = v + rng.standard_normal((n, 3)) * vs
    pos = ant + e
    lat, lon, h = earth.ned_to_geodetic(pos, traj.lat[0], traj.lon[0], traj.h[0])
    t = traj.t[iv]
    return RtkData(t=t, t_valid=t, index=iv, index_valid=iv, lat=lat, lon=lon, h=h, pos_n=pos, v_n=v,
                   quality=q, sigma=rep, error_n=e)


# ----------------------------------------------------------------------------------------------
# The scenario
# ----------------------------------------------------------------------------------------------
#: Outage windows (s, GNSS time) of ``car_rtk``: the 30 s ones through a curve at 17 m/s, the
#: highway at 25 m/s, a highway curve and a curve at 16 m/s; the 60 s ones through the on-ramp
#: loop, the highway with its lane change and curve, and the exit ramp with a stop at a light.
CAR_RTK_OUTAGES_30 = ((100.0, 130.0), (195.0, 225.0), (280.0, 310.0), (400.0, 430.0))
CAR_RTK_OUTAGES_60 = ((150.0, 210.0), (240.0, 300.0), (330.0, 390.0))


def car_rtk(seed=0, rate_hz=100.0, imu_delay_s=None, mount_error_deg=None, vibration_on=True,
            timing_on=True, rtk=None, imu_ahead_m=1.2, roll_per_accel=0.006, name="car_rtk"):
    """The drive of this module's docstring, from a standstill: 20 s parked, town, an arterial
    road, a cloverleaf on-ramp, 110 s of highway at 25 m/s with curves and a lane change, an exit
    ramp, traffic lights, a roundabout; 486 s.

    IMU: a roof MEMS unit (gyro 0.01 deg/s/sqrt(Hz), bias 0.2 deg/s, instability 8 deg/h, 0.1 %
    scale and 1 mrad misalignment; accelerometer 150 ug/sqrt(Hz), bias 10 mg, 0.3 %), at
    ``rate_hz`` (interval means), with the car's vibration (``vibration_on``), a mounting error
    of ``mount_error_deg`` (roll, pitch, yaw; default drawn per seed, about 1 deg) that the
    filter is not told, ``imu_delay_s`` late stamps (default drawn per seed between 2 and 12
    ms) and 0.3 ms jitter with 0.05 % of the samples lost (``timing_on``). GNSS: an RTK receiver
    (:class:`RtkSpec`, or ``rtk``) with the antenna at ``RtkSpec.lever_arm_b_m``.
    ``params["sensor_model"]`` holds what a user knows (the lever arm) and what they do not (the
    mounting error, the delay); ``params["events"]`` the stops and the outage windows.
    """
    from .scenarios import Scenario, _LAT0, _LON0, _H0, _spec_dict
    rng = np.random.default_rng(seed)
    r_imu, r_gnss, r_vib, r_time, r_draw = rng.spawn(5)
    segs, labels = car_rtk_segments(imu_ahead_m=imu_ahead_m, roll_per_accel=roll_per_accel)
    traj_rate = 2 * rate_hz
    traj = make_trajectory(segs, traj_rate, lat0=_LAT0, lon0=_LON0, h0=_H0, rpy0=(0.0, 0.0, np.radians(-20.0)),
                           speed0=0.0)
    if mount_error_deg is None:
        mount_error_deg = tuple(float(x) for x in r_draw.normal(0.0, [0.7, 0.7, 1.0]))
    if imu_delay_s is None:
        imu_delay_s = float(r_draw.uniform(0.002, 0.012))
    if not timing_on:
        imu_delay_s = 0.0
    vib_spec = VibrationSpec()
    imu_spec = ImuSpec(gyro=GyroSpec(bias_deg_per_h=tuple(r_draw.normal(0.0, 720.0, 3)), bias_instability_deg_per_h=8.0,
                                     noise_density_dps_per_sqrt_hz=0.01, scale_factor_ppm=tuple(r_draw.normal(0, 1000, 3)),
                                     misalignment_mrad=tuple(r_draw.normal(0, 1.0, 6)), range_deg_per_s=500.0,
                                     quantization_deg_per_s=0.004),
                       accel=AccelSpec(bias_ug=tuple(r_draw.normal(0.0, 10000.0, 3)), bias_instability_ug=100.0,
                                       noise_density_ug_per_sqrt_hz=150.0,
                                       scale_factor_ppm=tuple(r_draw.normal(0, 3000, 3)),
                                       misalignment_mrad=tuple(r_draw.normal(0, 1.0, 6)), range_g=8.0,
                                       quantization_mg=0.5),
                       rate_hz=rate_hz, mounting_rpy_deg=tuple(mount_error_deg))
    imu = simulate_imu(traj, imu_spec, r_imu)
    t_imu_true = imu.t.copy()
    if vibration_on:  # the value at each sample's time, in the IMU's axes
        speed = np.linalg.norm(traj.v_n, axis=1)
        tv, acc_v, gyr_v = vibration(float(traj.t[-1]), lambda x: np.interp(x, traj.t, speed), vib_spec, r_vib)
        C = quat.to_rotmat(imu.q_b_imu)
        at = lambda x: np.column_stack([np.interp(imu.t, tv, x[:, j]) for j in range(3)]) @ C  # noqa: E731
        imu = replace(imu, gyro=imu.gyro + at(gyr_v), accel=imu.accel + at(acc_v))
    if timing_on:
        t_stamp = imu.t + imu_delay_s + r_time.normal(0.0, 3e-4, len(imu.t))
        keep = np.ones(len(imu.t), bool)
        keep[1:] = r_time.uniform(size=len(imu.t) - 1) > 5e-4
        # stamps strictly increasing
        keep &= np.concatenate([[True], np.diff(t_stamp) > 0.2 / rate_hz])
        imu = replace(imu, t=t_stamp[keep], index=imu.index[keep], gyro=imu.gyro[keep], accel=imu.accel[keep],
                      gyro_bias=imu.gyro_bias[keep], accel_bias=imu.accel_bias[keep], saturated=imu.saturated[keep])
        t_imu_true = t_imu_true[keep]
    rtk = rtk or RtkSpec()
    gnss = simulate_rtk(traj, rtk, r_gnss)
    starts = np.concatenate([[0.0], np.cumsum([s.duration for s in segs])])
    stops = [[float(starts[i]), float(starts[i + 1])] for i, n in enumerate(labels)
             if n in ("standstill", "traffic light", "parked")]
    sensor_model = {"lever_arm_b_m": [float(x) for x in rtk.lever_arm_b_m],
                    "mount_error_rpy_deg": [float(x) for x in mount_error_deg],
                    "q_b_imu": mounting_quaternion(mount_error_deg).tolist(),
                    "imu_delay_s": float(imu_delay_s), "imu_time_true": "imu.t - imu_delay_s (plus the jitter)",
                    "gnss_time": "time of validity (GPS time)"}
    events = {"stops": stops, "outages_30": [list(o) for o in CAR_RTK_OUTAGES_30],
              "outages_60": [list(o) for o in CAR_RTK_OUTAGES_60],
              "segments": [[n, float(starts[i]), float(starts[i + 1])] for i, n in enumerate(labels)],
              "rtk_fraction": {"fixed": float(np.mean(gnss.quality == 1)), "float": float(np.mean(gnss.quality == 2)),
                               "single": float(np.mean(gnss.quality == 5))}}
    params = {"trajectory": {"rate_hz": traj.rate_hz, "duration_s": float(traj.t[-1])}, "imu": _spec_dict(imu_spec),
              "rtk": _spec_dict(rtk), "vibration": _spec_dict(vib_spec) if vibration_on else None,
              "sensor_model": sensor_model, "events": events,
              "car": {"imu_ahead_m": imu_ahead_m, "roll_per_accel_rad_per_m_s2": roll_per_accel},
              "choices": {"imu": "roof MEMS, consumer to automotive grade", "vibration": bool(vibration_on),
                          "timing": bool(timing_on), "gnss": "RTK 4 Hz, fixed/float/single, multipath jumps"}}
    s = Scenario(name=name, seed=int(seed), description="car with a roof MEMS IMU and RTK GNSS: town, highway, "
                 "vibration, timing errors, fixed/float switching", truth=traj, imu=imu, gps=gnss, params=params)
    s.imu_t_true = t_imu_true
    return s
