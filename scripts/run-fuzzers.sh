#!/usr/bin/env bash
# Builds the libFuzzer targets (tests/fuzz) with clang into their own tree build-fuzz/
# (-DEXTREMAL_FUZZ=ON: ASan + UBSan, no recovery) and runs each in turn for SECONDS (default 600),
# seeded with tests/fuzz/corpus_<name> and guided by tests/fuzz/<name>.dict, each input allowed
# 10 s (-timeout=10). The STEP and IGES targets are also seeded with the shared data's files
# (../shared/data/step, ../shared/data/iges; EXTREMAL_SHARED_DATA), copied into
# build-fuzz/seeds/<name> at run time, those above FUZZ_SEED_MAX_BYTES (default 100000) left out
# (each execution reads the whole input with OpenCASCADE: large seeds make for few executions).
# New inputs go to build-fuzz/corpus/<name>, crashing ones to build-fuzz/artifacts/; a target
# that finds a crash, a leak or a timeout stops the script with its exit status.
# Usage: scripts/run-fuzzers.sh [SECONDS] [TARGET...]
# SECONDS is each target's run (not the total); TARGET: obj_freeform, scene, pose_table, step,
# iges, cli_options, with or without the fuzz_ prefix; default all. The hour per target of the
# CAD import: scripts/run-fuzzers.sh 3600 fuzz_step fuzz_iges fuzz_cli_options
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$root/build-fuzz"
seconds="${1:-600}"
shift || true
targets=()
for t in "$@"; do targets+=("${t#fuzz_}"); done  # fuzz_step and step name the same target
[ ${#targets[@]} -gt 0 ] || targets=(obj_freeform scene pose_table step iges cli_options)
shared="${EXTREMAL_SHARED_DATA:-$root/../shared/data}"
seed_max="${FUZZ_SEED_MAX_BYTES:-100000}"
"$root/scripts/setup.sh" --fuzz
generator=()
command -v ninja >/dev/null 2>&1 && generator=(-G Ninja)
if [ ! -f "$build/CMakeCache.txt" ]; then
  CXX=clang++ cmake -S "$root" -B "$build" "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
        -DEXTREMAL_FUZZ=ON -DEXTREMAL_BUILD_TESTS=OFF -DEXTREMAL_BUILD_BENCH=OFF
fi
cmake --build "$build" --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"

# Copies the shared data's STEP or IGES files of folder $2 into build-fuzz/seeds/$1.
shared_seeds() {
  local dir="$build/seeds/$1" f
  rm -rf "$dir"
  mkdir -p "$dir"
  if [ ! -d "$shared/$2" ]; then
    echo "run-fuzzers: no shared data at $shared/$2: no seeds from it" >&2
    return
  fi
  for f in "$shared/$2"/*; do
    case "${f,,}" in *.stp|*.step|*.igs|*.iges) ;; *) continue ;; esac
    if [ "$(stat -c %s "$f")" -le "$seed_max" ]; then
      cp "$f" "$dir/"
    else
      echo "run-fuzzers: $2/$(basename "$f") is larger than $seed_max bytes: not a seed" >&2
    fi
  done
}

export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
for target in "${targets[@]}"; do
  extra=()
  case "$target" in
    obj_freeform) seeds=obj; dict=obj ;;
    scene) seeds=scene; dict=scene ;;
    pose_table) seeds=pose_table; dict=pose_table ;;
    step) seeds=step; dict=step; shared_seeds step step; extra=("$build/seeds/step") ;;
    iges) seeds=iges; dict=iges; shared_seeds iges iges; extra=("$build/seeds/iges") ;;
    cli_options) seeds=cli_options; dict=cli_options ;;
    *) echo "run-fuzzers: unknown target '$target' (obj_freeform, scene, pose_table, step, iges, cli_options)" >&2
       exit 2 ;;
  esac
  mkdir -p "$build/corpus/$target" "$build/artifacts"
  seed_dirs=("$build/corpus/$target")
  [ -d "$root/tests/fuzz/corpus_$seeds" ] && seed_dirs+=("$root/tests/fuzz/corpus_$seeds")
  for d in "${extra[@]}"; do seed_dirs+=("$d"); done
  # The CAD readers' child process (io/internal/Isolated_reader.cpp) meets its memory limit as
  # a failed allocation: ASan returns null (std::bad_alloc) instead of reporting it.
  asan="${ASAN_OPTIONS:-}"
  case "$target" in step|iges) asan="allocator_may_return_null=1:max_allocation_size_mb=1024${asan:+:$asan}" ;; esac
  echo "run-fuzzers: fuzz_$target for ${seconds} s"
  # The scene reader resolves relative file paths against the scene's folder: run where no
  # pose table or CAD file lies about, so those entries fail the same way every time.
  (cd "$build/artifacts" &&
   ASAN_OPTIONS="$asan" "$build/tests/fuzz/fuzz_$target" -max_total_time="$seconds" -timeout=10 \
       -print_final_stats=1 -dict="$root/tests/fuzz/$dict.dict" \
       -artifact_prefix="$build/artifacts/$target-" "${seed_dirs[@]}")
done
