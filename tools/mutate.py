#!/usr/bin/env python3
"""Inject typical slips into a scratch copy, one at a time, and report whether the tests catch them.

    python3 tools/mutate.py                 # every mutation: build, test, table (exit 1 if one is missed)
    python3 tools/mutate.py -k nav13        # only the mutations whose name or area contains "nav13"
    python3 tools/mutate.py --area attitude # only that area's (-k attitude also picks nav13's "velocity-attitude")
    python3 tools/mutate.py --list          # the mutations
    python3 tools/mutate.py --check         # only check that every pattern matches its file exactly once
    python3 tools/mutate.py --markdown      # the table as docs/DEVELOPING.md shows it

A mutation is a file, an exact text that must occur there exactly once (the tool fails loudly
when it does not: the code moved, update the pattern), its replacement, the build targets it needs
and the tests that should catch it (GoogleTest executables, then pytest node ids, in that order;
the first that fails catches it and the rest are not run). A few "mutations" change no file but
an environment variable: QUATNAV_TEST_VARIANCE_SCALE = 1/1.5 or 1.5 runs every consistency test
with the filter told Q, R and P0 scaled (tests/python/_consistency.py), and each must fail.

The scratch copy (the tracked and untracked, not ignored, files of this checkout) lives in
``build/mutate/src`` with its own build in ``build/mutate/src/build/dev``: the same relative layout
as a checkout's ``build/dev``, so that ccache serves every unit a mutation does not touch. The
tool first builds every needed target and runs every test unmutated: all must pass. Then, per
mutation: write the mutated file, build, run its tests, restore the file.

tests/python/test_regression.py is never one of the tests: it fails on any numerical change by
design (change indication), so it would "catch" every mutation and tell nothing about the others.
"""
from __future__ import annotations

import argparse
import dataclasses
import fcntl
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]

OVER, UNDER = "0.6666666666666666", "1.5"


@dataclasses.dataclass(frozen=True)
class Mutation:
    name: str                 #: the slip, in words
    area: str                 #: the filter or part
    path: str = ""            #: the file, relative to the repository ("" for an environment mutation)
    find: str = ""            #: exact text, found exactly once
    replace: str = ""
    targets: tuple = ()       #: CMake targets to build
    cpp: tuple = ()           #: GoogleTest executables ("name" or "name:gtest filter")
    py: tuple = ()            #: pytest node ids or files under tests/python
    env: tuple = ()           #: (name, value) pairs set for the tests


def _m(name, area, path, find, replace, cpp=(), py=(), targets=None):
    if targets is None:
        targets = tuple(c.split(":")[0] for c in cpp) + (("_core",) if py and path.startswith("cpp/") else ())
    return Mutation(name, area, path, find, replace, tuple(targets), tuple(cpp), tuple(py))


NAV13 = "cpp/include/quatnav/nav/nav_filter13.hpp"
NAV13_TESTS_PY = ("tests/python/test_nav13.py", "tests/python/test_nav13_smoother.py")
KALMAN = "cpp/include/quatnav/core/kalman.hpp"
ESKF = "cpp/include/quatnav/attitude/quaternion_ekf.hpp"
QEKF = "cpp/include/quatnav/attitude/quaternion_ekf_paper.hpp"
EULER = "cpp/include/quatnav/attitude/euler_ekf.hpp"
MARG = "cpp/include/quatnav/attitude/marg_filter.hpp"
STRAP = "cpp/include/quatnav/nav/strapdown.hpp"
GPSINS_AIDS = "cpp/include/quatnav/nav/gps_ins/aids.hpp"
GPSINS_BATCH = "cpp/include/quatnav/nav/gps_ins/batch.hpp"
QUAT = "cpp/include/quatnav/core/quaternion.hpp"

