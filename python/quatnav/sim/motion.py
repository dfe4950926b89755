"""Fast-motion segments: what a body-worn, hand-held or swinging sensor goes through.

Each segment is a smooth analytic function of its local time (so :func:`make_trajectory` gives
exact truth), starts and ends at rest (the motion fades in and out over ``ramp`` seconds) and
composes with the segments of :mod:`quatnav.sim.trajectory`:

* :class:`Pendulum`: the sensor hanging at ``length`` below a pivot, swinging (a spherical
  pendulum with an elliptic swing and a twist about the string): centripetal acceleration
  ``length * rate^2`` along the string, up to about g.
* :class:`LimbSwing`: a sensor on the forearm of a swinging arm (shoulder and elbow swinging
  with a phase lag, the forearm twisting) while the body walks or runs: rates of several hundred
  deg/s and centripetal accelerations of 1-3 g.
* :class:`Running`: a torso-mounted sensor while running: foot-strike impacts (a periodic train
  of short vertical pulses, 2-4 g), the trunk's roll / pitch / yaw sway at the stride and step
  frequencies, and the course weaving left and right (sustained centripetal acceleration).
* :class:`Shaking`: a hand shaking the sensor while turning it slowly: random rotations and
  translations at 2-7 Hz (linear accelerations of 1-2 g).
* :class:`Vibration`: wraps another segment and adds a vibration along the body axes
  (tens of Hz, several m/s^2) with a small angular vibration.

Each attitude is ``q_nb(tau) = q_nav(tau) * q_nb(0) * q_body(tau)``: a rotation in the navigation
frame applied to the start attitude, times a body-frame twist. Velocities are either given in
closed form or the 5-point central difference (step 1e-4 s) of a closed-form position.
"""
from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import Optional, Sequence

import numpy as np

from ..core import quaternion as quat
from .trajectory import MotionState, Segment, _check_finite, _check_positive, _window

__all__ = ["Pendulum", "LimbSwing", "Running", "Shaking", "Vibration"]

_H = 1e-4  # s, step of the position differences
_C1 = np.array([1.0, -8.0, 0.0, 8.0, -1.0]) / (12.0 * _H)
_ST = np.array([-2.0, -1.0, 0.0, 1.0, 2.0]) * _H


def _unit(yaw):
    return np.array([np.cos(yaw), np.sin(yaw), 0.0])


def _lateral(yaw):
    return np.array([-np.sin(yaw), np.cos(yaw), 0.0])


class _Motion(Segment):
    """Base of the motions that start and end at rest (see the module text)."""

    ramp: float
    duration: float

    def _check(self):
        _check_positive("duration", self.duration)
        _check_positive("ramp", self.ramp)
        if 2 * self.ramp > self.duration:
            raise ValueError(f"ramp={self.ramp} must be at most half the duration {self.duration}")

    def _rotation(self, tau, s0):
        """(q_nav (n, 4), q_body (n, 4) or None)."""
        raise NotImplementedError

    def _position(self, tau, s0):
        """(n, 3) NED offset from the start (m); None: no translation."""
        return None

    def _velocity(self, tau, s0):
        """(n, 3) NED velocity; default: the derivative of :meth:`_position`."""
        n = tau.shape[0]
        p = self._position((tau[:, None] + _ST[None, :]).reshape(-1), s0)
        if p is None:
            return np.zeros((n, 3))
        return np.einsum("j,njc->nc", _C1, p.reshape(n, 5, 3))

    def evaluate(self, tau, s0: MotionState):
        if abs(s0.speed) > 1e-12 or np.linalg.norm(s0.v_n) > 1e-12:
            raise ValueError(f"{type(self).__name__}: start it from rest")
        tau = np.asarray(tau, float)
        q_nav, q_body = self._rotation(tau, s0)
        q = quat.mul(q_nav, np.broadcast_to(s0.q_nb, q_nav.shape))
        if q_body is not None:
            q = quat.mul(q, q_body)
        return q, self._velocity(tau, s0)

    def end_state(self, s0):
        q, _ = self.evaluate(np.array([self.duration]), s0)
        rpy = quat.to_euler(q[0])
        rpy[2] = s0.rpy[2] + np.angle(np.exp(1j * (rpy[2] - s0.rpy[2])))  # yaw kept unwrapped
        return dataclasses.replace(s0, rpy=rpy, q_nb=q[0], speed=0.0, v_n=np.zeros(3))


