#!/usr/bin/env bash
# Builds Extremal with AddressSanitizer and UndefinedBehaviorSanitizer into build-asan/ (a tree of
# its own; the default Release build in build/ is untouched) and runs the whole ctest suite there.
# Any sanitizer report fails the test that produced it: UBSan does not recover
# (-fno-sanitize-recover), ASan aborts on the first error, LeakSanitizer runs at exit.
# Extra arguments go to ctest (e.g. -R Nurbs).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-asan"
"$root/scripts/setup.sh"
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  # RelWithDebInfo: optimised like the real build (so optimiser-exposed bugs show) with line
  # numbers in the reports.
  cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DEXTREMAL_SANITIZE=ON
fi
cmake --build "$build" --parallel "$(nproc)"

# Third-party libraries' process-lifetime allocations are suppressed by the narrow list in
# tests/sanitizer/lsan.supp (each entry says why); nothing of ours is suppressed.
# exitcode=86: a report must not pass for one of the CLI's own exit codes (tests run the CLI on
# bad input and expect 1 or 2), so a sanitizer exit is a status no test expects.
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:strict_string_checks=1:detect_stack_use_after_return=1:check_initialization_order=1:halt_on_error=1:abort_on_error=0:exitcode=86}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1:exitcode=86}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$root/tests/sanitizer/lsan.supp:print_suppressions=0:exitcode=86}"
ctest --test-dir "$build" --output-on-failure --parallel "$(nproc)" --timeout 600 "$@"
