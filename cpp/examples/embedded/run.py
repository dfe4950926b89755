#!/usr/bin/env python3
"""Embedded baseline of quatnav: every filter in float32 on a Cortex-M4F, without heap.

    python cpp/examples/embedded/run.py [--check] [--opt Os O2] [--filters A,B] [--report-dir DIR]

What it does, in order:
  1. generates the recorded inputs (``quatnav.sim`` scenarios, a few thousand samples each) as
     C headers embedded in the image (build/embedded/input_<kind>.h);
  2. cross-compiles one firmware image per filter and optimization level for QEMU's
     mps2-an386 (Cortex-M4, hard float, ``Scalar = float``, ``-fno-exceptions -fno-rtti
     -DEIGEN_NO_MALLOC``), plus one image without a filter per input (the baseline that the
     filter sizes are measured against), and the same firmware source for the host in double
     and in float;
  3. measures: .text and .data + .bss of the filter (image minus baseline, arm-none-eabi-size),
     the worst-case stack of one step from GCC's call graph (``-fcallgraph-info=su``: the
     deepest chain of static frames from ``qn_step``) and as measured on the target (stack
     painting), sizeof the state and of the filter object (printed by the firmware), and
     instructions per step (SysTick under ``qemu -icount``, calibrated with a loop of known
     length);
  4. runs every image in QEMU with semihosting, runs the host builds, and compares the
     attitude after every sample: target float32 against host double (and host float32);
  5. checks that no image links a heap (malloc, _sbrk), exceptions or RTTI;
  6. writes report.json and REPORT.md (the markdown table) into --report-dir (default: this
     directory).

With --check it exits non-zero when a check fails (emulator output incomplete or faulted,
heap or exception support linked, attitude difference above --tol-deg).

Needs: arm-none-eabi-gcc with newlib and the C++ standard headers (Debian: gcc-arm-none-eabi
libnewlib-arm-none-eabi libstdc++-arm-none-eabi-dev; the images link no C++ runtime library),
qemu-system-arm, a host C++ compiler ($CXX, else clang++ where installed, else c++), Eigen 3.4
(the cmeel-eigen wheel or libeigen3-dev) and the quatnav Python package (for quatnav.sim).
Compilations are cached in build/embedded (keyed on the command line and the content of every
source and header).

Adding a filter: one line in FILTERS below if an adapter in adapters.hpp fits it (attitude
filters fed like quatnav::run_attitude_batch, the strapdown, NavFilter13 with each time update,
GpsInsFilter), otherwise a small adapter there. Navigation adapters also print position and
velocity (nav()), compared in metres and m/s.
"""

from __future__ import annotations

import argparse
import concurrent.futures as cf
import functools
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
INCLUDE = ROOT / "cpp" / "include"

# name, recorded input, adapter type (QN_SCALAR is float on the target, float or double on the
# host). Attitude filters whose Python class has the same name are also run through
# quatnav.<name>(...).run on the same samples, to tie the host double run to the library.
FILTERS = [
    ("QuaternionEKF", "marg", "qn_fw::AttitudeAdapter<quatnav::QuaternionEKF<QN_SCALAR>>"),  # the default: 6-state error state
    ("QuaternionEKFPaper", "marg", "qn_fw::AttitudeAdapter<quatnav::QuaternionEKFPaper<QN_SCALAR>>"),  # paper 000's 7 states
    ("EulerEKF", "marg", "qn_fw::AttitudeAdapter<quatnav::EulerEKF<QN_SCALAR>>"),
    ("MargFilter", "marg", "qn_fw::MargAdapter<QN_SCALAR>"),
    ("Strapdown", "nav", "qn_fw::StrapdownAdapter<QN_SCALAR>"),
    ("NavFilter13-Ekf", "nav13", "qn_fw::Nav13Adapter<QN_SCALAR, quatnav::TimeUpdate::Ekf>"),
    ("NavFilter13-SecondOrder", "nav13", "qn_fw::Nav13Adapter<QN_SCALAR, quatnav::TimeUpdate::SecondOrder>"),
    ("NavFilter13-Ukf", "nav13", "qn_fw::Nav13Adapter<QN_SCALAR, quatnav::TimeUpdate::Ukf>"),
    ("GpsInsFilter", "gpsins", "qn_fw::GpsInsAdapter<QN_SCALAR>"),
]
# Navigation filters: the firmware also prints position and velocity (adapters with nav()).
NAV_KINDS = ("nav13", "gpsins")
NULL_ADAPTER = "qn_fw::NullAdapter<QN_SCALAR>"

# The recorded inputs: scenario, options, samples.
INPUTS = {
    "marg": dict(scenario="handheld_marg", options=dict(rate_hz=100.0, duration=25.0), n=3000,
                 what="hand-held MARG, smooth random rotations, 100 Hz, first 30 s"),
    "nav": dict(scenario="paper001_constant_turn", options={}, n=4000,
                what="paper 001 vehicle: rest, accelerate, straight, start of a 12 deg/s turn; 100 Hz, first 40 s"),
    "nav13": dict(scenario="paper002_straight_then_circle", options={}, n=3000,
                  what="paper 002 robot at 2 m/s, IMU 100 Hz, NED velocity and yaw at 10 Hz, the paper's "
                       "initial errors (10/10/20 deg, 1 ft/s, biases unknown); first 30 s"),
    "gpsins": dict(scenario="paper004_walk", options={}, n=4000,
                   what="paper 004 walk: 10 s rest (alignment), then 1.4 m/s along the path; MEMS IMU 50 Hz, "
                        "GPS 5 Hz (position + velocity, lever arm), altimeter 10 Hz, compass 10 Hz; first 80 s"),
}
SEED = 1

CPU_FLAGS = ["-mcpu=cortex-m4", "-mfpu=fpv4-sp-d16", "-mfloat-abi=hard", "-mthumb"]
# -fno-math-errno: std::sqrt becomes the FPU's vsqrt.f32 and libm never touches errno (no
# reentrancy structure linked); the filters check finiteness themselves.
TARGET_CXXFLAGS = CPU_FLAGS + ["-std=c++17", "-fno-exceptions", "-fno-rtti", "-fno-threadsafe-statics",
                               "-DEIGEN_NO_MALLOC", "-DNDEBUG", "-fstack-usage", "-fcallgraph-info=su",
                               "-ffunction-sections", "-fdata-sections", "-fno-math-errno", "-Wall"]
