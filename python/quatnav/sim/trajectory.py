"""Reference trajectories: motion segments and waypoints, with exact truth at every sample.

How the truth is computed
-------------------------
A trajectory is a list of motion segments. Each segment is an analytic, smooth function of its
local time ``tau`` that gives the attitude ``q_nb(tau)`` with respect to the local NED frame and
the velocity ``v_n(tau)`` with respect to the Earth. From these two functions alone:

1. ``omega_nb_b = 2 vec(conj(q) * dq/dt)`` and ``alpha_nb_b = 2 vec(conj(q) * d2q/dt2)`` and
   ``a_n = dv_n/dt`` are computed with 5-point central differences (step 1e-3 s, truncation
   error O(1e-13), well below anything a navigation filter can see);
2. latitude, longitude and height are integrated from ``v_n`` with Simpson's rule on a grid of
   half the sample period (cumulative, O(h^4) at every grid point), iterating the weak
   dependence of the radii on latitude;
3. with the Earth model of :mod:`quatnav.core.earth`::

       omega_ib_b = omega_nb_b + C_bn (omega_ie_n + omega_en_n)
       f_ib_b     = C_bn (a_n + (2 omega_ie_n + omega_en_n) x v_n - g_n)

   (with ``earth_rate=False`` the two Earth terms are zero: a flat, non-rotating Earth whose
   gravity is still WGS-84 normal gravity at the current latitude and height);
4. the IMU increments over each sample interval, ``dtheta_b[k] = int omega_ib_b dt`` and
   ``dv_b[k] = int f_ib_b dt`` over ``(t[k-1], t[k]]``, by Simpson's rule on the half-step
   grid (error O(dt^5) per interval). Row 0 holds zeros.

A real IMU reports increments or interval means; the simulated IMU (:mod:`quatnav.sim.sensors`)
reports the interval mean ``dtheta_b / dt`` and ``dv_b / dt``, which is what
:func:`quatnav.core.strapdown.strapdown_step` expects. Segment boundaries are placed on the sample
grid (durations are rounded to whole samples) so no interval straddles a change of segment.

Segments
--------
:class:`Rest`, :class:`Accelerate`, :class:`Cruise` (constant velocity), :class:`Turn`
(constant-rate level turn), :class:`CoordinatedTurn` (turn with the bank of a coordinated turn),
:class:`Climb`, :class:`Rotate` (rotation about a body axis at a given rate, as on a turntable),
:class:`RandomMotion` (smooth random rotations and small translations, as a hand-held device) and
:class:`WaypointPath` (smooth quintic path through positions at a given speed).
Rates switch on and off with raised-cosine ramps of length ``ramp`` (> 0) so angular rate and
specific force are continuous; a step in rate is not physical and would make the rate at the
switching sample ambiguous.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, field
from typing import Optional, Sequence

import numpy as np

from ..core import earth
from ..core import quaternion as quat

__all__ = [
    "MotionState", "Segment", "Rest", "Accelerate", "Cruise", "Turn", "CoordinatedTurn", "Climb",
    "Rotate", "RandomMotion", "WaypointPath", "Trajectory", "make_trajectory",
    "trajectory_from_waypoints",
]

_STENCIL = np.array([-2.0, -1.0, 0.0, 1.0, 2.0])
_DIFF_STEP = 1e-3  # s, step of the 5-point central differences


def _check_positive(name, value, allow_zero=False):
    v = float(value)
    if not np.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        raise ValueError(f"{name} must be a finite {'non-negative' if allow_zero else 'positive'}"
                         f" number, got {value!r}")
    return v


def _check_finite(name, value):
    v = np.asarray(value, dtype=float)
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} must be finite, got {value!r}")
    return v


# ----------------------------------------------------------------------------------------------
# Smooth windows
# ----------------------------------------------------------------------------------------------
def _ramp_up(tau, tr):
    """Raised-cosine step: 0 for tau <= 0, 1 for tau >= tr; returns (value, derivative, integral)."""
    tau = np.asarray(tau, float)
    if tr <= 0:
        w = (tau > 0).astype(float)
        return w, np.zeros_like(tau), np.maximum(tau, 0.0)
    x = np.clip(tau / tr, 0.0, 1.0)
    w = 0.5 * (1.0 - np.cos(np.pi * x))
    dw = np.where((tau > 0) & (tau < tr), 0.5 * np.pi / tr * np.sin(np.pi * x), 0.0)
    # integral of w from 0 to tau
    integ = np.where(tau <= 0, 0.0,
                     np.where(tau >= tr, 0.5 * tr + (tau - tr),
                              0.5 * (tau - tr / np.pi * np.sin(np.pi * x))))
    return w, dw, integ


def _window(tau, T, tr):
    """Smooth trapezoid on [0, T] with ramps of length tr: returns (W, dW/dtau, int_0^tau W)."""
    tau = np.asarray(tau, float)
    up, dup, iup = _ramp_up(tau, tr)
    dn, ddn, idn = _ramp_up(T - tau, tr)
    total = T - tr if tr > 0 else T
    # On [0, T] at most one ramp is active (T >= 2 tr), so W = up * dn and the integral splits.
    w = up * dn
    dw = dup * dn - up * ddn
    integ = np.where(tau <= T - tr, iup, total - idn)
    integ = np.where(tau >= T, total, integ)
    return w, dw, integ


def _cumulative_simpson(y, h):
    """Cumulative integral of samples ``y`` (M odd, spacing h) from 0, O(h^4) at every point.

    Even points: composite Simpson. Odd points: the panel's parabola integrated over its first
    half, h/12 (5 y0 + 8 y1 - y2).
    """
    y = np.asarray(y, float)
    out = np.zeros_like(y)
    panels = h / 3.0 * (y[0:-2:2] + 4.0 * y[1:-1:2] + y[2::2])
    out[2::2] = np.cumsum(panels)
    out[1::2] = out[0:-2:2] + h / 12.0 * (5.0 * y[0:-2:2] + 8.0 * y[1:-1:2] - y[2::2])
    return out


def _direction(course, path):
    """Unit NED vector of a course (rad from north) and a flight-path angle (rad, up positive)."""
    cp = np.cos(path)
    return np.stack([cp * np.cos(course), cp * np.sin(course), -np.sin(path)], axis=-1)


# ----------------------------------------------------------------------------------------------
# Motion state and segments
# ----------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class MotionState:
    """Kinematic state at a segment boundary.

    Attributes
    ----------
    rpy : ndarray, shape (3,)
        Euler angles [roll, pitch, yaw] (rad), ZYX; yaw is unwrapped (may leave (-pi, pi]).
    q_nb : ndarray, shape (4,)
        Attitude, body to NED.
    speed : float
        Speed along the path (m/s).
    course, path : float
        Course (rad from north) and flight-path angle (rad, climbing positive) of the velocity.
    v_n : ndarray, shape (3,)
        Velocity in NED (m/s).
    """

    rpy: np.ndarray
    q_nb: np.ndarray
    speed: float
    course: float
    path: float
    v_n: np.ndarray


class Segment:
    """A piece of motion. Subclasses define ``duration`` (s) and ``_evaluate``."""

    duration: float

    def evaluate(self, tau, s0: MotionState):
        """Attitude and velocity at local times ``tau`` (s), shape (n,).

        Returns
        -------
        q_nb : ndarray, shape (n, 4)
        v_n : ndarray, shape (n, 3)
            Velocity with respect to the Earth in NED (m/s).
        """
        raise NotImplementedError

    def end_state(self, s0: MotionState) -> MotionState:
        raise NotImplementedError


class _EulerSegment(Segment):
    """Segment defined by Euler-angle increments and a speed profile; course follows yaw and the
    flight path follows pitch (no sideslip, no angle of attack)."""

    def _profile(self, tau, s0):
        """Return (d_rpy (n,3), speed (n,), d_ned (n,3) or None, v_extra (n,3) or None)."""
        raise NotImplementedError

    def evaluate(self, tau, s0):
        tau = np.asarray(tau, float)
        d_rpy, speed, v_extra = self._profile(tau, s0)
        rpy = s0.rpy + d_rpy
        q = quat.from_euler(rpy)
        course = s0.course + d_rpy[:, 2]
        path = s0.path + d_rpy[:, 1]
        v = speed[:, None] * _direction(course, path)
        if v_extra is not None:
            v = v + v_extra
        return q, v

    def end_state(self, s0):
        T = np.array([self.duration])
        d_rpy, speed, v_extra = self._profile(T, s0)
        rpy = s0.rpy + d_rpy[0]
        course = s0.course + d_rpy[0, 2]
        path = s0.path + d_rpy[0, 1]
        v = speed[0] * _direction(course, path)
        if v_extra is not None:
            v = v + v_extra[0]
        return MotionState(rpy=rpy, q_nb=quat.from_euler(rpy), speed=float(speed[0]),
                           course=float(course), path=float(path), v_n=v)


@dataclass(frozen=True)
class Rest(_EulerSegment):
    """Stand still for ``duration`` seconds (the vehicle must already be at rest)."""

    duration: float

    def __post_init__(self):
        _check_positive("duration", self.duration)

    def _profile(self, tau, s0):
        if abs(s0.speed) > 1e-12:
            raise ValueError(f"Rest: the vehicle is moving at {s0.speed} m/s; stop it first "
                             "with Accelerate(to_speed=0)")
        n = tau.shape[0]
        return np.zeros((n, 3)), np.zeros(n), None


@dataclass(frozen=True)
class Cruise(_EulerSegment):
    """Constant velocity (and attitude) for ``duration`` seconds."""

    duration: float

    def __post_init__(self):
        _check_positive("duration", self.duration)

    def _profile(self, tau, s0):
        n = tau.shape[0]
        return np.zeros((n, 3)), np.full(n, s0.speed), None


@dataclass(frozen=True)
class Accelerate(_EulerSegment):
    """Change speed along the path smoothly (raised-cosine speed profile).

    Give exactly one of ``to_speed`` (m/s) or ``delta_speed`` (m/s). The peak acceleration is
    ``pi/2 * |delta| / duration``. With ``from_peak`` the speed follows a quarter sine,
    ``delta sin(pi/2 tau/duration)``: the acceleration is at its peak at the start and eases to
    zero, as in a log that begins while the vehicle is already accelerating (the segment must
    then be the first one, started with ``speed0 > 0``).
    """

    duration: float
    to_speed: Optional[float] = None
    delta_speed: Optional[float] = None
    from_peak: bool = False

    def __post_init__(self):
        _check_positive("duration", self.duration)
        if (self.to_speed is None) == (self.delta_speed is None):
            raise ValueError("Accelerate: give exactly one of to_speed and delta_speed")
        if self.to_speed is not None:
            _check_positive("to_speed", self.to_speed, allow_zero=True)
        else:
            _check_finite("delta_speed", self.delta_speed)

    def _delta(self, s0):
        d = (self.to_speed - s0.speed) if self.to_speed is not None else self.delta_speed
        if s0.speed + d < -1e-12:
            raise ValueError(f"Accelerate: delta_speed={d} would make the speed negative")
        return d

    def _profile(self, tau, s0):
        d = self._delta(s0)
        if self.from_peak:
            # no clip below 0: the sine continues smoothly before the start, so the derivatives
            # at the first sample are those of an acceleration already under way
            speed = s0.speed + d * np.sin(0.5 * np.pi * np.minimum(tau / self.duration, 1.0))
        else:
            x = np.clip(tau / self.duration, 0.0, 1.0)
            speed = s0.speed + d * 0.5 * (1.0 - np.cos(np.pi * x))
        return np.zeros((tau.shape[0], 3)), speed, None


@dataclass(frozen=True)
class Turn(_EulerSegment):
    """Level turn at a constant yaw rate (no bank): a ground vehicle or a turning platform.

    Give ``rate`` (rad/s, positive clockwise seen from above) or ``angle`` (rad). The rate ramps
    up and down over ``ramp`` seconds, so ``angle = rate * (duration - ramp)``.
    """

    duration: float
    rate: Optional[float] = None
    angle: Optional[float] = None
    ramp: float = 1.0

    def __post_init__(self):
        _check_positive("duration", self.duration)
        _check_positive("ramp", self.ramp)
        if 2 * self.ramp > self.duration:
            raise ValueError(f"ramp={self.ramp} must be at most half the duration {self.duration}")
        if (self.rate is None) == (self.angle is None):
            raise ValueError(f"{type(self).__name__}: give exactly one of rate and angle")
        _check_finite("rate" if self.rate is not None else "angle",
                      self.rate if self.rate is not None else self.angle)

    def _rate(self):
        if self.rate is not None:
            return float(self.rate)
        return float(self.angle) / (self.duration - self.ramp)

    def _yaw(self, tau):
        w, _, integ = _window(tau, self.duration, self.ramp)
        return self._rate() * integ, self._rate() * w

    def _profile(self, tau, s0):
        d = np.zeros((tau.shape[0], 3))
        d[:, 2], _ = self._yaw(tau)
        return d, np.full(tau.shape[0], s0.speed), None


@dataclass(frozen=True)
class CoordinatedTurn(Turn):
    """Turn at a constant yaw rate with the bank of a coordinated turn, roll = atan(V r / g).

    Needs a moving vehicle. The bank follows the ramped yaw rate, so it is smooth too.
    """

    def _profile(self, tau, s0):
        if s0.speed <= 0:
            raise ValueError("CoordinatedTurn: the vehicle must be moving (speed > 0)")
        d = np.zeros((tau.shape[0], 3))
        d[:, 2], r = self._yaw(tau)
        d[:, 0] = np.arctan(s0.speed * r / earth.STANDARD_GRAVITY)
        return d, np.full(tau.shape[0], s0.speed), None


@dataclass(frozen=True)
class Climb(_EulerSegment):
    """Pitch up to ``angle`` (rad; negative descends) over ``ramp`` s, hold, and pitch back.

    The flight path follows the pitch, so the height change is about
    ``speed * sin(angle) * (duration - ramp)``.
    """

    duration: float
    angle: float
    ramp: float = 2.0

    def __post_init__(self):
        _check_positive("duration", self.duration)
        _check_positive("ramp", self.ramp)
        if 2 * self.ramp > self.duration:
            raise ValueError(f"ramp={self.ramp} must be at most half the duration {self.duration}")
        a = float(_check_finite("angle", self.angle))
        if abs(a) >= np.radians(80):
            raise ValueError(f"angle={a} rad is too steep (|angle| must be below 80 deg)")

    def _profile(self, tau, s0):
        d = np.zeros((tau.shape[0], 3))
        w, _, _ = _window(tau, self.duration, self.ramp)
        d[:, 1] = self.angle * w
        return d, np.full(tau.shape[0], s0.speed), None


@dataclass(frozen=True)
class Rotate(Segment):
    """Rotation about a body axis at a given rate, as on a turntable; velocity unchanged.

    ``axis`` is ``"roll"``, ``"pitch"``, ``"yaw"`` (body x, y, z) or a 3-vector; ``rate`` in rad/s
    (or ``angle`` in rad); the rate ramps up and down over ``ramp`` seconds.
    """

    axis: object
    duration: float
    rate: Optional[float] = None
    angle: Optional[float] = None
    ramp: float = 0.5

    def __post_init__(self):
        _check_positive("duration", self.duration)
        _check_positive("ramp", self.ramp)
        if 2 * self.ramp > self.duration:
            raise ValueError(f"ramp={self.ramp} must be at most half the duration {self.duration}")
        if (self.rate is None) == (self.angle is None):
            raise ValueError("Rotate: give exactly one of rate and angle")
        self._unit_axis()

    def _unit_axis(self):
        names = {"roll": [1.0, 0, 0], "pitch": [0, 1.0, 0], "yaw": [0, 0, 1.0]}
        if isinstance(self.axis, str):
            if self.axis not in names:
                raise ValueError(f"axis must be 'roll', 'pitch', 'yaw' or a 3-vector, got {self.axis!r}")
            return np.array(names[self.axis])
        a = _check_finite("axis", self.axis).reshape(-1)
        if a.shape != (3,) or np.linalg.norm(a) == 0:
            raise ValueError(f"axis must be a non-zero 3-vector, got {self.axis!r}")
        return a / np.linalg.norm(a)

    def _angle(self, tau):
        rate = self.rate if self.rate is not None else self.angle / (self.duration - self.ramp)
        _, _, integ = _window(tau, self.duration, self.ramp)
        return rate * integ

    def evaluate(self, tau, s0):
        tau = np.asarray(tau, float)
        dq = quat.from_rotvec(self._angle(tau)[:, None] * self._unit_axis())
        q = quat.mul(np.broadcast_to(s0.q_nb, dq.shape), dq)
        return q, np.broadcast_to(s0.v_n, (tau.shape[0], 3)).copy()

    def end_state(self, s0):
        q, _ = self.evaluate(np.array([self.duration]), s0)
        q = q[0]
        rpy = quat.to_euler(q)
        rpy[2] = s0.rpy[2] + np.angle(np.exp(1j * (rpy[2] - s0.rpy[2])))  # keep yaw unwrapped
        return dataclasses.replace(s0, rpy=rpy, q_nb=q)


@dataclass(frozen=True)
class RandomMotion(_EulerSegment):
    """Smooth random rotations (and optional small translations), as a hand-held device.

    Each Euler angle moves by a sum of ``n_tones`` sinusoids with random frequencies up to
    ``max_freq`` (Hz) and random phases, scaled so its standard deviation is about
    ``amplitude`` (rad, per axis [roll, pitch, yaw]); pitch stays within +/-70 deg. With
    ``translation`` > 0 (m) the position also moves by such a sum (linear accelerations).
    The motion fades in and out over ``ramp`` seconds. All draws come from ``seed``.
    """

    duration: float
    amplitude: Sequence[float] = (0.5, 0.4, 1.0)
    max_freq: float = 0.5
    translation: float = 0.0
    n_tones: int = 4
    ramp: float = 2.0
    seed: int = 0

    def __post_init__(self):
        _check_positive("duration", self.duration)
        _check_positive("max_freq", self.max_freq)
        _check_positive("translation", self.translation, allow_zero=True)
        _check_positive("ramp", self.ramp)
        if 2 * self.ramp > self.duration:
            raise ValueError(f"ramp={self.ramp} must be at most half the duration {self.duration}")
        amp = _check_finite("amplitude", self.amplitude)
        if amp.shape != (3,) or np.any(amp < 0):
            raise ValueError(f"amplitude must be 3 non-negative numbers (rad), got {self.amplitude!r}")
        rng = np.random.default_rng(self.seed)
        k = int(self.n_tones)
        f = rng.uniform(0.2 * self.max_freq, self.max_freq, size=(2, 3, k))
        ph = rng.uniform(0, 2 * np.pi, size=(2, 3, k))
        object.__setattr__(self, "_tones", (f, ph, np.sqrt(2.0 / k)))

    def _sum(self, tau, which, scale):
        f, ph, norm = self._tones
        arg = 2 * np.pi * f[which][None] * tau[:, None, None] + ph[which][None]
        s = scale * norm * np.sum(np.sin(arg) - np.sin(ph[which][None]), axis=-1)
        ds = scale * norm * np.sum(2 * np.pi * f[which][None] * np.cos(arg), axis=-1)
        return s, ds

    def _profile(self, tau, s0):
        w, dw, _ = _window(tau, self.duration, self.ramp)
        s, _ = self._sum(tau, 0, np.asarray(self.amplitude, float))
        d = s * w[:, None]
        lim = np.radians(70.0)
        d[:, 1] = lim * (np.tanh((s0.rpy[1] + d[:, 1]) / lim) - np.tanh(s0.rpy[1] / lim))
        # Course and flight path must not follow a hand-held device's attitude: report zero
        # path speed and carry the (small) translation velocity separately.
        v_extra = None
        if self.translation > 0:
            p, dp = self._sum(tau, 1, self.translation)
            v_extra = dp * w[:, None] + p * dw[:, None]
        n = tau.shape[0]
        return d, np.full(n, s0.speed), v_extra

    def evaluate(self, tau, s0):
        if abs(s0.speed) > 1e-12:
            raise ValueError("RandomMotion: start it from rest")
        return super().evaluate(tau, s0)

    def end_state(self, s0):
        st = super().end_state(s0)
        return dataclasses.replace(st, course=s0.course, path=s0.path, speed=s0.speed,
                                   v_n=np.zeros(3))


@dataclass(frozen=True)
class WaypointPath(Segment):
    """Smooth path through positions at a given speed (a quintic spline in time).

    Parameters
    ----------
    points_n : array_like, shape (K, 3) or (K, 2)
        Positions in NED (m) relative to where the segment starts; the start itself is the
        implicit first point.
    speed : float or array_like, shape (K,)
        Speed (m/s) on each leg; the time of each leg is its length over its speed.
    bank : bool
        If True the vehicle banks as in a coordinated turn, else it stays level (walker, car).
    max_leg : float, optional
        Split legs longer than this (m) into equal parts, keeping straight legs straight (an
        interpolating spline rings where knot spacing or curvature changes abruptly; give curves
        about as many points per metre). Default 2 m;
        ``None`` keeps the points as given.

    The vehicle must enter moving along its current course; the path is C4-smooth, it leaves
    with the direction of the last leg and zero acceleration. Yaw follows the horizontal
    velocity and pitch the flight-path angle. ``duration`` is set from the legs.
    """

    points_n: object
    speed: object
    bank: bool = False
    max_leg: Optional[float] = 2.0

    def __post_init__(self):
        p = _check_finite("points_n", self.points_n)
        if p.ndim != 2 or p.shape[1] not in (2, 3) or p.shape[0] < 1:
            raise ValueError(f"points_n must have shape (K, 2) or (K, 3), got {p.shape}")
        if p.shape[1] == 2:
            p = np.column_stack([p, np.zeros(len(p))])
        sp = np.broadcast_to(_check_finite("speed", self.speed), (len(p),)).astype(float)
        if np.any(sp <= 0):
            raise ValueError(f"speed must be positive, got {self.speed!r}")
        pts = np.vstack([np.zeros(3), p])
        legs = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        if np.any(legs <= 0):
            raise ValueError("points_n: consecutive points must differ")
        if self.max_leg is not None:
            ml = _check_positive("max_leg", self.max_leg)
            dense, dsp = [pts[0]], []
            for i, L in enumerate(legs):
                m = max(1, int(np.ceil(L / ml - 1e-9)))
                for j in range(1, m + 1):
                    dense.append(pts[i] + (pts[i + 1] - pts[i]) * j / m)
                    dsp.append(sp[i])
            pts, sp = np.array(dense), np.array(dsp)
            legs = np.linalg.norm(np.diff(pts, axis=0), axis=1)
        times = np.concatenate([[0.0], np.cumsum(legs / sp)])
        object.__setattr__(self, "_pts", pts)
        object.__setattr__(self, "_times", times)
        object.__setattr__(self, "_speeds", sp)
        object.__setattr__(self, "_spline_cache", {})

    @property
    def duration(self):
        return float(self._times[-1])

    def _spline(self, s0):
        key = (tuple(np.round(s0.v_n, 12)),)
        if key not in self._spline_cache:
            from .._optional import require
            make_interp_spline = require("scipy.interpolate", "quatnav.sim waypoint paths").make_interp_spline
            if s0.speed <= 0:
                raise ValueError("WaypointPath: the vehicle must be moving when the path starts "
                                 "(precede it with Accelerate)")
            v_end = self._speeds[-1] * (self._pts[-1] - self._pts[-2]) / np.linalg.norm(
                self._pts[-1] - self._pts[-2])
            bc = ([(1, s0.v_n), (2, np.zeros(3))], [(1, v_end), (2, np.zeros(3))])
            self._spline_cache[key] = make_interp_spline(self._times, self._pts, k=5, bc_type=bc)
        return self._spline_cache[key]

    def _state(self, tau, s0):
        sp = self._spline(s0)
        v = sp(tau, 1)
        a = sp(tau, 2)
        hor = np.hypot(v[:, 0], v[:, 1])
        if np.any(hor < 1e-3):
            raise ValueError("WaypointPath: the path stops or goes vertical; yaw is undefined")
        yaw_raw = np.arctan2(v[:, 1], v[:, 0])
        # unwrap consistently with a dense reference table starting from the entry yaw
        dense_t = np.linspace(-0.01, self.duration + 0.01, max(200, int(self.duration * 50)))
        vd = sp(dense_t, 1)
        dense_yaw = np.unwrap(np.arctan2(vd[:, 1], vd[:, 0]))
        i0 = np.argmin(np.abs(dense_t))
        dense_yaw += s0.rpy[2] - dense_yaw[i0] + np.angle(np.exp(1j * (dense_yaw[i0] - s0.rpy[2])))
        ref = np.interp(tau, dense_t, dense_yaw)
        yaw = yaw_raw + 2 * np.pi * np.round((ref - yaw_raw) / (2 * np.pi))
        pitch = np.arctan2(-v[:, 2], hor)
        if self.bank:
            yaw_rate = (v[:, 0] * a[:, 1] - v[:, 1] * a[:, 0]) / hor**2
            roll = np.arctan(np.linalg.norm(v, axis=1) * yaw_rate / earth.STANDARD_GRAVITY)
        else:
            roll = np.zeros_like(yaw)
        return np.column_stack([roll, pitch, yaw]), v

    def evaluate(self, tau, s0):
        rpy, v = self._state(np.asarray(tau, float), s0)
        return quat.from_euler(rpy), v

    def end_state(self, s0):
        rpy, v = self._state(np.array([self.duration]), s0)
        rpy, v = rpy[0], v[0]
        return MotionState(rpy=rpy, q_nb=quat.from_euler(rpy), speed=float(np.linalg.norm(v)),
                           course=float(rpy[2]), path=float(rpy[1]), v_n=v)


# ----------------------------------------------------------------------------------------------
# Trajectory
# ----------------------------------------------------------------------------------------------
@dataclass
class Trajectory:
    """Truth at every sample (N samples). Shapes and units:

    Attributes
    ----------
    t : (N,) s
    lat, lon : (N,) rad, geodetic
    h : (N,) m, above the ellipsoid
    pos_n : (N, 3) m, local NED position with respect to the start (small-displacement
        conversion of :func:`quatnav.core.earth.geodetic_to_ned`)
    v_n : (N, 3) m/s, velocity with respect to the Earth in NED
    a_n : (N, 3) m/s^2, dv_n/dt
    q_nb : (N, 4) attitude [w, x, y, z], body to NED
    rpy : (N, 3) rad, ZYX Euler angles [roll, pitch, yaw] (yaw wrapped to (-pi, pi])
    omega_nb_b : (N, 3) rad/s, body rate with respect to NED
    omega_ib_b : (N, 3) rad/s, body rate with respect to inertial space (what a gyro senses)
    alpha_nb_b : (N, 3) rad/s^2, body angular acceleration d(omega_nb_b)/dt
    f_ib_b : (N, 3) m/s^2, specific force (what an accelerometer senses)
    dtheta_b, dv_b : (N, 3) rad, m/s, exact increments of omega_ib_b and f_ib_b over
        (t[k-1], t[k]]; row 0 is zero
    rate_hz : float, sample rate
    earth_rate : bool, whether Earth rate, Coriolis and transport terms are included
    """

    t: np.ndarray
    lat: np.ndarray
    lon: np.ndarray
    h: np.ndarray
    pos_n: np.ndarray
    v_n: np.ndarray
    a_n: np.ndarray
    q_nb: np.ndarray
    rpy: np.ndarray
    omega_nb_b: np.ndarray
    omega_ib_b: np.ndarray
    alpha_nb_b: np.ndarray
    f_ib_b: np.ndarray
    dtheta_b: np.ndarray
    dv_b: np.ndarray
    rate_hz: float
    earth_rate: bool = True

    ARRAYS = ("t", "lat", "lon", "h", "pos_n", "v_n", "a_n", "q_nb", "rpy", "omega_nb_b",
              "omega_ib_b", "alpha_nb_b", "f_ib_b", "dtheta_b", "dv_b")

    @property
    def dt(self) -> float:
        return 1.0 / self.rate_hz

    def __len__(self):
        return self.t.shape[0]

    @property
    def omega_mean_b(self):
        """Mean of omega_ib_b over each interval (rad/s), row 0 the instantaneous value."""
        out = self.dtheta_b / self.dt
        out[0] = self.omega_ib_b[0]
        return out

    @property
    def f_mean_b(self):
        """Mean of f_ib_b over each interval (m/s^2), row 0 the instantaneous value."""
        out = self.dv_b / self.dt
        out[0] = self.f_ib_b[0]
        return out


def _initial_state(rpy0, speed0):
    rpy0 = _check_finite("rpy0", rpy0).reshape(-1)
    if rpy0.shape != (3,):
        raise ValueError(f"rpy0 must be [roll, pitch, yaw] (rad), got {rpy0!r}")
    speed0 = _check_positive("speed0", speed0, allow_zero=True)
    course, path = rpy0[2], rpy0[1]
    return MotionState(rpy=rpy0, q_nb=quat.from_euler(rpy0), speed=speed0, course=course,
                       path=path, v_n=speed0 * _direction(course, path))


def make_trajectory(segments, rate_hz, lat0=np.radians(36.37), lon0=np.radians(127.36), h0=50.0,
                    rpy0=(0.0, 0.0, 0.0), speed0=0.0, earth_rate=True, t_end=None) -> Trajectory:
    """Build the truth of a segment sequence.

    Parameters
    ----------
    segments : sequence of Segment
        Motion in order; each duration is rounded to a whole number of samples.
    rate_hz : float
        Sample rate (Hz).
    lat0, lon0 : float
        Start latitude and longitude (rad); the default is Daejeon, Korea.
    h0 : float
        Start height above the ellipsoid (m).
    rpy0 : array_like, shape (3,)
        Initial [roll, pitch, yaw] (rad).
    speed0 : float
        Initial speed (m/s) along yaw/pitch.
    earth_rate : bool
        Include Earth rotation, Coriolis and transport-rate terms.
    t_end : float, optional
        Keep only samples with t <= t_end (s), e.g. to stop inside a turn instead of after
        its ramp-down.

    Returns
    -------
    Trajectory
    """
    rate_hz = _check_positive("rate_hz", rate_hz)
    lat0 = float(_check_finite("lat0", lat0))
    if abs(lat0) > np.radians(89.0):
        raise ValueError(f"lat0={lat0} rad is too close to a pole (|lat0| must be below 89 deg)")
    lon0 = float(_check_finite("lon0", lon0))
    h0 = float(_check_finite("h0", h0))
    segments = list(segments)
    if not segments:
        raise ValueError("segments must not be empty")
    dt = 1.0 / rate_hz
    state = _initial_state(rpy0, speed0)

    # Round durations to the sample grid (WaypointPath keeps its own timing: it is evaluated on
    # its rounded interval, and the next segment starts from its state at that time).
    starts, ns, states = [], [], []
    k = 0
    for i_seg, seg in enumerate(segments):
        if not isinstance(seg, Segment):
            raise ValueError(f"segments must be Segment objects, got {seg!r}")
        n = int(round(seg.duration * rate_hz))
        if n < 1:
            raise ValueError(f"{type(seg).__name__}: duration={seg.duration} is shorter than one "
                             f"sample at {rate_hz} Hz")
        if not isinstance(seg, WaypointPath) and abs(n * dt - seg.duration) > 1e-9:
            seg_r = dataclasses.replace(seg, duration=n * dt)
        else:
            seg_r = seg
        starts.append(k)
        ns.append(n)
        states.append(state)
        segments[i_seg] = seg_r
        if isinstance(seg_r, WaypointPath):
            T = n * dt
            q_e, v_e = seg_r.evaluate(np.array([T]), state)
            rpy_e = quat.to_euler(q_e[0])
            rpy_e[2] = state.rpy[2] + np.angle(np.exp(1j * (rpy_e[2] - state.rpy[2])))
            state = MotionState(rpy=rpy_e, q_nb=q_e[0], speed=float(np.linalg.norm(v_e[0])),
                                course=float(rpy_e[2]), path=float(rpy_e[1]), v_n=v_e[0])
        else:
            state = seg_r.end_state(state)
        k += n
    N = k + 1
    M = 2 * N - 1  # half-step grid
    h2 = 0.5 * dt
    tf = np.arange(M) * h2
    q = np.empty((M, 4))
    dq = np.empty((M, 4))
    ddq = np.empty((M, 4))
    v = np.empty((M, 3))
    dv = np.empty((M, 3))
    for i, (seg, k0, n, s0) in enumerate(zip(segments, starts, ns, states)):
        lo = 2 * k0
        hi = 2 * (k0 + n) + (1 if i == len(segments) - 1 else 0)
        tau = tf[lo:hi] - k0 * dt
        st = (tau[:, None] + _DIFF_STEP * _STENCIL[None, :]).reshape(-1)
        qs, vs = seg.evaluate(st, s0)
        qs = qs.reshape(-1, 5, 4)
        vs = vs.reshape(-1, 5, 3)
        # make the stencil quaternions share the sign of the centre one
        sgn = np.sign(np.sum(qs * qs[:, 2:3, :], axis=-1, keepdims=True))
        qs = qs * sgn
        c1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / (12.0 * _DIFF_STEP)
        c2 = np.array([-1.0, 16.0, -30.0, 16.0, -1.0]) / (12.0 * _DIFF_STEP**2)
        q[lo:hi] = qs[:, 2]
        dq[lo:hi] = np.einsum("j,njc->nc", c1, qs)
        ddq[lo:hi] = np.einsum("j,njc->nc", c2, qs)
        v[lo:hi] = vs[:, 2]
        dv[lo:hi] = np.einsum("j,njc->nc", c1, vs)
    # keep the quaternion sign continuous along the grid
    flip = np.sum(q[1:] * q[:-1], axis=1) < 0
    sign = np.concatenate([[1.0], np.where(np.cumsum(flip) % 2 == 1, -1.0, 1.0)])
    q *= sign[:, None]
    dq *= sign[:, None]
    ddq *= sign[:, None]
    qn = np.linalg.norm(q, axis=1)
    q /= qn[:, None]
    qc = quat.conj(q)
    omega_nb_b = 2.0 * quat.mul(qc, dq)[:, 1:]
    alpha_nb_b = 2.0 * quat.mul(qc, ddq)[:, 1:]

    # Position by Simpson's rule on the half-step grid.
    hgt = h0 - _cumulative_simpson(v[:, 2], h2)
    lat = np.full(M, lat0)
    for _ in range(3):
        R_M, _ = earth.radii(lat)
        lat = lat0 + _cumulative_simpson(v[:, 0] / (R_M + hgt), h2)
    _, R_N = earth.radii(lat)
    lon = lon0 + _cumulative_simpson(v[:, 1] / ((R_N + hgt) * np.cos(lat)), h2)

    g_n = earth.gravity_n(lat, hgt)
    if earth_rate:
        w_ie = earth.earth_rate_n(lat)
        w_en = earth.transport_rate_n(lat, hgt, v)
    else:
        w_ie = np.zeros((M, 3))
        w_en = np.zeros((M, 3))
    omega_ib_b = omega_nb_b + quat.rotate_inv(q, w_ie + w_en)
    f_ib_b = quat.rotate_inv(q, dv + np.cross(2 * w_ie + w_en, v) - g_n)

    def simpson_increments(x):
        out = np.zeros(((x.shape[0] + 1) // 2, 3))
        out[1:] = dt / 6.0 * (x[0:-1:2] + 4.0 * x[1::2] + x[2::2])
        return out

    n_keep = N if t_end is None else int(np.floor(float(_check_positive("t_end", t_end)) * rate_hz + 1e-9)) + 1
    if n_keep > N:
        raise ValueError(f"t_end={t_end} is beyond the end of the segments ({(N - 1) * dt} s)")
    M = 2 * n_keep - 1
    ev = slice(0, M, 2)
    rpy = quat.to_euler(q[ev])
    return Trajectory(
        t=tf[ev].copy(), lat=lat[ev], lon=lon[ev], h=hgt[ev],
        pos_n=earth.geodetic_to_ned(lat[ev], lon[ev], hgt[ev], lat0, lon0, h0),
        v_n=v[ev], a_n=dv[ev], q_nb=q[ev], rpy=rpy, omega_nb_b=omega_nb_b[ev],
        omega_ib_b=omega_ib_b[ev], alpha_nb_b=alpha_nb_b[ev], f_ib_b=f_ib_b[ev],
        dtheta_b=simpson_increments(omega_ib_b[:M])[:n_keep],
        dv_b=simpson_increments(f_ib_b[:M])[:n_keep],
        rate_hz=rate_hz, earth_rate=bool(earth_rate))


def trajectory_from_waypoints(points_n, speed, rate_hz, rest=5.0, accel_time=4.0, bank=False,
                              **kwargs) -> Trajectory:
    """A trajectory that rests, accelerates along the first leg, follows the waypoints, slows
    down and rests again.

    Parameters
    ----------
    points_n : array_like, shape (K, 2) or (K, 3)
        Waypoints in NED (m) relative to the start; the first leg sets the initial heading.
    speed : float
        Speed (m/s).
    rate_hz : float
        Sample rate (Hz).
    rest : float
        Rest at each end (s).
    accel_time : float
        Time to reach ``speed`` (s); the distance covered meanwhile is taken off the first leg.
    bank : bool
        Bank as an aircraft in coordinated turns.
    **kwargs
        Passed to :func:`make_trajectory` (lat0, lon0, h0, earth_rate).
    """
    p = _check_finite("points_n", points_n)
    if p.ndim != 2 or p.shape[1] not in (2, 3) or len(p) < 1:
        raise ValueError(f"points_n must have shape (K, 2) or (K, 3), got {p.shape}")
    if p.shape[1] == 2:
        p = np.column_stack([p, np.zeros(len(p))])
    speed = _check_positive("speed", speed)
    first = p[0]
    d = np.linalg.norm(first)
    run = 0.5 * speed * accel_time  # distance covered by the raised-cosine acceleration
    if d <= run + 1e-6:
        raise ValueError("points_n: the first leg is shorter than the acceleration run "
                         f"({run:.2f} m); reduce accel_time or move the first point")
    u = first / d
    yaw0 = np.arctan2(u[1], u[0])
    path0 = np.arctan2(-u[2], np.hypot(u[0], u[1]))
    segs = [Rest(rest), Accelerate(accel_time, to_speed=speed),
            WaypointPath(p - run * u, speed, bank=bank)]
    segs += [Accelerate(accel_time, to_speed=0.0), Rest(rest)]
    return make_trajectory(segs, rate_hz, rpy0=(0.0, path0, yaw0), **kwargs)
