#!/usr/bin/env bash
# A/B timing of the dense phase of the pour bed (examples/pour.toml, 20,000 spheres) for two
# or more sable binaries, run alternately on the same settled snapshot so that the VM's drift
# (10 % between runs minutes apart on the project's 2-vCPU machine) hits every binary alike.
# A change to the DEM step is worth keeping only if it wins here; bench/pour.sh alone is too
# noisy to see a 5 % effect.
#
# Usage: bench/ab_dense.sh [-t THREADS] [-r REPEATS] BINARY...
#        bench/ab_dense.sh -s [-r REPEATS] BINARY...
#   e.g. bench/ab_dense.sh -r 3 /tmp/base/build/release/bin/sable build/release/bin/sable
# The settled bed is made once with the first binary (out/bench-ab/settled.h5, stage 1 of
# pour.toml: until the kinetic energy falls below 1e-7 J); every run resumes it and times
# stage 2 (5,000 steps). Prints "binary grain-steps/s state-hash" per run, then the medians.
#
# -s: two threads against one. Each round runs every binary on one thread then on two, back
# to back, so that both runs of a pair see the same state of the VM (its speed drifts by
# 10-50 % over minutes: a ratio of two medians taken minutes apart is unreliable). Prints
# "binary one-thread-s two-thread-s state-hash" per pair (the two hashes must agree), then
# each binary's median ratio.
set -euo pipefail
cd "$(dirname "$0")/.."
threads=1
repeats=3
scaling=0
while getopts "t:r:s" opt; do
  case "$opt" in
    t) threads="$OPTARG" ;;
    r) repeats="$OPTARG" ;;
    s) scaling=1 ;;
    *) echo "usage: bench/ab_dense.sh [-t THREADS | -s] [-r REPEATS] BINARY..." >&2; exit 2 ;;
  esac
done
shift $((OPTIND - 1))
if [ $# -lt 1 ]; then
  echo "bench/ab_dense.sh: give at least one sable binary" >&2
  exit 2
fi
for b in "$@"; do
  [ -x "$b" ] || { echo "bench/ab_dense.sh: '$b' is not an executable" >&2; exit 2; }
done
work=out/bench-ab
mkdir -p "$work"
sed -e 's/^vtk_interval = .*/vtk_interval = 0/' -e 's/^csv_interval = .*/csv_interval = 5000/' \
  examples/pour.toml > "$work/pour.toml"
if [ ! -f "$work/settled.h5" ]; then
  rm -rf "$work/settle"
  "$1" run "$work/pour.toml" --out "$work/settle" --threads "$threads" 2> "$work/settle.log"
  cp "$work/settle/snapshots/end_of_stage_1.h5" "$work/settled.h5"
fi

# One run of the dense stage: prints "grain-steps/s seconds state-hash".
dense() {  # BINARY THREADS
  rm -rf "$work/run"
  "$1" run "$work/pour.toml" --resume "$work/settled.h5" --out "$work/run" \
    --threads "$2" 2> "$work/run.log"
  local line
  line=$(grep "^stage 'dense' done: " "$work/run.log") ||
    { echo "bench/ab_dense.sh: $1: no dense stage in $work/run.log" >&2; exit 1; }
  echo "$(sed -n 's/.*, \([0-9.e+]*\) grain-steps\/s.*/\1/p' <<< "$line")" \
    "$(sed -n 's/.* in \([0-9.]*\) s, .*/\1/p' <<< "$line")" \
    "$(sed -n 's/.*state hash \([0-9a-f]*\).*/\1/p' "$work/run.log")"
}

: > "$work/results.txt"
for r in $(seq 1 "$repeats"); do
  for b in "$@"; do
    if [ "$scaling" = 0 ]; then
      out=$(dense "$b" "$threads")  # set -e: a failed run stops the script here
      read -r rate _ hash <<< "$out"
      echo "$b $rate $hash" | tee -a "$work/results.txt"
    else
      one=$(dense "$b" 1)
      two=$(dense "$b" 2)
      read -r _ s1 h1 <<< "$one"
      read -r _ s2 h2 <<< "$two"
      [ "$h1" = "$h2" ] ||
        { echo "bench/ab_dense.sh: $b: state hash $h1 on one thread, $h2 on two" >&2; exit 1; }
      echo "$b $s1 $s2 $h1" | tee -a "$work/results.txt"
    fi
  done
done
/usr/bin/python3 - "$work/results.txt" "$scaling" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    b, *values, _ = line.split()
    runs.setdefault(b, []).append([float(x) for x in values])
for b, v in runs.items():
    if sys.argv[2] == "1":
        ratios = [s1 / s2 for s1, s2 in v]
        pairs = ", ".join(f"{s1:.2f}/{s2:.2f}" for s1, s2 in v)
        print(f"two threads / one: median {statistics.median(ratios):.2f}x (min "
              f"{min(ratios):.2f}, max {max(ratios):.2f}; seconds {pairs})  {b}")
    else:
        rates = [x[0] for x in v]
        print(f"median {statistics.median(rates) / 1e6:.2f} M grain-steps/s (min "
              f"{min(rates) / 1e6:.2f}, max {max(rates) / 1e6:.2f}, {len(v)} runs)  {b}")
PY