def _twist(s0, angle):
    """Body-frame rotations by ``angle`` (n,) about the body axis that points down at the start."""
    axis = quat.rotate_inv(s0.q_nb, np.array([0.0, 0.0, 1.0]))
    return quat.from_rotvec(np.asarray(angle, float)[:, None] * axis)


@dataclass(frozen=True)
class Pendulum(_Motion):
    """A sensor hanging ``length`` (m) below a pivot, swinging.

    The swing angle about the horizontal axis at heading ``axis_yaw`` (rad) is
    ``amplitude * sin(2 pi tau / period)``, with ``cone * amplitude * cos(...)`` about the axis
    perpendicular to it (an elliptic, spherical-pendulum swing); the sensor twists about the string
    by ``twist * sin(pi tau / period)``. ``period`` defaults to that of a simple pendulum,
    ``2 pi sqrt(length / 9.81)``. Amplitudes fade in and out over ``ramp``.
    """

    duration: float
    length: float = 0.8
    amplitude: float = 1.0
    period: Optional[float] = None
    cone: float = 0.3
    twist: float = 0.3
    axis_yaw: float = 0.0
    ramp: float = 3.0

    def __post_init__(self):
        self._check()
        _check_positive("length", self.length)
        _check_positive("amplitude", self.amplitude, allow_zero=True)
        if self.period is not None:
            _check_positive("period", self.period)

    def _omega(self):
        return 2.0 * np.pi / (self.period if self.period else 2.0 * np.pi * np.sqrt(self.length / 9.81))

    def _rotvec(self, tau):
        w, _, _ = _window(tau, self.duration, self.ramp)
        ph = self._omega() * tau
        a1, a2 = _unit(self.axis_yaw), _lateral(self.axis_yaw)
        return (self.amplitude * w * np.sin(ph))[:, None] * a1 + (self.cone * self.amplitude * w * np.cos(ph))[:, None] * a2

    def _rotation(self, tau, s0):
        w, _, _ = _window(tau, self.duration, self.ramp)
        return quat.from_rotvec(self._rotvec(tau)), _twist(s0, self.twist * w * np.sin(0.5 * self._omega() * tau))

    def _position(self, tau, s0):
        r0 = np.array([0.0, 0.0, self.length])
        return quat.rotate(quat.from_rotvec(self._rotvec(tau)), np.broadcast_to(r0, (tau.shape[0], 3))) - r0


@dataclass(frozen=True)
class LimbSwing(_Motion):
    """A sensor on the forearm (at ``lower`` m from the elbow) of an arm swinging at ``freq`` (Hz)
    while the body moves at ``speed`` (m/s) towards ``heading`` (rad).

    Shoulder angle ``shoulder * sin(2 pi f tau)``; elbow ``bend + elbow * sin(2 pi f tau - lag)``
    (rad, about the body's lateral axis; the forearm's angle is their sum); the forearm twists by
    ``twist * sin(2 pi f tau + 1)``; the shoulder bobs by ``bounce`` (m) twice per swing (two steps).
    """

    duration: float
    freq: float = 0.9
    shoulder: float = 0.6
    elbow: float = 0.5
    bend: float = 0.4
    lag: float = 0.6
    twist: float = 0.5
    upper: float = 0.30
    lower: float = 0.25
    speed: float = 1.4
    heading: float = 0.0
    bounce: float = 0.04
    ramp: float = 3.0

    def __post_init__(self):
        self._check()
        for name in ("freq", "upper", "lower"):
            _check_positive(name, getattr(self, name))
        _check_positive("speed", self.speed, allow_zero=True)

    def _angles(self, tau):
        w, _, integ = _window(tau, self.duration, self.ramp)
        ph = 2.0 * np.pi * self.freq * tau
        th1 = self.shoulder * w * np.sin(ph)
        th2 = th1 + w * (self.bend + self.elbow * np.sin(ph - self.lag))
        return w, integ, ph, th1, th2

    def _rotation(self, tau, s0):
        w, _, ph, _, th2 = self._angles(tau)
        q_nav = quat.from_rotvec(th2[:, None] * _lateral(self.heading))
        return q_nav, _twist(s0, self.twist * w * np.sin(ph + 1.0))

    def _position(self, tau, s0):
        w, integ, ph, th1, th2 = self._angles(tau)
        lat = _lateral(self.heading)
        down = np.array([0.0, 0.0, 1.0])

        def hang(th, length):
            return quat.rotate(quat.from_rotvec(th[:, None] * lat), np.broadcast_to(down * length, (tau.shape[0], 3)))

        p = (self.speed * integ)[:, None] * _unit(self.heading)
        p[:, 2] -= self.bounce * w * np.sin(ph) ** 2
        return p + hang(th1, self.upper) + hang(th2, self.lower) - down * (self.upper + self.lower)


