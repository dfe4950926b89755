"""Throughput of the attitude filters' batch ``run`` next to the peer libraries.

``quatnav bench`` (or ``python -m quatnav bench``) runs every registered filter on the same
simulated MARG data (the ``handheld_marg`` scenario, 200 Hz gyro + accelerometer +
magnetometer, tiled to N samples) in the same process, and prints samples per second and the
ratios to quatnav's QuaternionEKF (float64) and to VQF's C++ batch call. ``--scaling`` adds the
time and peak traced memory of the batch runs for N = 1e3 ... ``--max-n``.

Peers that loop over the samples in Python (imufusion's per-sample API, ahrs, filterpy, the
numpy reference) run on the first ``limit`` samples only; their rate is extrapolated to N and the
table says so. A peer whose package is missing is listed as skipped.

Adding a filter is one :func:`register` call (see the bottom of this module).
"""
from __future__ import annotations

import datetime as _dt
import gc
import os
import platform
import statistics
import sys
import time
import tracemalloc
from dataclasses import dataclass
from typing import Callable, Dict, List, Optional

import numpy as np

__all__ = ["MargData", "marg_data", "register", "entries", "run_throughput", "run_scaling",
           "add_parser", "main"]


# ----------------------------------------------------------------------------------------------
# Data
# ----------------------------------------------------------------------------------------------
@dataclass
class MargData:
    """MARG samples: ``gyr`` (N, 3) rad/s, ``acc`` (N, 3) m/s^2, ``mag`` (N, 3) T, ``dt`` s."""

    gyr: np.ndarray
    acc: np.ndarray
    mag: np.ndarray
    dt: float
    field_n: np.ndarray

    def __len__(self) -> int:
        return self.gyr.shape[0]

    def head(self, n: int) -> "MargData":
        return MargData(self.gyr[:n], self.acc[:n], self.mag[:n], self.dt, self.field_n)

    def astype(self, dtype) -> "MargData":
        c = lambda a: np.ascontiguousarray(a, dtype=dtype)  # noqa: E731
        return MargData(c(self.gyr), c(self.acc), c(self.mag), self.dt, self.field_n)


_SCENARIO_CACHE: Dict[int, object] = {}


