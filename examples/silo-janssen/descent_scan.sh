#!/usr/bin/env bash
# How the descent protocol of the 2D silo (silo-dem-2d.toml, silo-cd-2d.toml) shapes the side
# walls' friction: lower the bottom wall at a chosen speed over a chosen distance, then measure,
# per side-wall contact, whether it sits on the Coulomb cone and whether its disk rolls down
# the wall without slip. The shipped scenarios lower the bottom by 3 mm at 5 mm/s; this scans
# other speeds, distances and seeds with everything else unchanged. Writes
# out/silo-janssen/descent-scan/SOLVER-vSPEED-dDISTANCE/:
#   seed-N/scenario.toml     the shipped scenario with seed, descent and output intervals edited
#   seed-N/run.log           the run's log (state hash, run time)
#   seed-N/series.csv        energies and wall forces against time
#   seed-N/snapshots/        the end of each stage and the snapshots from the descent on (~12
#                            over the descent; those of the deposit are deleted)
#   seed-N/descent/          sable analyze of those descent snapshots pooled (walls, Janssen,
#                            polarization of contacts, stress); seed-N/descent.log its log
#   wall_contacts.json       side-wall contacts pooled over seeds and descent snapshots: on-cone
#                            fraction, shear/normal, rolling without slip, per-snapshot table
#                            (wall_contacts.py; its printout is in wall_contacts.txt)
# Usage: [ROLLING=MU_R] examples/silo-janssen/descent_scan.sh dem|cd SPEED_MM_S DISTANCE_MM SEED...
#   e.g. examples/silo-janssen/descent_scan.sh dem 5 3 2010 2011   (~15 s a DEM seed on 1 core)
# Needs build/release/bin/sable (bash scripts/build.sh release), numpy and h5py.
set -euo pipefail
shopt -s nullglob
cd "$(dirname "$0")/../.."

usage() {
  echo "error: $1" >&2
  echo "usage: $0 dem|cd SPEED_MM_S DISTANCE_MM SEED..." >&2
  echo "  SPEED_MM_S, DISTANCE_MM: positive numbers (bottom-wall speed in mm/s, descent in mm)" >&2
  echo "  SEED: one or more non-negative integers (the shipped scenarios use 2010)" >&2
  exit 2
}
[ $# -ge 4 ] || usage "expected a solver, a speed, a distance and at least one seed (got $# arguments)"
solver=$1 speed=$2 dist=$3
shift 3
case "$solver" in
  dem | cd) ;;
  *) usage "unknown solver '$solver' (expected dem or cd)" ;;
esac
# A decimal number (no sign, no exponent) with a non-zero digit: it names the output directory.
positive() { [[ $1 =~ ^([0-9]+([.][0-9]*)?|[.][0-9]+)$ && $1 =~ [1-9] ]]; }
positive "$speed" || usage "speed '$speed' is not a positive decimal number of mm/s"
positive "$dist" || usage "distance '$dist' is not a positive decimal number of mm"
for seed in "$@"; do
  [[ $seed =~ ^[0-9]+$ ]] || usage "seed '$seed' is not a non-negative integer"
done
bin=./build/release/bin/sable
[ -x "$bin" ] || usage "no sable binary at $PWD/${bin#./} (build it: bash scripts/build.sh release)"

base=examples/silo-janssen/silo-$solver-2d.toml
case_dir=out/silo-janssen/descent-scan/$solver-v$speed-d$dist
# ROLLING=MU_R: the same silo with rolling resistance (contact.rolling = "epsd",
# rolling_friction = MU_R for grains and walls); the case directory gets "-rollMU_R".
rolling=${ROLLING:-}
if [ -n "$rolling" ]; then
  positive "$rolling" || usage "ROLLING '$rolling' is not a positive decimal number"
  case_dir=$case_dir-roll$rolling
fi
mkdir -p "$case_dir"