TARGET_CFLAGS = CPU_FLAGS + ["-Os", "-ffunction-sections", "-fdata-sections", "-Wall"]
TARGET_LDFLAGS = CPU_FLAGS + ["-nostartfiles", "--specs=nano.specs", "-Wl,--gc-sections"]
HOST_CXXFLAGS = ["-std=c++17", "-O2", "-fno-exceptions", "-fno-rtti", "-DEIGEN_NO_MALLOC", "-DNDEBUG"]
# GCC's garbage collector kept from running (as for the Python module, CMakeLists.txt): the
# same objects, 5-10 % less CPU per filter (bench/README.md, "Compiler processes and GCC's
# garbage collector"). For GCC only (the cross compiler, and a host compiler that is GCC).
GCC_PARAMS = ["--param=ggc-min-expand=1000", "--param=ggc-min-heapsize=2097152"]
QEMU = ["qemu-system-arm", "-machine", "mps2-an386", "-cpu", "cortex-m4", "-nographic", "-monitor", "none",
        "-serial", "none", "-semihosting-config", "enable=on,target=native",
        "-icount", "shift=6,align=off,sleep=off"]
# Symbols that must not be in any image: heap, exceptions, RTTI, iostream.
FORBIDDEN = re.compile(r"^(malloc|free|calloc|realloc|_sbrk|_sbrk_r|_malloc_r|__cxa_throw|__cxa_begin_catch|"
                       r"__cxa_allocate_exception|__gxx_personality_v0|_Znwj|_Znaj|_ZdlPv|_ZdaPv|"
                       r"_ZTVN10__cxxabiv.*|_ZSt4cout|_ZNSt8ios_base4Init.*)$")
SOFT_DOUBLE = re.compile(r"^__aeabi_(dadd|dsub|dmul|ddiv|d2f|f2d|dcmp\w*|i2d|ui2d|d2iz|d2uiz)$")


def log(msg):
    print(msg, flush=True)


# --------------------------------------------------------------------------------------------
# Recorded inputs
# --------------------------------------------------------------------------------------------

def make_input(kind):
    """Arrays of one recording (float32 sensor samples) and its truth (float64)."""
    from quatnav.sim import make_scenario

    spec = INPUTS[kind]
    s = make_scenario(spec["scenario"], seed=SEED, **spec["options"])
    n = spec["n"]
    imu = s.imu
    if len(imu.t) < n:
        raise SystemExit(f"scenario {spec['scenario']} has {len(imu.t)} IMU samples, fewer than {n}")
    idx = np.asarray(imu.index[:n])
    t = np.asarray(imu.t[:n], float)
    dt = np.empty(n)
    dt[1:] = np.diff(t)
    dt[0] = 1.0 / imu.rate_hz
    mag = np.full((n, 3), np.nan)
    if s.mag is not None:
        row = {int(i): r for r, i in enumerate(idx)}
        for j, i in enumerate(np.asarray(s.mag.index)):
            if int(i) in row:
                mag[row[int(i)]] = s.mag.mag[j]
    tr = s.truth
    i0 = int(idx[0])
    extra = {}
    if kind == "nav13":
        extra = _nav13_extra(s, t, dt, n)
    elif kind == "gpsins":
        extra = _gpsins_extra(s, t, n)
    return {"extra": extra, "t": t,
            "truth_llh": np.column_stack([tr.lat[idx], tr.lon[idx], tr.h[idx]]), "truth_v": np.asarray(tr.v_n[idx]),
        "dt": dt, "gyr": np.asarray(imu.gyro[:n]), "acc": np.asarray(imu.accel[:n]), "mag": mag,
        "q0": tr.q_nb[i0], "v0": tr.v_n[i0], "llh0": np.array([tr.lat[i0], tr.lon[i0], tr.h[i0]]),
        "earth_rotation": int(bool(tr.earth_rate)),
        "truth_q": np.asarray(tr.q_nb[idx], float),
    }


def _aid_index(t, dt, tau, before_first):
    """Sample index after whose step an aid at time tau is applied (>= n: after the recording).

    before_first (run_nav13_batch): an aid at tau <= t[0] + 1e-4 dt goes to sample 0, after the
    reset; otherwise (gpsins_batch) an aid at tau <= t[0] gets index 0 and is not used."""
    eps = 1e-4 * dt[0] if before_first else 0.0
    k = np.searchsorted(t + eps, tau, side="left")
    return np.where(tau <= t[0] + eps, 0, np.maximum(k, 1))


def _nav13_extra(s, t, dt, n):
    """NavFilter13 on paper 002: the experiment's parameters and initial state (paper errors)."""
    from quatnav.experiments import nav13 as ex

    v0, q0, ba, bg, P0 = ex.initial_state(s, "paper", np.random.default_rng(0))
    kv = _aid_index(t, dt, np.asarray(s.gps.t_valid, float), True)
    ky = _aid_index(t, dt, np.asarray(s.compass.t, float), True)
    mv, my = kv < n, ky < n
    return {
        "accel_noise": ("float", ex._density(s, "accel")), "gyro_noise": ("float", ex._density(s, "gyro")),
        "vel_noise": ("float", s.params["gps"]["vel_sigma_m_s"]),
        "yaw_noise": ("float", np.radians(s.params["compass"]["noise_deg"])),
        "x0_v": ("float", v0), "x0_q": ("float", q0), "P0": ("float", P0),
        "vel_k": ("unsigned", kv[mv]), "vel": ("float", np.asarray(s.gps.v_n)[mv]),
        "yaw_k": ("unsigned", ky[my]), "yaw": ("float", np.asarray(s.compass.yaw)[my]),
    }


def _gpsins_extra(s, t, n):
    """GpsInsFilter on paper 004: GPS (antenna position + velocity), altimeter, compass."""
    dt0 = np.array([0.0])
    kg = _aid_index(t, dt0, np.asarray(s.gps.t_valid, float), False)
    kb = _aid_index(t, dt0, np.asarray(s.baro.t, float), False)
    kc = _aid_index(t, dt0, np.asarray(s.compass.t, float), False)
    mg, mb, mc = kg < n, kb < n, kc < n
    return {
        "lever_arm_b": ("float", np.asarray(s.params["gps"]["lever_arm_b_m"], float)),
        "gps_k": ("unsigned", kg[mg]),
        "gps_llh": ("double", np.column_stack([s.gps.lat, s.gps.lon, s.gps.h])[mg]),
        "gps_vel": ("float", np.asarray(s.gps.v_n)[mg]),
        "baro_k": ("unsigned", kb[mb]), "baro_h": ("float", np.asarray(s.baro.h)[mb]),
        "compass_k": ("unsigned", kc[mc]), "compass": ("float", np.asarray(s.compass.yaw)[mc]),
    }


