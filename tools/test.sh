#!/usr/bin/env bash
# Build and run every test of quatnav on a fresh Debian machine:
#   1. installs what is missing (GoogleTest from Debian's libgtest-dev; Python test extras),
#   2. installs the quatnav package (builds the C++ extension with scikit-build-core),
#   3. builds and runs the GoogleTest suite with ctest,
#   4. installs the headers with `cmake --install` and builds a separate CMake project that
#      does find_package(quatnav) (cpp/examples/consumer),
#   5. cross-compiles every filter in float32 for a Cortex-M4F and compares it in QEMU with the
#      host double run (cpp/examples/embedded/run.py; apt gcc-arm-none-eabi, qemu-system-arm),
#   6. runs pytest on tests/python against the installed package (QUATNAV_JOBS workers, pytest-xdist),
#   7. builds the documentation site with warnings as errors (tools/docs.sh).
# Environment: PYTHON (an interpreter to use as it is; default: a virtual environment in .venv,
#              see tools/setup_env.sh), QUATNAV_JOBS (default 2),
#              QUATNAV_SANITIZE=1 also builds and runs the C++ tests under ASan + UBSan,
#              QUATNAV_FUZZ_SECONDS=N (with clang) also fuzzes the filters for N s (tests/fuzz/run.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
JOBS=${QUATNAV_JOBS:-2}
source tools/setup_env.sh   # $PY: a virtual environment in .venv unless one is active (or PYTHON=...)

# --- system packages -----------------------------------------------------------------------
need=()
[ -f /usr/include/gtest/gtest.h ] || need+=(libgtest-dev)
if [ "${QUATNAV_FUZZ_SECONDS:-0}" -gt 0 ]; then   # libFuzzer: clang and its runtime
  command -v "${CXX_FUZZ:-clang++}" >/dev/null || need+=(clang)
  ls /usr/lib/llvm-*/lib/clang/*/lib/linux/libclang_rt.fuzzer-x86_64.a >/dev/null 2>&1 \
    || [ "$(uname -m)" != x86_64 ] || need+=(libclang-rt-dev)
fi
[ ${#need[@]} -eq 0 ] || apt_install "${need[@]}"

# --- Python package and test dependencies ---------------------------------------------------
pip_quiet cmake ninja cmeel-eigen pybind11 scikit-build-core
pip_build ".[sim,test,eval,peers,logs]"

EIGEN_PREFIX=$("$PY" -m cmeel cmake)
export CMAKE_GENERATOR=${CMAKE_GENERATOR:-Ninja}   # ninja comes from pip above; no make needed

# --- C++ tests --------------------------------------------------------------------------------
echo "== building the GoogleTest suite"
cmake -S . -B build/tests -DQUATNAV_BUILD_TESTS=ON -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$EIGEN_PREFIX" -DCMAKE_INSTALL_PREFIX="$ROOT/build/install" >/dev/null
cmake --build build/tests -j "$JOBS"
ctest --test-dir build/tests --output-on-failure -j "$JOBS"

if [ "${QUATNAV_SANITIZE:-0}" = 1 ]; then
  echo "== GoogleTest suite under AddressSanitizer + UndefinedBehaviorSanitizer"
  cmake -S . -B build/tests-asan -DQUATNAV_BUILD_TESTS=ON -DQUATNAV_SANITIZE=ON -DCMAKE_BUILD_TYPE=Debug \
        -DCMAKE_PREFIX_PATH="$EIGEN_PREFIX" >/dev/null
  cmake --build build/tests-asan -j "$JOBS"
  ctest --test-dir build/tests-asan --output-on-failure -j "$JOBS"
fi

if [ "${QUATNAV_FUZZ_SECONDS:-0}" -gt 0 ]; then
  if command -v "${CXX_FUZZ:-clang++}" >/dev/null; then
    PYTHON="$PY" bash tests/fuzz/run.sh "$QUATNAV_FUZZ_SECONDS"
  else
    echo "== fuzzing skipped: ${CXX_FUZZ:-clang++} not found (libFuzzer needs clang)"
  fi
fi

# --- the installed package as a C++ dependency -----------------------------------------------
echo "== cmake --install and a find_package(quatnav) consumer"
cmake --install build/tests >/dev/null
cmake -S cpp/examples/consumer -B build/consumer -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_PREFIX_PATH="$ROOT/build/install;$EIGEN_PREFIX" >/dev/null
cmake --build build/consumer -j "$JOBS" >/dev/null
./build/consumer/quatnav_consumer

# --- embedded baseline: float32 on a Cortex-M4F in QEMU (cpp/examples/embedded/run.py) ------
apt_install gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib qemu-system-arm
echo "== embedded: cross-compile every filter for a Cortex-M4F, run it in QEMU, compare with the host"
QUATNAV_JOBS="$JOBS" timeout 1500 "$PY" cpp/examples/embedded/run.py --check --opt O2 --report-dir build/embedded/report

# --- Python tests ---------------------------------------------------------------------------
# pytest-xdist: one worker per job, each test file on one worker (module fixtures built once)
echo "== pytest ($JOBS workers)"
"$PY" -m pytest -q -n "$JOBS" --dist loadfile tests/python "$@"

# --- documentation site (sphinx -W: a warning fails) ------------------------------------------
echo "== documentation site"
PYTHON="$PY" bash tools/docs.sh
