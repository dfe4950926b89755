"""Differences between two tracks aligned in time (what ``quatnav compare`` reports).

Each track is a :class:`quatnav.io.Log`: its ``reference`` (an estimate or a truth: attitude,
position, velocity) or else its GNSS. The reference track is interpolated onto the judged one's
times inside their common span: quaternions by slerp, the rest linearly. The attitude error
``q_err = q_run * conj(q_ref)`` is split as in :mod:`quatnav.evaluation.metrics` into heading and
inclination; positions into horizontal and vertical (NED about the reference's first point);
velocities when both have them. For each: RMS, max, median (p50), p95 (:func:`stats`).
"""
from __future__ import annotations

import math

import numpy as np

from ..core import earth as E
from ..core import quaternion as Q
from . import metrics as M

__all__ = ["slerp_at", "stats", "attitude_difference", "track", "compare_tracks"]


def slerp_at(t, tr, qr):
    """Quaternions ``qr`` at times ``tr`` interpolated (slerp) at ``t`` (inside [tr[0], tr[-1]])."""
    k = np.clip(np.searchsorted(tr, t, side="right") - 1, 0, len(tr) - 2)
    s = (t - tr[k]) / (tr[k + 1] - tr[k])
    q0, q1 = qr[k], qr[k + 1].copy()
    q1[np.sum(q0 * q1, axis=1) < 0] *= -1
    d = Q.to_rotvec(Q.mul(Q.conj(q0), q1))
    return Q.normalize(Q.mul(q0, Q.from_rotvec(d * s[:, None])))


def _lin(t, tr, x):
    return np.column_stack([np.interp(t, tr, x[:, j]) for j in range(x.shape[1])]) if x.ndim == 2 else np.interp(t, tr, x)


def stats(x) -> dict:
    x = np.abs(np.asarray(x, float))
    x = x[np.isfinite(x)]
    if x.size == 0:
        return dict(rms=math.nan, max=math.nan, p50=math.nan, p95=math.nan, n=0)
    return dict(rms=float(np.sqrt(np.mean(x ** 2))), max=float(x.max()), p50=float(np.percentile(x, 50)),
                p95=float(np.percentile(x, 95)), n=int(x.size))


def attitude_difference(t, q, tr, qr) -> dict:
    """Heading, inclination and total angle (deg) of ``q * conj(qr)`` at the times of ``t`` in
    the span of ``tr``."""
    okr = np.isfinite(qr).all(1)
    tr, qr = tr[okr], qr[okr]
    m = (t >= tr[0]) & (t <= tr[-1]) & np.isfinite(q).all(1)
    e = M.error_quat(q[m], slerp_at(t[m], tr, qr))
    return dict(t=t[m], heading_deg=np.degrees(M.heading_error(e)), inclination_deg=np.degrees(M.inclination_error(e)),
                total_deg=np.degrees(M.total_error(e)))


def track(log):
    """(t, quat or None, position as (lat, lon, h) or p_n or None, vel_n or None) of a Log."""
    r = log.reference
    if r is not None:
        pos = ("geo", r.lat, r.lon, r.h) if r.lat is not None else (("ned", r.p_n) if r.p_n is not None else None)
        return r.t, r.quat, pos, r.vel_n
    g = log.gnss
    if g is not None:
        return g.t, None, ("geo", g.lat, g.lon, g.h), g.vel_n
    raise ValueError(f"{log.source}: no track in it (no attitude, position or GNSS)")


def compare_tracks(run_log, ref_log) -> dict:
    """The figures of ``quatnav compare`` for two :class:`quatnav.io.Log`: {quantity: stats} plus
    'span' (the common time span, s) and '_series' (the differences over time, for a figure)."""
    t, q, pos, vel = track(run_log)
    tr, qr, posr, velr = track(ref_log)
    lo, hi = max(t[0], tr[0]), min(t[-1], tr[-1])
    if not hi > lo:
        raise ValueError(f"{run_log.source} ({t[0]:.3f}..{t[-1]:.3f} s) and {ref_log.source} "
                         f"({tr[0]:.3f}..{tr[-1]:.3f} s): no common time span")
    out = {"span": [float(lo), float(hi)]}
    series = {}
    if q is not None and qr is not None:
        d = attitude_difference(t, q, tr, qr)
        series.update(t_att=d["t"])
        for k in ("total", "heading", "inclination"):
            out[f"attitude_{k}_deg"] = stats(d[f"{k}_deg"])
            series[k] = d[f"{k}_deg"]
    m = (t >= lo) & (t <= hi)
    if pos is not None and posr is not None and pos[0] == posr[0]:
        if pos[0] == "geo":
            ok = np.isfinite(posr[1])
            lat0, lon0, h0 = posr[1][ok][0], posr[2][ok][0], posr[3][ok][0]
            a = E.geodetic_to_ned(pos[1][m], pos[2][m], pos[3][m], lat0, lon0, h0)
            b = E.geodetic_to_ned(_lin(t[m], tr[ok], posr[1][ok]), _lin(t[m], tr[ok], posr[2][ok]),
                                  _lin(t[m], tr[ok], posr[3][ok]), lat0, lon0, h0)
        else:
            a, b = pos[1][m], _lin(t[m], tr, posr[1])
        d = np.asarray(a) - np.asarray(b)
        out["position_horizontal_m"] = stats(np.hypot(d[:, 0], d[:, 1]))
        out["position_vertical_m"] = stats(d[:, 2])
        series.update(t_pos=t[m], horizontal=np.hypot(d[:, 0], d[:, 1]), vertical=d[:, 2])
    if vel is not None and velr is not None:
        d = vel[m] - _lin(t[m], tr, velr)
        out["velocity_horizontal_m_s"] = stats(np.hypot(d[:, 0], d[:, 1]))
        if np.isfinite(d[:, 2]).any():
            out["velocity_vertical_m_s"] = stats(d[:, 2])
    if len(out) == 1:
        raise ValueError(f"{run_log.source} and {ref_log.source}: no quantity in common (attitude, position, velocity)")
    out["_series"] = series
    return out
