#!/usr/bin/env bash
# Times two builds of one benchmark side by side on this noisy shared machine: each round runs
# OLD and NEW at once, each pinned to its own core (taskset), with the cores swapped every round,
# so both see the same machine state. Each output line is prefixed by "old" or "new" and the
# round. Usage:
#   scripts/ab-same-time.sh ROUNDS OLD_BINARY NEW_BINARY [ARGS...]
# e.g. the tracker step of two checkouts' builds:
#   scripts/ab-same-time.sh 4 ../base/build/bench/bench_tracker_step build/bench/bench_tracker_step \
#     --benchmark_filter=Ellipsoids --benchmark_repetitions=5 --benchmark_report_aggregates_only=true | grep median
set -euo pipefail
if [ $# -lt 3 ]; then
  echo "usage: $0 ROUNDS OLD_BINARY NEW_BINARY [ARGS...]" >&2
  exit 2
fi
rounds=$1 old=$2 new=$3
shift 3
for b in "$old" "$new"; do
  [ -x "$b" ] || { echo "$0: '$b' is not an executable" >&2; exit 2; }
done
[ "$(nproc)" -ge 2 ] || { echo "$0: needs two cores" >&2; exit 2; }
for ((round = 1; round <= rounds; ++round)); do
  if ((round % 2)); then core_old=0 core_new=1; else core_old=1 core_new=0; fi
  taskset -c "$core_old" "$old" "$@" 2>/dev/null | sed "s/^/old $round: /" &
  taskset -c "$core_new" "$new" "$@" 2>/dev/null | sed "s/^/new $round: /" &
  wait
done