MUTATIONS: list[Mutation] = [
    # ---- NavFilter13 (paper 002) ------------------------------------------------------------------
    _m("F: sign of the velocity-attitude block (eq. A.9)", "nav13", NAV13,
       "F.template block<3, 4>(kV, kQ) = dt * dCa_dq(q, a);",
       "F.template block<3, 4>(kV, kQ) = -dt * dCa_dq(q, a);", cpp=("test_nav13",)),
    _m("F: gyro-bias block of the quaternion rows halved (eq. A.15)", "nav13", NAV13,
       "F.template block<4, 3>(kQ, kBg) = (-dt / S(2)) * quat::xi(q);",
       "F.template block<4, 3>(kQ, kBg) = (-dt / S(4)) * quat::xi(q);", cpp=("test_nav13",)),
    _m("Coriolis factor 2 dropped (eq. A.4)", "nav13", NAV13,
       "const Vec3<S> alpha = S(2) * u.omega_ie_n + u.omega_en_n;  // eq. (A.4)",
       "const Vec3<S> alpha = u.omega_ie_n + u.omega_en_n;  // eq. (A.4)", cpp=("test_nav13_consistency",),
       py=NAV13_TESTS_PY),
    _m("rotation correction of the velocity increment with the wrong sign (eq. 12)", "nav13", NAV13,
       "return f_ib_b + (dt / S(2)) * Vec3<S>(omega_ib_b - b_g).cross(Vec3<S>(f_ib_b - b_a));",
       "return f_ib_b - (dt / S(2)) * Vec3<S>(omega_ib_b - b_g).cross(Vec3<S>(f_ib_b - b_a));",
       cpp=("test_nav13_consistency",)),
    _m("process noise: the gyro term dropped (eq. 11)", "nav13", NAV13,
       "Q.template block<4, 4>(kQ, kQ) = (dt * p.gyro_noise * p.gyro_noise / S(4)) * X * X.transpose();",
       "Q.template block<4, 4>(kQ, kQ).setZero();", cpp=("test_nav13_consistency",), py=NAV13_TESTS_PY),
    _m("process noise: accelerometer variance not times dt (eq. 12)", "nav13", NAV13,
       "Q.template block<3, 3>(kV, kV) = (dt * p.acc_noise * p.acc_noise) * C * C.transpose();",
       "Q.template block<3, 3>(kV, kV) = (p.acc_noise * p.acc_noise) * C * C.transpose();",
       cpp=("test_nav13_consistency",), py=NAV13_TESTS_PY),
    _m("R of the velocity scaled by 2 (eq. 21)", "nav13", NAV13,
       "const Mat3<S> R = Mat3<S>::Identity() * (params_.gps_vel_sigma * params_.gps_vel_sigma);",
       "const Mat3<S> R = Mat3<S>::Identity() * (S(2) * params_.gps_vel_sigma * params_.gps_vel_sigma);",
       cpp=("test_nav13_consistency",), py=NAV13_TESTS_PY),
    _m("yaw Jacobian with the wrong sign (eq. 21)", "nav13", NAV13,
       "  return (d * dn - n * dd) / (n * n + d * d);",
       "  return (n * dd - d * dn) / (n * n + d * d);", cpp=("test_nav13",)),
    _m("second-order term: the q-b_g part's sign (eq. 17)", "nav13", NAV13,
       "  s.template segment<4>(kQ) = (-dt / S(2)) * sq;",
       "  s.template segment<4>(kQ) = (dt / S(2)) * sq;", cpp=("test_nav13",)),
    _m("covariance not symmetrized after the time update", "nav13", NAV13,
       "  Mat13<S> Pn = nav13_propagate(F, P) + nav13_process_noise(Quat<S>(x.template segment<4>(kQ)), u.dt, p);  // (19)-(20)\n  symmetrize(Pn);",
       "  Mat13<S> Pn = nav13_propagate(F, P) + nav13_process_noise(Quat<S>(x.template segment<4>(kQ)), u.dt, p);  // (19)-(20)",
       cpp=("test_nav13", "test_nav13_float"), py=NAV13_TESTS_PY),
    _m("UKF: the mean rotation vector's refinement dropped", "nav13", NAV13,
       "  qm = quat::mul(qm, quat::from_rotvec(dmean));\n",
       "", cpp=("test_nav13",), py=NAV13_TESTS_PY),
    _m("batch: a measurement applied one IMU sample early", "nav13", NAV13,
       "    apply(t[k] + 1e-4 * double(dt[k]), fl);",
       "    apply(t[k] + 1.0001 * double(dt[k]), fl);", py=NAV13_TESTS_PY),
    _m("measurement update: quaternion not renormalized", "nav13", NAV13,
       "          detail::nav13_normalize(xv, Pc);\n          if (!detail::nav13_state_ok(xv, Pc)) return false;",
       "          if (!detail::nav13_state_ok(xv, Pc)) return false;", cpp=("test_nav13",)),
    _m("numpy twin: F's velocity-attitude block with the wrong sign", "nav13", "python/quatnav/reference/nav13.py",
       "F[V, QI] = dt * dCa_dq(q, a)", "F[V, QI] = -dt * dCa_dq(q, a)", py=NAV13_TESTS_PY),
    # ---- the Kalman correction shared by every filter --------------------------------------------
    _m("Joseph form: the K R K^T term dropped", "core", KALMAN,
       "  W.noalias() = K.lazyProduct(R);\n", "  W.setZero();\n", cpp=("test_kalman",)),
    _m("Joseph form: not symmetrized", "core", KALMAN,
       "  P_out.noalias() += W.lazyProduct(K.transpose());\n  symmetrize(P_out);",
       "  P_out.noalias() += W.lazyProduct(K.transpose());", cpp=("test_kalman",)),
    _m("NIS from the innovation covariance without R", "core", KALMAN,
       "  Mat<S, M, M> Sm = R;\n  Sm.noalias() += Hc.lazyProduct(PHt.template middleRows<NC>(C0));",
       "  Mat<S, M, M> Sm = R;\n  Sm.noalias() = Hc.lazyProduct(PHt.template middleRows<NC>(C0));",
       cpp=("test_kalman",)),
    # ---- attitude filters (paper 000, paper 004's Euler form) -------------------------------------
    _m("ESKF: R of the accelerometer scaled by 2", "attitude", ESKF,
       "    r << Vec3<S>::Constant(params_.acc_sigma * params_.acc_sigma),",
       "    r << Vec3<S>::Constant(S(2) * params_.acc_sigma * params_.acc_sigma),",
       cpp=("test_qekf_eskf:EskfConsistency*", "test_qekf_eskf_joint")),
    _m("ESKF: the gravity rows' NIS without the row along h", "attitude", ESKF,
       "  res.nis = yt.dot(z) + y3 * y3 / r;", "  res.nis = yt.dot(z);",
       cpp=("test_qekf_eskf:EskfGravity*",)),
    _m("ESKF: gyro noise dropped from the time update", "attitude", ESKF,
       "    const S qa = dt * params_.gyro_noise * params_.gyro_noise;",
       "    const S qa = S(0) * params_.gyro_noise * params_.gyro_noise;",
       cpp=("test_qekf_eskf",)),
    _m("ESKF: the error-reset Jacobian's sign (G = I - [dtheta/2]x)", "attitude", ESKF,
       "  const Mat3<S> G = Mat3<S>::Identity() - quat::skew(Vec3<S>(dtheta * S(0.5)));",
       "  const Mat3<S> G = Mat3<S>::Identity() + quat::skew(Vec3<S>(dtheta * S(0.5)));",
       cpp=("test_qekf_eskf",), py=("tests/python/test_attitude_consistency.py",)),
    _m("7-state QuaternionEKF: process noise not divided by 4 (eq. 6)", "attitude", QEKF,
       "Mat4<S> Qqq = (dt * params_.gyro_noise * params_.gyro_noise / S(4)) * X * X.transpose();",
       "Mat4<S> Qqq = (dt * params_.gyro_noise * params_.gyro_noise) * X * X.transpose();",
       cpp=("test_attitude_filters",), py=("tests/python/test_attitude_consistency.py",)),
    _m("EulerEKF: gyro noise variance not times dt", "attitude", EULER,
       "predict_covariance_fb<S, 3, 3>(st_.P, G, B, (dt * params_.gyro_noise * params_.gyro_noise) * E * E.transpose(),",
       "predict_covariance_fb<S, 3, 3>(st_.P, G, B, (params_.gyro_noise * params_.gyro_noise) * E * E.transpose(),",
       cpp=("test_attitude_filters",), py=("tests/python/test_attitude_consistency.py",)),
    _m("GyroClip: the low-pass not restarted after a clipped step", "attitude", ESKF,
       "    if ((clip_var.array() > S(0)).any()) AccFilter<S>::restart(st_.acc);",
       "    if (false && (clip_var.array() > S(0)).any()) AccFilter<S>::restart(st_.acc);",
       cpp=("test_qekf_robust:GyroClip*",), py=("tests/python/test_attitude_fast_motion.py",)),
    _m("EulerEKF: the exact step dropped (paper 004's Euler step only)", "attitude", EULER,
       "  if (exact && !singular) {", "  if (false && exact && !singular) {",
       cpp=("test_attitude_filters",), py=("tests/python/test_attitude_fast_motion.py",)),
    # ---- MargFilter (paper 001) -------------------------------------------------------------------
    _m("lever arm: the centripetal term's sign (eq. 7')", "marg", MARG,
       "  return f_b + omega_dot_b.cross(d_b) + omega_b.cross(omega_b.cross(d_b));",
       "  return f_b + omega_dot_b.cross(d_b) - omega_b.cross(omega_b.cross(d_b));",
       cpp=("test_marg",), py=("tests/python/test_marg.py",)),
    _m("batch: a GPS fix used one IMU sample early", "marg", MARG,
       "    while (j < m && gps_t[j] <= t[k]) {",
       "    while (j < m && gps_t[j] <= t[k] + dt[k]) {", cpp=("test_marg",), py=("tests/python/test_marg.py",)),
    # ---- strapdown --------------------------------------------------------------------------------
    _m("sculling: the rotation term's sign", "strapdown", STRAP,
       "  Vec3<S> dv_rot = dvb + S(0.5) * c + dth.cross(c) / S(6);",
       "  Vec3<S> dv_rot = dvb - S(0.5) * c + dth.cross(c) / S(6);",
       cpp=("test_earth_strapdown",), py=("tests/python/test_sim_strapdown.py",)),
    _m("Coriolis factor 2 dropped", "strapdown", STRAP,
       "(g_n - (S(2) * e.w_ie + e.w_en).cross(v_m)) * dt);",
       "(g_n - (e.w_ie + e.w_en).cross(v_m)) * dt);",
       cpp=("test_earth_strapdown",), py=("tests/python/test_sim_strapdown.py",)),
    # ---- quaternion helpers shared by every filter ------------------------------------------------
    _m("to_rotvec: the angle halved (beyond the small-angle branch)", "core", QUAT,
       "  return (S(2) * std::atan2(sn, q[0]) / sn) * v;", "  return (std::atan2(sn, q[0]) / sn) * v;",
       cpp=("test_quaternion",)),
    # ---- GpsInsFilter (paper 004) ---------------------------------------------------------------
    _m("GPS velocity: the lever-arm term's sign", "gpsins", GPSINS_AIDS,
       "  return s.nav.v_n + C * s.omega_b.cross(p.lever_arm_b);",
       "  return s.nav.v_n - C * s.omega_b.cross(p.lever_arm_b);",
       cpp=("test_gpsins_aids",), py=("tests/python/test_gpsins.py",)),
    _m("ZUPT: R scaled by 2", "gpsins", GPSINS_AIDS,
       "    m.R.diagonal().setConstant(p.zupt_sigma * p.zupt_sigma);",
       "    m.R.diagonal().setConstant(S(2) * p.zupt_sigma * p.zupt_sigma);",
       cpp=("test_gpsins_aids",), py=("tests/python/test_gpsins.py", "tests/python/test_gpsins_motion.py")),
    _m("batch: the compass applied one IMU sample early", "gpsins", GPSINS_BATCH,
       "      for (; ic < io.nc && io.compass_t[ic] <= tk; ++ic) {",
       "      for (; ic < io.nc && io.compass_t[ic] <= tk + (k + 1 < io.n ? io.t[k + 1] - tk : 0.0); ++ic) {",
       cpp=("test_gpsins_smoother",), py=("tests/python/test_gpsins.py",)),
]