def _c_float(x):
    x = float(np.float32(x))
    if math.isnan(x):
        return "QN_NAN"
    return repr(x) + "f" if ("." in repr(x) or "e" in repr(x)) else repr(x) + ".0f"


def input_header(kind, d):
    n = len(d["dt"])
    rows = lambda a: ",\n".join("  {" + ", ".join(_c_float(v) for v in r) + "}" for r in a)
    lines = [
        f"// Generated by cpp/examples/embedded/run.py: {INPUTS[kind]['what']}.",
        f"// quatnav.sim scenario {INPUTS[kind]['scenario']!r}, seed {SEED}, options {INPUTS[kind]['options']}.",
        "// Sensor samples as float32: gyr rad/s, acc m/s^2 (specific force), mag T (NaN row: no",
        "// sample), dt s (row 0: the nominal interval); q0, v0, llh0: true initial state.",
        "#pragma once",
        f"#define QN_INPUT_{kind.upper()} 1",
        "namespace qn_input {",
        "#define QN_NAN __builtin_nanf(\"\")",
        f"constexpr unsigned kN = {n};",
        "static const float dt[kN] = {" + ", ".join(_c_float(v) for v in d["dt"]) + "};",
    ]
    for name in ("gyr", "acc", "mag"):
        lines.append(f"static const float {name}[kN][3] = {{\n{rows(d[name])}}};")
    touch = []
    for name, (ctype, val) in d.get("extra", {}).items():
        a = np.asarray(val)
        if a.ndim == 0:
            lines.append(f"constexpr float {name} = {_c_float(a)};")
            continue
        if ctype == "unsigned":
            fmt = lambda v: f"{int(v)}u"
        elif ctype == "double":
            fmt = lambda v: repr(float(v))
        else:
            fmt = _c_float
        m = max(1, len(a))
        if a.ndim == 1:
            if name.endswith("_k"):  # index array: its length is the aid count kN<Aid>
                lines.append(f"constexpr unsigned kN{_camel(name[:-2])} = {len(a)};")
            lines.append(f"static const {ctype} {name}[{m}] = {{" + ", ".join(fmt(v) for v in a) + "};")
            touch.append(f"float({name}[k % {m}])")
        else:
            body = ",\n".join("  {" + ", ".join(fmt(v) for v in r) + "}" for r in a)
            lines.append(f"static const {ctype} {name}[{m}][{a.shape[1]}] = {{\n{body}}};")
            touch.append(f"float({name}[k % {m}][k % {a.shape[1]}])")
    lines += [
        "static const float q0[4] = {" + ", ".join(_c_float(v) for v in d["q0"]) + "};",
        "static const float v0[3] = {" + ", ".join(_c_float(v) for v in d["v0"]) + "};",
        "static const double llh0[3] = {" + ", ".join(repr(float(v)) for v in d["llh0"]) + "};",
        f"static const int earth_rotation = {d['earth_rotation']};",
        "/// Reads one sample (the baseline image uses it so that it holds the same recording).",
        "inline float touch(unsigned k) {",
        "  return dt[k] + gyr[k][0] + gyr[k][1] + gyr[k][2] + acc[k][0] + acc[k][1] + acc[k][2] +",
        "         mag[k][0] + mag[k][1] + mag[k][2] + q0[k & 3] + v0[k % 3] + float(llh0[k % 3]) +",
        "         float(earth_rotation)" + "".join(f" +\n         {x}" for x in touch) + ";",
        "}",
        "#undef QN_NAN",
        "}  // namespace qn_input",
        "",
    ]
    return "\n".join(lines)


def _camel(name):
    """'compass' -> 'Compass', 'gps' -> 'Gps' (aid counts kNCompass, kNGps, ...)."""
    return "".join(w.capitalize() for w in name.split("_"))


def write_if_changed(path, text):
    path = Path(path)
    if path.exists() and path.read_text() == text:
        return
    path.write_text(text)


# --------------------------------------------------------------------------------------------
# Building (cached)
# --------------------------------------------------------------------------------------------

def eigen_include():
    env = os.environ.get("EIGEN_INCLUDE")
    if env:
        return env
    try:
        prefix = subprocess.run([sys.executable, "-m", "cmeel", "cmake"], capture_output=True, text=True,
                                check=True).stdout.strip().splitlines()[-1]
        p = Path(prefix) / "include" / "eigen3"
        if (p / "Eigen" / "Core").exists():
            return str(p)
    except (subprocess.CalledProcessError, FileNotFoundError, IndexError):
        pass
    if Path("/usr/include/eigen3/Eigen/Core").exists():
        return "/usr/include/eigen3"
    raise SystemExit("Eigen 3.4 not found: pip install cmeel-eigen, apt-get install libeigen3-dev, or set EIGEN_INCLUDE")


def sources_digest(extra_files):
    h = hashlib.sha256()
    files = sorted(INCLUDE.rglob("*.hpp")) + sorted(HERE.glob("*.[ch]*")) + [Path(f) for f in extra_files]
    for f in files:
        h.update(str(f).encode())
        h.update(Path(f).read_bytes())
    return h.hexdigest()


def run_cached(cmd, outputs, digest, cwd):
    """Run a build command unless its outputs exist with the same command and sources."""
    key = hashlib.sha256((" ".join(cmd) + digest).encode()).hexdigest()
    stamp = Path(str(outputs[0]) + ".key")
    if stamp.exists() and stamp.read_text() == key and all(Path(o).exists() for o in outputs):
        return False
    r = subprocess.run(cmd, cwd=cwd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"build failed: {' '.join(cmd)}\n{r.stdout}{r.stderr}")
    stamp.write_text(key)
    return True


def defines(name, kind, adapter, scalar):
    return [f"-DQN_SCALAR={scalar}", f"-DQN_ADAPTER={adapter}", f'-DQN_INPUT="input_{kind}.h"',
            f'-DQN_NAME="{name}"']


