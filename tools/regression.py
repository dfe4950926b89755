#!/usr/bin/env python3
"""Reference outputs of every filter on fixed inputs, so that a numerical change shows as a diff.

    python3 tools/regression.py            # recompute every case, compare, print a table (exit 1 on any difference)
    python3 tools/regression.py --update   # rewrite tests/regression/*.csv from the current code
    python3 tools/regression.py -k gpsins  # only the cases whose name contains "gpsins"
    python3 tools/regression.py --list     # the cases

Each case is one filter configuration (:data:`CASES`) on one seeded scenario or one BROAD trial
(:data:`SCENARIOS`). Its file ``tests/regression/<case>.csv`` holds a header of ``#`` lines (the
call, the sha256 of the inputs, the sha256 of the outputs at every sample, a summary such as the
aiding counters) and a CSV table of every ``stride``-th sample and the last one. Floats are written
as the shortest decimal that reads back to the same value (float64 ``repr``; float32 the shortest
``%.Ng`` that reads back through ``float32(float(text))``), so the text is equal exactly when the
numbers are equal bit for bit; flags are unsigned integers. ``tests/python/test_regression.py``
recomputes every case and requires the same file.

The calling code of each filter lives in one small function below (``run_qekf``, ``run_euler``,
``run_marg``, ``run_nav13``, ``run_gpsins``, ``run_strapdown``): an API change edits that function
only; the references must not move when it does.
"""
from __future__ import annotations

import argparse
import dataclasses
import functools
import hashlib
import math
import os
import sys
from pathlib import Path
from typing import Callable

import numpy as np

REPO = Path(__file__).resolve().parents[1]
OUT_DIR = REPO / "tests" / "regression"
REGENERATE = "python3 tools/regression.py --update"

BROAD_TRIAL = "28_disturbed_stationary_magnet_A"


# ------------------------------------------------------------------------------------------------
# Inputs: seeded scenarios and one BROAD trial. Each returns a dict of named arrays and numbers;
# its sha256 is written to the file, so a changed input is told apart from a changed filter.
# ------------------------------------------------------------------------------------------------
class DataMissing(Exception):
    """The real data a case needs is not present (its test skips)."""


def _align(sensor_index, values, imu_index):
    """(N, 3) rows at the IMU samples, all-NaN where the sensor has no sample."""
    n = len(imu_index)
    out = np.full((n, 3), np.nan)
    pos = np.searchsorted(imu_index, sensor_index)
    ok = (pos < n) & (imu_index[np.minimum(pos, n - 1)] == sensor_index)
    out[pos[ok]] = values[ok]
    return out


def scn_rotation():
    from quatnav.demo import rotation_scenario
    d = rotation_scenario(seed=0)
    return {"dt": d.dt, "gyr": d.gyr, "acc": d.acc, "mag": d.mag}


def _sim(name, seed=0):
    from quatnav.sim import make_scenario
    return make_scenario(name, seed=seed)


def scn_handheld():
    s = _sim("handheld_marg_disturbed")
    return {"t": s.imu.t, "gyr": s.imu.gyro, "acc": s.imu.accel,
            "mag": _align(s.mag.index, s.mag.mag, s.imu.index)}


def scn_turn():
    s = _sim("paper001_constant_turn")
    return {"t": s.imu.t, "gyr": s.imu.gyro, "acc": s.imu.accel,
            "mag": _align(s.mag.index, s.mag.mag, s.imu.index),
            "gps_t": s.gps.t_valid, "gps_vel_n": s.gps.v_n,
            "lever_arm_b": np.asarray(s.params["gps"]["lever_arm_b_m"], float),
            "declination": float(np.radians(s.params["mag"]["declination_deg"]))}


def scn_paper002():
    """Paper 002's run with the paper's fixed initial errors (as ``quatnav experiment nav13``)."""
    from quatnav.core import quaternion as Q
    from quatnav.filters.nav13 import initial_covariance
    s = _sim("paper002_straight_then_circle")
    tr, si = s.truth, s.params["initial_errors"]["si"]
    d_rpy = np.array([si["roll"], si["pitch"], si["yaw"]])
    q0 = Q.from_euler(tr.rpy[0] + d_rpy)
    gyro = s.params["imu"]["gyro"]
    accel = s.params["imu"]["accel"]
    return {
        # IMU row 0 is the reading at t[0], where the filter starts; row k >= 1 is the mean over
        # (t[k-1], t[k]].
        "t": s.imu.t[1:], "f_ib_b": s.imu.accel[1:], "omega_ib_b": s.imu.gyro[1:],
        "vel_t": s.gps.t_valid, "vel": s.gps.v_n, "yaw_t": s.compass.t, "yaw": s.compass.yaw,
        # The filter's initial state and covariance (computed here, so that they are part of the
        # inputs' sha256): biases start at zero.
        "v0": tr.v_n[0] + si["velocity"], "q0": q0, "P0": initial_covariance(q0, si["velocity"], d_rpy,
                                                                              si["accel_bias"], si["gyro_bias"]),
        "llh0": np.array([tr.lat[0], tr.lon[0], tr.h[0]]),
        "accel_noise": accel["noise_density_ug_per_sqrt_hz"] * 1e-6 * 9.80665,
        "gyro_noise": float(np.radians(gyro["noise_density_dps_per_sqrt_hz"])),
        "vel_noise": s.params["gps"]["vel_sigma_m_s"], "yaw_noise": float(np.radians(s.params["compass"]["noise_deg"])),
        # Strapdown: the truth state at t[0] integrated with the simulated (erroneous) IMU.
        "q0_true": tr.q_nb[0], "v0_true": tr.v_n[0],
    }


def _paper004(name):
    s = _sim(f"paper004_{name}")
    return {"t": s.imu.t, "gyro": s.imu.gyro, "accel": s.imu.accel,
            "gps_t": s.gps.t_valid, "gps_llh": np.column_stack([s.gps.lat, s.gps.lon, s.gps.h]),
            "gps_vel": s.gps.v_n, "baro_t": s.baro.t, "baro_h": s.baro.h,
            "compass_t": s.compass.t, "compass_yaw": s.compass.yaw,
            "lever_arm_b": np.asarray(s.params["gps"]["lever_arm_b_m"], float)}


def scn_broad():
    from quatnav.datasets import broad
    # $QUATNAV_DATA, else ../shared/data beside this checkout (as tests/python/conftest.py; not
    # relative to the package, which may be installed elsewhere).
    path = Path(os.environ.get("QUATNAV_DATA", REPO.parent / "shared" / "data")) / "broad" / f"{BROAD_TRIAL}.mat"
    if not path.is_file():
        raise DataMissing(f"BROAD trial not found: {path} (set QUATNAV_DATA)")
    tr = broad.load_trial(path)
    return {"dt": tr.dt, "gyr": tr.gyr, "acc": tr.acc, "mag": tr.mag}


#: name -> (function, what it is, as written to the files)
SCENARIOS: dict[str, tuple[Callable[[], dict], str]] = {
    "rotation": (scn_rotation, "quatnav.demo.rotation_scenario(seed=0): 60 s random rotation, 100 Hz"),
    "handheld": (scn_handheld, "quatnav.sim.make_scenario('handheld_marg_disturbed', seed=0): 70 s, 200 Hz, "
                               "magnet-near events, linear accelerations"),
    "turn": (scn_turn, "quatnav.sim.make_scenario('paper001_constant_turn', seed=0): 98 s, 100 Hz, GPS 20 Hz"),
    "paper002": (scn_paper002, "quatnav.sim.make_scenario('paper002_straight_then_circle', seed=0): 200 s, 100 Hz, "
                               "velocity and yaw 10 Hz; the paper's initial errors"),
    "static": (functools.partial(_paper004, "static"),
               "quatnav.sim.make_scenario('paper004_static', seed=0): 120 s, 50 Hz, GPS 5 Hz, altimeter, compass"),
    "turntable": (functools.partial(_paper004, "turntable"),
                  "quatnav.sim.make_scenario('paper004_turntable', seed=0): 78 s, 50 Hz, GPS 5 Hz, altimeter, compass"),
    "walk": (functools.partial(_paper004, "walk"),
             "quatnav.sim.make_scenario('paper004_walk', seed=0): 98 s, 50 Hz, GPS 5 Hz, altimeter, compass"),
    "broad": (scn_broad, f"BROAD trial {BROAD_TRIAL} (/work/shared/data/broad, Laidig et al. 2021, CC BY 4.0), "
                         "all samples, 285.7 Hz"),
}


