#!/usr/bin/env bash
# Run every example the README names, in its quick form, into a fresh output root, and check
# what each one produces (exit codes, then the key figures of its summaries against bounds
# that scripts/check_examples.py states and justifies):
#   examples/silo-janssen/run.sh quick    2D CD silo, with and without rolling resistance
#   examples/cd-arrays/run.sh             CD on regular disk arrays (analytic forces)
#   examples/force-pdf/run.sh quick       dry force PDFs by DEM (iso-dem, triaxial-dem)
#   examples/force-pdf/run.sh wet         wet packings with capillary bridges (its only form)
#   sable run examples/pour.toml          shortened: 2,000 of its 20,000 spheres (the full
#                                         pour settles over up to 150,000 steps; bench/pour.sh
#                                         times it)
# Usage: scripts/run-examples.sh [ROOT]   (default out/examples-check; removed first)
# Writes ROOT/EXAMPLE/... (each run.sh's outputs, through SABLE_OUT), ROOT/NAME.log for each
# step, and ROOT/times.txt; prints the checks and exits 1 if any step or check fails.
set -euo pipefail
cd "$(dirname "$0")/.."
root="${1:-out/examples-check}"
case "$(realpath -m "$root")" in
  / | "$PWD" | "$HOME" | "$(realpath -m out)")
    echo "run-examples: will not empty $root; give a folder of its own" >&2
    exit 2
    ;;
esac
rm -rf "$root"
mkdir -p "$root"
export SABLE_OUT="$root"
# One OpenMP thread per run, each example's own default (the silo runs its seeds side by
# side): on the project's 2-core VM shared with other builds, two threads per run took the
# force-pdf study 784 s, against 326 s on one thread in an earlier run.
export SABLE_THREADS=1
bash scripts/build.sh release > /dev/null

failed=0
# Run one step, NAME then its command, its output into ROOT/NAME.log, timed.
step() {
  local name="$1" t0 t1 status=0
  shift
  echo "== $name: $*"
  t0=$(date +%s)
  "$@" > "$root/$name.log" 2>&1 || status=$?
  if [ "$status" -ne 0 ]; then
    echo "FAIL: $name exited with status $status; the end of $root/$name.log:" >&2
    tail -n 15 "$root/$name.log" >&2
    failed=1
  fi
  t1=$(date +%s)
  echo "$name $((t1 - t0))" >> "$root/times.txt"
  echo "   $((t1 - t0)) s"
}

# The pour of 20,000 spheres, cut to its first 2,000 (six of its lattice's layers of 324),
# everything else as in examples/pour.toml. Its settling criterion scales with the grain
# count (the same mean speed, ~1.5 mm/s, in a tenth of the grains: a tenth of the energy).
short_pour() {
  mkdir -p "$root/pour"
  sed -e 's/^count = 20000$/count = 2000/' \
    -e 's/^kinetic_energy_below = 1.0e-7$/kinetic_energy_below = 1.0e-8/' \
    examples/pour.toml > "$root/pour/pour-2000.toml"
  grep -q '^count = 2000$' "$root/pour/pour-2000.toml" &&
    grep -q '^kinetic_energy_below = 1.0e-8$' "$root/pour/pour-2000.toml" || {
    echo "examples/pour.toml changed: its count or settling criterion was not found" >&2
    return 1
  }
  build/release/bin/sable run "$root/pour/pour-2000.toml" --out "$root/pour/run" \
    --threads "$SABLE_THREADS"
}

# The regular arrays, then the contact forces of the two frictionless ones (whose forces are
# unique and known: scripts/check_examples.py).
cd_arrays() {
  bash examples/cd-arrays/run.sh
  local name
  for name in cannonball rectangular; do
    build/release/bin/sable analyze "$root/cd-arrays/$name/snapshots/end_of_stage_1.h5" \
      --only polarization --out "$root/cd-arrays/$name/analysis"
  done
}

t_start=$(date +%s)
step silo-janssen bash examples/silo-janssen/run.sh quick
step cd-arrays cd_arrays
step force-pdf bash examples/force-pdf/run.sh quick
step force-pdf-wet bash examples/force-pdf/run.sh wet
step pour short_pour
echo "== checks"
/usr/bin/python3 scripts/check_examples.py "$root" || failed=1
echo "total $(($(date +%s) - t_start)) s (runs; the build before them not counted)"
if [ "$failed" -ne 0 ]; then
  echo "run-examples: FAILED" >&2
  exit 1
fi
echo "run-examples: all examples ran and passed their checks"
