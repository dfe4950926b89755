#!/usr/bin/env bash
# Build the libFuzzer target tests/fuzz/fuzz_*.cpp with clang (-fsanitize=fuzzer,address,
# undefined) and run it for a bounded time. Usage: bash tests/fuzz/run.sh [seconds] [extra libFuzzer flags]
# Environment: CXX_FUZZ (default clang++), EIGEN_INCLUDE (default: from the cmeel-eigen wheel,
# else /usr/include/eigen3), FUZZ_DIR (build and corpus directory, default build/fuzz).
set -euo pipefail
cd "$(dirname "$0")/../.."
SECONDS_TO_RUN=${1:-60}
shift || true
CXX_FUZZ=${CXX_FUZZ:-clang++}
OUT=${FUZZ_DIR:-build/fuzz}
mkdir -p "$OUT/corpus"
if [ -z "${EIGEN_INCLUDE:-}" ]; then
  prefix=$(${PYTHON:-python3} -m cmeel cmake 2>/dev/null || true)
  if [ -n "$prefix" ] && [ -d "$prefix/include/eigen3" ]; then EIGEN_INCLUDE="$prefix/include/eigen3"
  else EIGEN_INCLUDE=/usr/include/eigen3; fi
fi
# The target is four units (the entry and one per filter family, tests/fuzz/fuzz_*.cpp) compiled
# side by side on FUZZ_JOBS cores (default 2), then linked; all of them again when a header or a
# unit is newer than the target.
if [ ! -x "$OUT/fuzz_filters" ] \
   || [ -n "$(find cpp/include tests/fuzz -newer "$OUT/fuzz_filters" \( -name '*.hpp' -o -name '*.cpp' \) | head -1)" ]; then
  echo "== building the fuzz target with $CXX_FUZZ"
  # Line tables only: the reports name file and line; full debug information (-g) made the
  # compile about 1.4 times longer (docs/DEVELOPING.md, "Sanitizer build").
  flags=(-std=c++17 -O1 -gline-tables-only -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=all
         -fno-omit-frame-pointer -I cpp/include -I "$EIGEN_INCLUDE")
  printf '%s\n' tests/fuzz/fuzz_*.cpp \
    | xargs -P "${FUZZ_JOBS:-2}" -I{} sh -c '"$0" "$@" -c {} -o "'"$OUT"'/$(basename {} .cpp).o"' "$CXX_FUZZ" "${flags[@]}"
  "$CXX_FUZZ" -fsanitize=fuzzer,address,undefined "$OUT"/fuzz_*.o -o "$OUT/fuzz_filters"
fi
echo "== fuzzing the filters for ${SECONDS_TO_RUN} s"
"$OUT/fuzz_filters" -max_total_time="$SECONDS_TO_RUN" -max_len=4096 -print_final_stats=1 \
  -artifact_prefix="$OUT/" "$@" "$OUT/corpus"