def build_target(job, build, eigen, digest):
    name, kind, adapter, opt = job
    d = build / f"{name}-{opt}"
    d.mkdir(parents=True, exist_ok=True)
    inc = ["-I", str(build), "-I", str(HERE), "-I", str(INCLUDE), "-isystem", eigen]
    fw_o, st_o, elf = d / "firmware.o", d / "startup.o", d / "fw.elf"
    run_cached(["arm-none-eabi-g++", f"-{opt}", *TARGET_CXXFLAGS, *GCC_PARAMS, *inc, *defines(name, kind, adapter, "float"),
                "-c", str(HERE / "firmware.cpp"), "-o", str(fw_o)], [fw_o], digest, d)
    run_cached(["arm-none-eabi-gcc", *TARGET_CFLAGS, "-I", str(HERE), "-c", str(HERE / "startup.c"), "-o",
                str(st_o)], [st_o], digest, d)
    # Linked by the C driver: the image needs no C++ runtime library (no exceptions, RTTI, heap or
    # static destructors), so Debian's 1.6 GB libstdc++-arm-none-eabi-newlib is not needed; the C++
    # headers come from libstdc++-arm-none-eabi-dev. A firmware that needed libsupc++ fails to link.
    run_cached(["arm-none-eabi-gcc", *TARGET_LDFLAGS, "-T", str(HERE / "mps2_an386.ld"),
                f"-Wl,-Map={d / 'fw.map'}", str(st_o), str(fw_o), "-lm", "-o", str(elf)], [elf], digest, d)
    return elf


def host_cxx():
    """The host programs' compiler: $CXX when set, else clang++ where it is installed (it compiles
    these Eigen-heavy programs in less CPU: the whole check 474 s of CPU against 606 s with g++,
    docs/DEVELOPING.md, "Test build"), else the system's c++. The host runs are references
    (double) and a comparison (float32), not the product: the Python module stays GCC's."""
    cxx = os.environ.get("CXX")
    if cxx:
        return cxx
    return "clang++" if shutil.which("clang++") else "c++"


@functools.lru_cache(maxsize=None)
def _is_gcc(cxx):
    """True when the compiler `cxx` is GCC (it takes GCC_PARAMS; clang does not)."""
    try:
        out = subprocess.run([cxx, "--version"], capture_output=True, text=True, check=True).stdout
    except (OSError, subprocess.CalledProcessError):
        return False
    return "Free Software Foundation" in out and "clang" not in out.lower()


def build_host(job, build, eigen, digest):
    name, kind, adapter, scalar = job
    d = build / f"host-{name}-{scalar}"
    d.mkdir(parents=True, exist_ok=True)
    exe = d / "fw_host"
    cxx = host_cxx()
    run_cached([cxx, *HOST_CXXFLAGS, *(GCC_PARAMS if _is_gcc(cxx) else []), "-I", str(build), "-I", str(HERE), "-I", str(INCLUDE), "-isystem", eigen,
                *defines(name, kind, adapter, scalar), str(HERE / "firmware.cpp"), "-o", str(exe)], [exe], digest, d)
    return exe


# --------------------------------------------------------------------------------------------
# Measuring
# --------------------------------------------------------------------------------------------

def section_sizes(elf):
    out = subprocess.run(["arm-none-eabi-size", "-A", str(elf)], capture_output=True, text=True, check=True).stdout
    sec = {}
    for line in out.splitlines():
        p = line.split()
        if len(p) >= 2 and p[0].startswith(".") and p[1].isdigit():
            sec[p[0]] = int(p[1])
    text = sec.get(".isr_vector", 0) + sec.get(".text", 0) + sec.get(".ARM.exidx", 0)
    return {"text": text, "data": sec.get(".data", 0), "bss": sec.get(".bss", 0)}


def library_text(map_path):
    """Bytes of code and read-only data that the link took from libm, libgcc and libc."""
    total, cur, in_map = 0, "", False
    pat = re.compile(r"\s(0x[0-9a-f]+)\s+(0x[0-9a-f]+)\s+\S*lib(m|gcc|c_nano|c)\.a\(")
    for line in Path(map_path).read_text().splitlines():
        if line.startswith("Linker script and memory map"):
            in_map = True
            continue
        if not in_map:
            continue
        if line.startswith(" .") or line.startswith(" *"):
            cur = line.split()[0]
        m = pat.search(line)
        if m and cur.startswith((".text", ".rodata")):
            total += int(m.group(2), 16)
    return total


def symbols(elf):
    out = subprocess.run(["arm-none-eabi-nm", "-g", "--defined-only", str(elf)], capture_output=True, text=True,
                         check=True).stdout
    return [line.split()[-1] for line in out.splitlines() if line.strip()]


def parse_callgraph(ci_path):
    """Nodes (title -> (name, static frame bytes or None)) and edges of a .ci (VCG) file."""
    nodes, edges = {}, {}
    node_re = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
    edge_re = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
    for line in Path(ci_path).read_text().splitlines():
        m = node_re.match(line)
        if m:
            parts = m.group(2).split("\\n")
            b = re.search(r"(\d+) bytes \((static|dynamic[^)]*)\)", m.group(2))
            nodes[m.group(1)] = (parts[0], int(b.group(1)) if b else None, b.group(2) if b else None)
            continue
        m = edge_re.match(line)
        if m:
            edges.setdefault(m.group(1), set()).add(m.group(2))
    return nodes, edges


def worst_stack(ci_path, root="qn_step"):
    """Deepest chain of frames from the step function: (bytes, chain of names, unknown callees)."""
    nodes, edges = parse_callgraph(ci_path)
    roots = [t for t in nodes if t == root or t.endswith(":" + root)]
    if not roots:
        return None
    unknown, dynamic = set(), set()
    memo = {}

    def walk(t, path):
        if t in memo:
            return memo[t]
        if t in path:  # recursion: not bounded statically
            dynamic.add(nodes.get(t, (t,))[0])
            return 0, []
        name, frame, kind = nodes.get(t, (t, None, None))
        if frame is None:
            unknown.add(name)
            frame = 0
        elif kind != "static":
            dynamic.add(name)
        best, chain = 0, []
        for c in edges.get(t, ()):
            b, ch = walk(c, path | {t})
            if b > best:
                best, chain = b, ch
        memo[t] = (frame + best, [name] + chain)
        return memo[t]

    total, chain = walk(roots[0], frozenset())
    return {"bytes": total, "depth": len(chain), "chain": chain, "unknown_callees": sorted(unknown),
            "dynamic": sorted(dynamic)}


