#!/usr/bin/env bash
# Configures and builds Extremal (Release, warnings as errors) into build/ after installing the
# dependencies. Both README commands call it with the same flags, so the second one rebuilds
# nothing the first built. Extra arguments go to the CMake configure step.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/setup.sh"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f "$root/build/CMakeCache.txt" ]; then
  cmake -S "$root" -B "$root/build" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DEXTREMAL_WERROR=ON "$@"
elif [ $# -gt 0 ]; then
  cmake "$root/build" "$@"
fi
cmake --build "$root/build" --parallel "$(nproc)"
