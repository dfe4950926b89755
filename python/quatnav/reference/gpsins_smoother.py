"""The Rauch-Tung-Striebel smoother of the numpy GpsInsFilter (``quatnav.reference.gpsins``), the
twin of ``cpp/include/quatnav/nav/gps_ins/smoother.hpp``.
"""
from __future__ import annotations

import numpy as np

from ..core import quaternion as Q
from ..core.strapdown import StrapdownState
from .gpsins_model import _new_state, geodetic_diff, inject
from .smoother import Recorder


class GpsInsRtsModel:
    """The smoother's model of :class:`GpsInsFilter` (``quatnav.reference.smoother``): a snapshot
    is the posterior ``(lat, lon, h, baro_offset, q_nb, v_n, acc_bias, gyro_bias, P, breaks,
    baro_valid)`` while navigating (``breaks``: resets to a fix and covariance inflations so far),
    then ``(acc_scale, gyro_scale)`` with the scale factors; the error chart is the filter's
    (estimate minus truth):
    ``local(base, x)`` the error of ``base`` if ``x`` were the truth, ``retract(base, d)`` the
    injection of the error ``d`` into ``base``. ``f``: the filter whose run is recorded (its
    ``sample_transition``)."""

    def __init__(self, f):
        self.f = f

    def snapshot(self, f):
        if not f.navigating:
            return None
        s = f.s
        post = (s.nav.lat, s.nav.lon, s.nav.h, s.baro_offset, s.nav.q_nb.copy(), s.nav.v_n.copy(),
                s.acc_bias.copy(), s.gyro_bias.copy(), s.P.copy(),
                sum(c["resets"] + c["inflated"] for c in s.counters.values()),
                s.baro_offset_valid)
        return post + (s.acc_scale.copy(), s.gyro_scale.copy()) if f.scale_factors else post

    @staticmethod
    def same(a, b):
        return all(np.array_equal(x, y) for x, y in zip(a, b))

    @staticmethod
    def restart(prior, post):
        """A reset to a fix, a covariance inflation or the initialization of the altimeter offset:
        not crossed (nav/gps_ins/smoother.hpp says why)."""
        return prior[9] != post[9] or prior[10] != post[10]

    def transition(self, post, k):
        return self.f.sample_transition

    @staticmethod
    def error_covariance(x):
        return x[8]

    @staticmethod
    def local(base, x):
        d = np.concatenate([geodetic_diff(base[0], base[1], base[2], x[0], x[1], x[2]), base[5] - x[5],
                            Q.to_rotvec(Q.mul(base[4], Q.conj(x[4]))), base[6] - x[6], base[7] - x[7],
                            [base[3] - x[3]]])
        return np.concatenate([d, base[11] - x[11], base[12] - x[12]]) if len(base) > 11 else d

    @staticmethod
    def retract(base, d, Ps):
        s = _new_state()
        s.nav = StrapdownState(q_nb=base[4], v_n=base[5], lat=base[0], lon=base[1], h=base[2])
        s.acc_bias, s.gyro_bias, s.baro_offset = base[6], base[7], base[3]
        if len(base) > 11:
            s.acc_scale, s.gyro_scale = base[11], base[12]
        inject(s, d)
        x = (s.nav.lat, s.nav.lon, s.nav.h, s.baro_offset, s.nav.q_nb, s.nav.v_n, s.acc_bias, s.gyro_bias, Ps,
             base[9], base[10])
        return x + (s.acc_scale, s.gyro_scale) if len(base) > 11 else x


class _GpsInsRecorder(Recorder):
    """The record, with the filter's restarts (no link across them)."""

    def after_predict(self, k, f):
        super().after_predict(k, f)
        if self._pending is not None and not isinstance(self._pending[1], str):
            self._prior = self._pending[1][0]
        else:
            self._prior = None

    def after_sample(self, k, f):
        pending = self._pending
        prior = getattr(self, "_prior", None)
        super().after_sample(k, f)
        if pending is not None and prior is not None and self.links and self.posts:
            if pending[0] == k and self.model.restart(prior, self.posts[-1]):
                self.links[-1] = None
        self._prior = None


class _Both:
    """Two observers of one run, in order."""

    def __init__(self, a, b):
        self.a, self.b = a, b

    def after_predict(self, k, f):
        self.a.after_predict(k, f)
        self.b.after_predict(k, f)

    def after_sample(self, k, f):
        self.a.after_sample(k, f)
        self.b.after_sample(k, f)


def run_smoothed(f, gyr, acc, mag=None, *, t=None, dt=None, gps_pos=None, gps_vel=None, baro=None, compass=None,
                 odometer=None, outages=(), imu_input="rate", observer=None, gps_solution=None):
    """:meth:`GpsInsFilter.run` (the same arguments) followed by the backward pass. Returns
    ``(out, smoothed)``: the forward dict and ``{"llh", "v_n", "q_nb", "acc_bias", "gyro_bias",
    "sigma", "baro_offset"}`` (and ``"acc_scale", "gyro_scale"`` with the scale factors), the
    smoothed values at the navigating samples and the forward ones elsewhere. ``observer``: also
    told of every sample (after the smoother's record)."""
    rec = _GpsInsRecorder(GpsInsRtsModel(f))
    out = f.run(gyr, acc, mag, t=t, dt=dt, gps_pos=gps_pos, gps_vel=gps_vel, baro=baro, compass=compass,
                odometer=odometer, outages=outages, imu_input=imu_input, gps_solution=gps_solution,
                observer=rec if observer is None else _Both(rec, observer))
    keys = ("llh", "v_n", "q_nb", "acc_bias", "gyro_bias", "sigma", "baro_offset")
    sm = {k: np.array(out[k], dtype=float, copy=True)
          for k in keys + (("acc_scale", "gyro_scale") if f.scale_factors else ())}
    if rec.first is None:
        return out, sm
    first, xs, Ps = rec.smooth()
    for i, (x, P) in enumerate(zip(xs, Ps)):
        k = first + i
        sm["llh"][k] = x[0:3]
        sm["v_n"][k], sm["q_nb"][k], sm["acc_bias"][k], sm["gyro_bias"][k] = x[5], x[4], x[6], x[7]
        sm["sigma"][k] = np.sqrt(np.maximum(np.diag(P), 0.0))
        sm["baro_offset"][k] = x[3] if x[10] else np.nan
        if f.scale_factors:
            sm["acc_scale"][k], sm["gyro_scale"][k] = x[11], x[12]
    return out, sm
