#!/usr/bin/env bash
# A/B timing of the dense phase of the pour bed (examples/pour.toml, 20,000 spheres) for two
# or more sable binaries, run alternately on the same settled snapshot so that the VM's drift
# (10 % between runs minutes apart on the project's 2-vCPU machine) hits every binary alike.
# A change to the DEM step is worth keeping only if it wins here; bench/pour.sh alone is too
# noisy to see a 5 % effect.
#
# Usage: bench/ab_dense.sh [-t THREADS] [-r REPEATS] BINARY...
#   e.g. bench/ab_dense.sh -r 3 /tmp/base/build/release/bin/sable build/release/bin/sable
# The settled bed is made once with the first binary (out/bench-ab/settled.h5, stage 1 of
# pour.toml: until the kinetic energy falls below 1e-7 J); every run resumes it and times
# stage 2 (5,000 steps). Prints "binary grain-steps/s state-hash" per run, then the medians.
set -euo pipefail
cd "$(dirname "$0")/.."
threads=1
repeats=3
while getopts "t:r:" opt; do
  case "$opt" in
    t) threads="$OPTARG" ;;
    r) repeats="$OPTARG" ;;
    *) echo "usage: bench/ab_dense.sh [-t THREADS] [-r REPEATS] BINARY..." >&2; exit 2 ;;
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
: > "$work/results.txt"
for r in $(seq 1 "$repeats"); do
  for b in "$@"; do
    rm -rf "$work/run"
    "$b" run "$work/pour.toml" --resume "$work/settled.h5" --out "$work/run" \
      --threads "$threads" 2> "$work/run.log"
    rate=$(sed -n "s/^stage 'dense' done: .*, \([0-9.e+]*\) grain-steps\/s.*/\1/p" "$work/run.log")
    hash=$(sed -n 's/.*state hash \([0-9a-f]*\).*/\1/p' "$work/run.log")
    echo "$b $rate $hash" | tee -a "$work/results.txt"
  done
done
/usr/bin/python3 - "$work/results.txt" <<'PY'
import statistics, sys
runs = {}
for line in open(sys.argv[1]):
    b, rate, _ = line.split()
    runs.setdefault(b, []).append(float(rate))
for b, v in runs.items():
    print(f"median {statistics.median(v) / 1e6:.2f} M grain-steps/s "
          f"(min {min(v) / 1e6:.2f}, max {max(v) / 1e6:.2f}, {len(v)} runs)  {b}")
PY
