#!/usr/bin/env bash
# Set up, build (the same build as scripts/run-demo.sh: warnings are errors, the tree builds clean
# with -Wall -Wextra -Wpedantic), and run the whole test suite.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$root/scripts/build.sh"
ctest --test-dir "$root/build" --output-on-failure --parallel "$(nproc)"