#: Every scenario but BROAD (real data, read in place) is stored in the repository: simulating it
#: again would give other bits elsewhere (numpy's vectorized sin/cos/exp differ in the last bit
#: between CPU feature sets and numpy versions), and the inputs must not drift.
STORED = tuple(name for name in SCENARIOS if name != "broad")
INPUT_DIR = OUT_DIR / "inputs"
UPDATE_INPUTS = "python3 tools/regression.py --update-inputs"


class InputsMissing(Exception):
    """A stored scenario's file is missing (run ``--update-inputs``)."""


@functools.lru_cache(maxsize=None)
def scenario(name: str) -> dict:
    """The inputs of scenario ``name``: read from ``tests/regression/inputs/<name>.npz`` for a
    stored one (every scenario but BROAD), from the data folder for BROAD."""
    if name in STORED:
        path = INPUT_DIR / f"{name}.npz"
        if not path.is_file():
            raise InputsMissing(f"{path.relative_to(REPO)} is missing: {UPDATE_INPUTS}")
        return read_inputs(path)
    return SCENARIOS[name][0]()


# ------------------------------------------------------------------------------------------------
# Stored inputs. One zip (LZMA) of .npy members per scenario, readable with numpy.load. A float
# array of more than SMALL values is written as integer counts of a step, x = counts * step (one
# IEEE multiplication, the same bits on every machine), the counts as differences along the first
# axis in the smallest integer type (a smooth signal plus noise then takes about 1 byte a value):
#   * exactly, when the array lies on a grid (x == rint(x / s) * s bit for bit; the time stamps,
#     and sensors the simulator already quantized);
#   * else rounded to a power-of-two step of at most 1/16 of the array's noise (estimated from its
#     fourth differences), as a real sensor's converter would: the rounding adds at most 1/192 of
#     the noise variance (step^2 / 12 against sigma^2), which changes no filter's character.
# Everything else (scalars, small arrays, integers, arrays without noise) is stored as it is.
# ------------------------------------------------------------------------------------------------
SMALL = 256
_NOISE_STEPS = 16
_ZIP_DATE = (2026, 1, 1, 0, 0, 0)  # fixed member dates: the same inputs give the same file bytes


def _on_grid(x: np.ndarray, candidates) -> tuple[float, np.ndarray] | None:
    for s in candidates:
        if not (np.isfinite(s) and s > 0):
            continue
        with np.errstate(over="ignore", invalid="ignore"):
            k = np.rint(x / s)
        if np.all(np.abs(k) < 2.0 ** 52) and np.array_equal((k * s).view(np.uint64), x.view(np.uint64)):
            return float(s), k.astype(np.int64)
    return None


def _grid_candidates(x: np.ndarray, times) -> list[float]:
    """Steps to try for an exact grid: the smallest difference of the values, the sampling steps
    1/r and 1/(2r) of the rates r it suggests (the simulator's time grid), and the same for every
    time array of the scenario."""
    out = []
    for a in [x] + list(times):
        u = np.unique(a[np.isfinite(a)])
        d = np.diff(u)
        d = d[d > 0]
        if not d.size:
            continue
        s0 = float(d.min())
        out.append(s0)
        # a grid x = k * Q written as rint(x / Q) * Q: Q is x / k at the largest |k| to within an
        # ulp or two (s0, a difference of two grid points, is rarely Q exactly)
        j = np.argmax(np.abs(u))
        k = round(float(u[j]) / s0)
        if k != 0:
            q = np.float64(float(u[j]) / k)
            out += [float(q + i * np.spacing(q)) for i in (0, 1, -1, 2, -2)]
        r = round(1.0 / s0)
        for rr in (r, 2 * r):
            if rr > 0:
                out += [1.0 / rr, 0.5 / rr]
    return out


def _noise_step(x: np.ndarray) -> float | None:
    """A power of two of at most 1/16 of the noise of x, None when x has none. The noise of each
    column is estimated from its fourth differences along the first axis, where a smooth signal
    leaves nothing and white noise of standard deviation sigma has sqrt(70) sigma, robustly (the
    median absolute deviation, so that jumps such as a heading's wrap at +-pi do not count)."""
    a = x.reshape(len(x), -1)
    sig = []
    for j in range(a.shape[1]):
        c = a[:, j]
        c = c[np.isfinite(c)]
        if c.size >= 16:
            d4 = np.diff(c, 4)
            s = 1.4826 * np.median(np.abs(d4 - np.median(d4))) / np.sqrt(70.0)
            sig.append(s if s > 0 else np.std(d4) / np.sqrt(70.0))
    sig = [s for s in sig if s > 0]
    if not sig:
        return None
    return float(2.0 ** np.floor(np.log2(min(sig) / _NOISE_STEPS)))


def encode_inputs(d: dict) -> dict[str, np.ndarray]:
    """The members of a stored scenario (see the comment above); :func:`decode_inputs` inverts it."""
    times = [np.asarray(v, float).ravel() for k, v in d.items() if k == "t" or k.endswith("_t")]
    out = {}
    for key, v in d.items():
        a = np.asarray(v)
        if a.dtype.kind != "f" or a.size <= SMALL:
            out[key] = a
            continue
        a = a.astype(np.float64)
        nan = np.isnan(a)
        x = np.where(nan, 0.0, a)
        if not np.isfinite(x).all():
            out[key] = a
            continue
        flat = x.ravel()
        g = _on_grid(flat, _grid_candidates(flat, times))
        if g is None and not (key == "t" or key.endswith("_t")):  # time stamps are never rounded
            step = _noise_step(np.where(nan, np.nan, x))
            if step is not None:
                k = np.rint(flat / step)
                if np.all(np.abs(k) < 2.0 ** 52):
                    g = (step, k.astype(np.int64))
        if g is None:
            out[key] = a
            continue
        step, counts = g
        counts = counts.reshape(a.shape)
        delta = np.diff(counts, axis=0, prepend=np.zeros((1,) + counts.shape[1:], np.int64))
        lim = int(np.abs(delta).max())
        for t in (np.int8, np.int16, np.int32, np.int64):
            if lim <= np.iinfo(t).max:
                break
        out[f"{key}.delta"] = delta.astype(t)
        out[f"{key}.step"] = np.float64(step)
        if nan.any():
            out[f"{key}.nan"] = nan
    return out


def decode_inputs(members: dict) -> dict:
    d = {}
    for name in members:
        key, _, part = name.partition(".")
        if part == "":
            a = np.asarray(members[name])
            d[key] = a.item() if a.ndim == 0 else a
        elif part == "delta":
            counts = np.cumsum(members[name].astype(np.int64), axis=0)
            x = counts.astype(np.float64) * np.float64(members[f"{key}.step"])
            if f"{key}.nan" in members:
                x[members[f"{key}.nan"]] = np.nan
            d[key] = x
    return d


def write_inputs(path: Path, d: dict) -> None:
    import io
    import zipfile
    members = encode_inputs(d)
    back = decode_inputs(members)
    with zipfile.ZipFile(path, "w", zipfile.ZIP_LZMA) as z:
        for name, a in members.items():
            buf = io.BytesIO()
            np.save(buf, np.asarray(a), allow_pickle=False)
            info = zipfile.ZipInfo(f"{name}.npy", _ZIP_DATE)
            info.compress_type = zipfile.ZIP_LZMA
            z.writestr(info, buf.getvalue())
    # What is read back is what the cases run on: it must be exactly what was decoded here.
    got = read_inputs(path)
    if _digest(sorted((k, np.asarray(v)) for k, v in got.items())) != _digest(
            sorted((k, np.asarray(v)) for k, v in back.items())):
        raise RuntimeError(f"{path}: the stored inputs do not read back")


