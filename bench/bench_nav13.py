"""Cost of one NavFilter13 time update (EKF, second order, UKF) in C++, float64: the median over
repeats of the mean of consecutive predicts, the three policies interleaved in every repeat.
Run: PYTHONPATH=python python bench/bench_nav13.py [repeats] [iterations]"""
import sys

from quatnav import _core


def main():
    repeats = int(sys.argv[1]) if len(sys.argv) > 1 else 21
    iterations = int(sys.argv[2]) if len(sys.argv) > 2 else 2000
    d = _core.nav13_time_update_cost_ns(repeats=repeats, iterations=iterations)
    for k in ("ekf", "second_order", "ukf"):
        print(f"{k:13s} {d[k]:8.0f} ns per time update ({d[k] / d['ekf']:.2f} x EKF)")


if __name__ == "__main__":
    main()