#: Every consistency test, run with the filter told Q, R and P0 scaled (each must fail).
CONSISTENCY_CPP = ("test_nav13_consistency:Nav13Consistency.*", "test_qekf_eskf:EskfConsistency.*")
CONSISTENCY_PY = ("tests/python/test_nav13_consistency.py::test_nees_within_chi_square_bounds_on_paper002_scenario",
                  "tests/python/test_attitude_consistency.py", "tests/python/test_gpsins_consistency.py",
                  "tests/python/test_gpsins_smoother.py::test_smoothed_nees_within_chi2_bounds")
for _label, _value in (("1.5x over-confident (Q, R, P0 x 1/1.5)", OVER), ("1.5x under-confident (Q, R, P0 x 1.5)", UNDER)):
    for _c in CONSISTENCY_CPP:
        MUTATIONS.append(Mutation(f"{_label}: {_c.split(':')[0]}", "consistency", targets=(_c.split(":")[0],),
                                  cpp=(_c,), env=(("QUATNAV_TEST_VARIANCE_SCALE", _value),)))
    for _p in CONSISTENCY_PY:
        MUTATIONS.append(Mutation(f"{_label}: {Path(_p.split('::')[0]).name}", "consistency", py=(_p,),
                                  env=(("QUATNAV_TEST_VARIANCE_SCALE", _value),)))