@dataclass(frozen=True)
class Running(_Motion):
    """A torso-mounted sensor while running at ``speed`` (m/s), ``cadence`` steps per second.

    Vertical: a foot-strike impact at every step, a Gaussian pulse of upward acceleration of
    height ``impact`` (m/s^2) and width ``impact_width`` (s, standard deviation), less its mean
    (a Fourier series up to 60 Hz): the sensor reads about ``g + impact`` at the strike and less
    than g in flight. Trunk sway ``sway`` = (roll, pitch, yaw) amplitudes (rad): roll and yaw at
    the stride frequency (half the cadence), pitch at the cadence. The course weaves:
    ``weave * sin(2 pi tau / weave_period)`` (rad), a sustained centripetal acceleration of
    ``speed * d(course)/dt``.
    """

    duration: float
    speed: float = 3.0
    cadence: float = 2.8
    impact: float = 20.0
    impact_width: float = 0.025
    sway: Sequence[float] = (0.06, 0.05, 0.12)
    weave: float = 1.2
    weave_period: float = 30.0
    ramp: float = 3.0

    def __post_init__(self):
        self._check()
        for name in ("speed", "cadence", "impact_width", "weave_period"):
            _check_positive(name, getattr(self, name))
        _check_positive("impact", self.impact, allow_zero=True)
        s = _check_finite("sway", self.sway)
        if s.shape != (3,):
            raise ValueError(f"sway must be 3 amplitudes (rad), got {self.sway!r}")

    def _course(self, tau):
        w, _, _ = _window(tau, self.duration, self.ramp)
        return self.weave * w * np.sin(2.0 * np.pi * tau / self.weave_period)

    def _rotation(self, tau, s0):
        w, _, _ = _window(tau, self.duration, self.ramp)
        sr, sp, sy = np.asarray(self.sway, float)
        ph = np.pi * self.cadence * tau  # stride phase (half the cadence)
        d = np.column_stack([sr * w * np.sin(ph), sp * w * np.sin(2.0 * ph + 0.4), sy * w * np.sin(ph + 0.8)])
        q = quat.from_euler(s0.rpy + d + np.column_stack([np.zeros((len(tau), 2)), self._course(tau)]))
        return quat.mul(q, quat.conj(np.broadcast_to(s0.q_nb, q.shape))), None

    def _velocity(self, tau, s0):
        w, _, _ = _window(tau, self.duration, self.ramp)
        course = s0.rpy[2] + self._course(tau)
        v = (self.speed * w)[:, None] * np.column_stack([np.cos(course), np.sin(course), np.zeros_like(tau)])
        # vertical: sum_k c_k cos(2 pi k f tau) is the pulse train less its mean; its integral is the
        # upward velocity (NED: down = -up)
        f = self.cadence
        k = np.arange(1, int(60.0 / f) + 1)
        c = 2.0 * self.impact * np.sqrt(2.0 * np.pi) * self.impact_width * f * np.exp(
            -0.5 * (2.0 * np.pi * k * f * self.impact_width) ** 2)
        v_up = np.sin(2.0 * np.pi * f * tau[:, None] * k[None, :]) @ (c / (2.0 * np.pi * k * f))
        v[:, 2] = -w * v_up
        return v


