#!/usr/bin/env bash
# The main job: set up, build, and run the batch distance report on the bundled demo scene.
# The report goes to build/demo-report.csv, the scene at t = 3 s to build/demo-t3.glb, the page
# to open to build/demo-report.html; a readable summary to the terminal.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh"
"$root/build/cli/extremal" report "$root/data/demo/demo.json" -o "$root/build/demo-report.csv" \
  --snapshot "$root/build/demo-t3.glb" --at 3
"$root/build/cli/extremal" report "$root/data/demo/demo.json" -o "$root/build/demo-report.html" \
  --quiet
echo "report: $root/build/demo-report.csv"
echo "page (summary, classes, plots, 3D view; open it in a browser): $root/build/demo-report.html"
echo "scene at t = 3 s (glTF): $root/build/demo-t3.glb"
