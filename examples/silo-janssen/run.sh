#!/usr/bin/env bash
# The silo of Dumont, Fortin & Ouafik (2010), section 5.2 and Figure 7, end to end: deposit,
# lower the bottom wall, measure wall stresses and the polarization of wall contacts, fit
# Janssen's model, draw the figure. Writes out/silo-janssen/:
#   CASE/                    the run (series.csv, ParaView files, snapshots)
#   CASE/before/             analysis of the deposit at rest, before the bottom moves
#   CASE/relax/              analysis averaged over the snapshots taken during the descent
#   CASE/after/              analysis once the bottom has stopped
#   summary.json             K with its uncertainty and R^2, polarization fractions, balance,
#                            run times, for every case
#   silo-janssen.png         force network coloured by |ft| / (mu fn) beside the wall-stress
#                            profile and the fitted Janssen curve (the paper's Figure 7)
# Usage: examples/silo-janssen/run.sh [quick | full | large]
#   quick  2D contact dynamics only (the README's main job, ~2 minutes on 2 cores)
#   full   2D CD, 2D DEM (Hertz-Mindlin, stiff grains) and 3D CD (cylindrical silo; the 3D
#          run alone takes 15-25 minutes)
#   large  the 3,000-grain 2D DEM variant of docs/examples.md (~10 minutes)
set -euo pipefail
cd "$(dirname "$0")/../.."
mode="${1:-quick}"
case "$mode" in
  quick) cases="cd-2d" ;;
  full) cases="cd-2d dem-2d cd-3d" ;;
  large) cases="dem-2d-large" ;;
  *) echo "usage: $0 [quick | full | large]" >&2; exit 2 ;;
esac
bin=./build/release/bin/sable
out=out/silo-janssen
mkdir -p "$out"

# Wall-profile bins: six mean diameters (18 mm) in 2D, so that each bin of the 350-grain silo
# holds ~10 wall contacts per snapshot and the profile averaged over the descent is smooth
# enough to test Janssen's shape; four (12 mm) for the 3D silo, whose wall is a surface with
# many more contacts per bin (docs/examples.md).
bin_for() { if [ "$1" = cd-3d ]; then echo 0.012; else echo 0.018; fi; }

step_of() { "$bin" info "$1" | awk '$1 == "step" { print $2 }'; }

run_case() {
  local name="$1" scenario="examples/silo-janssen/silo-${1}.toml"
  local dir="$out/$name"
  echo "== $name: $scenario"
  local t0 t1
  t0=$(date +%s.%N)
  "$bin" run "$scenario" --out "$dir"
  t1=$(date +%s.%N)
  /usr/bin/python3 -c "print(round($t1 - $t0, 1))" > "$dir/run_seconds"
  local snaps="$dir/snapshots"
  local s1 s2 relax=()
  s1=$(step_of "$snaps/end_of_stage_1.h5")
  s2=$(step_of "$snaps/end_of_stage_2.h5")
  for f in "$snaps"/step_*.h5; do
    local s=${f##*/step_}
    s=$((10#${s%.h5}))
    if [ "$s" -gt "$s1" ] && [ "$s" -lt "$s2" ]; then relax+=("$f"); fi
  done
  relax+=("$snaps/end_of_stage_2.h5")
  local what="walls,janssen,polarization,stress" bin_height
  bin_height=$(bin_for "$name")
  "$bin" analyze "$snaps/end_of_stage_1.h5" --only "$what" --wall-bin "$bin_height" \
    --out "$dir/before" 2> "$dir/before.log"
  "$bin" analyze "${relax[@]}" --only "$what" --wall-bin "$bin_height" --out "$dir/relax" \
    2> "$dir/relax.log"
  "$bin" analyze "$snaps/end_of_stage_3.h5" --only "$what" --wall-bin "$bin_height" \
    --out "$dir/after" 2> "$dir/after.log"
}

bash scripts/build.sh release > /dev/null
for c in $cases; do run_case "$c"; done
/usr/bin/python3 examples/silo-janssen/report.py "$out" $cases
echo
echo "Results: $out/summary.json and $out/silo-janssen.png;"
echo "profiles: $out/CASE/relax/janssen.csv and wall_profile_*.csv; ParaView: $out/CASE/*.pvd"