def parse_output(text, scalar_bytes=None):
    res = {"q": [], "flags": [], "llh": [], "v": [], "end": False, "fault": None}
    fmt = {8: ">f", 16: ">d"}
    for line in text.splitlines():
        p = line.split()
        if not p:
            continue
        if p[0] == "BEGIN":
            res.update(name=p[1], n=int(p[2], 16), scalar_bytes=int(p[3], 16), state_bytes=int(p[4], 16),
                       object_bytes=int(p[5], 16))
        elif p[0] == "Q":
            res["flags"].append(int(p[2], 16))
            res["q"].append([np.frombuffer(bytes.fromhex(h), dtype=fmt[len(h)])[0] for h in p[3:7]])
        elif p[0] == "N":
            val = [np.frombuffer(bytes.fromhex(h), dtype=fmt[len(h)])[0] for h in p[2:8]]
            res["llh"].append(val[:3])
            res["v"].append(val[3:])
        elif p[0] == "STACK":
            res["stack"] = int(p[1], 16)
        elif p[0] == "TICKS":
            res["ticks"] = dict(sum=int(p[1], 16), min=int(p[2], 16), max=int(p[3], 16), overhead=int(p[4], 16))
        elif p[0] == "CAL":
            res["cal"] = dict(ticks=int(p[1], 16), insns=int(p[2], 16))
        elif p[0] == "END":
            res["end"] = True
        elif p[0] == "FAULT":
            res["fault"] = line
    res["q"] = np.array(res["q"], float)
    res["flags"] = np.array(res["flags"], np.uint32)
    res["llh"] = np.array(res["llh"], float).reshape(-1, 3)
    res["v"] = np.array(res["v"], float).reshape(-1, 3)
    return res


def pos_diff_m(llh1, llh2):
    """Distance (m) between two arrays of geodetic positions [lat, lon rad, h m] (WGS-84 radii)."""
    a, e2 = 6378137.0, 6.69437999014e-3
    lat = llh2[:, 0]
    sl2 = np.sin(lat) ** 2
    rm = a * (1 - e2) / (1 - e2 * sl2) ** 1.5 + llh2[:, 2]
    rn = a / np.sqrt(1 - e2 * sl2) + llh2[:, 2]
    dn = (llh1[:, 0] - llh2[:, 0]) * rm
    de = np.angle(np.exp(1j * (llh1[:, 1] - llh2[:, 1]))) * rn * np.cos(lat)
    dd = llh1[:, 2] - llh2[:, 2]
    return np.sqrt(dn ** 2 + de ** 2 + dd ** 2), np.hypot(dn, de), np.abs(dd)


def att_diff_deg(q1, q2):
    """Angle (deg) of the rotation between two arrays of attitude quaternions [w, x, y, z]."""
    q1 = q1 / np.linalg.norm(q1, axis=1, keepdims=True)
    q2 = q2 / np.linalg.norm(q2, axis=1, keepdims=True)
    d = np.abs(np.sum(q1 * q2, axis=1)).clip(0.0, 1.0)  # |cos(angle/2)|
    # 2 atan2(|vec(q1* q2)|, |w|) is exact for small angles too
    w1, v1, w2, v2 = q1[:, :1], q1[:, 1:], q2[:, :1], q2[:, 1:]
    vec = w1 * v2 - w2 * v1 - np.cross(v1, v2)
    return np.degrees(2.0 * np.arctan2(np.linalg.norm(vec, axis=1), d))


def tilt_err_deg(q, q_true):
    """Angle (deg) between the down axis seen in the body frame by q and by the truth."""
    from quatnav.core import quaternion as quat

    down = np.array([0.0, 0.0, 1.0])
    a = quat.rotate_inv(q / np.linalg.norm(q, axis=1, keepdims=True), np.broadcast_to(down, (len(q), 3)))
    b = quat.rotate_inv(q_true, np.broadcast_to(down, (len(q), 3)))
    return np.degrees(np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), np.sum(a * b, axis=1)))


def python_run(name, kind, d):
    """quatnav.<name>(dtype=float64).run on the recording (attitude after every sample), for the
    attitude and navigation filters; else None. Samples as the target sees them (float32)."""
    import quatnav

    if kind in NAV_KINDS:
        return python_nav_run(name, kind, d)
    cls = getattr(quatnav, name, None)
    if kind != "marg" or cls is None or not hasattr(cls, "run"):
        return None
    f32 = lambda a: np.asarray(a, np.float32).astype(np.float64)  # the samples as the target sees them
    r = cls(dtype=np.float64).run(f32(d["gyr"]), f32(d["acc"]), f32(d["mag"]), dt=f32(d["dt"]))
    return np.asarray(r.quat, float)


def python_nav_run(name, kind, d):
    """NavFilter13 / GpsInsFilter through the Python package, fed exactly like the adapters: the
    sample times are the running sum of the float32 intervals (exact in double), each aid is
    given the time of the sample after which the adapter applies it. Returns the attitude (NaN
    rows where the package reports none)."""
    import quatnav

    f32 = lambda a: np.asarray(a, np.float32).astype(np.float64)
    x = {k: (c, np.asarray(v)) for k, (c, v) in d["extra"].items()}
    dt = f32(d["dt"])
    t = np.concatenate([[0.0], np.cumsum(dt[1:])])
    acc, gyr = f32(d["acc"]), f32(d["gyr"])
    if kind == "nav13":
        tu = name.split("-")[1]
        tu = {"Ekf": "ekf", "SecondOrder": "second_order", "Ukf": "ukf"}[tu]
        f = quatnav.NavFilter13(time_update=tu, dtype=np.float64, acc_noise=float(f32(x["accel_noise"][1])),
                                gyro_noise=float(f32(x["gyro_noise"][1])), gps_vel_sigma=float(f32(x["vel_noise"][1])),
                                yaw_sigma=float(f32(x["yaw_noise"][1])))
        f.reset(f32(x["x0_v"][1]), f32(x["x0_q"][1]), np.zeros(3), np.zeros(3), f32(x["P0"][1]),
                lat=float(d["llh0"][0]), lon=float(d["llh0"][1]), h=float(d["llh0"][2]))
        r = f.run(gyr[1:], acc[1:], t=t[1:], gps_vel=quatnav.Aid(t[x["vel_k"][1]], f32(x["vel"][1])),
                  yaw=quatnav.Aid(t[x["yaw_k"][1]], f32(x["yaw"][1])))
        # sample 0 is the reset and its aids, which run() applies before its first sample
        return np.vstack([np.full(4, np.nan), r.quat])
    f = quatnav.GpsInsFilter(dtype=np.float64, lever_arm_b=tuple(f32(x["lever_arm_b"][1])))
    tg = t[x["gps_k"][1]]
    r = f.run(gyr, acc, t=t, gps_pos=quatnav.Aid(tg, x["gps_llh"][1]), gps_vel=quatnav.Aid(tg, f32(x["gps_vel"][1])),
              baro=quatnav.Aid(t[x["baro_k"][1]], f32(x["baro_h"][1])),
              compass=quatnav.Aid(t[x["compass_k"][1]], f32(x["compass"][1])))
    return np.asarray(r.quat, float)


