#!/usr/bin/env bash
# CD benchmark: NLGS sweeps per step to tolerance 1e-4 and nanoseconds per contact per sweep,
# on the settled 20,000-sphere bed of examples/pour.toml (settled by DEM, then resumed by CD).
# Usage: bench/pour_cd.sh [LOCAL_SOLVER]   (bipotential | exact)
#   SABLE=PATH     the binary to time (default build/release/bin/sable, built first), e.g. an
#                  older build for a before / after comparison; SABLE_BUILD=0: do not build
#   OUT=DIR        this run's output (default out/bench-pour-cd/cd)
set -euo pipefail
cd "$(dirname "$0")/.."
local_solver="${1:-bipotential}"
case "$local_solver" in bipotential|exact) ;; *) echo "pour_cd.sh: local solver '$local_solver': expected bipotential or exact" >&2; exit 2 ;; esac
[ "${SABLE_BUILD:-1}" = 0 ] || bash scripts/build.sh release >/dev/null
sable="${SABLE:-./build/release/bin/sable}"
[ -x "$sable" ] || { echo "pour_cd.sh: no Sable binary at $sable" >&2; exit 1; }
work=out/bench-pour-cd
out="${OUT:-$work/cd}"
mkdir -p "$work"
snap="$work/dem/snapshots/end_of_stage_1.h5"
if [ ! -f "$snap" ]; then
  sed -e 's/^vtk_interval = .*/vtk_interval = 0/' examples/pour.toml > "$work/pour.toml"
  "$sable" run "$work/pour.toml" --out "$work/dem" 2>/dev/null
fi
sed "s/^criterion = .*/criterion = \"natural\"\nlocal_solver = \"$local_solver\"/" bench/pour_cd.toml > "$work/pour_cd.toml"
rm -rf "$out"
mkdir -p "$out"
"$sable" run "$work/pour_cd.toml" --out "$out" --resume "$snap" 2> "$out/cd.log"
grep -E "^stage 'cd' done|^done:|warning" "$out/cd.log" || true
/usr/bin/python3 - "$out/series.csv" "$out/cd.log" <<'PY'
import csv, re, sys
rows = list(csv.DictReader(open(sys.argv[1])))[1:]  # drop the resume row
log = open(sys.argv[2]).read()
m = re.search(r"stage 'cd' done: (\d+) steps in ([\d.]+) s.*NLGS solve (\d+)%", log)
steps, secs, solve_pct = int(m.group(1)), float(m.group(2)), float(m.group(3))
sweeps = [float(r["nlgs_iterations"]) for r in rows]
work = sum(float(r["nlgs_iterations"]) * float(r["nlgs_contacts"]) for r in rows)
contacts = sum(float(r["nlgs_contacts"]) for r in rows) / len(rows)
ns = secs * solve_pct / 100 / work * 1e9
print(f"steps {steps}, contacts in the problem {contacts:.0f} (mean), sweeps/step mean {sum(sweeps)/len(sweeps):.1f} "
      f"(min {min(sweeps):.0f}, max {max(sweeps):.0f}), NLGS {secs*solve_pct/100:.2f} s, "
      f"{ns:.1f} ns per contact per sweep, final residual {float(rows[-1]['nlgs_residual']):.2e}")
PY
