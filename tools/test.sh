#!/usr/bin/env bash
# Build and run every test of quatnav on a fresh Debian machine:
#   1. installs what is missing (GoogleTest from Debian's libgtest-dev, clang, the ARM cross
#      compiler and QEMU; the Python test extras),
#   2. installs the quatnav package (builds the C++ extension with scikit-build-core; after
#      tools/demo.sh it reuses that build and compiles nothing),
#   3. builds and runs the GoogleTest suite in Release with ctest (compiled with clang: it compiles
#      these Eigen-heavy tests in a third of GCC's CPU time; GCC builds the extension;
#      docs/DEVELOPING.md, "Test build"),
#   4. installs the headers with `cmake --install` and builds a separate CMake project that
#      does find_package(quatnav) (cpp/examples/consumer),
#   5. cross-compiles every filter in float32 for a Cortex-M4F and compares it in QEMU with the
#      host double run (cpp/examples/embedded/run.py; apt gcc-arm-none-eabi, qemu-system-arm),
#   6. runs pytest on tests/python against the installed package (QUATNAV_JOBS workers, pytest-xdist),
#   7. builds the documentation site with warnings as errors (tools/docs.sh).
# Stages that use one core (the consumer, the documentation, the fuzz run) run beside the others;
# their output is printed when they end. Every stage is timed (tools/setup_env.sh, `timed`).
# Environment: PYTHON (an interpreter to use as it is; default: a virtual environment in .venv,
#              see tools/setup_env.sh), QUATNAV_JOBS (default 2),
#              CXX_TESTS (the compiler of the GoogleTest suite, default clang++, else c++),
#              QUATNAV_SANITIZE=1 also builds and runs the C++ tests that exercise memory (the fault
#              sequences of every filter, the smoothers, the batch loops) under ASan + UBSan
#              (CXX_SANITIZE, default clang++; docs/DEVELOPING.md, "Sanitizer build": which, and why),
#              QUATNAV_FUZZ_SECONDS=N (with clang) also fuzzes the filters for N s (tests/fuzz/run.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${QUATNAV_JOBS:-2}
source tools/setup_env.sh   # $PY, apt_install, pip_quiet, pip_build, timed, in_background
own_timings=0
if [ -z "${QUATNAV_TIMINGS:-}" ]; then
  export QUATNAV_TIMINGS=$ROOT/build/test-timings.tsv
  mkdir -p build
  : >"$QUATNAV_TIMINGS"
  own_timings=1
fi
SANITIZE=${QUATNAV_SANITIZE:-0}
FUZZ_SECONDS=${QUATNAV_FUZZ_SECONDS:-0}
CXX_TESTS=${CXX_TESTS:-clang++}
CXX_SANITIZE=${CXX_SANITIZE:-clang++}

# --- system packages (one apt-get run) --------------------------------------------------------
mapfile -t need < <(test_system_packages)   # tools/apt.sh
timed "apt: system packages" apt_install "${need[@]}"

# --- Python package and test dependencies ---------------------------------------------------
timed "pip: build requirements" pip_quiet cmake ninja cmeel-eigen pybind11 scikit-build-core
timed "pip install .[...] (the extension once)" pip_build ".[sim,test,eval,peers,logs,docs]"

EIGEN_PREFIX=$("$PY" -m cmeel cmake)
export CMAKE_GENERATOR=${CMAKE_GENERATOR:-Ninja}   # ninja comes from pip above; no make needed

# --- C++ tests --------------------------------------------------------------------------------
# The compiler of a C++ test build: the one asked for, else the default one.
test_compiler() {
  if command -v "$1" >/dev/null; then echo "$1"; else echo "c++"; fi
}
cxx=$(test_compiler "$CXX_TESTS")
echo "== building the GoogleTest suite (Release, $cxx)"
timed "C++ tests: configure and build (Release, $cxx)" bash -c '
  CXX=$1 cmake -S . -B build/tests -DQUATNAV_BUILD_TESTS=ON -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$2" -DCMAKE_INSTALL_PREFIX="$3/build/install" >/dev/null
  cmake --build build/tests -j "$4"' _ "$cxx" "$EIGEN_PREFIX" "$ROOT" "$JOBS"

