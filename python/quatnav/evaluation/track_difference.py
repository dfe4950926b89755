"""Differences between two tracks aligned in time (what ``quatnav compare`` reports).

Each track is a :class:`quatnav.io.Log`: its ``reference`` (an estimate or a truth: attitude,
position, velocity) or else its GNSS. The reference track is interpolated onto the judged one's
times inside their common span: quaternions by slerp, the rest linearly. The attitude error
``q_err = q_run * conj(q_ref)`` is split as in :mod:`quatnav.evaluation.metrics` into heading and
inclination; positions into horizontal and vertical (NED about the reference's first point);
velocities when both have them. For each: RMS, max, median (p50), p95 (:func:`stats`).

A reference in another convention (most motion-capture systems and BROAD give the attitude as
body to ENU, east-north-up; ROS bodies are forward-left-up) is turned into quatnav's (NED,
forward-right-down) with ``ref_frame="enu"`` and ``ref_body="flu"`` (:func:`to_ned_frd`); the
common mismatch, an attitude difference of about 180 deg that one of these would remove, is
named in an :class:`~quatnav.AxesWarning`.
"""
from __future__ import annotations

import math
import warnings

import numpy as np

from ..core import earth as E
from ..core import quaternion as Q
from ..plausibility.categories import AxesWarning
from . import metrics as M

__all__ = ["slerp_at", "stats", "attitude_difference", "track", "compare_tracks", "to_ned_frd", "FRAMES", "BODIES"]

#: Navigation frames and body axes a reference may be given in.
FRAMES = ("ned", "enu")
BODIES = ("frd", "flu")
#: Body to body: forward-right-down in forward-left-up axes (a roll of 180 deg).
_Q_FLU_FRD = np.array([0.0, 1.0, 0.0, 0.0])


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


def to_ned_frd(quat=None, vec=None, frame: str = "ned", body: str = "frd"):
    """An attitude ``quat`` (N, 4), body to ``frame``, as body forward-right-down to NED, and
    vectors ``vec`` (N, 3) in ``frame`` (velocity, position) in NED: ENU's (east, north, up) are
    NED's (north, east, down) reordered; a forward-left-up body is forward-right-down turned by
    180 deg about x. None stays None."""
    if frame not in FRAMES or body not in BODIES:
        raise ValueError(f"frame, body: expected one of {FRAMES} and {BODIES}, got {frame!r}, {body!r}")
    q, v = quat, vec
    if q is not None:
        q = np.asarray(q, float)
        if frame == "enu":
            q = Q.enu_to_ned(q)
        if body == "flu":
            q = Q.mul(q, _Q_FLU_FRD)
    if v is not None and frame == "enu":
        v = np.asarray(v, float)[:, [1, 0, 2]] * [1.0, 1.0, -1.0]
    return q, v


def _frame_hint(t, q, tr, qr_given, frame, body, where):
    """An AxesWarning when the attitude differs by more than 30 deg (median) with the reference
    ``qr_given`` (as given) read in ``frame``/``body``, and reading it in another convention
    brings that below a quarter and below 30 deg (or None)."""
    def median(f, b):
        d = attitude_difference(t, q, tr, to_ned_frd(qr_given, None, f, b)[0])["total_deg"]
        return float(np.median(d)) if d.size else math.nan
    now = median(frame, body)
    if not now > 30.0:
        return None
    m, f, b = min((median(f, b), f, b) for f in FRAMES for b in BODIES if (f, b) != (frame, body))
    if not (m < 30.0 and m < 0.25 * now):
        return None
    opts = " ".join(x for x in (f"--ref-frame {f}" if f != "ned" else "", f"--ref-body {b}" if b != "frd" else "") if x)
    kw = ", ".join(x for x in (f"ref_frame={f!r}" if f != "ned" else "", f"ref_body={b!r}" if b != "frd" else "") if x)
    return AxesWarning(
        f"{where}: the attitude differs by {now:.1f} deg (median) with the reference read as {frame.upper()}, body "
        f"{body.upper()}, and by {m:.1f} deg read as {f.upper()}, body {b.upper()}: the reference looks like "
        f"{'east-north-up' if f == 'enu' else 'north-east-down'} with a "
        f"{'forward-left-up' if b == 'flu' else 'forward-right-down'} body, as most motion-capture systems give it; "
        f"compare with {opts or '--ref-frame ned --ref-body frd'} ({kw or 'the defaults'})")


def compare_tracks(run_log, ref_log, *, ref_frame: str = "ned", ref_body: str = "frd") -> dict:
    """The figures of ``quatnav compare`` for two :class:`quatnav.io.Log`: {quantity: stats} plus
    'span' (the common time span, s) and '_series' (the differences over time, for a figure).

    ``ref_frame``, ``ref_body``: the conventions of the reference's attitude and vectors
    (:func:`to_ned_frd`); an attitude difference that another convention of the reference would
    remove is named in an :class:`~quatnav.AxesWarning`."""
    t, q, pos, vel = track(run_log)
    tr, qr_given, posr, velr = track(ref_log)
    qr, velr = to_ned_frd(qr_given, velr, ref_frame, ref_body)
    if posr is not None and posr[0] == "ned":
        posr = ("ned", to_ned_frd(None, posr[1], ref_frame, ref_body)[1])
    lo, hi = max(t[0], tr[0]), min(t[-1], tr[-1])
    if not hi > lo:
        raise ValueError(f"{run_log.source} ({t[0]:.3f}..{t[-1]:.3f} s) and {ref_log.source} "
                         f"({tr[0]:.3f}..{tr[-1]:.3f} s): no common time span")
    out = {"span": [float(lo), float(hi)], "ref_frame": ref_frame, "ref_body": ref_body}
    series = {}
    if q is not None and qr is not None:
        d = attitude_difference(t, q, tr, qr)
        series.update(t_att=d["t"])
        for k in ("total", "heading", "inclination"):
            out[f"attitude_{k}_deg"] = stats(d[f"{k}_deg"])
            series[k] = d[f"{k}_deg"]
        hint = _frame_hint(t, q, tr, qr_given, ref_frame, ref_body, str(ref_log.source))
        if hint is not None:
            warnings.warn(hint, stacklevel=2)
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
        series.update(t_vel=t[m], velocity_horizontal=np.hypot(d[:, 0], d[:, 1]))
        if np.isfinite(d[:, 2]).any():
            out["velocity_vertical_m_s"] = stats(d[:, 2])
            series.update(velocity_vertical=d[:, 2])
    if len(out) == 3:
        raise ValueError(f"{run_log.source} and {ref_log.source}: no quantity in common (attitude, position, velocity)")
    out["_series"] = series
    return out