# --------------------------------------------------------------------------------------------

def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--opt", nargs="+", default=["Os", "O2"], choices=["Os", "O2", "O3", "O1"],
                    help="optimization levels of the target build (default: Os O2)")
    ap.add_argument("--filters", default=None, help="comma-separated subset of: "
                    + ", ".join(f[0] for f in FILTERS))
    ap.add_argument("--build-dir", default=str(ROOT / "build" / "embedded"))
    ap.add_argument("--report-dir", default=str(HERE), help="where report.json and REPORT.md go")
    ap.add_argument("--no-host-float", action="store_true", help="skip the host float32 run")
    ap.add_argument("--check", action="store_true", help="exit non-zero when a check fails")
    ap.add_argument("--tol-deg", type=float, default=0.05,
                    help="largest allowed attitude difference target float32 vs host double (deg)")
    ap.add_argument("--jobs", type=int, default=int(os.environ.get("QUATNAV_JOBS", "2")))
    ap.add_argument("--qemu-timeout", type=float, default=120.0)
    args = ap.parse_args(argv)

    for tool in ("arm-none-eabi-g++", "arm-none-eabi-size", "arm-none-eabi-nm", "qemu-system-arm"):
        if shutil.which(tool) is None:
            raise SystemExit(f"{tool} not found (Debian: apt-get install gcc-arm-none-eabi "
                             "libnewlib-arm-none-eabi qemu-system-arm)")
    probe = subprocess.run(["arm-none-eabi-g++", *CPU_FLAGS, "-x", "c++", "-fsyntax-only", "-"],
                           input="#include <cstddef>\n#include <cmath>\n", capture_output=True, text=True)
    if probe.returncode != 0:
        raise SystemExit("arm-none-eabi-g++ has no C++ standard headers (Debian: apt-get install "
                         "libstdc++-arm-none-eabi-dev)\n" + probe.stderr[-500:])
    filters = FILTERS
    if args.filters:
        want = args.filters.split(",")
        unknown = set(want) - {f[0] for f in FILTERS}
        if unknown:
            raise SystemExit(f"unknown filters: {sorted(unknown)}")
        filters = [f for f in FILTERS if f[0] in want]
    kinds = sorted({f[1] for f in filters})
    build = Path(args.build_dir)
    build.mkdir(parents=True, exist_ok=True)
    t_start = time.time()

    log("== recorded inputs: " + ", ".join(f"{k} ({INPUTS[k]['scenario']}, {INPUTS[k]['n']} samples)" for k in kinds))
    inputs = {}
    from quatnav.filters.tables import FLAGS  # the one flag table (core/flags.hpp)

    for k in kinds:
        inputs[k] = make_input(k)
        write_if_changed(build / f"input_{k}.h", input_header(k, inputs[k]))
    eigen = eigen_include()
    digest = sources_digest([build / f"input_{k}.h" for k in kinds])

    jobs_t = [(f"null_{k}", k, NULL_ADAPTER, o) for k in kinds for o in args.opt]
    jobs_t += [(n, k, a, o) for (n, k, a) in filters for o in args.opt]
    scalars = ["double"] + ([] if args.no_host_float else ["float"])
    jobs_h = [(n, k, a, s) for (n, k, a) in filters for s in scalars]
    log(f"== building {len(jobs_t)} target images and {len(jobs_h)} host programs (-j{args.jobs})")
    with cf.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as ex:
        ft = {j: ex.submit(build_target, j, build, eigen, digest) for j in jobs_t}
        fh = {j: ex.submit(build_host, j, build, eigen, digest) for j in jobs_h}
        elfs = {(j[0], j[3]): f.result() for j, f in ft.items()}
        hosts = {(j[0], j[3]): f.result() for j, f in fh.items()}
    log(f"   built in {time.time() - t_start:.0f} s")

    def qemu(elf):
        r = subprocess.run(QEMU + ["-kernel", str(elf)], capture_output=True, text=True, timeout=args.qemu_timeout)
        return r.returncode, r.stdout + r.stderr

    failures = []
    host_runs = {}
    for key, exe in hosts.items():
        r = subprocess.run([str(exe)], capture_output=True, text=True, timeout=300)
        host_runs[key] = parse_output(r.stdout)
        if r.returncode != 0 or not host_runs[key]["end"]:
            failures.append(f"host run {key} failed (exit {r.returncode})")

    rows = []
    base = {(k, o): section_sizes(elfs[(f"null_{k}", o)]) for k in kinds for o in args.opt}
    base_lib = {(k, o): library_text(elfs[(f"null_{k}", o)].parent / "fw.map") for k in kinds for o in args.opt}
    base_syms = {(k, o): set(symbols(elfs[(f"null_{k}", o)])) for k in kinds for o in args.opt}
    for (name, kind, adapter) in filters:
        for opt in args.opt:
            elf = elfs[(name, opt)]
            t0 = time.time()
            rc, out = qemu(elf)
            t_qemu = time.time() - t0
            tg = parse_output(out)
            row = {"filter": name, "input": kind, "opt": opt, "qemu_s": round(t_qemu, 2)}
            if rc != 0 or not tg["end"] or tg["fault"] or len(tg["q"]) != INPUTS[kind]["n"]:
                failures.append(f"{name} -{opt}: emulator run incomplete (exit {rc}, {tg['fault'] or ''})")
                row["error"] = out[-2000:]
                rows.append(row)
                continue
            sz, b = section_sizes(elf), base[(kind, opt)]
            syms = symbols(elf)
            bad = sorted(s for s in syms if FORBIDDEN.match(s))
            if bad:
                failures.append(f"{name} -{opt}: links {bad}")
            st = worst_stack(elf.parent / "firmware.ci")
            cal = tg["cal"]
            insn_per_tick = cal["insns"] / max(1, cal["ticks"] - tg["ticks"]["overhead"])
            n_steps = len(tg["q"]) - 1
            ticks = tg["ticks"]
            mean_insn = (ticks["sum"] / n_steps - ticks["overhead"]) * insn_per_tick
            hd = host_runs[(name, "double")]
            diff = att_diff_deg(tg["q"], hd["q"])
            row.update({
                "text": sz["text"] - b["text"],
                "text_libraries": library_text(elf.parent / "fw.map") - base_lib[(kind, opt)], "data_bss": sz["data"] + sz["bss"] - b["data"] - b["bss"],
                "image_text": sz["text"], "image_data": sz["data"], "image_bss": sz["bss"],
                "stack_static": st["bytes"] if st else None, "stack_depth": st["depth"] if st else None,
                "stack_chain": st["chain"] if st else None,
                "stack_unknown_callees": st["unknown_callees"] if st else None,
                "stack_measured": tg["stack"], "state_bytes": tg["state_bytes"], "object_bytes": tg["object_bytes"],
                "insn_per_step_mean": round(mean_insn),
                "insn_per_step_max": round((ticks["max"] - ticks["overhead"]) * insn_per_tick),
                "insn_per_step_min": round((ticks["min"] - ticks["overhead"]) * insn_per_tick),
                "max_att_diff_vs_host_double_deg": float(diff.max()),
                "final_att_diff_vs_host_double_deg": float(diff[-1]),
                "flags_differ_vs_host_double": int(np.count_nonzero(tg["flags"] != hd["flags"])),
                "soft_double": sorted(s for s in syms if SOFT_DOUBLE.match(s) and s not in base_syms[(kind, opt)]),
                "forbidden_symbols": bad,
            })
            if (name, "float") in host_runs:
                row["max_att_diff_vs_host_float_deg"] = float(att_diff_deg(tg["q"], host_runs[(name, "float")]["q"]).max())
            if kind in NAV_KINDS:
                if len(tg["llh"]) != len(tg["q"]) or len(hd["llh"]) != len(hd["q"]):
                    failures.append(f"{name} -{opt}: position/velocity output incomplete")
                else:
                    dp, dph, dpv = pos_diff_m(tg["llh"], hd["llh"])
                    dv = np.linalg.norm(tg["v"] - hd["v"], axis=1)
                    row.update({"max_pos_diff_vs_host_double_m": float(dp.max()),
                                "final_pos_diff_vs_host_double_m": float(dp[-1]),
                                "max_horiz_pos_diff_vs_host_double_m": float(dph.max()),
                                "max_height_diff_vs_host_double_m": float(dpv.max()),
                                "max_vel_diff_vs_host_double_m_s": float(dv.max()),
                                "final_vel_diff_vs_host_double_m_s": float(dv[-1])})
                    if (name, "float") in host_runs and len(host_runs[(name, "float")]["llh"]) == len(tg["llh"]):
                        hf = host_runs[(name, "float")]
                        row["max_pos_diff_vs_host_float_m"] = float(pos_diff_m(tg["llh"], hf["llh"])[0].max())
                        row["max_vel_diff_vs_host_float_m_s"] = float(np.linalg.norm(tg["v"] - hf["v"], axis=1).max())
                    nav = np.ones(len(hd["q"]), bool)
                    if kind == "gpsins":  # position and velocity exist once navigation has started
                        nav = (hd["flags"] & FLAGS["navigating"]) != 0
                    if nav.any():
                        e_p = pos_diff_m(hd["llh"][nav], inputs[kind]["truth_llh"][nav])[0]
                        e_v = np.linalg.norm(hd["v"][nav] - inputs[kind]["truth_v"][nav], axis=1)
                        row["host_double_pos_err_rms_m"] = float(np.sqrt(np.mean(e_p ** 2)))
                        row["host_double_vel_err_rms_m_s"] = float(np.sqrt(np.mean(e_v ** 2)))
            py = python_run(name, kind, inputs[kind])
            if py is not None:
                ok = np.all(np.isfinite(py), axis=1)
                row["host_double_vs_python_deg"] = float(att_diff_deg(hd["q"][ok], py[ok]).max())
            truth = inputs[kind]["truth_q"]
            if kind == "gpsins":  # attitude once levelled (before that the filter has none)
                lev = (hd["flags"] & (FLAGS["levelled"] | FLAGS["navigating"])) != 0
                row["host_double_att_err_rms_deg"] = float(np.sqrt(np.mean(att_diff_deg(hd["q"][lev], truth[lev]) ** 2)))
            elif kind == "marg":  # heading is relative to magnetic north: compare the tilt only
                row["host_double_tilt_err_rms_deg"] = float(np.sqrt(np.mean(tilt_err_deg(hd["q"], truth) ** 2)))
            else:
                row["host_double_att_err_rms_deg"] = float(np.sqrt(np.mean(att_diff_deg(hd["q"], truth) ** 2)))
            if not diff.max() <= args.tol_deg:
                failures.append(f"{name} -{opt}: attitude differs from host double by {diff.max():.3g} deg "
                                f"> {args.tol_deg} deg")
            rows.append(row)
            log(f"   {name:14s} -{opt}: text {row['text']:6d} B, data+bss {row['data_bss']:5d} B, "
                f"stack {row['stack_static']} B static / {row['stack_measured']} B measured, "
                f"state {row['state_bytes']} B, {row['insn_per_step_mean']} insn/step, "
                f"max diff vs double {row['max_att_diff_vs_host_double_deg']:.2e} deg"
                + (f", {row['max_pos_diff_vs_host_double_m']:.2e} m, {row['max_vel_diff_vs_host_double_m_s']:.2e} m/s"
                   if "max_pos_diff_vs_host_double_m" in row else "") + f" ({t_qemu:.1f} s in QEMU)")

    report = {
        "command": " ".join(["python cpp/examples/embedded/run.py"] + list(sys.argv[1:] if argv is None else argv)),
        "target": "QEMU mps2-an386 (Cortex-M4), " + " ".join(CPU_FLAGS),
        "target_cxxflags": TARGET_CXXFLAGS, "host_cxxflags": HOST_CXXFLAGS,
        "compiler": subprocess.run(["arm-none-eabi-g++", "--version"], capture_output=True,
                                   text=True).stdout.splitlines()[0],
        "qemu": subprocess.run(["qemu-system-arm", "--version"], capture_output=True, text=True).stdout.splitlines()[0],
        "inputs": {k: {kk: vv for kk, vv in INPUTS[k].items()} | {"seed": SEED} for k in kinds},
        "baseline": {f"{k}-{o}": v for (k, o), v in base.items()},
        "rows": rows, "failures": failures, "seconds": round(time.time() - t_start, 1),
    }
    rep = Path(args.report_dir)
    rep.mkdir(parents=True, exist_ok=True)
    (rep / "report.json").write_text(json.dumps(report, indent=1) + "\n")
    (rep / "REPORT.md").write_text(markdown(report))
    log(f"== wrote {rep / 'report.json'} and {rep / 'REPORT.md'} ({report['seconds']} s)")
    for f in failures:
        log("FAIL " + f)
    if args.check and failures:
        return 1
    return 0


