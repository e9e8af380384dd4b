#!/usr/bin/env bash
# Build the libFuzzer targets (the fuzz build preset: the asan-ubsan configuration, clang with
# ASan + UBSan and libFuzzer's coverage, which also builds the sanitized unit tests) and run
# each for SECONDS:
#
#   bash scripts/fuzz.sh [SECONDS] [TARGET...]     (default: 60 s each; scenario snapshot fc3d)
#   FUZZ_RUNS=1000000 bash scripts/fuzz.sh 0 TARGET   (a campaign: that many inputs, no time limit)
#
# Each target starts from its seeds (examples/*.toml and examples/*/*.toml, the small
# ../shared/data/fc3d problems, tests/fuzz/corpus/TARGET, tests/fuzz/regressions/TARGET) in
# build/fuzz/corpus/TARGET, which keeps what the fuzzer adds between runs. An input that
# crashes, times out (-timeout) or runs out of memory (-rss_limit_mb) is kept in
# build/fuzz/crashes/TARGET/; every target runs, then the script fails if any found one.
# Replay one with build/asan-ubsan/bin/fuzz_TARGET FILE; once fixed, commit it (minimized:
# fuzz_TARGET -minimize_crash=1 -runs=10000 FILE) under tests/fuzz/regressions/TARGET/, which
# the ctest FuzzReplay.TARGET replays in every build.
set -euo pipefail
cd "$(dirname "$0")/.."

seconds="${1:-60}"
[ $# -gt 0 ] && shift
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(scenario snapshot fc3d)

cmake --preset asan-ubsan >/dev/null
cmake --build --preset fuzz -j "$(nproc)"

# Per target: the longest input tried (bytes) and the dictionary, if any. Scenarios: the
# examples are at most 6 KB. Snapshot edit scripts: a few hundred bytes decode to 8 edits.
# fc3d: the seeds are the problems of at most 16 KB (the larger ones are read whole by the
# validation tests).
declare -A max_len=([scenario]=16384 [snapshot]=512 [fc3d]=16384)
declare -A dict=([scenario]=tests/fuzz/scenario.dict)
# The snapshot target opens HDF5 files, whose metadata caches are megabyte allocations: ASan's
# default 256 MB quarantine of freed memory made every input fault in fresh pages (2.5 times
# slower). 16 MB still holds each input's freed memory for the rest of that input.
declare -A asan=([snapshot]=quarantine_size_mb=16)

seed() {  # seed TARGET FILES...: copy the files that exist into the target's corpus
  local t=$1
  shift
  local f
  for f in "$@"; do
    if [ -f "$f" ]; then cp -n "$f" "build/fuzz/corpus/$t/" || true; fi
  done
}

failed=()
for t in "${targets[@]}"; do
  bin="build/asan-ubsan/bin/fuzz_$t"
  [ -x "$bin" ] || { echo "fuzz: no target '$t' (known: scenario snapshot fc3d)" >&2; exit 2; }
  mkdir -p "build/fuzz/corpus/$t" "build/fuzz/crashes/$t" build/fuzz/logs
  seed "$t" tests/fuzz/corpus/"$t"/* tests/fuzz/regressions/"$t"/*
  case "$t" in
    scenario) seed "$t" examples/*.toml examples/*/*.toml ;;
    fc3d) seed "$t" $(find ../shared/data/fc3d ../shared/data/fc2d -name '*.dat' -size -17k 2>/dev/null) ;;
  esac
  args=(-max_total_time="$seconds" -max_len="${max_len[$t]}" -timeout=10 -rss_limit_mb=2048
        -print_final_stats=1 -artifact_prefix="build/fuzz/crashes/$t/")
  [ -n "${FUZZ_RUNS:-}" ] && args+=(-runs="$FUZZ_RUNS")
  [ -n "${dict[$t]:-}" ] && args+=(-dict="${dict[$t]}")
  log="build/fuzz/logs/$t.log"
  echo "== fuzz $t: ${seconds} s${FUZZ_RUNS:+ (or $FUZZ_RUNS inputs)}, corpus build/fuzz/corpus/$t" \
    "($(ls "build/fuzz/corpus/$t" | wc -l) inputs)"
  if OMP_NUM_THREADS=1 UBSAN_OPTIONS=print_stacktrace=1 ASAN_OPTIONS="${asan[$t]:-}" \
    "$bin" "${args[@]}" "build/fuzz/corpus/$t" >"$log" 2>&1; then
    grep -E '^stat::(number_of_executed_units|average_exec_per_sec|peak_rss_mb)' "$log" || true
    grep -E '^#[0-9]+[[:space:]]+DONE' "$log" || true
  else
    echo "fuzz $t FAILED: the input is in build/fuzz/crashes/$t/; the end of $log:" >&2
    tail -n 60 "$log" >&2
    failed+=("$t")
  fi
done

if ((${#failed[@]})); then
  echo "fuzz: failures in ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: no failure in ${targets[*]}"