# The find_package consumer needs one core for a few seconds: beside the test run.
consumer() {
  cmake --install build/tests >/dev/null
  cmake -S cpp/examples/consumer -B build/consumer -DCMAKE_BUILD_TYPE=Release \
        -DCMAKE_PREFIX_PATH="$ROOT/build/install;$EIGEN_PREFIX" >/dev/null
  cmake --build build/consumer -j 1 >/dev/null
  ./build/consumer/quatnav_consumer
}
in_background "cmake --install and a find_package(quatnav) consumer" consumer
timed "C++ tests: ctest (Release)" ctest --test-dir build/tests --output-on-failure -j "$JOBS"

if [ "$SANITIZE" = 1 ]; then
  cxx=$(test_compiler "$CXX_SANITIZE")
  echo "== GoogleTest suite under AddressSanitizer + UndefinedBehaviorSanitizer ($cxx)"
  timed "C++ tests: configure and build (ASan + UBSan, $cxx)" bash -c '
    CXX=$1 cmake -S . -B build/tests-asan -DQUATNAV_BUILD_TESTS=ON -DQUATNAV_SANITIZE=ON \
          -DCMAKE_BUILD_TYPE=Debug -DCMAKE_PREFIX_PATH="$2" >/dev/null
    cmake --build build/tests-asan -j "$3"' _ "$cxx" "$EIGEN_PREFIX" "$JOBS"
  # The fuzz target compiles in one unit (one core): beside the sanitizer run.
  if [ "$FUZZ_SECONDS" -gt 0 ]; then
    if command -v "${CXX_FUZZ:-clang++}" >/dev/null; then
      in_background "fuzzing: build, then ${FUZZ_SECONDS} s" env PYTHON="$PY" bash tests/fuzz/run.sh "$FUZZ_SECONDS"
    else
      echo "== fuzzing skipped: ${CXX_FUZZ:-clang++} not found (libFuzzer needs clang)"
    fi
  fi
  timed "C++ tests: ctest (ASan + UBSan)" \
    env UBSAN_OPTIONS=print_stacktrace=1 ctest --test-dir build/tests-asan --output-on-failure -j "$JOBS"
elif [ "$FUZZ_SECONDS" -gt 0 ]; then
  if command -v "${CXX_FUZZ:-clang++}" >/dev/null; then
    in_background "fuzzing: build, then ${FUZZ_SECONDS} s" env PYTHON="$PY" bash tests/fuzz/run.sh "$FUZZ_SECONDS"
  else
    echo "== fuzzing skipped: ${CXX_FUZZ:-clang++} not found (libFuzzer needs clang)"
  fi
fi

# --- embedded baseline: float32 on a Cortex-M4F in QEMU (cpp/examples/embedded/run.py) ------
# Before pytest: tests/python/test_embedded.py replays it from its cache (build/embedded).
echo "== embedded: cross-compile every filter for a Cortex-M4F, run it in QEMU, compare with the host"
timed "embedded: Cortex-M4F in QEMU against the host" env QUATNAV_JOBS="$JOBS" timeout 1500 \
  "$PY" cpp/examples/embedded/run.py --check --opt O2 --report-dir build/embedded/report

# --- documentation site (sphinx -W: a warning fails), beside pytest ---------------------------
in_background "documentation site (tools/docs.sh)" env PYTHON="$PY" bash tools/docs.sh

# --- Python tests ---------------------------------------------------------------------------
# pytest-xdist: one worker per job, each test file on one worker (module fixtures built once)
echo "== pytest ($JOBS workers)"
rc=0
timed "pytest ($JOBS workers)" "$PY" -m pytest -q -n "$JOBS" --dist loadfile tests/python "$@" || rc=$?

wait_background || rc=1
if [ "$own_timings" = 1 ]; then
  echo "== stages of tools/test.sh"
  print_timings
fi
exit "$rc"