def update_inputs(names=STORED, out_dir: Path = INPUT_DIR) -> list[str]:
    """Simulate the stored scenarios ``names`` again and rewrite their files; returns the names
    whose file changed. Their cases' outputs must then be rewritten too (``--update``)."""
    out_dir.mkdir(parents=True, exist_ok=True)
    changed = []
    for name in names:
        path = out_dir / f"{name}.npz"
        old = path.read_bytes() if path.is_file() else None
        write_inputs(path, SCENARIOS[name][0]())
        if path.read_bytes() != old:
            changed.append(name)
    scenario.cache_clear()
    return changed


def read_inputs(path: Path) -> dict:
    with np.load(path, allow_pickle=False) as z:
        return decode_inputs({name: z[name] for name in z.files})


# ------------------------------------------------------------------------------------------------
# The filters: one function per filter. Each takes the scenario dict and its options and returns
# (columns, summary): columns an ordered dict name -> (N,) array, summary a dict of plain values.
# ------------------------------------------------------------------------------------------------
def _cols(out: dict, prefix: str, a, names) -> None:
    a = np.asarray(a)
    if a.ndim == 1:
        out[prefix] = a
        return
    if a.shape[1] != len(names):
        raise ValueError(f"{prefix}: {a.shape[1]} columns, expected {len(names)}")
    for j, n in enumerate(names):
        out[f"{prefix}_{n}"] = a[:, j]


WXYZ, XYZ, NED = ("w", "x", "y", "z"), ("x", "y", "z"), ("n", "e", "d")


def _times_of(d):
    return d["t"] if "t" in d else np.arange(len(d["gyr"])) * d["dt"]


def _time_kw(d):
    return {"t": d["t"]} if "t" in d else {"dt": d["dt"]}


def run_qekf(d, dtype=np.float64, mag=True, **params):
    import quatnav
    r = quatnav.QuaternionEKF(dtype=dtype, **params).run(d["gyr"], d["acc"], d["mag"] if mag else None,
                                                         on_invalid="skip", **_time_kw(d))
    out = {"t": _times_of(d)}
    _cols(out, "q", r.quat, WXYZ)
    _cols(out, "bias", r.bias, XYZ)
    _cols(out, "sigma", r.sigma, r.sigma_names)  # q0..q3, bx..bz (paper) or dtheta_x..z, bx..bz
    _cols(out, "att_sigma", r.att_sigma, XYZ)
    out["flags"] = r.flags
    return out, {}


def run_euler(d, dtype=np.float64, mag=True, **params):
    import quatnav
    r = quatnav.EulerEKF(dtype=dtype, **params).run(d["gyr"], d["acc"], d["mag"] if mag else None,
                                                    on_invalid="skip", **_time_kw(d))
    out = {"t": _times_of(d)}
    _cols(out, "q", r.quat, WXYZ)
    _cols(out, "bias", r.bias, XYZ)
    _cols(out, "sigma", r.sigma, ("roll", "pitch", "yaw", "bx", "by", "bz"))
    _cols(out, "att_sigma", r.att_sigma, XYZ)
    out["flags"] = r.flags
    return out, {}