# ------------------------------------------------------------------------------------------------
def check_patterns(mutations, root: Path = REPO) -> list[str]:
    """The problems: a file missing or a pattern not found exactly once."""
    problems = []
    for m in mutations:
        if not m.path:
            continue
        p = root / m.path
        if not p.is_file():
            problems.append(f"{m.name}: {m.path} does not exist")
            continue
        n = p.read_text().count(m.find)
        if n != 1:
            problems.append(f"{m.name}: the text is found {n} times in {m.path} (expected once): {m.find!r}")
    return problems


def _copy_tree(src: Path, dst: Path) -> None:
    files = subprocess.run(["git", "ls-files", "-co", "--exclude-standard"], cwd=src, check=True,
                           capture_output=True, text=True).stdout.splitlines()
    for rel in files:
        s, d = src / rel, dst / rel
        if not s.is_file():
            continue
        d.parent.mkdir(parents=True, exist_ok=True)
        if not d.is_file() or d.read_bytes() != s.read_bytes():
            shutil.copy2(s, d)


def _env(extra=()) -> dict:
    env = dict(os.environ)
    data = REPO.parent / "shared" / "data"
    env.setdefault("QUATNAV_DATA", str(data))
    env.setdefault("CCACHE_BASEDIR", str(REPO.parent))
    env.pop("QUATNAV_TEST_VARIANCE_SCALE", None)
    env.update(dict(extra))
    return env


