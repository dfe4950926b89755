"""``quatnav compare RUN REF``: differences between two tracks aligned in time.

Each file is read by :func:`quatnav.io.read`: the output of ``quatnav ahrs run`` / ``ins run``
(CSV or Parquet), a log with its own estimate (PX4 ``vehicle_attitude`` and local/global
position), a truth CSV, or a GNSS solution (RTKLIB, NMEA: position and velocity only). REF is
interpolated onto RUN's times inside their common span: quaternions by slerp, the rest
linearly. The attitude error ``q_err = q_run * conj(q_ref)`` is split as in
:mod:`quatnav.evaluation.metrics` into heading and inclination; positions into horizontal and
vertical (NED about REF's first point); velocities when both have them. For each: RMS, max,
median (p50), p95.
"""
from __future__ import annotations

import argparse
import math

import numpy as np

from ..core import earth as E
from ..core import quaternion as Q
from ..evaluation import metrics as M
from .._command import UsageError, write_json

EPILOG = """\
inputs: any file quatnav.io.read knows; a CSV track has time and q_w..q_z (ahrs run output) or
  roll, pitch, yaw (deg), and/or lat, lon (deg), h (m), v_n, v_e, v_d (m/s) (ins run output);
  a ULog gives PX4's own estimate (vehicle_attitude, vehicle_local/global_position); an RTKLIB
  or NMEA file gives positions. Both on one clock (seconds).
output: a table of RMS, max, p50, p95 of: attitude total, heading, inclination (deg);
  horizontal and vertical position (m) and velocity (m/s) when both tracks have them.
--json FILE writes the figures; --plot FILE.png plots the differences over time.
exit status: 0 on success, 2 on an input error (no common time span, no common quantity)."""


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


def compare(run_log, ref_log) -> dict:
    """The figures of ``quatnav compare`` for two Logs: {quantity: stats} plus 'span'."""
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


def add_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``quatnav compare``."""
    p = subparsers.add_parser("compare", help="differences between two tracks (attitude, position, velocity)",
                              description="Compare RUN with REF, aligned in time (REF interpolated, slerp for "
                                          "quaternions): RMS, max, p50, p95 of the differences.",
                              epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run", metavar="RUN", help="the track to judge (e.g. the output of 'ahrs run')")
    p.add_argument("ref", metavar="REF", help="the reference (truth, or a log with its own estimate)")
    p.add_argument("--run-format", default="auto", help="format of RUN (default: detected)")
    p.add_argument("--ref-format", default="auto", help="format of REF (default: detected)")
    p.add_argument("--plot", metavar="FILE.png", help="plot the differences over time")
    p.add_argument("--json", metavar="FILE", help="write the figures as JSON ('-': to stdout)")
    p.set_defaults(func=_run)
    return p


def _read_track(path, fmt):
    from .. import io
    if str(path).lower().endswith(".parquet"):
        import pandas as pd
        import tempfile, os
        try:
            df = pd.read_parquet(path)
        except ImportError:
            raise UsageError(f"{path}: reading Parquet needs pyarrow: pip install 'quatnav[logs]'") from None
        with tempfile.TemporaryDirectory() as d:
            p = os.path.join(d, "track.csv")
            df.to_csv(p, index=False)
            log = io.read(p, format="csv", kind="reference")
        log.source = str(path)
        return log
    return io.read(path, format=fmt)


def _run(args) -> int:
    a = _read_track(args.run, args.run_format)
    b = _read_track(args.ref, args.ref_format)
    res = compare(a, b)
    series = res.pop("_series")
    print(f"{args.run} against {args.ref}, common span {res['span'][0]:.3f} .. {res['span'][1]:.3f} s")
    print(f"{'quantity':28s} {'rms':>10s} {'max':>10s} {'p50':>10s} {'p95':>10s} {'n':>8s}")
    for k, s in res.items():
        if k == "span":
            continue
        print(f"{k:28s} {s['rms']:10.4g} {s['max']:10.4g} {s['p50']:10.4g} {s['p95']:10.4g} {s['n']:8d}")
    write_json(res, args)
    if args.plot:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        fig, ax = plt.subplots(2, 1, figsize=(9, 5))
        if "t_att" in series:
            for k in ("heading", "inclination"):
                ax[0].plot(series["t_att"], series[k], label=k)
            ax[0].set_ylabel("attitude difference, deg")
            ax[0].legend(fontsize=7)
        if "t_pos" in series:
            ax[1].plot(series["t_pos"], series["horizontal"], label="horizontal")
            ax[1].plot(series["t_pos"], series["vertical"], label="vertical")
            ax[1].set_ylabel("position difference, m")
            ax[1].legend(fontsize=7)
        ax[1].set_xlabel("t, s")
        fig.tight_layout()
        fig.savefig(args.plot, dpi=90)
        plt.close(fig)
        print(f"wrote {args.plot}")
    return 0
