#!/usr/bin/env bash
# Build bench/long_run.cpp (-O2) and run it: bash bench/long_run.sh [steps] [filter] [float32|float64] [no-baro]
# (default 10 million steps of every filter in float64 and float32).
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${BENCH_DIR:-build/bench}
mkdir -p "$OUT"
prefix=$(${PYTHON:-python3} -m cmeel cmake 2>/dev/null || true)
EIGEN_INCLUDE=${EIGEN_INCLUDE:-$([ -n "$prefix" ] && [ -d "$prefix/include/eigen3" ] && echo "$prefix/include/eigen3" || echo /usr/include/eigen3)}
if [ ! -x "$OUT/long_run" ] || [ bench/long_run.cpp -nt "$OUT/long_run" ] || [ tests/cpp/nav_truth.hpp -nt "$OUT/long_run" ] \
   || [ -n "$(find cpp/include -newer "$OUT/long_run" -name '*.hpp' | head -1)" ]; then
  ${CXX:-g++} -std=c++17 -O2 -DNDEBUG -I cpp/include -I "$EIGEN_INCLUDE" bench/long_run.cpp -o "$OUT/long_run"
fi
"$OUT/long_run" "$@"
