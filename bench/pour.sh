#!/usr/bin/env bash
# Pour benchmark: run examples/pour.toml (20,000 spheres, the LIGGGHTS peer's bed) and print
# grain-steps per second for the settling phase and the 5,000-step dense phase, with the
# phase breakdown and peak memory. Usage: [NP=N] bench/pour.sh [THREADS] [REPEATS]
# NP=N: under `mpirun -np N` (THREADS OpenMP threads in each process; the same state hash).
# Builds the release preset first. Outputs go to a temporary directory (VTK off).
set -euo pipefail
cd "$(dirname "$0")/.."
threads="${1:-1}"
repeats="${2:-1}"
bash scripts/build.sh release >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The same scenario with VTK frames off, so the timing is the solver's.
sed -e 's/^vtk_interval = .*/vtk_interval = 0/' -e 's/^csv_interval = .*/csv_interval = 5000/' \
  examples/pour.toml > "$work/pour.toml"
launch=()
if [ "${NP:-0}" -gt 0 ]; then
  launch=(mpirun -np "$NP" --oversubscribe)
  [ "$(id -u)" = 0 ] && export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
fi
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; threads: $threads; processes: ${NP:-1 (no mpirun)}; $(date -u +%F)"
for r in $(seq 1 "$repeats"); do
  OMP_NUM_THREADS="$threads" "${launch[@]}" ./build/release/bin/sable run "$work/pour.toml" \
    --out "$work/out" --overwrite --threads "$threads" 2> "$work/log.txt" ||
    { cat "$work/log.txt"; exit 1; }
  grep -E "^stage '.*' done|^done:" "$work/log.txt" | sed "s/^/run $r: /"
done