def _configure(src: Path, build: Path) -> None:
    """Configure the copy (again: a cache written before an option existed would keep its default)
    with one GoogleTest executable per test file (QUATNAV_TEST_GROUPS=OFF), so that a mutation
    rebuilds only the executables it names, by their file's name."""
    prefix = subprocess.run([sys.executable, "-m", "cmeel", "cmake"], capture_output=True, text=True).stdout.strip()
    cmd = ["cmake", "-S", str(src), "-B", str(build), "-G", "Ninja", "-DQUATNAV_BUILD_PYTHON=ON",
           "-DQUATNAV_PYTHON_LTO=OFF", "-DQUATNAV_BUILD_TESTS=ON", f"-DPython_EXECUTABLE={sys.executable}",
           f"-DCMAKE_PREFIX_PATH={prefix}", "-DQUATNAV_TEST_GROUPS=OFF"]
    if shutil.which("ccache"):
        cmd.append("-DCMAKE_CXX_COMPILER_LAUNCHER=ccache")
    subprocess.run(cmd, check=True, env=_env(), stdout=subprocess.DEVNULL)


def _build(build: Path, targets, jobs: int, log) -> bool:
    if not targets:
        return True
    r = subprocess.run(["cmake", "--build", str(build), "-j", str(jobs), "--target", *sorted(set(targets))],
                       env=_env(), capture_output=True, text=True)
    log.write(r.stdout[-4000:] + r.stderr[-4000:])
    return r.returncode == 0