@dataclass(frozen=True)
class Shaking(_Motion):
    """A hand shaking the sensor while turning it slowly: fast rotations (rad per axis, NED) and
    translations (m), sums of ``n_tones`` sinusoids with random frequencies between ``min_freq``
    and ``max_freq`` (Hz) and random phases, scaled to about ``rotation`` / ``translation``
    standard deviation, on top of slow rotations of about ``slow`` (rad) with tones up to
    ``slow_max_freq`` (Hz); all draws from ``seed``."""

    duration: float
    rotation: Sequence[float] = (0.12, 0.12, 0.15)
    translation: float = 0.015
    min_freq: float = 2.0
    max_freq: float = 7.0
    slow: Sequence[float] = (0.4, 0.3, 0.8)
    slow_max_freq: float = 0.2
    n_tones: int = 5
    seed: int = 0
    ramp: float = 2.0

    def __post_init__(self):
        self._check()
        _check_positive("min_freq", self.min_freq)
        _check_positive("slow_max_freq", self.slow_max_freq)
        if not self.max_freq > self.min_freq:
            raise ValueError(f"max_freq={self.max_freq} must exceed min_freq={self.min_freq}")
        rng = np.random.default_rng(self.seed)
        k = int(self.n_tones)
        f = rng.uniform(self.min_freq, self.max_freq, size=(3, 3, k))
        f[2] = rng.uniform(0.2 * self.slow_max_freq, self.slow_max_freq, size=(3, k))
        ph = rng.uniform(0, 2 * np.pi, size=(3, 3, k))
        object.__setattr__(self, "_tones", (f, ph, np.sqrt(2.0 / k)))

    def _sum(self, tau, which, scale):
        f, ph, norm = self._tones
        w, _, _ = _window(tau, self.duration, self.ramp)
        arg = 2 * np.pi * f[which][None] * tau[:, None, None] + ph[which][None]
        return w[:, None] * scale * norm * np.sum(np.sin(arg) - np.sin(ph[which][None]), axis=-1)

    def _rotation(self, tau, s0):
        rv = self._sum(tau, 0, np.asarray(self.rotation, float)) + self._sum(tau, 2, np.asarray(self.slow, float))
        return quat.from_rotvec(rv), None

    def _position(self, tau, s0):
        return self._sum(tau, 1, self.translation) if self.translation > 0 else None


@dataclass(frozen=True)
class Vibration(Segment):
    """``segment`` with a vibration along the body axes added: accelerations of amplitude
    ``accel`` (m/s^2) at ``freqs`` (Hz, one per body axis) and an angular vibration of amplitude
    ``angular`` (rad) at the same frequencies, fading in and out over ``ramp``."""

    segment: Segment
    accel: float = 8.0
    freqs: Sequence[float] = (47.0, 53.0, 59.0)
    angular: float = 0.002
    ramp: float = 1.0
    duration: float = 0.0  # that of ``segment`` (a different one is given to it)

    def __post_init__(self):
        if not self.duration:
            object.__setattr__(self, "duration", float(self.segment.duration))
        elif self.duration != self.segment.duration:  # make_trajectory rounds durations to samples
            object.__setattr__(self, "segment", dataclasses.replace(self.segment, duration=self.duration))
        _check_positive("accel", self.accel, allow_zero=True)
        f = _check_finite("freqs", self.freqs)
        if f.shape != (3,) or np.any(f <= 0):
            raise ValueError(f"freqs must be 3 positive frequencies (Hz), got {self.freqs!r}")

    def evaluate(self, tau, s0):
        tau = np.asarray(tau, float)
        q, v = self.segment.evaluate(tau, s0)
        w, _, _ = _window(tau, self.duration, self.ramp)
        om = 2.0 * np.pi * np.asarray(self.freqs, float)
        arg = om[None, :] * tau[:, None]
        dq = quat.from_rotvec(self.angular * w[:, None] * np.sin(arg + 1.3))
        q = quat.mul(q, dq)
        v_b = -(self.accel / om)[None, :] * w[:, None] * np.cos(arg)
        return q, v + quat.rotate(q, v_b)

    def end_state(self, s0):
        return self.segment.end_state(s0)
