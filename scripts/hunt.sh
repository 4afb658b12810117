#!/usr/bin/env bash
# The long certificate hunt: scripts/hunt.py on fresh seeds until HOURS are up (docs/checking.md,
# "The certificate hunt"). Scenes, checks and the log go to build/hunt/<start time>/ (hunt.log,
# summary.json); extra arguments go to scripts/hunt.py (e.g. --heavy 0.1, --count 8).
#
#   scripts/hunt.sh HOURS [SEED] [HUNT_ARGS...]
#
# SEED: the first seed (default: a random one, printed in the log); the next are SEED+1, ...
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
if [[ $# -lt 1 ]]; then
  echo "usage: scripts/hunt.sh HOURS [SEED] [HUNT_ARGS...]" >&2
  exit 2
fi
hours="$1"
shift
seed_args=()
if [[ $# -gt 0 && "$1" =~ ^[0-9]+$ ]]; then
  seed_args=(--seeds "$1")
  shift
fi
out="$root/build/hunt/$(date -u +%Y%m%dT%H%M%SZ)"
mkdir -p "$out"
echo "scripts/hunt.sh: writing $out/hunt.log"
exec python3 "$root/scripts/hunt.py" "$out" --hours "$hours" "${seed_args[@]}" --heavy 0.1 "$@"
