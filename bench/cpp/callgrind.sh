#!/usr/bin/env bash
# Instructions per step of every case of quatnav_bench_filters, counted by callgrind: a figure
# that does not depend on the machine's load (the ns column does). Only the timed loop
# (qb::timed_steps) is collected; per step = collected Ir / (warm-up + timed steps).
#   bash bench/cpp/callgrind.sh [build/bench/bench/cpp/quatnav_bench_filters] [STEPS]
set -euo pipefail
BIN=${1:-build/bench/bench/cpp/quatnav_bench_filters}
STEPS=${2:-2000}
OUT=$(mktemp -d)
printf "%-46s %12s %12s\n" "filter [policy]" "Ir/step f64" "Ir/step f32"
"$BIN" --list | while IFS=$'\t' read -r label name; do
  line=$(printf "%-46s" "$label")
  for scalar in double float; do
    # The case struct of this label: find the instantiation through its scalar.
    valgrind --tool=callgrind --callgrind-out-file="$OUT/cg.out" \
      --toggle-collect="*timed_steps<*<${scalar}*>, ${scalar}>*" \
      "$BIN" --no-flops --reps 1 --steps "$STEPS" --scalar "$scalar" --filter "$label" >/dev/null 2>"$OUT/log"
    ir=$(callgrind_annotate "$OUT/cg.out" 2>/dev/null | awk '/PROGRAM TOTALS/ {gsub(",", "", $1); print $1}')
    line+=$(printf " %12.0f" "$(echo "$ir / (2 * $STEPS)" | bc -l)")
  done
  echo "$line"
done
rm -rf "$OUT"