def run_marg(d, dtype=np.float64, mag=True, gps=False, lever=False, declination=False, **params):
    import quatnav
    if declination:
        params["declination"] = d["declination"]
    if lever:
        params["lever_arm_b"] = d["lever_arm_b"]
    kw = dict(gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel_n"])) if gps else {}
    r = quatnav.MargFilter(dtype=dtype, **params).run(d["gyr"], d["acc"], d["mag"] if mag else None,
                                                      on_invalid="skip", **_time_kw(d), **kw)
    out = {"t": _times_of(d)}
    _cols(out, "q", r.quat, WXYZ)
    _cols(out, "bias", r.bias, XYZ)
    _cols(out, "gps_acc", r.gps_acc_n, NED)
    out["residual"] = r.residual
    out["flags"] = r.flags
    return out, {}


def run_nav13(d, time_update="ekf", dtype=np.float64, cov_floor=0.0):
    import quatnav
    f = quatnav.NavFilter13(time_update=time_update, dtype=dtype, acc_noise=d["accel_noise"],
                            gyro_noise=d["gyro_noise"], gps_vel_sigma=d["vel_noise"], yaw_sigma=d["yaw_noise"],
                            cov_floor=cov_floor)
    lat, lon, h = d["llh0"]
    f.reset(d["v0"], d["q0"], np.zeros(3), np.zeros(3), d["P0"], lat=lat, lon=lon, h=h)
    r = f.run(d["omega_ib_b"], d["f_ib_b"], t=d["t"], gps_vel=quatnav.Aid(d["vel_t"], d["vel"]),
              yaw=quatnav.Aid(d["yaw_t"], d["yaw"]))
    out = {"t": r.t}
    _cols(out, "v", r.velocity, NED)
    _cols(out, "q", r.quat, WXYZ)
    _cols(out, "ba", r.acc_bias, XYZ)
    _cols(out, "bg", r.bias, XYZ)
    _cols(out, "sigma", r.sigma, ("vn", "ve", "vd", "q0", "q1", "q2", "q3", "bax", "bay", "baz", "bgx", "bgy", "bgz"))
    _cols(out, "att_sigma", r.att_sigma, XYZ)
    out["flags"] = r.flags
    summary = {}
    for kind, aid in (("vel", "gps_vel"), ("yaw", "yaw")):  # the files' summary keys
        st = np.asarray(r.aids[aid].status).ravel()
        codes, counts = np.unique(st, return_counts=True)
        summary[f"{kind}_status"] = {str(int(c)): int(n) for c, n in zip(codes, counts)}
        nis = np.asarray(r.aids[aid].nis, float)
        summary[f"{kind}_nis_sum"] = math.fsum(nis[np.isfinite(nis)])  # exactly rounded: no numpy summation order
    return out, summary


def run_gpsins(d, dtype=np.float64, baro=True, compass=True, outage=False):
    import quatnav
    kw = dict(gps_pos=quatnav.Aid(d["gps_t"], d["gps_llh"]), gps_vel=quatnav.Aid(d["gps_t"], d["gps_vel"]))
    if baro:
        kw.update(baro=quatnav.Aid(d["baro_t"], d["baro_h"]))
    if compass:
        kw.update(compass=quatnav.Aid(d["compass_t"], d["compass_yaw"]))
    if outage:  # 10 s from the middle of the run, as quatnav experiment gpsins
        t0 = float(d["t"][0] + 0.5 * (d["t"][-1] - d["t"][0]))
        kw["outages"] = [(t0, t0 + 10.0)]
    r = quatnav.GpsInsFilter(dtype=dtype, lever_arm_b=d["lever_arm_b"]).run(d["gyro"], d["accel"], t=d["t"], **kw)
    out = {"t": r.t}
    _cols(out, "llh", r.position, ("lat", "lon", "h"))
    _cols(out, "v", r.velocity, NED)
    _cols(out, "q", r.quat, WXYZ)
    _cols(out, "ba", r.acc_bias, XYZ)
    _cols(out, "bg", r.bias, XYZ)
    _cols(out, "sigma", r.sigma, ("pn", "pe", "pd", "vn", "ve", "vd", "psin", "psie", "psid",
                                  "bax", "bay", "baz", "bgx", "bgy", "bgz", "bo"))
    out["q_scale"] = r.q_scale
    out["flags"] = r.flags
    # the alignment's numbers and names (its "reason" is a sentence, None while navigating)
    summary = {"counters": r.counters, "alignment": {k: v for k, v in r.alignment.items() if k != "reason"}}
    for key, aids in (("gps", ("gps_pos", "gps_vel")), ("baro", ("baro", "baro_vd")), ("compass", ("compass",))):
        # the files' sums run over the C++ (K, 2) tables row by row: position, velocity of each fix
        nis = np.column_stack([r.aids[a].nis for a in aids if a in r.aids]).ravel() if any(
            a in r.aids for a in aids) else np.zeros(0)
        summary[f"{key}_nis_sum"] = math.fsum(nis[np.isfinite(nis)])
    return out, summary


def run_strapdown(d, dtype=np.float64):
    from quatnav.core.strapdown import StrapdownState
    from quatnav.filters.strapdown import strapdown_run_cpp
    lat, lon, h = d["llh0"]
    s0 = StrapdownState(np.asarray(d["q0_true"], float), np.asarray(d["v0_true"], float),
                        float(lat), float(lon), float(h))
    dt = np.diff(np.concatenate([[d["t"][0] - (d["t"][1] - d["t"][0])], d["t"]]))
    r = strapdown_run_cpp(s0, d["omega_ib_b"], d["f_ib_b"], dt, dtype=dtype)
    out = {"t": d["t"]}
    out["lat"], out["lon"], out["h"] = r["lat"], r["lon"], r["h"]
    _cols(out, "v", r["v_n"], NED)
    _cols(out, "q", r["q_nb"], WXYZ)
    codes = {"ok": 0, "non_finite": 2, "invalid_dt": 4, "numerical_failure": 8}
    out["status"] = np.array([codes.get(s, 255) for s in r["status"]], dtype=np.uint32)
    return out, {}


# ------------------------------------------------------------------------------------------------
# The cases.
# ------------------------------------------------------------------------------------------------
@dataclasses.dataclass(frozen=True)
class Case:
    name: str          #: file stem: <filter>[-variant]_<scenario>
    scenario: str      #: key of SCENARIOS
    run: Callable      #: one of the run_* functions with its options bound
    call: str          #: the call, in words, for the header
    stride: int        #: every stride-th sample is written (and the last)


def _case(name, scen, fn, call, stride, **opts):
    return Case(name, scen, functools.partial(fn, **opts), call, stride)


F32 = np.float32
CASES: list[Case] = []
for _scen, _stride in (("rotation", 50), ("broad", 400)):
    for _tag, _opts, _call in (
            ("qekf", {}, "QuaternionEKF()"),
            ("qekf-6d", {"mag": False}, "QuaternionEKF(), no magnetometer"),
            ("qekf-paper", {"paper": True}, "QuaternionEKF(paper=True)"),
            ("qekf-paper-6d", {"paper": True, "mag": False}, "QuaternionEKF(paper=True), no magnetometer"),
            ("qekf-f32", {"dtype": F32}, "QuaternionEKF(dtype=float32)"),
            ("qekf-6d-f32", {"dtype": F32, "mag": False}, "QuaternionEKF(dtype=float32), no magnetometer"),
            ("qekf-paper-f32", {"dtype": F32, "paper": True}, "QuaternionEKF(paper=True, dtype=float32)"),
            ("qekf-paper-6d-f32", {"dtype": F32, "paper": True, "mag": False},
             "QuaternionEKF(paper=True, dtype=float32), no magnetometer")):
        if _scen == "broad" and _tag not in ("qekf", "qekf-paper", "qekf-f32"):
            continue
        CASES.append(_case(f"{_tag}_{_scen}", _scen, run_qekf, _call, _stride, **_opts))
    CASES.append(_case(f"euler_{_scen}", _scen, run_euler, "EulerEKF()", _stride))
    CASES.append(_case(f"euler-paper_{_scen}", _scen, run_euler, "EulerEKF(paper=True)", _stride, paper=True))
    CASES.append(_case(f"marg_{_scen}", _scen, run_marg, "MargFilter()", _stride))
    CASES.append(_case(f"marg-paper_{_scen}", _scen, run_marg, "MargFilter(paper=True)", _stride, paper=True))
    if _scen == "rotation":
        CASES += [
            _case("euler-6d_rotation", _scen, run_euler, "EulerEKF(), no magnetometer", _stride, mag=False),
            _case("euler-f32_rotation", _scen, run_euler, "EulerEKF(dtype=float32)", _stride, dtype=F32),
            _case("marg-bias_rotation", _scen, run_marg, "MargFilter(bias_gain=0.05)", _stride, bias_gain=0.05),
            _case("marg-6d_rotation", _scen, run_marg, "MargFilter(), no magnetometer", _stride, mag=False),
            _case("marg-f32_rotation", _scen, run_marg, "MargFilter(dtype=float32)", _stride, dtype=F32),
        ]
CASES += [
    _case("qekf_handheld", "handheld", run_qekf, "QuaternionEKF()", 100),
    _case("qekf-paper_handheld", "handheld", run_qekf, "QuaternionEKF(paper=True)", 100, paper=True),
    _case("euler_handheld", "handheld", run_euler, "EulerEKF()", 100),
    _case("euler-paper_handheld", "handheld", run_euler, "EulerEKF(paper=True)", 100, paper=True),
    _case("marg-bias_handheld", "handheld", run_marg, "MargFilter(bias_gain=0.05)", 100, bias_gain=0.05),
    _case("marg_turn", "turn", run_marg, "MargFilter(), no GPS", 70),
    _case("marg-gps_turn", "turn", run_marg,
          "MargFilter(declination=scenario's, lever_arm_b=scenario's, gps_acc_tau=0.05), GPS velocity", 70,
          gps=True, lever=True, declination=True, gps_acc_tau=0.05),
    _case("marg-paper-gps_turn", "turn", run_marg,
          "MargFilter(paper=True, declination=scenario's, lever_arm_b=scenario's, gps_acc_tau=0.05), GPS velocity",
          70, gps=True, lever=True, declination=True, gps_acc_tau=0.05, paper=True),
    _case("marg-gps-f32_turn", "turn", run_marg,
          "MargFilter(declination=scenario's, lever_arm_b=scenario's, gps_acc_tau=0.05, dtype=float32), GPS velocity",
          70, gps=True, lever=True, declination=True, gps_acc_tau=0.05, dtype=F32),
]
for _tu in ("ekf", "second_order", "ukf"):
    _t = _tu.replace("_", "")
    CASES.append(_case(f"nav13-{_t}_paper002", "paper002", run_nav13, f"NavFilter13({_tu!r}), velocity + yaw", 200,
                       time_update=_tu))
    # Float32 without a covariance floor, the ekf and second-order time updates lose the velocity
    # covariance after 90-100 s and diverge (docs/PORTING.md): the cases run as a float32 port must.
    _floor = 0.0 if _tu == "ukf" else 1e-12
    _desc = f"NavFilter13({_tu!r}, dtype=float32" + (", cov_floor=1e-12" if _floor else "") + "), velocity + yaw"
    CASES.append(_case(f"nav13-{_t}-f32_paper002", "paper002", run_nav13, _desc, 200, time_update=_tu, dtype=F32,
                       cov_floor=_floor))
CASES += [
    _case("strapdown_paper002", "paper002", run_strapdown, "strapdown_run_cpp from the true state", 200),
    _case("strapdown-f32_paper002", "paper002", run_strapdown, "strapdown_run_cpp(dtype=float32) from the true state",
          200, dtype=F32),
]
for _scen in ("static", "turntable", "walk"):
    CASES.append(_case(f"gpsins_{_scen}", _scen, run_gpsins, "GpsInsFilter(lever_arm_b): GPS, altimeter, compass", 60))
CASES += [
    _case("gpsins-gps-only_walk", "walk", run_gpsins, "GpsInsFilter(lever_arm_b): GPS only", 60,
          baro=False, compass=False),
    _case("gpsins-no-compass_walk", "walk", run_gpsins, "GpsInsFilter(lever_arm_b): GPS, altimeter", 60, compass=False),
    _case("gpsins-no-baro_walk", "walk", run_gpsins, "GpsInsFilter(lever_arm_b): GPS, compass", 60, baro=False),
    _case("gpsins-outage_walk", "walk", run_gpsins,
          "GpsInsFilter(lever_arm_b): GPS (10 s outage mid-run), altimeter, compass", 60, outage=True),
    _case("gpsins-f32_walk", "walk", run_gpsins, "GpsInsFilter(lever_arm_b, dtype=float32): GPS, altimeter, compass",
          60, dtype=F32),
]
CASES_BY_NAME = {c.name: c for c in CASES}
assert len(CASES_BY_NAME) == len(CASES), "duplicate case names"


# ------------------------------------------------------------------------------------------------
# Writing: exact decimal text.
# ------------------------------------------------------------------------------------------------
def format_value(x, dtype) -> str:
    """The shortest text that reads back to exactly ``x`` (see :func:`parse_value`)."""
    dtype = np.dtype(dtype)
    if dtype.kind in "ui":
        return str(int(x))
    if dtype.kind == "b":
        return str(int(bool(x)))
    if dtype == np.float32:
        x = np.float32(x)
        if not np.isfinite(x):
            return repr(float(x))
        with np.errstate(over="ignore"):  # a short text of a value near the maximum may read back as inf
            for p in range(1, 10):
                s = "%.*g" % (p, float(x))
                y = np.float32(float(s))
                if y == x and (x != 0 or np.signbit(y) == np.signbit(x)):
                    return s
        raise AssertionError(f"no 9-digit text for float32 {x!r}")  # pragma: no cover
    if dtype == np.float64:
        return repr(float(x))
    raise TypeError(f"cannot write dtype {dtype}")


def parse_value(s: str, dtype):
    dtype = np.dtype(dtype)
    if dtype.kind in "uib":
        return int(s)
    if dtype == np.float32:
        return np.float32(float(s))
    return float(s)


def _digest(items) -> str:
    h = hashlib.sha256()
    for name, a in items:
        if isinstance(a, dict):
            h.update(f"{name}:dict;".encode())
            h.update(_digest(sorted(a.items())).encode())
            continue
        a = np.ascontiguousarray(a)
        if a.dtype == object:
            raise TypeError(f"{name}: object array")
        h.update(f"{name}:{a.dtype.str}:{a.shape};".encode())
        h.update(a.tobytes())
    return h.hexdigest()


def _summary_text(summary: dict, prefix="") -> list[str]:
    lines = []
    for k in sorted(summary):
        v = summary[k]
        if isinstance(v, dict):
            lines += _summary_text(v, f"{prefix}{k}.")
        elif isinstance(v, float):
            lines.append(f"{prefix}{k}={v!r}")
        else:
            lines.append(f"{prefix}{k}={v}")
    return lines


def rows_of(n: int, stride: int) -> np.ndarray:
    k = np.arange(0, n, stride)
    return k if k[-1] == n - 1 else np.append(k, n - 1)


@dataclasses.dataclass
class Result:
    header: list[str]
    names: list[str]
    columns: list[np.ndarray]  #: the written rows of every column
    text: str


def compute(case: Case) -> Result:
    """Run one case (raises :class:`DataMissing` when its data is absent)."""
    d = scenario(case.scenario)
    inputs_sha = _digest(sorted((k, np.asarray(v)) for k, v in d.items()))
    cols, summary = case.run(d)
    n = len(next(iter(cols.values())))
    for k, v in cols.items():
        if v.shape != (n,):
            raise ValueError(f"{case.name}: column {k} has shape {v.shape}, expected ({n},)")
    outputs_sha = _digest(cols.items())
    k = rows_of(n, case.stride)
    names = ["k"] + list(cols)
    columns = [k.astype(np.uint64)] + [np.asarray(v)[k] for v in cols.values()]
    header = [f"quatnav reference outputs: {case.name} (regenerate: {REGENERATE}; see docs/DEVELOPING.md)",
              f"filter: {case.call}",
              f"inputs: {SCENARIOS[case.scenario][1]}" + (
                  f"; simulated once, stored in tests/regression/inputs/{case.scenario}.npz" if case.scenario in STORED
                  else ""),
              f"inputs sha256: {inputs_sha}",
              f"rows: k = 0, {case.stride}, {2 * case.stride}, ... and the last of {n} samples",
              f"outputs sha256 (every sample): {outputs_sha}",
              "types: " + ",".join(c.dtype.str.lstrip("<>|=") for c in columns)]
    header += [f"summary: {s}" for s in _summary_text(summary)]
    lines = [f"# {h}" for h in header] + [",".join(names)]
    fmt = [c.dtype for c in columns]
    for i in range(len(k)):
        lines.append(",".join(format_value(c[i], f) for c, f in zip(columns, fmt)))
    return Result(header, names, columns, "\n".join(lines) + "\n")


# ------------------------------------------------------------------------------------------------
# Comparing.
# ------------------------------------------------------------------------------------------------
def read(path: Path):
    """(header lines without '# ', column names, list of column string lists)."""
    header, body = [], []
    for line in path.read_text().splitlines():
        (header if line.startswith("#") else body).append(line)
    header = [h[2:] if h.startswith("# ") else h[1:] for h in header]
    names = body[0].split(",") if body else []
    cells = [r.split(",") for r in body[1:]]
    columns = [[r[j] if j < len(r) else "" for r in cells] for j in range(len(names))]
    return header, names, columns


def _header_field(header, key):
    for h in header:
        if h.startswith(key + ":"):
            return h[len(key) + 1:].strip()
    return None


def _same(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Element-wise: equal bit for bit (NaN equals NaN, -0.0 differs from 0.0)."""
    a = np.asarray(a, np.float64)
    b = np.asarray(b, np.float64)
    both_nan = np.isnan(a) & np.isnan(b)
    return both_nan | (a.view(np.uint64) == b.view(np.uint64))


# ------------------------------------------------------------------------------------------------
# The arithmetic environment. With the inputs stored, what still decides the last bits of an
# output is the arithmetic that produces it: the compiled module (its compiler; quatnav builds
# for the baseline instruction set, without -march, so without FMA contraction), the C library's
# libm (glibc on x86-64 picks FMA variants of sin, cos, exp, atan2, ... at run time on a CPU with
# FMA and AVX2, whose results may differ in the last bit from its SSE2 variants; another glibc
# version or another libm may differ likewise), the machine, and numpy (the Python wrappers
# compute a few outputs with it; measured: numpy's SIMD paths do not change any output).
# tests/regression/environment.txt records the one the files were written in. Where this
# environment is the same, the outputs must be equal bit for bit. Where it differs, each column
# within its tolerance of tests/regression/tolerance.csv (below), integers equal.
# ------------------------------------------------------------------------------------------------
ENV_FILE = OUT_DIR / "environment.txt"
TOL_FILE = OUT_DIR / "tolerance.csv"

# The tolerances are measured, per case and column, by --update: how far the column moves (in
# units eps * max|column|, eps the machine epsilon of the case's type: float32 for the float32
# cases) when the arithmetic changes by one rounding unit, the largest of (a) every float input
# moved by -1, 0 or +1 unit in the last place at random (3 seeds), and (b) glibc's other libm
# variant (GLIBC_TUNABLES, where it applies). The tolerance is TOL_SAFETY times that response
# rounded up to a power of ten, at least TOL_SAFETY units. A column that moves by more than
# CHAOTIC of its scale under one rounding unit (no tolerance derived from rounding would mean
# anything), and an integer column that changed under (a) or (b) (a flag flipped at a threshold),
# is compared only bit for bit: not at all where the environment differs (the report says so).
TOL_SAFETY = 10.0
TOL_SEEDS = (1, 2, 3)
CHAOTIC = 1e-4
EXACT_ONLY = "exact"

def _so_compiler() -> str:
    """The compiler recorded in the compiled module's .comment section (e.g. 'GCC: (Debian
    12.2.0-14) 12.2.0'); for a module without one (clang's Release modules are stripped of it), the
    compiler as the module reports itself (`quatnav._core.compiler`, e.g. 'clang 14.0.6');
    'unknown' if neither."""
    try:
        import quatnav._core as core
        data = Path(core.__file__).read_bytes()
    except (ImportError, OSError):
        return "unknown"
    import re
    found = sorted({m.decode("ascii", "replace") for m in re.findall(rb"(?:GCC|clang version|Ubuntu clang): ?[ -~]{3,80}", data)})
    if found:
        return "; ".join(found)
    reported = getattr(core, "compiler", None)
    return reported.strip() if isinstance(reported, str) and reported.strip() else "unknown"


def _cpu_flags() -> set[str]:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("flags"):
                return set(line.split(":", 1)[1].split())
    except OSError:
        pass
    return set()


def environment() -> dict:
    """What besides quatnav decides the bits of the outputs (the inputs being stored): machine,
    C library and the variant of its libm, the compiler of quatnav._core, numpy."""
    import platform
    machine = platform.machine()
    libc = " ".join(platform.libc_ver()) or "unknown"
    libm = "-"
    if machine in ("x86_64", "AMD64") and libc.startswith("glibc"):
        # glibc's ifunc choice, unless GLIBC_TUNABLES masks the features (the measurement does)
        flags = _cpu_flags()
        masked = os.environ.get("GLIBC_TUNABLES", "")
        fma = {"fma", "avx2"} <= flags and "-FMA" not in masked and "-AVX2" not in masked
        libm = "fma" if fma else "sse2"
    return {"machine": machine, "libc": libc, "libm": libm, "compiler": _so_compiler(),
            "numpy": np.__version__}


def write_environment(path: Path = ENV_FILE) -> None:
    lines = ["# The arithmetic environment tests/regression/*.csv were written in (python3 tools/regression.py",
             "# --update). Where it is the same the outputs must be equal bit for bit, elsewhere within the",
             "# tolerances of tolerance.csv (see docs/DEVELOPING.md)."]
    lines += [f"{k}: {v}" for k, v in environment().items()]
    path.write_text("\n".join(lines) + "\n")


def recorded_environment(path: Path = ENV_FILE) -> dict:
    if not path.is_file():
        return {}
    return dict(line.split(": ", 1) for line in path.read_text().splitlines()
                if ": " in line and not line.startswith("#"))


def environment_differences(path: Path = ENV_FILE) -> list[str]:
    """How this environment differs from the recorded one (empty: the same)."""
    rec = recorded_environment(path)
    return [f"{k}: {rec.get(k)!r} there, {v!r} here" for k, v in environment().items() if rec.get(k) != v]


def default_mode(path: Path = ENV_FILE) -> str:
    """'exact' where this arithmetic environment is the recorded one, else 'tolerance'."""
    return "tolerance" if environment_differences(path) else "exact"


# ------------------------------------------------------------------------------------------------
# Comparing.
# ------------------------------------------------------------------------------------------------
@dataclasses.dataclass
class Difference:
    column: str
    first_row: int       #: sample index k of the first differing row
    n_rows: int          #: differing rows
    max_abs: float       #: largest |new - old| (NaN against a number: inf)
    max_rel: float
    tol: float = 0.0     #: the allowed |new - old| (0: bit for bit)


def case_eps(case: Case) -> float:
    """The machine epsilon of the case's arithmetic (float32 for the float32 cases, whose double
    outputs such as the carried position are driven by float32 quantities)."""
    return float(np.finfo(case.run.keywords.get("dtype", np.float64)).eps)


def column_tolerance(case: Case, column: str, old: np.ndarray, tolerances: dict | None = None):
    """The allowed |new - old| of a float column where the environment differs: ulps * eps(case) *
    max|old| with ulps from tolerance.csv; EXACT_ONLY for a column compared only bit for bit;
    None when the table has no entry (run --update)."""
    tolerances = read_tolerances() if tolerances is None else tolerances
    ulps = tolerances.get(case.name, {}).get(column)
    if ulps is None or ulps == EXACT_ONLY:
        return ulps
    fin = np.abs(old[np.isfinite(old)].astype(np.float64))
    scale = float(fin.max()) if fin.size else 0.0
    return float(ulps) * case_eps(case) * max(scale, float(np.finfo(np.float64).tiny))


# ------------------------------------------------------------------------------------------------
# Measuring the tolerances (--update).
# ------------------------------------------------------------------------------------------------
def _perturbed(d: dict, dtype, seed: int) -> dict:
    """The inputs with every float value moved by -1, 0 or +1 unit in the last place of ``dtype``
    at random (time stamps and scalars kept)."""
    rng = np.random.default_rng(seed)
    out = dict(d)
    for k, v in d.items():
        a = np.asarray(v)
        if a.dtype.kind != "f" or a.ndim == 0 or a.size <= 16 or k == "t" or k.endswith("_t"):
            continue
        a = a.astype(dtype)
        step = rng.integers(-1, 2, size=a.shape)
        up, down = np.nextafter(a, dtype(np.inf)), np.nextafter(a, dtype(-np.inf))
        out[k] = np.where(step > 0, up, np.where(step < 0, down, a)).astype(np.float64)
    return out


def _run_all(cases) -> dict:
    """case name -> (columns over every sample, summary)."""
    out = {}
    for c in cases:
        try:
            out[c.name] = c.run(scenario(c.scenario))
        except DataMissing:
            continue
    return out


def _other_libm_run(cases) -> dict | None:
    """The outputs with glibc's SSE2 libm instead of its FMA variants (a subprocess with
    GLIBC_TUNABLES), None where that does not apply (no glibc FMA variants here)."""
    if environment()["libm"] != "fma":
        return None
    import pickle
    import subprocess
    import tempfile
    with tempfile.TemporaryDirectory() as tmp:
        f = Path(tmp) / "outputs.pkl"
        import quatnav
        here = str(Path(quatnav.__file__).resolve().parents[1])  # the quatnav this process runs
        env = dict(os.environ, GLIBC_TUNABLES="glibc.cpu.hwcaps=-AVX2,-FMA",
                   PYTHONPATH=os.pathsep.join([here] + [p for p in [os.environ.get("PYTHONPATH")] if p]))
        subprocess.run([sys.executable, str(Path(__file__).resolve()), "--dump", str(f),
                        "--cases", ",".join(c.name for c in cases)], env=env, check=True)
        with open(f, "rb") as fh:
            return pickle.load(fh)


def _response(case: Case, base, other) -> dict:
    """Per column: the largest |other - base| in units of eps(case) * max|base| (float), or
    whether any value changed (integer)."""
    out = {}
    for k, x in base[0].items():
        x, y = np.asarray(x), np.asarray(other[0][k])
        if x.dtype.kind in "uib":
            out[k] = bool(np.any(x != y))
            continue
        x64, y64 = x.astype(np.float64), y.astype(np.float64)
        nan_differs = np.isnan(x64) != np.isnan(y64)
        fin = np.isfinite(x64)
        scale = max(float(np.abs(x64[fin]).max()) if fin.any() else 0.0, float(np.finfo(np.float64).tiny))
        with np.errstate(invalid="ignore"):
            d = np.abs(x64 - y64)
        d = d[np.isfinite(d)]
        out[k] = np.inf if nan_differs.any() else (float(d.max()) if d.size else 0.0) / (case_eps(case) * scale)
    other_sum = dict(_summary_values("summary: " + t)[::2] for t in _summary_text(other[1]))
    for t in _summary_text(base[1]):
        key, v, text = _summary_values("summary: " + t)
        w = other_sum.get(key)
        if v is None or "." not in text + (w or ""):  # an integer or a name
            out[f"summary:{key}"] = w != text
        else:
            out[f"summary:{key}"] = abs(float(w) - v) / (case_eps(case) * max(abs(v), 1e-300))
    return out


def measure_tolerances(cases) -> dict:
    """case -> column -> ulps (float) or EXACT_ONLY, measured as the comment above says."""
    base = _run_all(cases)
    others = []
    for seed in TOL_SEEDS:
        pert = {}
        for c in cases:
            if c.name in base:
                dtype = c.run.keywords.get("dtype", np.float64)
                pert[c.name] = c.run(_perturbed(scenario(c.scenario), dtype, seed))
        others.append(pert)
    libm = _other_libm_run([c for c in cases if c.name in base])
    if libm is not None:
        others.append(libm)
    table = {}
    for c in cases:
        if c.name not in base:
            continue
        worst = {}
        for o in others:
            for k, r in _response(c, base[c.name], o[c.name]).items():
                worst[k] = max(worst.get(k, 0), r) if not isinstance(r, bool) else (worst.get(k, False) or r)
        row = {}
        for k, r in worst.items():
            if isinstance(r, bool):
                row[k] = EXACT_ONLY if r else 0
            elif not np.isfinite(r) or r * case_eps(c) > CHAOTIC:
                row[k] = EXACT_ONLY
            else:
                row[k] = TOL_SAFETY * 10.0 ** math.ceil(math.log10(max(r, 1.0)))
        table[c.name] = row
    return table


def read_tolerances(path: Path | None = None) -> dict:
    path = path or TOL_FILE
    if not path.is_file():
        return {}
    table: dict = {}
    for line in path.read_text().splitlines():
        if line.startswith("#") or line.startswith("case,") or not line.strip():
            continue
        case, column, ulps = line.split(",")
        table.setdefault(case, {})[column] = ulps if ulps == EXACT_ONLY else float(ulps)
    return table


def write_tolerances(table: dict, path: Path | None = None) -> None:
    """Write (merge) the measured tolerances: the cases of ``table`` replace theirs."""
    path = path or TOL_FILE
    old = read_tolerances(path)
    old.update(table)
    lines = ["# Tolerances of tests/regression/*.csv where the arithmetic environment differs from",
             "# environment.txt (measured by python3 tools/regression.py --update; docs/DEVELOPING.md):",
             f"# a float column may differ by ulps * eps * max|column|, eps the machine epsilon of the",
             f"# case's type; {TOL_SAFETY:g} times its response to one rounding unit, rounded up to a power",
             f"# of ten. '{EXACT_ONLY}': compared only bit for bit (a float moved by more than {CHAOTIC:g} of its",
             "# scale, or an integer changed, under one rounding unit); 0: an integer, equal.",
             "case,column,ulps"]
    order = {c.name: i for i, c in enumerate(CASES)}
    for case in sorted(old, key=lambda n: order.get(n, len(order))):
        for column, ulps in old[case].items():
            text = ulps if ulps == EXACT_ONLY else format(ulps, "g")
            lines.append(f"{case},{column},{text}")
    path.write_text("\n".join(lines) + "\n")


def _summary_values(line: str):
    """'summary: key=value' -> (key, value as float or None, text)."""
    key, _, text = line[len("summary:"):].strip().partition("=")
    try:
        return key, float(text), text
    except ValueError:
        return key, None, text


def _compare_summaries(case, old_sum, new_sum, mode, tolerances, messages, not_compared) -> bool:
    ok = len(old_sum) == len(new_sum)
    if not ok:
        messages.append(f"summary lines: {len(old_sum)} -> {len(new_sum)}")
    for a, b in zip(old_sum, new_sum):
        if a == b:
            continue
        ka, va, ta = _summary_values(a)
        kb, vb, tb = _summary_values(b)
        if mode == "tolerance" and ka == kb:
            ulps = tolerances.get(case.name, {}).get(f"summary:{ka}")
            if ulps == EXACT_ONLY:
                not_compared.append(f"summary:{ka}")
                continue
            # a float sum (NIS) within its tolerance of its own size; integers and names exactly
            if (ulps is not None and va is not None and vb is not None and "." in ta + tb
                    and abs(va - vb) <= float(ulps) * case_eps(case) * max(abs(va), 1e-300)):
                continue
        ok = False
        messages.append(f"{a!r} -> {b!r}")
    return ok


def compare(case: Case, path: Path | None = None, mode: str | None = None) -> dict:
    """Recompute ``case`` and compare with its file, bit for bit (``mode='exact'``) or within
    the tolerance (``'tolerance'``); by default exact where the arithmetic environment is the
    recorded one. Returns a dict with ``ok`` (bool), ``mode``, ``messages`` (list of str) and
    ``differences`` (list of :class:`Difference`)."""
    path = path or OUT_DIR / f"{case.name}.csv"
    mode = mode or default_mode()
    if mode not in ("exact", "tolerance"):
        raise ValueError(f"mode: 'exact' or 'tolerance', got {mode!r}")
    res = compute(case)
    out = {"ok": True, "mode": mode, "messages": [], "differences": [], "result": res, "inputs_changed": False,
           "path": path, "not_compared": []}
    if not path.is_file():
        out["ok"] = False
        out["messages"].append(f"{path.relative_to(REPO) if path.is_relative_to(REPO) else path}: missing")
        return out
    old_text = path.read_text()
    if old_text == res.text:
        return out
    header, names, cols = read(path)
    blocking = []  # differences that fail in either mode
    if _header_field(header, "inputs sha256") != _header_field(res.header, "inputs sha256"):
        out["inputs_changed"] = True
        blocking.append("the inputs changed (the stored inputs, their reader or the data): the file cannot "
                        "judge the filter")
    key = "outputs sha256 (every sample)"
    sha_differs = _header_field(header, key) != _header_field(res.header, key)
    for key in ("filter", "inputs", "rows", "types"):
        if _header_field(header, key) != _header_field(res.header, key):
            blocking.append(f"{key}: was {_header_field(header, key)!r}, now {_header_field(res.header, key)!r}")
    tol_file = path.parent / TOL_FILE.name  # the table beside the file, else the committed one
    tolerances = read_tolerances(tol_file if tol_file.is_file() else TOL_FILE) if mode == "tolerance" else {}
    if mode == "tolerance" and case.name not in tolerances:
        blocking.append(f"no tolerances of {case.name} in {TOL_FILE.name} ({REGENERATE})")
    not_compared = out["not_compared"] = []
    old_sum = [h for h in header if h.startswith("summary:")]
    new_sum = [h for h in res.header if h.startswith("summary:")]
    _compare_summaries(case, old_sum, new_sum, mode, tolerances, blocking, not_compared)
    if names != res.names:
        blocking.append(f"columns: was {names}, now {res.names}")
    old_k = cols[0] if names and names[0] == "k" else []
    new_k = [str(int(x)) for x in res.columns[0]]
    if old_k != new_k:
        blocking.append(f"rows: {len(old_k)} written before, {len(new_k)} now")
        out.update(ok=False, messages=blocking)
        return out
    # Each file's cells are read with that file's own types (a float32 result now returned as
    # float64 with the same values is a change of type, not of value).
    old_types = (_header_field(header, "types") or "").split(",")
    for name, new in zip(res.names[1:], res.columns[1:]):
        if name not in names:
            continue
        j = names.index(name)
        try:
            t = np.dtype(old_types[j]) if len(old_types) == len(names) else new.dtype
            old = np.array([parse_value(s, t) for s in cols[j]], dtype=t)
        except (ValueError, TypeError):
            blocking.append(f"{name}: unreadable values in the file")
            continue
        integer = new.dtype.kind in "uib" or old.dtype.kind in "uib"
        tol = 0.0
        if mode == "tolerance":
            tol = column_tolerance(case, name, old, tolerances) if not integer else tolerances.get(case.name, {}).get(name)
            if tol == EXACT_ONLY:
                not_compared.append(name)
                continue
            if tol is None:
                blocking.append(f"{name}: no tolerance in {TOL_FILE.name} ({REGENERATE})")
                continue
            tol = float(tol) if not integer else 0.0
        if integer:
            bad = old.astype(np.int64) != new.astype(np.int64)
            diff = np.abs(old.astype(np.float64) - new.astype(np.float64))
        else:
            with np.errstate(invalid="ignore"):
                diff = np.abs(new.astype(np.float64) - old.astype(np.float64))
            nan_differs = np.isnan(old.astype(np.float64)) != np.isnan(new.astype(np.float64))
            if mode == "exact":
                bad = ~_same(old, new)
            else:
                inf_same = np.isinf(old) & (old.astype(np.float64) == new.astype(np.float64))
                with np.errstate(invalid="ignore"):
                    bad = nan_differs | (~np.isnan(diff) & ~inf_same & ~(diff <= tol))
            diff[nan_differs] = np.inf
        if bad.any():
            i = np.flatnonzero(bad)
            scale = np.maximum(np.abs(old.astype(np.float64)[i]), np.finfo(float).tiny)
            with np.errstate(invalid="ignore"):
                rel = np.nan if integer else (np.nanmax(diff[i] / scale) if np.isfinite(diff[i]).any() else np.inf)
            out["differences"].append(Difference(name, int(res.columns[0][i[0]]), int(i.size),
                                                 float(np.nanmax(diff[i])), float(rel), tol))
    messages = list(blocking)
    if sha_differs:
        if mode == "exact" and not out["differences"]:
            types_changed = _header_field(header, "types") != _header_field(res.header, "types")
            messages.append("outputs differ only at samples not written to the file (sha256 over every sample); "
                            "the written rows are the same" + (" (the sha256 covers the types too)"
                                                               if types_changed else ""))
        elif mode == "exact":
            messages.append("outputs differ (sha256 over every sample)")
    if mode == "exact" and not out["differences"] and not messages:
        messages.append("text differs (formatting or header)")
    ok = not blocking and not out["differences"]
    if mode == "exact":
        ok = ok and not messages
    out.update(ok=ok, messages=messages)
    return out


def report(case: Case, cmp: dict) -> str:
    """Human-readable account of one comparison."""
    path = cmp.get("path", OUT_DIR / f"{case.name}.csv")
    shown = path.relative_to(REPO) if path.is_relative_to(REPO) else path
    how = "bit for bit" if cmp["mode"] == "exact" else f"within the tolerances of {TOL_FILE.name}"
    lines = [f"{case.name}: {shown} differs from the current code ({how})"]
    lines += [f"  {m}" for m in cmp["messages"]]
    if cmp.get("not_compared"):
        lines.append(f"  compared only bit for bit, so not here: {', '.join(cmp['not_compared'])}")
    for d in cmp["differences"]:
        rel = "" if np.isnan(d.max_rel) else f" (relative {d.max_rel:.3g})"
        allowed = f", allowed {d.tol:.3g}" if d.tol else ""
        lines.append(f"  column {d.column}: first at row k={d.first_row}, {d.n_rows} rows, "
                     f"largest |diff| {d.max_abs:.3g}{rel}{allowed}")
    lines.append(f"  if the change is intended: {REGENERATE} and say in the commit message why the numbers moved")
    return "\n".join(lines)


# ------------------------------------------------------------------------------------------------
# Command line.
# ------------------------------------------------------------------------------------------------
def _select(pattern):
    cases = [c for c in CASES if pattern is None or pattern in c.name]
    if not cases:
        raise SystemExit(f"no case matches {pattern!r}")
    return cases


def _update(cases, out_dir: Path, pattern, tolerances=True) -> None:
    out_dir.mkdir(parents=True, exist_ok=True)
    changed = []
    for c in cases:
        try:
            res = compute(c)
        except DataMissing as e:
            print(f"{c.name}: skipped, file left as it is ({e})")
            continue
        p = out_dir / f"{c.name}.csv"
        if not p.is_file() or p.read_text() != res.text:
            p.write_text(res.text)
            changed.append(c.name)
    env_file = out_dir / ENV_FILE.name
    old_env = env_file.read_text() if env_file.is_file() else None
    write_environment(env_file)
    if env_file.read_text() != old_env:
        changed.append(env_file.name)
    tol_file = out_dir / TOL_FILE.name
    old_tol = tol_file.read_text() if tol_file.is_file() else None
    if tolerances:
        write_tolerances(measure_tolerances(cases), tol_file)
        if tol_file.read_text() != old_tol:
            changed.append(tol_file.name)
    if pattern is None:
        known = {f"{c.name}.csv" for c in CASES} | {TOL_FILE.name}
        for p in sorted(out_dir.glob("*.csv")):
            if p.name not in known:
                p.unlink()
                print(f"{p.name}: no such case any more, removed")
    size = sum(p.stat().st_size for p in out_dir.glob("*.csv") if p.name != TOL_FILE.name)
    print(f"{len(changed)} files rewritten ({', '.join(changed) or 'none'}; {len(cases)} cases); "
          f"{size / 1e6:.2f} MB in {out_dir}")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--update", action="store_true", help="rewrite the files from the current code")
    ap.add_argument("--update-inputs", action="store_true",
                    help="simulate the stored scenarios again, rewrite tests/regression/inputs/, then the outputs")
    ap.add_argument("-k", metavar="TEXT", help="only the cases whose name contains TEXT")
    ap.add_argument("--list", action="store_true", help="list the cases and exit")
    ap.add_argument("--mode", choices=("auto", "exact", "tolerance"), default="auto",
                    help="bit for bit, within the tolerance, or (auto, the default) bit for bit where the "
                         "arithmetic environment is the recorded one")
    ap.add_argument("--dir", type=Path, default=OUT_DIR, help="where the files are (default tests/regression)")
    ap.add_argument("--no-tolerances", action="store_true",
                    help="with --update: leave tolerance.csv as it is (its measurement takes 4 more runs)")
    ap.add_argument("--dump", type=Path, help=argparse.SUPPRESS)  # the other libm's run of measure_tolerances
    ap.add_argument("--cases", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.dump:
        import pickle
        names = set(args.cases.split(","))
        with open(args.dump, "wb") as fh:
            pickle.dump(_run_all([c for c in CASES if c.name in names]), fh)
        return 0
    cases = _select(args.k)
    if args.list:
        for c in cases:
            print(f"{c.name:32s} {c.scenario:10s} {c.call}")
        return 0
    if args.update_inputs:
        scens = sorted({c.scenario for c in cases if c.scenario in STORED})
        changed = update_inputs(scens)
        size = sum(p.stat().st_size for p in INPUT_DIR.glob("*.npz"))
        print(f"inputs rewritten: {', '.join(changed) or 'none'} (of {', '.join(scens)}); "
              f"{size / 1e6:.2f} MB in {INPUT_DIR}")
        args.update = True
    if args.update:
        _update(cases, args.dir, args.k, tolerances=not args.no_tolerances)
        return 0
    mode = default_mode(args.dir / ENV_FILE.name) if args.mode == "auto" else args.mode
    env = environment_differences(args.dir / ENV_FILE.name)
    print(f"mode: {mode}" + (" (this arithmetic environment differs from the recorded one: " + "; ".join(env) + ")"
                             if env else ""))
    print(f"{'case':32s} {'result':10s} {'column':14s} {'first k':>8s} {'rows':>6s} {'max |diff|':>11s} "
          f"{'relative':>9s}")
    details, skipped, failed = [], 0, 0
    for c in cases:
        try:
            cmp = compare(c, args.dir / f"{c.name}.csv", mode=mode)
        except DataMissing as e:
            print(f"{c.name:32s} {'skipped':10s} ({e})")
            skipped += 1
            continue
        if cmp["ok"]:
            print(f"{c.name:32s} {'same' if cmp['result'].text == (args.dir / f'{c.name}.csv').read_text() else 'within':10s}")
            continue
        failed += 1
        details.append(report(c, cmp))
        if not cmp["differences"]:
            print(f"{c.name:32s} {'DIFFERS':10s} {cmp['messages'][0] if cmp['messages'] else ''}")
        for i, d in enumerate(cmp["differences"]):
            print(f"{c.name if i == 0 else '':32s} {'DIFFERS' if i == 0 else '':10s} {d.column:14s} {d.first_row:8d} "
                  f"{d.n_rows:6d} {d.max_abs:11.3g} {'-' if np.isnan(d.max_rel) else format(d.max_rel, '9.3g'):>9s}")
    if details:
        print()
        print("\n\n".join(details))
        print(f"\n{failed} of {len(cases)} cases differ; if intended: {REGENERATE}")
        return 1
    note = f"; {skipped} skipped (data absent)" if skipped else ""
    print(f"all {len(cases) - skipped} compared cases agree with the files in {args.dir} ({mode}){note}")
    return 0


if __name__ == "__main__":
    if any((REPO / "python" / "quatnav").glob("_core.*")):  # a built source tree's quatnav
        sys.path.insert(0, str(REPO / "python"))                # before an installed one
    sys.exit(main())
