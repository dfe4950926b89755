"""Time and peak memory of the Rauch-Tung-Striebel smoother (docs/SMOOTHING.md) against the
forward run alone, for N samples.

    python bench/bench_smoother.py --filter qekf --n 1e5,1e6,1e7 [--json FILE]
    python bench/bench_smoother.py --filter nav13 --n 1e5,1e6,1e7
    python bench/bench_smoother.py --filter gpsins --n 1e5,1e6,1e7

Every (filter, N, mode) runs in its own process under ``/usr/bin/time -v`` (when present): its
maximum resident set size is the process's peak memory, whatever allocated it (numpy, the
C++ record). Inside, the run call alone is timed (``time.perf_counter``), the peak of the numpy
buffers is read with :mod:`tracemalloc` (numpy registers them; the C++ record is not, and is
reported by the smoother itself: ``smoother["bytes"]``). Wall times depend on the machine's load
(printed); the memory figures do not.

Data: ``qekf``/``euler``: the simulated hand-held MARG samples of ``quatnav bench``
(:func:`quatnav.evaluation.bench.marg_data`, 200 Hz); ``nav13``: an IMU at rest (gravity and the
Earth rate with the filter's noise densities) at 100 Hz with zero NED velocity and yaw measured at
10 Hz; ``gpsins``: the same at 200 Hz with GNSS position and velocity and a compass at 5 Hz (the rest detection
off, as on a moving vehicle: the records are the GNSS epochs).
"""
from __future__ import annotations

import argparse
import json
import os
import re
import shutil
import subprocess
import sys
import time
import tracemalloc

import numpy as np


def _data(name: str, n: int):
    if name in ("qekf", "euler"):
        from quatnav.evaluation.bench import marg_data
        d = marg_data(n)
        return dict(gyr=d.gyr, acc=d.acc, mag=d.mag, dt=d.dt)
    # A level IMU at rest, x north, at 0.6 rad latitude and 50 m: gravity and the Earth rate
    # (quatnav.core.earth) with white noise at the filter's densities, 100 Hz; zero NED velocity
    # and yaw measured at 10 Hz: consistent for any length (a moving signal made up of sines is
    # not, and the filter drifts off it over hours).
    from quatnav.core import earth
    dt = 0.005 if name == "gpsins" else 0.01
    t = np.arange(1, n + 1) * dt
    rng = np.random.default_rng(0)
    g = earth.gravity_n(0.6, 50.0)[2]
    w_ie = earth.earth_rate_n(0.6)
    f = np.array([0.0, 0.0, -g]) + 2.9420e-5 / np.sqrt(dt) * rng.standard_normal((n, 3))
    w = w_ie + 1.4544e-7 / np.sqrt(dt) * rng.standard_normal((n, 3))
    k = np.arange(9, n, 10) if name != "gpsins" else np.arange(39, n, 40)
    return dict(gyr=w, acc=f, t=t, kv=k)


def _run(name: str, n: int, smooth: bool) -> dict:
    import quatnav
    d = _data(name, n)
    tracemalloc.start()
    base = tracemalloc.get_traced_memory()[0]
    t0 = time.perf_counter()
    if name in ("qekf", "euler"):
        f = quatnav.QuaternionEKF() if name == "qekf" else quatnav.EulerEKF()
        r = f.run(d["gyr"], d["acc"], d["mag"], dt=d["dt"], smooth=smooth)
    elif name == "gpsins":
        f = quatnav.GpsInsFilter(zupt=False)
        kv = d["kv"]
        tg = d["t"][kv]
        r = f.run(d["gyr"], d["acc"], t=d["t"], smooth=smooth,
                  gps_pos=quatnav.Aid(tg, np.tile([0.6, 2.0, 50.0], (len(kv), 1))),
                  gps_vel=quatnav.Aid(tg, np.zeros((len(kv), 3))), compass=quatnav.Aid(tg, np.zeros(len(kv))))
    else:
        f = quatnav.NavFilter13()
        f.reset([0.0, 0.0, 0.0], [1.0, 0.0, 0.0, 0.0], lat=0.6, lon=2.0, h=50.0)
        kv = d["kv"]
        r = f.run(d["gyr"], d["acc"], t=d["t"], gps_vel=quatnav.Aid(d["t"][kv], np.zeros((len(kv), 3))),
                  yaw=quatnav.Aid(d["t"][kv], np.zeros(len(kv))), smooth=smooth)
    elapsed = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1] - base
    tracemalloc.stop()
    out = dict(filter=name, n=n, smooth=smooth, run_s=elapsed, numpy_peak_bytes=int(peak))
    if smooth:
        out["smoother"] = {k: (int(v) if not isinstance(v, str) else v) for k, v in r.smoother.items()}
    return out


def _child(name: str, n: int, smooth: bool) -> dict:
    cmd = [sys.executable, __file__, "--one", name, str(n), "1" if smooth else "0"]
    timer = shutil.which("time") and os.path.exists("/usr/bin/time")
    if timer:
        cmd = ["/usr/bin/time", "-v"] + cmd
    p = subprocess.run(cmd, capture_output=True, text=True, check=True)
    res = json.loads(p.stdout.strip().splitlines()[-1])
    if timer:
        m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr)
        res["max_rss_bytes"] = int(m.group(1)) * 1024 if m else None
    res["load_avg"] = os.getloadavg()
    return res


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--filter", default="qekf", choices=("qekf", "euler", "nav13", "gpsins"))
    ap.add_argument("--n", default="1e5,1e6", help="comma list of sample counts (default 1e5,1e6)")
    ap.add_argument("--json", default=None, metavar="FILE")
    ap.add_argument("--one", nargs=3, help=argparse.SUPPRESS)
    a = ap.parse_args(argv)
    if a.one:
        print(json.dumps(_run(a.one[0], int(a.one[1]), a.one[2] == "1")))
        return 0
    rows = []
    for n in (int(float(x)) for x in a.n.split(",")):
        fwd, sm = _child(a.filter, n, False), _child(a.filter, n, True)
        rows.append(dict(n=n, forward=fwd, smoothed=sm))
        mb = 1 / 2**20
        print(f"{a.filter} N={n:.0e}: forward {fwd['run_s']:.2f} s, max RSS {fwd.get('max_rss_bytes', 0) * mb:.0f} MiB; "
              f"smoothed {sm['run_s']:.2f} s, max RSS {sm.get('max_rss_bytes', 0) * mb:.0f} MiB, record "
              f"{sm['smoother']['bytes'] * mb:.0f} MiB ({sm['smoother']['records']} records of "
              f"{sm['smoother']['record_bytes']} B); load {sm['load_avg'][0]:.1f}", flush=True)
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(rows, fh, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