def short_name(sig):
    """'quatnav::Status quatnav::kalman_correct(...) [with ...]' -> 'kalman_correct'."""
    head = sig.split("(")[0].split(" [")[0]
    return head.split(" ")[-1].split("::")[-1] or sig


def markdown(rep):
    L = ["# Embedded baseline: quatnav filters in float32 on a Cortex-M4F", "",
         f"Generated by `{rep['command']}` ({rep['seconds']} s). Target: {rep['target']}; "
         f"`{rep['compiler']}`; `{rep['qemu']}`.", "",
         "| filter | opt | .text (B) (of which libm/libgcc) | .data+.bss (B) | stack/step static (B, frames) | stack/step measured (B) "
         "| state (B) | object (B) | instructions/step mean (max) | max attitude diff vs host double (deg) "
         "| vs host float (deg) |",
         "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rep["rows"]:
        if "error" in r:
            L.append(f"| {r['filter']} | -{r['opt']} | emulator run failed | | | | | | | | |")
            continue
        vf = r.get("max_att_diff_vs_host_float_deg")
        L.append(f"| {r['filter']} | -{r['opt']} | {r['text']} ({r['text_libraries']}) | {r['data_bss']} | {r['stack_static']} "
                 f"({r['stack_depth']}) | {r['stack_measured']} | {r['state_bytes']} | {r['object_bytes']} | "
                 f"{r['insn_per_step_mean']} ({r['insn_per_step_max']}) | {r['max_att_diff_vs_host_double_deg']:.2e} | "
                 + (f"{vf:.2e}" if vf is not None else "-") + " |")
    nav_rows = [r for r in rep["rows"] if "max_pos_diff_vs_host_double_m" in r]
    if nav_rows:
        L += ["", "Navigation filters, position and velocity of the target's float32 run against the host's double "
              "(resp. float) run:", "",
              "| filter | opt | max position diff (m) (horizontal / height) | final position diff (m) "
              "| max velocity diff (m/s) | vs host float: position (m) / velocity (m/s) "
              "| host double vs truth RMS: position (m) / velocity (m/s) |",
              "|---|---|---|---|---|---|---|"]
        for r in nav_rows:
            pf = r.get("max_pos_diff_vs_host_float_m")
            vf = r.get("max_vel_diff_vs_host_float_m_s")
            L.append(f"| {r['filter']} | -{r['opt']} | {r['max_pos_diff_vs_host_double_m']:.3g} "
                     f"({r['max_horiz_pos_diff_vs_host_double_m']:.3g} / {r['max_height_diff_vs_host_double_m']:.3g}) | "
                     f"{r['final_pos_diff_vs_host_double_m']:.3g} | {r['max_vel_diff_vs_host_double_m_s']:.2e} | "
                     + (f"{pf:.3g} / {vf:.2e}" if pf is not None else "-") + " | "
                     + (f"{r['host_double_pos_err_rms_m']:.3g} / {r['host_double_vel_err_rms_m_s']:.3g}"
                        if "host_double_pos_err_rms_m" in r else "-") + " |")
        L += ["", "Both filters keep the geodetic position (latitude, longitude, height) in double for every "
              "scalar type (a float32 latitude resolves only 0.38 m); on a Cortex-M4F that is software "
              "floating point. docs/PORTING.md explains the difference these columns show."]
    L += ["", "Columns:",
          "- **.text**, **.data+.bss**: the image with the filter minus the same firmware without it "
          "(same recording, startup and output code), from `arm-none-eabi-size`; in parentheses the part "
          "taken from libm, libgcc (software double) and libc, from the linker map. The filter object is "
          "a static, so it is in .bss.",
          "- **stack/step static**: the deepest chain of frames below `qn_step` (one sample: "
          "predict + updates, or the initialization) in GCC's call graph (`-fcallgraph-info=su`); "
          "libm/libc leaf functions (no stack information) count 0. **measured**: high-water mark "
          "of the painted stack over the whole run on the target, from the stack pointer at the call.",
          "- **state**: `sizeof(State)` (what `state()`/`set_state()` copy); **object**: `sizeof` the "
          "filter with its parameters.",
          "- **instructions/step**: SysTick read around each step under `qemu -icount` (a fixed virtual "
          "time per instruction), calibrated against a loop of known length; mean over the run "
          "(max = worst single step). Instructions, not cycles: a Cortex-M4 spends 1 cycle on most "
          "FPU instructions but 14 on vdiv/vsqrt and more on loads after stores and taken branches.",
          "- **max attitude diff**: largest rotation angle between the target's float32 attitude and "
          "the host's double (resp. float) run of the same source on the same samples.",
          ""]
    L.append("Inputs: " + "; ".join(f"`{k}` = `{v['scenario']}` seed {v['seed']}, {v['n']} samples ({v['what']})"
                                     for k, v in rep["inputs"].items()) + ".")
    extra = []
    for r in rep["rows"]:
        if "error" in r:
            continue
        t = ("tilt error vs truth RMS " + f"{r['host_double_tilt_err_rms_deg']:.2f} deg"
             if "host_double_tilt_err_rms_deg" in r else
             "attitude error vs truth RMS " + f"{r['host_double_att_err_rms_deg']:.3f} deg")
        sd = ", ".join(r["soft_double"]) if r["soft_double"] else "none"
        if "host_double_vs_python_deg" in r:
            t += f"; host double vs `quatnav.{r['filter']}().run` {r['host_double_vs_python_deg']:.1e} deg"
        extra.append(f"- {r['filter']} -{r['opt']}: host double {t}; step flags differing from host double: "
                     f"{r['flags_differ_vs_host_double']}; soft-float double helpers added by the filter: {sd}; "
                     f"deepest static chain: {' > '.join(short_name(c) for c in r['stack_chain'] or [])}.")
    L += ["", "Per filter:"] + extra
    if rep["failures"]:
        L += ["", "Failures:"] + [f"- {f}" for f in rep["failures"]]
    else:
        L += ["", "Checks passed: every image runs to the end in the emulator; no image links malloc, "
              "_sbrk, operator new, exception or RTTI support, or iostream."]
    return "\n".join(L) + "\n"


if __name__ == "__main__":
    sys.exit(main())
