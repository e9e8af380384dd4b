#!/usr/bin/env bash
# CD benchmark: NLGS sweeps per step to tolerance 1e-4 and nanoseconds per contact per sweep,
# on the settled 20,000-sphere bed of examples/pour.toml (settled by DEM, then resumed by CD).
# Usage: bench/pour_cd.sh [LOCAL_SOLVER]   (bipotential | exact)
#   SABLE=PATH     the binary to time (default build/release/bin/sable, built first), e.g. an
#                  older build for a before / after comparison; SABLE_BUILD=0: do not build
#   OUT=DIR        this run's output (default out/bench-pour-cd/cd)
#   DEM_REORDER=N  [simulation] reorder_every of the DEM pour that makes the bed (default: the
#                  scenario's, "auto"); such a bed is kept apart, in out/bench-pour-cd/dem-reorderN
#   CD_REORDER=N   reorder_every of the CD run (default "auto"). A resume keeps the snapshot's
#                  count of neighbour builds, so the CD run sorts only at a 20th build.
#   CD_SWEEP=ORDER the CD run's cd.sweep (default "forward"; "coloured": the parallel sweep,
#                  threads from OMP_NUM_THREADS); CD_BLOCK=N its cd.colour_block (default 16)
set -euo pipefail
cd "$(dirname "$0")/.."
local_solver="${1:-bipotential}"
case "$local_solver" in bipotential|exact) ;; *) echo "pour_cd.sh: local solver '$local_solver': expected bipotential or exact" >&2; exit 2 ;; esac
[ "${SABLE_BUILD:-1}" = 0 ] || bash scripts/build.sh release >/dev/null
sable="${SABLE:-./build/release/bin/sable}"
[ -x "$sable" ] || { echo "pour_cd.sh: no Sable binary at $sable" >&2; exit 1; }
case "${CD_SWEEP:-forward}" in forward|alternating|shuffled|coloured) ;; *) echo "pour_cd.sh: CD_SWEEP='$CD_SWEEP': expected forward, alternating, shuffled or coloured" >&2; exit 2 ;; esac
[[ "${CD_BLOCK:-16}" =~ ^[1-9][0-9]*$ ]] || { echo "pour_cd.sh: CD_BLOCK='$CD_BLOCK': expected a whole number of contacts >= 1" >&2; exit 2; }
for knob in DEM_REORDER CD_REORDER; do
  v="${!knob:-auto}"
  [[ "$v" =~ ^(auto|[0-9]+)$ ]] || { echo "pour_cd.sh: $knob='$v': expected \"auto\" or a whole number of neighbour builds" >&2; exit 2; }
done
reorder_line() {  # VALUE -> a TOML line for [simulation], or nothing for the default
  case "$1" in auto) ;; *) printf '\\nreorder_every = %s' "$1" ;; esac
}
work=out/bench-pour-cd
out="${OUT:-$work/cd}"
mkdir -p "$work"
dem="$work/dem${DEM_REORDER:+-reorder$DEM_REORDER}"
snap="$dem/snapshots/end_of_stage_1.h5"
if [ ! -f "$snap" ]; then
  sed -e 's/^vtk_interval = .*/vtk_interval = 0/' \
      -e "s/^\[simulation\]/[simulation]$(reorder_line "${DEM_REORDER:-auto}")/" examples/pour.toml > "$dem.toml"
  "$sable" run "$dem.toml" --out "$dem" 2>/dev/null
fi
sed -e "s/^criterion = .*/criterion = \"natural\"\nlocal_solver = \"$local_solver\"\nsweep = \"${CD_SWEEP:-forward}\"\ncolour_block = ${CD_BLOCK:-16}/" \
    -e "s/^\[simulation\]/[simulation]$(reorder_line "${CD_REORDER:-auto}")/" bench/pour_cd.toml > "$work/pour_cd.toml"
rm -rf "$out"
mkdir -p "$out"
"$sable" run "$work/pour_cd.toml" --out "$out" --resume "$snap" --accept-changes 2> "$out/cd.log"
grep -E "^stage 'cd' done|^done:|warning" "$out/cd.log" || true
/usr/bin/python3 - "$out/series.csv" "$out/cd.log" <<'PY'
import csv, re, sys
rows = list(csv.DictReader(open(sys.argv[1])))[1:]  # drop the resume row
log = open(sys.argv[2]).read()
# The stage summary names each phase's seconds: "... NLGS solve 6.25 s (88%) ...".
m = re.search(r"stage 'cd' done: (\d+) steps in [\d.]+ s.*NLGS solve ([\d.]+) s", log)
if m is None:
    sys.exit(f"pour_cd.sh: no \"stage 'cd' done: ... NLGS solve <seconds> s\" line in {sys.argv[2]}")
steps, nlgs_s = int(m.group(1)), float(m.group(2))
sweeps = [float(r["nlgs_iterations"]) for r in rows]
work = sum(float(r["nlgs_iterations"]) * float(r["nlgs_contacts"]) for r in rows)
contacts = sum(float(r["nlgs_contacts"]) for r in rows) / len(rows)
ns = nlgs_s / work * 1e9
print(f"steps {steps}, contacts in the problem {contacts:.0f} (mean), sweeps/step mean {sum(sweeps)/len(sweeps):.1f} "
      f"(min {min(sweeps):.0f}, max {max(sweeps):.0f}), NLGS {nlgs_s:.2f} s, "
      f"{ns:.1f} ns per contact per sweep, final residual {float(rows[-1]['nlgs_residual']):.2e}")
PY
