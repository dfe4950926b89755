"""Speed of the strapdown mechanization: numpy twin against the C++ batch (float64, float32),
and of trajectory generation. Run: PYTHONPATH=python python bench/bench_strapdown.py"""
import time

import numpy as np

from quatnav.sim import Cruise, Turn, make_trajectory
from quatnav.core.strapdown import StrapdownState, strapdown_run
from quatnav.filters.strapdown import strapdown_run_cpp


def timed(fn, repeat=3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def main():
    segs = [Cruise(100.0), Turn(110.0, rate=0.1, ramp=1.0)]
    t_gen = timed(lambda: make_trajectory(segs, 100.0, speed0=2.0, t_end=200.0), repeat=2)
    tr = make_trajectory(segs, 100.0, speed0=2.0, t_end=200.0)
    s = StrapdownState(tr.q_nb[0], tr.v_n[0], tr.lat[0], tr.lon[0], tr.h[0])
    w, f, n = tr.omega_mean_b[1:], tr.f_mean_b[1:], len(tr) - 1
    t_py = timed(lambda: strapdown_run(s, w, f, tr.dt), repeat=1)
    t_cd = timed(lambda: strapdown_run_cpp(s, w, f, tr.dt))
    t_cf = timed(lambda: strapdown_run_cpp(s, w, f, tr.dt, dtype=np.float32))
    print(f"trajectory generation, {n + 1} samples: {t_gen * 1e3:.0f} ms")
    for name, t in (("numpy", t_py), ("C++ float64", t_cd), ("C++ float32", t_cf)):
        print(f"strapdown {name:12s} {n} steps: {t * 1e3:8.1f} ms  ({t / n * 1e9:7.0f} ns/step)")


if __name__ == "__main__":
    main()
