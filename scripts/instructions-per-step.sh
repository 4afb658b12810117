#!/usr/bin/env bash
# Instructions per tracker step, counted by callgrind (repeatable whatever the machine's load,
# unlike time): everything executed inside Extremal_tracker::step, divided by its calls.
# Usage: scripts/instructions-per-step.sh [BINARY] [FILTER...]
#   BINARY defaults to build/bench/bench_tracker_step; FILTERs to Ellipsoids and Bicubic.
set -euo pipefail
binary=${1:-build/bench/bench_tracker_step}
[ $# -gt 0 ] && shift
filters=("$@")
[ ${#filters[@]} -gt 0 ] || filters=(Ellipsoids Bicubic)
command -v valgrind >/dev/null || { echo "$0: needs valgrind" >&2; exit 2; }
[ -x "$binary" ] || { echo "$0: '$binary' is not an executable" >&2; exit 2; }
out=$(mktemp)
trap 'rm -f "$out"' EXIT
for filter in "${filters[@]}"; do
  valgrind --tool=callgrind --callgrind-out-file="$out" --dump-instr=no --compress-strings=no \
    --toggle-collect='extremal::Extremal_tracker::step*' \
    "$binary" --benchmark_filter="$filter" --benchmark_min_time=0.05 >/dev/null 2>&1
  total=$(awk '/^summary:/ {print $2}' "$out")
  steps=$(grep -A1 '^cfn=.*Extremal_tracker::step(' "$out" | awk -F'[= ]' '/^calls=/ {s += $2} END {print s + 0}')
  [ "$steps" -gt 0 ] || { echo "$0: no tracker step ran for '$filter'" >&2; exit 1; }
  echo "$filter: $total instructions in $steps steps: $((total / steps)) per step"
done
