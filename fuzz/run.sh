#!/usr/bin/env bash
# Runs the libFuzzer targets built by `./build.sh fuzz` (which calls this script).
#
#   fuzz/run.sh [SECONDS [TARGET...]]     each TARGET (default: all) for SECONDS (default 600)
#   fuzz/run.sh --summary                 total time and executions per target so far
#
# One target at a time in one process (no -jobs: the machine is shared). The working
# corpus (build-fuzz/corpus/TARGET) persists between runs, so runs add up; seeds
# are rebuilt each time from the repository (see fuzz/README.md). Every run
# appends a line to build-fuzz/fuzz-runs.tsv: target, seconds, executions,
# executions per second, exit code. A crash or hang leaves its input in
# build-fuzz/artifacts/TARGET/; copy it into tests/data/fuzz_regressions/TARGET/
# (the test suite replays every file there) and fix the bug.
set -euo pipefail
cd "$(dirname "$0")/.."
FUZZ_DIR=${SODAEVO_FUZZ_DIR:-build-fuzz}
LOG="$FUZZ_DIR/fuzz-runs.tsv"
ALL_TARGETS=(model_xml run_config checkpoint)

summary() {
  [ -f "$LOG" ] || { echo "no fuzz runs recorded in $LOG"; return; }
  awk -F'\t' '{ s[$1] += $2; e[$1] += $3; if ($5 != 0) bad[$1]++ }
    END { printf "%-12s %10s %14s %12s %s\n", "target", "seconds", "executions", "exec/s", "failed runs";
          for (t in s) printf "%-12s %10d %14d %12d %d\n", t, s[t], e[t], (s[t] ? e[t] / s[t] : 0), bad[t] }' "$LOG"
}

if [ "${1:-}" = "--summary" ]; then summary; exit 0; fi
seconds=${1:-600}
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${ALL_TARGETS[@]}")

# Copies files into a seed folder under names made from their content (the
# repository has several files with the same name in different folders).
add_seeds() {
  local dest=$1; shift
  local f
  for f in "$@"; do
    [ -f "$f" ] && cp "$f" "$dest/$(sha1sum <"$f" | cut -c1-16)"
  done
  return 0
}

status=0
for t in "${targets[@]}"; do
  binary="$FUZZ_DIR/fuzz/fuzz_$t"
  [ -x "$binary" ] || { echo "fuzz/run.sh: $binary is missing: run ./build.sh fuzz" >&2; exit 2; }
  seeds="$FUZZ_DIR/seeds/$t" corpus="$FUZZ_DIR/corpus/$t" artifacts="$FUZZ_DIR/artifacts/$t"
  rm -rf "$seeds"
  mkdir -p "$seeds" "$corpus" "$artifacts" "$FUZZ_DIR/logs"
  shopt -s nullglob globstar
  case $t in
    model_xml) add_seeds "$seeds" tests/data/soda/**/*.xml models/*.xml ;;
    run_config) add_seeds "$seeds" configs/*.json ;;
    checkpoint) add_seeds "$seeds" fuzz/seeds/checkpoint/* ;;
  esac
  add_seeds "$seeds" tests/data/fuzz_regressions/"$t"/*
  shopt -u nullglob globstar
  max_len=()
  [ "$t" = model_xml ] && max_len=(-max_len=32768) # the largest race files are cut, not skipped
  log="$FUZZ_DIR/logs/$t-$(date +%Y%m%d-%H%M%S).log"
  echo "fuzz/run.sh: $t for ${seconds}s (log $log)"
  rc=0
  "$binary" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
    -dict="fuzz/$t.dict" -print_final_stats=1 -artifact_prefix="$artifacts/" "${max_len[@]}" \
    "$corpus" "$seeds" >"$log" 2>&1 || rc=$?
  execs=$(awk '/stat::number_of_executed_units/ { print $2 }' "$log" | tail -1)
  rate=$(awk '/stat::average_exec_per_sec/ { print $2 }' "$log" | tail -1)
  printf '%s\t%s\t%s\t%s\t%s\n' "$t" "$seconds" "${execs:-0}" "${rate:-0}" "$rc" >>"$LOG"
  echo "fuzz/run.sh: $t: ${execs:-?} executions, ${rate:-?}/s, exit $rc"
  if [ "$rc" -ne 0 ]; then
    status=1
    grep -E "ERROR|SUMMARY|Test unit written" "$log" | head -5 || true
  fi
done
summary
exit "$status"
