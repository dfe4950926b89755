# Sourced by tools/setup_env.sh and .ci/run: stages that are timed, and stages that run beside
# the others.
#   timed NAME CMD...         runs CMD as one stage; its wall time and CPU time (user + sys of all
#                             its processes, from the shell's `times`) go to $QUATNAV_TIMINGS when
#                             that is set (a file: name, start in s after $QUATNAV_T0, wall, CPU,
#                             exit status)
#   in_background NAME CMD... runs a timed stage beside the others: its output goes to a log that
#                             is printed when it ends; for a stage that uses one core, so that the
#                             second core does other work meanwhile
#   wait_background           waits for every such stage; fails when one did
#   print_timings [FILE]      the table of the stages (.ci/run and tools/test.sh print it at the end)

# Wall time from $EPOCHREALTIME; CPU time from `times` at the end of a subshell that runs the stage
# (user + sys of that subshell and of its finished child processes, so of everything the stage
# ran and nothing else: a stage beside it, reaped by the main shell meanwhile, does not count).
# A stage therefore cannot set variables of the calling shell. One line per stage in
# $QUATNAV_TIMINGS: name, start (s since QUATNAV_T0), wall, CPU, exit status.
export QUATNAV_T0=${QUATNAV_T0:-$EPOCHREALTIME}

timed() {
  local name=$1 t0 f rc=0
  shift
  t0=$EPOCHREALTIME
  f=$(mktemp "${TMPDIR:-/tmp}/quatnav-times.XXXXXX")
  ( rc=0; "$@" || rc=$?; times >"$f"; exit "$rc" ) || rc=$?
  if [ -n "${QUATNAV_TIMINGS:-}" ]; then
    awk -v n="$name" -v t0="$t0" -v t1="$EPOCHREALTIME" -v z="$QUATNAV_T0" -v rc="$rc" '
      { for (i = 1; i <= 2; i++) { split($i, a, "m"); cpu += a[1] * 60 + a[2] } }
      END { printf "%s\t%.0f\t%.0f\t%.0f\t%s\n", n, t0 - z, t1 - t0, cpu, rc }' "$f" >>"$QUATNAV_TIMINGS"
  fi
  rm -f "$f"
  return "$rc"
}

_bg_pids=()
_bg_names=()
_bg_logs=()
_kill_background() {   # on an early exit (a failed stage): no stage outlives the script
  local pid
  for pid in "${_bg_pids[@]}"; do kill -- "$pid" 2>/dev/null || true; done
}

in_background() {
  local name=$1 log
  shift
  trap _kill_background EXIT
  log=$(mktemp "${TMPDIR:-/tmp}/quatnav-stage.XXXXXX.log")
  echo "== started beside the others: $name (log $log)"
  ( timed "$name" "$@" ) >"$log" 2>&1 &
  _bg_pids+=($!)
  _bg_names+=("$name")
  _bg_logs+=("$log")
}

wait_background() {
  local i rc failed=0
  for i in "${!_bg_pids[@]}"; do   # in the order they started; each is waited for once
    rc=0
    wait "${_bg_pids[$i]}" || rc=$?
    echo "== ${_bg_names[$i]}: finished (exit $rc); its output:"
    sed 's/^/   /' "${_bg_logs[$i]}"
    rm -f "${_bg_logs[$i]}"
    [ "$rc" = 0 ] || { echo "quatnav: ${_bg_names[$i]} failed (exit $rc)" >&2; failed=1; }
  done
  _bg_pids=()
  _bg_names=()
  _bg_logs=()
  return "$failed"
}

# The table of $QUATNAV_TIMINGS (or of the file given).
print_timings() {
  local f=${1:-${QUATNAV_TIMINGS:-}}
  [ -n "$f" ] && [ -s "$f" ] || return 0
  awk -F '\t' '
    { name[NR] = $1; start[NR] = $2; wall[NR] = $3; cpu[NR] = $4; rc[NR] = $5
      if ($2 + $3 > end) end = $2 + $3; total += $4 }
    END {
      printf "%-44s %7s %7s %7s\n", "stage", "start", "wall", "CPU"
      for (i = 1; i <= NR; i++)
        printf "%-44s %7d %7d %7d%s\n", name[i], start[i], wall[i], cpu[i], rc[i] == 0 ? "" : "  (failed: exit " rc[i] ")"
      printf "%-44s %7s %7d %7d\n", "all (stages beside each other overlap)", "", end, total
    }' "$f"
  echo "   seconds; start: after the first stage began; CPU: user + sys of the stage's processes"
}