def _commands(m: Mutation, src: Path, build: Path):
    """(label, argv) of each test of a mutation, in order."""
    for c in m.cpp:
        exe, _, flt = c.partition(":")
        argv = [str(build / "tests" / "cpp" / exe)] + ([f"--gtest_filter={flt}"] if flt else [])
        yield c, argv
    for p in m.py:
        yield p, [sys.executable, "-m", "pytest", "-q", "-x", "-p", "no:cacheprovider", "-p", "no:randomly", p]


def _run(argv, src: Path, env, timeout: float, log) -> tuple[bool, float]:
    """(passed, CPU seconds)."""
    t0 = os.times()
    try:
        r = subprocess.run(argv, cwd=src, env=dict(env, PYTHONPATH=str(src / "python") + os.pathsep + str(src / "tests" / "python")),
                           capture_output=True, text=True, timeout=timeout)
        ok = r.returncode == 0
        log.write(f"$ {' '.join(argv)}\n{r.stdout[-3000:]}{r.stderr[-2000:]}\n")
    except subprocess.TimeoutExpired:
        ok = False
        log.write(f"$ {' '.join(argv)}\ntimed out after {timeout} s\n")
    t1 = os.times()
    return ok, (t1.children_user - t0.children_user) + (t1.children_system - t0.children_system)


def run(mutations, scratch: Path, jobs: int, timeout: float, log) -> list[dict]:
    src = scratch / "src"
    build = src / "build" / "dev"
    src.mkdir(parents=True, exist_ok=True)
    _copy_tree(REPO, src)
    problems = check_patterns(mutations, src)
    if problems:
        raise SystemExit("patterns that do not match (update them in tools/mutate.py):\n  " + "\n  ".join(problems))
    _configure(src, build)
    # The unmutated copy: every test's target, and the Python module whenever a pytest is listed
    # (a mutation of Python code or of the environment rebuilds nothing, but its tests import the
    # module: it must be this copy's, not one left by an older run).
    targets = {t for m in mutations for t in m.targets} | ({"_core"} if any(m.py for m in mutations) else set())
    print(f"building the unmutated copy ({', '.join(sorted(targets)) or 'nothing'}) ...", flush=True)
    if not _build(build, targets, jobs, log):
        raise SystemExit(f"the unmutated copy does not build (log: {log.name})")
    # Every test, unmutated (and without the variance scale), must pass.
    baseline = {}
    for m in mutations:
        for label, argv in _commands(m, src, build):
            if label not in baseline:
                print(f"  unmutated: {label} ...", flush=True)
                baseline[label] = _run(argv, src, _env(), timeout, log)[0]
    failing = [k for k, ok in baseline.items() if not ok]
    if failing:
        raise SystemExit(f"tests that fail unmutated (fix them first; log: {log.name}): {', '.join(failing)}")
    results = []
    for i, m in enumerate(mutations, 1):
        print(f"[{i}/{len(mutations)}] {m.area}: {m.name} ...", flush=True)
        path = src / m.path if m.path else None
        original = path.read_text() if path else None
        t0 = time.time()
        try:
            if path:
                path.write_text(original.replace(m.find, m.replace, 1))
            caught_by = None
            # Build lazily: each test's own target just before it (the C++ tests come first, so
            # a slip they catch never waits for the Python module's rebuild).
            for label, argv in _commands(m, src, build):
                need = [label.split(":")[0]] if label in m.cpp else [t for t in m.targets if t == "_core"]
                if not _build(build, need, jobs, log):
                    caught_by = "the build"
                    break
                ok, _ = _run(argv, src, _env(m.env), timeout, log)
                if not ok:
                    caught_by = label
                    break
        finally:
            if path:
                path.write_text(original)
        results.append({"mutation": m, "caught_by": caught_by, "seconds": time.time() - t0})
        print(f"    {'caught by ' + caught_by if caught_by else 'MISSED'} ({time.time() - t0:.0f} s)", flush=True)
    _build(build, targets, jobs, log)  # leave the copy built unmutated
    return results