# The descent lasts distance / speed; relax steps = that time / dt (dt from the scenario: 1 us
# DEM, 0.5 ms CD). ~12 snapshots over the descent give the pooled analysis enough contacts
# (~55 side-wall contacts a snapshot) while each is a different network; series.csv gets ~5
# rows a snapshot, at most one per 10,000 DEM or 20 CD steps as in the shipped scenarios. A
# descent beyond 3.5 mm takes the bottom below the domain's lower edge (-5 mm), so that edge
# goes 3 mm below the bottom's final position.
read -r steps snap csv vel lo < <(/usr/bin/python3 - "$base" "$speed" "$dist" <<'EOF'
import sys, tomllib
dt = tomllib.load(open(sys.argv[1], "rb"))["simulation"]["dt"]
v = float(sys.argv[2]) * 1e-3; d = float(sys.argv[3]) * 1e-3
steps = round(d / v / dt); snap = max(1, round(steps / 12))
csv = max(1, min(10000 if dt < 1e-4 else 20, snap // 5))
lo = -0.005 if d <= 0.0035 else -(d + 0.003)
print(steps, snap, csv, -v, lo)
EOF
)

# Snapshot step number, as `sable info` reports it.
step_of() { "$bin" info "$1" | awk '$1 == "step" { print $2 }'; }

runs=()
for seed in "$@"; do
  run=$case_dir/seed-$seed
  echo "== $solver, $speed mm/s over $dist mm, seed $seed: $steps relax steps, snapshot every $snap"
  rm -rf "$run"
  mkdir -p "$run"
  # The relax stage is the only one with 600000 (DEM) or 1200 (CD) steps, and the only one
  # moving the bottom at -5 mm/s; sed does not complain when a pattern stops matching (an
  # edited shipped scenario), so each edit is checked below.
  sed -e "s/^seed = .*/seed = $seed/" \
    -e "s/^steps = \(600000\|1200\)$/steps = $steps/" \
    -e "s/wall_velocity = { bottom = \[0.0, -0.005\] }/wall_velocity = { bottom = [0.0, $vel] }/" \
    -e "s/^snapshot_interval = .*/snapshot_interval = $snap/" \
    -e "s/^csv_interval = .*/csv_interval = $csv/" \
    -e "s/^lo = \[0.0, -0.005\]/lo = [0.0, $lo]/" \
    "$base" > "$run/scenario.toml"
  if [ -n "$rolling" ]; then
    # The CD silo has no [contact] table: it gets one before its [cd] table.
    sed -i -e "s/^tangential = \"history\"$/&\nrolling = \"epsd\"/" \
      -e "s/^\[cd\]$/[contact]\nrolling = \"epsd\"\n\n&/" \
      -e "s/^friction = 0.25$/&\nrolling_friction = $rolling/" "$run/scenario.toml"
    for line in 'rolling = "epsd"' "rolling_friction = $rolling"; do
      grep -qxF "$line" "$run/scenario.toml" ||
        { echo "error: $base no longer has the line that '$line' follows" >&2; exit 1; }
    done
  fi
  for line in "seed = $seed" "steps = $steps" "wall_velocity = { bottom = [0.0, $vel] }" \
    "snapshot_interval = $snap" "csv_interval = $csv" "lo = [0.0, $lo]"; do
    grep -qxF "$line" "$run/scenario.toml" ||
      { echo "error: $base no longer has the line that becomes '$line'" >&2; exit 1; }
  done
  "$bin" run "$run/scenario.toml" --out "$run" --threads 1 > "$run/run.log" 2>&1 ||
    { tail -n 20 "$run/run.log" >&2; echo "error: the run failed, see $run/run.log" >&2; exit 1; }
  tail -n 1 "$run/run.log"
  # ParaView files are not used here; deposit snapshots neither (only end_of_stage_1 is).
  rm -rf "$run/vtk" "$run"/*.pvd
  snaps=$run/snapshots
  s1=$(step_of "$snaps/end_of_stage_1.h5")
  s2=$(step_of "$snaps/end_of_stage_2.h5")
  descent=()
  for f in "$snaps"/step_*.h5; do
    s=${f##*/step_}
    s=$((10#${s%.h5}))
    if [ "$s" -le "$s1" ]; then rm -f "$f"; elif [ "$s" -lt "$s2" ]; then descent+=("$f"); fi
  done
  descent+=("$snaps/end_of_stage_2.h5")
  "$bin" analyze "${descent[@]}" --only walls,janssen,polarization,stress --wall-bin 0.018 \
    --out "$run/descent" > "$run/descent.log" 2>&1 ||
    { tail -n 20 "$run/descent.log" >&2; echo "error: analysis failed, see $run/descent.log" >&2; exit 1; }
  runs+=("$run")
done

echo
/usr/bin/python3 examples/silo-janssen/wall_contacts.py "${runs[@]}" | tee "$case_dir/wall_contacts.txt"
echo
echo "Results: $case_dir/wall_contacts.json; per seed: $case_dir/seed-*/descent/summary.json"