def marg_data(n: int, seed: int = 0) -> MargData:
    """``n`` samples of the ``handheld_marg`` scenario (70 s at 200 Hz), tiled when longer.

    Tiling repeats the sensor samples; the jump in attitude at each seam is one large innovation
    for the filters and does not change the cost of a step.
    """
    if seed not in _SCENARIO_CACHE:
        from ..sim import make_scenario
        _SCENARIO_CACHE[seed] = make_scenario("handheld_marg", seed)
    sc = _SCENARIO_CACHE[seed]
    g, a, m = sc.imu.gyro[1:], sc.imu.accel[1:], sc.mag.mag[1:]  # row 0 is instantaneous
    reps = -(-int(n) // len(g))
    tile = lambda x: np.ascontiguousarray(np.tile(x, (reps, 1))[:n], dtype=np.float64)  # noqa: E731
    return MargData(tile(g), tile(a), tile(m), 1.0 / sc.imu.rate_hz, np.asarray(sc.mag.field_n, float))


# ----------------------------------------------------------------------------------------------
# Registry
# ----------------------------------------------------------------------------------------------
@dataclass
class Entry:
    """One benchmarked implementation.

    ``make(data)`` prepares whatever the run needs and returns a zero-argument callable that
    processes all of ``data`` and returns its outputs. ``limit``: the most samples it is run on
    (None: all of them); a larger N is extrapolated from ``limit`` samples.
    """

    name: str
    library: str
    kind: str  # "C++ batch", "per-sample + Python loop", "pure Python"
    make: Callable[[MargData], Callable[[], object]]
    limit: Optional[int] = None
    dtype: type = np.float64
    requires: str = ""  # module that must import


_REGISTRY: List[Entry] = []


def register(name: str, library: str, kind: str, make, limit: Optional[int] = None,
             dtype=np.float64, requires: str = "") -> None:
    """Add an implementation to the benchmark (see :class:`Entry`)."""
    _REGISTRY.append(Entry(name, library, kind, make, limit, dtype, requires))


def entries(pattern: Optional[str] = None) -> List[Entry]:
    """Registered entries whose name or library contains ``pattern`` (case-insensitive)."""
    if not pattern:
        return list(_REGISTRY)
    pats = [p.strip().lower() for p in pattern.split(",") if p.strip()]
    return [e for e in _REGISTRY
            if any(p in e.name.lower() or p in e.library.lower() for p in pats)]


def _available(e: Entry) -> bool:
    if not e.requires:
        return True
    try:
        __import__(e.requires)
        return True
    except Exception:
        return False


# ----------------------------------------------------------------------------------------------
# Measurement
# ----------------------------------------------------------------------------------------------
def _time_once(fn) -> float:
    gc.collect()
    t0 = time.perf_counter()
    out = fn()
    t = time.perf_counter() - t0
    del out
    return t


def run_throughput(n: int = 1_000_000, repeat: int = 5, pattern: Optional[str] = None,
                   seed: int = 0, log=None) -> dict:
    """Samples per second of every registered entry on the same ``n`` samples.

    The repeats are interleaved (entry A, B, ..., then again) so that a change in the machine's
    load affects every entry alike; each entry's figure is the median of its repeats.
    """
    data64 = marg_data(n, seed)
    datas = {np.float64: data64, np.float32: data64.astype(np.float32)}
    chosen = [e for e in entries(pattern)]
    runs, skipped = [], []
    for e in chosen:
        if not _available(e):
            skipped.append({"name": e.name, "library": e.library, "reason": f"{e.requires} not installed"})
            continue
        m = n if e.limit is None else min(n, e.limit)
        d = datas[e.dtype] if m == n else datas[e.dtype].head(m)
        runs.append((e, m, e.make(d)))
        runs[-1][2]()  # warm-up (first-call costs, caches)
    times: Dict[str, List[float]] = {e.name: [] for e, _, _ in runs}
    for r in range(repeat):
        for e, m, fn in runs:
            reps = 1 if e.limit is None else max(1, repeat // 3)
            if r < reps or e.limit is None:
                times[e.name].append(_time_once(fn))
        if log:
            log(f"  repeat {r + 1}/{repeat} done")
    rows = []
    for e, m, _ in runs:
        t = statistics.median(times[e.name])
        rows.append({"name": e.name, "library": e.library, "kind": e.kind,
                     "dtype": np.dtype(e.dtype).name, "n_measured": m,
                     "extrapolated": m < n, "seconds_median": t,
                     "seconds_all": times[e.name], "samples_per_s": m / t})
    base = next((r["samples_per_s"] for r in rows if r["name"] == "QuaternionEKF f64"), None)
    vqf = next((r["samples_per_s"] for r in rows if r["name"] == "VQF"), None)
    for r in rows:
        r["vs_qekf_f64"] = r["samples_per_s"] / base if base else None
        r["vs_vqf"] = r["samples_per_s"] / vqf if vqf else None
    return {"n": n, "repeat": repeat, "seed": seed, "results": rows, "skipped": skipped}


def _out_bytes(out) -> int:
    if isinstance(out, np.ndarray):
        return out.nbytes
    if isinstance(out, dict):
        return sum(_out_bytes(v) for v in out.values())
    if isinstance(out, (tuple, list)):
        return sum(_out_bytes(v) for v in out)
    if hasattr(out, "__dict__"):
        return sum(_out_bytes(v) for v in vars(out).values())
    return 0


def run_scaling(max_n: int = 10_000_000, pattern: str = "QuaternionEKF,VQF", seed: int = 0,
                log=None) -> dict:
    """Time and peak traced memory of the batch entries for N = 1e3, 1e4, ..., ``max_n``.

    Time: one timed run (after a warm-up at the smallest N). Memory: a second run under
    :mod:`tracemalloc` (numpy registers its buffers with it); ``peak_bytes`` is the peak above
    the inputs, ``output_bytes`` the size of the returned arrays.
    """
    chosen = [e for e in entries(pattern) if e.limit is None and _available(e)]
    ns = [int(10**k) for k in range(3, 12) if 10**k <= max_n]
    rows = []
    for n in ns:
        data64 = marg_data(n, seed)
        datas = {np.float64: data64, np.float32: data64.astype(np.float32)}
        for e in chosen:
            fn = e.make(datas[e.dtype])
            if n == ns[0]:
                fn()
            t = _time_once(fn)
            gc.collect()
            tracemalloc.start()
            base = tracemalloc.get_traced_memory()[0]
            out = fn()
            peak = tracemalloc.get_traced_memory()[1] - base
            tracemalloc.stop()
            ob = _out_bytes(out)
            del out, fn
            rows.append({"name": e.name, "n": n, "seconds": t, "ns_per_sample": t / n * 1e9,
                         "peak_bytes": peak, "output_bytes": ob,
                         "peak_per_output": peak / ob if ob else None})
            if log:
                log(f"  {e.name:24s} N={n:>9d}  {t:8.3f} s  peak {peak / 1e6:9.1f} MB")
        del data64, datas
        gc.collect()
    return {"pattern": pattern, "results": rows}


# ----------------------------------------------------------------------------------------------
# Reports
# ----------------------------------------------------------------------------------------------
def machine_info() -> dict:
    cpu = platform.processor() or ""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    cpu = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    try:
        load = os.getloadavg()
    except OSError:
        load = None
    import importlib.metadata as md
    versions = {}
    for pkg in ("numpy", "vqf", "imufusion", "AHRS", "filterpy"):
        try:
            versions[pkg] = md.version(pkg)
        except md.PackageNotFoundError:
            pass
    from .. import __version__
    versions["quatnav"] = __version__
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "platform": platform.platform(), "load_average": load, "versions": versions,
            "date": _dt.datetime.now().astimezone().isoformat(timespec="seconds")}


def format_throughput(res: dict) -> str:
    lines = [f"Throughput on the same {res['n']:,} handheld_marg samples (median of "
             f"{res['repeat']} interleaved repeats)",
             f"{'filter':26s} {'library':10s} {'kind':26s} {'samples/s':>12s} {'ns/sample':>10s}"
             f" {'x QEKF f64':>10s} {'x VQF':>9s}"]
    for r in res["results"]:
        sps = r["samples_per_s"]
        note = f"  (extrapolated from {r['n_measured']:,})" if r["extrapolated"] else ""
        fmt = lambda v: f"{v:10.3g}" if v is not None else f"{'-':>10s}"  # noqa: E731
        lines.append(f"{r['name']:26s} {r['library']:10s} {r['kind']:26s} {sps:12,.0f} "
                     f"{1e9 / sps:10.0f} {fmt(r['vs_qekf_f64'])} {fmt(r['vs_vqf']):>9s}{note}")
    for s in res["skipped"]:
        lines.append(f"{s['name']:26s} {s['library']:10s} skipped: {s['reason']}")
    return "\n".join(lines)


def format_scaling(res: dict) -> str:
    lines = ["Scaling: time and peak traced memory of one batch run",
             f"{'filter':24s} {'N':>10s} {'seconds':>9s} {'ns/sample':>10s} {'peak MB':>9s}"
             f" {'output MB':>10s} {'peak/output':>11s}"]
    for r in res["results"]:
        lines.append(f"{r['name']:24s} {r['n']:10,d} {r['seconds']:9.3f} {r['ns_per_sample']:10.0f} "
                     f"{r['peak_bytes'] / 1e6:9.2f} {r['output_bytes'] / 1e6:10.2f} "
                     f"{(r['peak_per_output'] or 0):11.2f}")
    return "\n".join(lines)


# ----------------------------------------------------------------------------------------------
# Command line
# ----------------------------------------------------------------------------------------------
def add_parser(sub) -> None:
    p = sub.add_parser("bench", help="throughput of the batch runs next to VQF, imufusion, ahrs, filterpy",
                       description=__doc__.split("\n\n")[0])
    p.add_argument("-n", type=float, default=1e6, help="samples per run (default 1e6)")
    p.add_argument("--repeat", type=int, default=5, help="repeats; the median is reported (default 5)")
    p.add_argument("--filters", default=None,
                   help="comma-separated substrings of the filter/library names to run (default: all)")
    p.add_argument("--scaling", action="store_true",
                   help="also time the batch runs for N = 1e3 ... --max-n, with peak memory")
    p.add_argument("--max-n", type=float, default=1e7, help="largest N of --scaling (default 1e7)")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--json", metavar="FILE", default=None, help="write all figures to FILE as JSON ('-': stdout)")
    p.epilog = ("The data comes from quatnav.sim (needs scipy: pip install 'quatnav[sim]'); the peers from "
                "pip install 'quatnav[peers]' (a missing peer is listed as skipped).")
    p.set_defaults(func=_cli)


def _cli(args) -> int:
    from .._command import UsageError, write_json
    for opt, v, lo in (("-n", args.n, 1), ("--repeat", args.repeat, 1), ("--max-n", args.max_n, 1e3)):
        if not v >= lo:
            raise UsageError(f"{opt}: expected at least {lo:g}, got {v:g}")
    info = machine_info()
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    print(f"quatnav bench  {info['date']}  {info['cpu']} ({info['cores']} cores)  "
          f"Python {info['python']}  load {info['load_average']}")
    thr = run_throughput(int(args.n), args.repeat, args.filters, args.seed, log=log)
    print(format_throughput(thr))
    cmd = f"quatnav bench -n {args.n:g} --repeat {args.repeat}"
    if args.filters:
        cmd += f" --filters {args.filters}"
    if args.scaling:
        cmd += f" --scaling --max-n {args.max_n:g}"
    out = {"command": cmd, "machine": info, "throughput": thr}
    if args.scaling:
        sc = run_scaling(int(args.max_n), seed=args.seed, log=log)
        print()
        print(format_scaling(sc))
        out["scaling"] = sc
    write_json(out, args)
    return 0


# ----------------------------------------------------------------------------------------------
# The implementations
# ----------------------------------------------------------------------------------------------
def _quatnav(cls_name: str, dtype, **params):
    def make(d: MargData):
        from ..filters import attitude
        cls = getattr(attitude, cls_name)
        return lambda: cls(dtype=dtype, **params).run(d.gyr, d.acc, d.mag, dt=d.dt)
    return make


def _reference(cls_name: str):
    def make(d: MargData):
        from .. import reference
        cls = getattr(reference, cls_name)
        return lambda: cls().run(d.gyr, d.acc, d.mag, dt=d.dt)
    return make


def _vqf(d: MargData):
    from vqf import VQF
    return lambda: VQF(d.dt).updateBatch(d.gyr, d.acc, d.mag)


def _pyvqf(d: MargData):
    from vqf import PyVQF
    return lambda: PyVQF(d.dt).updateBatch(d.gyr, d.acc, d.mag)


def _imufusion(d: MargData):
    import imufusion

    def run():
        ahrs = imufusion.Ahrs()
        ahrs.set_sample_period(d.dt) if hasattr(ahrs, "set_sample_period") else None
        g = np.degrees(d.gyr)          # deg/s
        a = d.acc / 9.80665            # g
        m = d.mag * 1e6                # uT
        q = np.empty((len(d), 4))
        for k in range(len(d)):
            ahrs.update(g[k], a[k], m[k])
            q[k] = ahrs.get_quaternion()
        return q
    return run


def _ahrs(name: str):
    def make(d: MargData):
        import ahrs.filters as F
        cls = getattr(F, name)
        rate = 1.0 / d.dt
        if name == "EKF":
            # Reference field from the simulated one (avoids the WMM lookup), in nT.
            fn = d.field_n * 1e9
            return lambda: cls(gyr=d.gyr, acc=d.acc, mag=d.mag * 1e9, frequency=rate, frame="NED",
                               magnetic_ref=fn).Q
        return lambda: cls(gyr=d.gyr, acc=d.acc, mag=d.mag * 1e9, frequency=rate).Q
    return make


def _qekf_model(d: MargData):
    """Quaternion model of paper 000 from quatnav.reference, for the filterpy set-ups."""
    from ..reference import QuaternionEKFPaper as RefQEKF
    from ..reference.attitude import attitude_from_acc_mag
    ref = RefQEKF()  # the 7-state [q, b] filter with the default noise values
    p = ref.p
    fn = d.field_n / np.linalg.norm(d.field_n)
    rx, rz = np.hypot(fn[0], fn[1]), fn[2]
    q0, _ = attitude_from_acc_mag(d.acc[0], d.mag[0])
    unit = lambda v: v / np.linalg.norm(v)  # noqa: E731
    z = np.hstack([d.acc / np.linalg.norm(d.acc, axis=1, keepdims=True),
                   d.mag / np.linalg.norm(d.mag, axis=1, keepdims=True)])

    def hx(x):
        q = unit(x[:4])
        return np.concatenate([RefQEKF.h(q, 0.0, -1.0), RefQEKF.h(q, rx, rz)])

    def Hjac(x):
        H = np.zeros((6, 7))
        H[:3, :4] = RefQEKF.H(x[:4], 0.0, -1.0)
        H[3:, :4] = RefQEKF.H(x[:4], rx, rz)
        return H

    def Qn(q):
        from ..core import quaternion as Q
        X = Q.xi(q)
        out = np.zeros((7, 7))
        out[:4, :4] = d.dt * p.gyro_noise**2 / 4 * X @ X.T + 1e-12 * np.eye(4)
        out[4:, 4:] = np.eye(3) * d.dt * p.gyro_bias_noise**2
        return out

    R = np.diag([p.acc_sigma**2] * 3 + [p.mag_sigma**2] * 3)
    P0 = np.diag([(p.init_att_sigma / 2) ** 2] * 4 + [p.init_gyro_bias_sigma**2] * 3)
    x0 = np.concatenate([q0, np.zeros(3)])
    return ref, x0, P0, R, Qn, hx, Hjac, z


def _filterpy_ekf(d: MargData):
    from filterpy.kalman import ExtendedKalmanFilter
    ref, x0, P0, R, Qn, hx, Hjac, z = _qekf_model(d)

    class QuatEKF(ExtendedKalmanFilter):
        def predict_x(self, u=0):
            q, self.F, _ = ref.propagate(self.x[:4], self.x[4:], u, d.dt)
            self.x = np.concatenate([q, self.x[4:]])

    def run():
        f = QuatEKF(dim_x=7, dim_z=6)
        f.x, f.P, f.R = x0.copy(), P0.copy(), R
        q = np.empty((len(d), 4))
        for k in range(len(d)):
            f.Q = Qn(f.x[:4])
            f.predict(u=d.gyr[k])
            f.update(z[k], Hjac, hx)
            f.x[:4] /= np.linalg.norm(f.x[:4])
            q[k] = f.x[:4]
        return q
    return run


def _filterpy_ukf(d: MargData):
    from filterpy.kalman import MerweScaledSigmaPoints, UnscentedKalmanFilter
    ref, x0, P0, R, Qn, hx, Hjac, z = _qekf_model(d)

    def fx(x, dt, gyr):
        q, _, _ = ref.propagate(x[:4] / np.linalg.norm(x[:4]), x[4:], gyr, dt)
        return np.concatenate([q, x[4:]])

    def run():
        pts = MerweScaledSigmaPoints(7, alpha=0.5, beta=2.0, kappa=-4.0)
        f = UnscentedKalmanFilter(dim_x=7, dim_z=6, dt=d.dt, hx=hx, fx=fx, points=pts)
        f.x, f.P, f.R = x0.copy(), P0.copy(), R
        q = np.empty((len(d), 4))
        for k in range(len(d)):
            f.Q = Qn(f.x[:4])
            f.predict(gyr=d.gyr[k])
            f.update(z[k])
            f.x[:4] /= np.linalg.norm(f.x[:4])
            q[k] = f.x[:4]
        return q
    return run


# quatnav: one line per filter and precision.
register("QuaternionEKF f64", "quatnav", "C++ batch", _quatnav("QuaternionEKF", np.float64))
register("QuaternionEKF f32", "quatnav", "C++ batch", _quatnav("QuaternionEKF", np.float32), dtype=np.float32)
register("EulerEKF f64", "quatnav", "C++ batch", _quatnav("EulerEKF", np.float64))
register("EulerEKF f32", "quatnav", "C++ batch", _quatnav("EulerEKF", np.float32), dtype=np.float32)
register("QuaternionEKF numpy", "quatnav", "pure Python (reference)", _reference("QuaternionEKF"), limit=2000)
# peers
register("VQF", "vqf", "C++ batch", _vqf, requires="vqf")
register("PyVQF", "vqf", "pure Python", _pyvqf, limit=2000, requires="vqf")
register("imufusion Ahrs", "imufusion", "per-sample + Python loop", _imufusion, limit=50_000, requires="imufusion")
register("ahrs Madgwick", "ahrs", "pure Python", _ahrs("Madgwick"), limit=5000, requires="ahrs")
register("ahrs EKF", "ahrs", "pure Python", _ahrs("EKF"), limit=2000, requires="ahrs")
register("filterpy EKF (quat model)", "filterpy", "pure Python", _filterpy_ekf, limit=2000, requires="filterpy")
register("filterpy UKF (quat model)", "filterpy", "pure Python", _filterpy_ukf, limit=500, requires="filterpy")