def markdown(results) -> str:
    lines = ["| area | mutation | file | caught by |", "|---|---|---|---|"]
    for r in results:
        m = r["mutation"]
        where = f"`{Path(m.path).name}`" if m.path else "`" + " ".join(f"{k}={v[:6]}" for k, v in m.env) + "`"
        lines.append(f"| {m.area} | {m.name} | {where} | {r['caught_by'] or '**missed**'} |")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("-k", metavar="TEXT", help="only the mutations whose name or area contains TEXT")
    ap.add_argument("--area", help="only the mutations of this area (exact)")
    ap.add_argument("--list", action="store_true", help="list the mutations")
    ap.add_argument("--check", action="store_true", help="only check that every pattern matches once")
    ap.add_argument("--markdown", action="store_true", help="print the result table as markdown")
    ap.add_argument("--scratch", type=Path, default=REPO / "build" / "mutate", help="where the copy is built")
    ap.add_argument("-j", "--jobs", type=int, default=2, help="build jobs (default 2)")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds per test command (default 1800)")
    args = ap.parse_args(argv)
    muts = [m for m in MUTATIONS if (args.k is None or args.k in m.name or args.k in m.area)
            and (args.area is None or m.area == args.area)]
    if not muts:
        raise SystemExit(f"no mutation matches {args.k!r} / area {args.area!r}")
    if args.list:
        for m in muts:
            print(f"{m.area:12s} {m.name}  [{m.path or dict(m.env)}]")
        return 0
    problems = check_patterns(muts)
    if args.check or problems:
        if problems:
            print("patterns that do not match (update them in tools/mutate.py):\n  " + "\n  ".join(problems))
            return 1
        print(f"all {sum(1 for m in muts if m.path)} patterns match their files exactly once")
        return 0
    args.scratch = args.scratch.resolve()  # the tests run in the copy: a relative path would not be found
    args.scratch.mkdir(parents=True, exist_ok=True)
    # One run per copy at a time: a second run would copy the checkout over the first one's
    # mutated file and build the same targets, so that either could test the other's code.
    lock = open(args.scratch / "lock", "w")
    try:
        fcntl.flock(lock, fcntl.LOCK_EX | fcntl.LOCK_NB)
    except BlockingIOError:
        raise SystemExit(f"another run uses {args.scratch} (wait for it, or give --scratch)")
    log_path = args.scratch / "mutate.log"
    with open(log_path, "w") as log:
        results = run(muts, args.scratch, args.jobs, args.timeout, log)
    missed = [r for r in results if not r["caught_by"]]
    print()
    print(markdown(results) if args.markdown else "\n".join(
        f"{r['mutation'].area:12s} {'caught' if r['caught_by'] else 'MISSED':7s} {r['mutation'].name}"
        + (f"  ({r['caught_by']})" if r["caught_by"] else "") for r in results))
    print(f"\n{len(results) - len(missed)} of {len(results)} caught; log: {log_path}")
    return 1 if missed else 0


if __name__ == "__main__":
    sys.exit(main())
