"""Write the 1-hour 200 Hz log of the ``quatnav ins run`` benchmark (bench/README.md).

    python bench/make_long_log.py DIR [--hours 1] [--rate 200]

DIR/imu.csv (720,000 rows for one hour at 200 Hz: a level IMU at rest with white noise),
DIR/gnss.csv (5 Hz fixes with velocity and sigmas) and DIR/compass.csv (5 Hz headings), in
the columns of ``quatnav ins run``, seeded (the same files every time). Then:

    quatnav ins run --imu DIR/imu.csv --gnss DIR/gnss.csv --compass DIR/compass.csv --out DIR/out.csv
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np
import pandas as pd


def write(directory, hours=1.0, rate=200.0, seed=0):
    d = Path(directory)
    d.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(seed)
    n = int(round(hours * 3600 * rate))
    t = np.arange(n) / rate
    g = 9.80
    imu = pd.DataFrame({"time": t,
                        "gyro_x": rng.normal(0, 1e-3, n), "gyro_y": rng.normal(0, 1e-3, n),
                        "gyro_z": rng.normal(0, 1e-3, n),
                        "accel_x": rng.normal(0, 0.02, n), "accel_y": rng.normal(0, 0.02, n),
                        "accel_z": rng.normal(-g, 0.02, n)})
    imu.to_csv(d / "imu.csv", index=False, float_format="%.9g")
    m = int(round(hours * 3600 * 5))
    tg = np.arange(m) / 5.0 + 0.1
    lat0, lon0, h0 = 36.37, 127.36, 50.0
    gnss = pd.DataFrame({"time": tg, "lat": lat0 + rng.normal(0, 1e-5, m), "lon": lon0 + rng.normal(0, 1e-5, m),
                         "h": h0 + rng.normal(0, 1.0, m), "v_n": rng.normal(0, 0.05, m),
                         "v_e": rng.normal(0, 0.05, m), "v_d": rng.normal(0, 0.05, m),
                         "sigma_n": 1.0, "sigma_e": 1.0, "sigma_d": 2.0,
                         "sigma_vn": 0.05, "sigma_ve": 0.05, "sigma_vd": 0.05})
    gnss.to_csv(d / "gnss.csv", index=False, float_format="%.10g")
    comp = pd.DataFrame({"time": tg, "heading": rng.normal(30.0, 1.0, m)})
    comp.to_csv(d / "compass.csv", index=False, float_format="%.6g")
    return n, m


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("dir")
    p.add_argument("--hours", type=float, default=1.0)
    p.add_argument("--rate", type=float, default=200.0)
    a = p.parse_args(argv)
    n, m = write(a.dir, a.hours, a.rate)
    print(f"wrote {a.dir}: {n} IMU rows, {m} GNSS fixes, {m} compass headings")


if __name__ == "__main__":
    main()
