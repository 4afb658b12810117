#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang into their own tree build-fuzz/
# (-DEXTREMAL_FUZZ=ON: ASan + UBSan, no recovery) and runs each in turn for SECONDS (default 600),
# seeded with tests/fuzz/corpus_<name> and guided by tests/fuzz/<name>.dict. New inputs go to
# build-fuzz/corpus/<name>, crashing ones to build-fuzz/artifacts/; a target that finds a crash
# stops the script with its exit status. Usage: scripts/run-fuzzers.sh [SECONDS] [TARGET...]
# (TARGET: obj_freeform, scene, pose_table; default all).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-fuzz"
seconds="${1:-600}"
shift || true
targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(obj_freeform scene pose_table)
"$root/scripts/setup.sh" --fuzz
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DEXTREMAL_FUZZ=ON -DEXTREMAL_BUILD_TESTS=OFF -DEXTREMAL_BUILD_BENCH=OFF
fi
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"

export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
for target in "${targets[@]}"; do
  case "$target" in
    obj_freeform) seeds=obj; dict=obj ;;
    scene) seeds=scene; dict=scene ;;
    pose_table) seeds=pose_table; dict=pose_table ;;
    *) echo "run-fuzzers: unknown target '$target' (obj_freeform, scene, pose_table)" >&2; exit 2 ;;
  esac
  mkdir -p "$build/corpus/$target" "$build/artifacts"
  echo "run-fuzzers: fuzz_$target for ${seconds} s"
  # The scene reader resolves relative file paths against the scene's folder: run where no
  # pose table or CAD file lies about, so those entries fail the same way every time.
  (cd "$build/artifacts" &&
   "$build/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -print_final_stats=1 \
       -dict="$root/tests/fuzz/$dict.dict" -artifact_prefix="$build/artifacts/$target-" \
       "$build/corpus/$target" "$root/tests/fuzz/corpus_$seeds")
done
