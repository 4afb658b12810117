#!/usr/bin/env bash
# Time per step of the real scenes of bench/scenes (bench/scenes/README.md, "Real scenes: time
# per step"): runs `extremal report SCENE -o OUT.json --quiet` on each scene and prints a
# Markdown table of the scene step times from the JSON summary's "step_time_us" (the sum of
# the scene's pairs' step times at each step, writing rows not in it; docs/cli.md, "Summary"),
# with the least distance over the pairs and the process's wall time. Usage:
#   scripts/bench-step-times.sh [--binary PATH] [SCENE.json ...]
# Default binary build/cli/extremal; default scenes the four real scenes below. Needs python3
# (to read the JSON) and the shared data set beside the repository (../shared/data).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
binary=$root/build/cli/extremal
if [ "${1:-}" = "--binary" ]; then
  binary=$2
  shift 2
fi
[ -x "$binary" ] || { echo "$0: '$binary' is not an executable (build it: ninja -C build extremal)" >&2; exit 2; }
if [ $# -eq 0 ]; then
  set -- "$root"/bench/scenes/probe_past_linkrods.json "$root"/bench/scenes/linkrods_past_screw.json \
         "$root"/bench/scenes/ball_over_as1.json "$root"/bench/scenes/as1_all_pairs.json
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "| scene | pairs | steps | mean (us) | median (us) | p99 (us) | max (us) | least distance (mm) | run (s) |"
echo "|---|---|---|---|---|---|---|---|---|"
for scene in "$@"; do
  name=$(basename "$scene" .json)
  start=$(date +%s.%N)
  "$binary" report "$scene" -o "$out/$name.json" --quiet
  stop=$(date +%s.%N)
  python3 - "$out/$name.json" "$name" "$start" "$stop" <<'EOF'
import json, sys
report = json.load(open(sys.argv[1]))
name, start, stop = sys.argv[2], float(sys.argv[3]), float(sys.argv[4])
s = report["step_time_us"]
steps = report["summary"][0]["rows"] if report["summary"] else 0
least = [p["min_distance"] for p in report["summary"] if p["min_distance"] is not None]
least_text = "%.4g" % min(least) if least else "-"
print("| %s | %d | %d | %.0f | %.1f | %.0f | %.0f | %s | %.1f |" % (
    name, len(report["summary"]), steps, s["mean"], s["median"], s["p99"], s["max"],
    least_text, stop - start))
EOF
done
