#!/usr/bin/env bash
# Runs `extremal distance F F --pose-b P [--signed] --json` on every file of ../shared/data
# against itself at three poses, with and without --signed, and prints one line per run: file,
# pose, mode, exit code, distance, bounds, status and body names (no times, so that two runs
# or two builds compare with diff). Usage:
#   scripts/sweep-shared-data.sh [EXTREMAL_BINARY] > sweep.txt
# e.g. twice and `diff` for run-to-run determinism, or with another checkout's binary to see
# which answers a change moved (bench/RESULTS.md).
set -uo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="$(realpath "${1:-$root/build/cli/extremal}")"
cd "$root/../shared/data" || exit 2
for f in step/* iges/* mesh/*.stl mesh/*.ply mesh/*.obj obj/*; do
  [ -f "$f" ] || continue
  for pose in 0.5,0.2,0.1,0.9,0.1,0.3,0.2 0,0,0,0.2,0.9,0.1,0.3 3,1,-2; do
    for mode in "" --signed; do
      out="$(timeout 300 "$bin" distance "$f" "$f" --pose-b "$pose" $mode --json 2>/dev/null)"
      rc=$?
      summary="$(printf '%s' "$out" | python3 -c '
import json, sys
try:
    j = json.load(sys.stdin)
    print(repr(j["distance"]), repr(j["lower_bound"]), repr(j["upper_bound"]), j["status"],
          j["body_a"], "|", j["body_b"])
except Exception as e:
    print("no JSON:", e)
')"
      echo "$f ${pose} ${mode:-unsigned} rc=$rc $summary"
    done
  done
done
