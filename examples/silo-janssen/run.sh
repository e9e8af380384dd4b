#!/usr/bin/env bash
# The silo of Dumont, Fortin & Ouafik (2010), section 5.2 and Figure 7, end to end: deposit,
# lower the bottom wall, measure wall stresses and the polarization of wall contacts, fit
# Janssen's model, draw the figure. Writes out/silo-janssen/:
#   CASE/seed-N/             the runs (series.csv, ParaView files, snapshots; log: seed-N.log)
#   CASE/before/             analysis of the deposit at rest, before the bottom moves
#   CASE/relax/              analysis averaged over the snapshots taken during the descent
#                            (and over the seeds: DEM runs an ensemble of 4 seeds, CD with
#                            rolling resistance one of 8; see seeds_for)
#   CASE/after/              analysis once the bottom has stopped
#   summary.json             K with its uncertainty and R^2, polarization fractions, balance,
#                            run times, for every case
#   silo-janssen.png         force network coloured by |ft| / (mu fn) beside the wall-stress
#                            profile and the fitted Janssen curve (the paper's Figure 7)
# Usage: examples/silo-janssen/run.sh [quick | full | large | CASE...]
#   quick  2D contact dynamics, with rolling resistance (cd-2d-rolling: the figure's network)
#          and with freely rotating disks (cd-2d) (the README's main job, ~4 minutes)
#   full   quick's cases, the same two by DEM (dem-2d-rolling, dem-2d: Hertz-Mindlin, stiff
#          grains) and 3D CD (cd-3d-rolling, cd-3d: cylindrical silo; each 3D run takes 15-25
#          minutes)
#   large  the 3,000-grain 2D DEM variant of docs/examples.md (~10 minutes)
# The cases without "-rolling" are the paper's set-up as given (free disks); those with it add
# a rolling friction of 0.1, which puts > 90 % of the wall contacts on the Coulomb cone
# (silo-cd-2d-rolling.toml says why).
# Environment: SABLE_OUT, the output root (default out).
set -euo pipefail
cd "$(dirname "$0")/../.."
mode="${1:-quick}"
case "$mode" in
  quick) cases="cd-2d-rolling cd-2d" ;;
  full) cases="cd-2d-rolling cd-2d dem-2d-rolling dem-2d cd-3d-rolling cd-3d" ;;
  large) cases="dem-2d-large" ;;
  *)
    cases="$*"
    for c in $cases; do
      case "$c" in
        cd-2d | cd-2d-rolling | dem-2d | dem-2d-rolling | cd-3d | cd-3d-rolling | dem-2d-large) ;;
        *) echo "usage: $0 [quick | full | large | CASE...] with CASE among cd-2d cd-2d-rolling" \
          "dem-2d dem-2d-rolling cd-3d cd-3d-rolling dem-2d-large (got '$c')" >&2; exit 2 ;;
      esac
    done ;;
esac
bin=./build/release/bin/sable
out="${SABLE_OUT:-out}/silo-janssen"
mkdir -p "$out"

# Wall-profile bins: six mean diameters (18 mm) in 2D, so that each bin of the 350-grain silo
# holds ~10 wall contacts per snapshot and the profile averaged over the descent is smooth
# enough to test Janssen's shape; four (12 mm) for the 3D silo, whose wall is a surface with
# many more contacts per bin (docs/examples.md).
bin_for() { case "$1" in cd-3d*) echo 0.012 ;; *) echo 0.018 ;; esac; }

step_of() { "$bin" info "$1" | awk '$1 == "step" { print $2 }'; }
# An ensemble of seeds averages out the few force chains that carry a 350-grain silo's wall
# stress (docs/examples.md). DEM is cheap: four seeds. CD with rolling resistance pools eight:
# its rolling-locked arches make one seed's wall stress far patchier than DEM's (single-seed
# R^2 0.05-0.86), and four seeds fit Janssen with R^2 = 0.78 (2010-2013) or 0.96 (2014-2017).
# The scenarios' own seed is 2010.
seeds_for() {
  case "$1" in
    cd-2d-rolling) echo "2010 2011 2012 2013 2014 2015 2016 2017" ;;
    dem-2d | dem-2d-rolling) echo "2010 2011 2012 2013" ;;
    *) echo 2010 ;;
  esac
}

# Every run (a case and a seed) is independent: they share one pool of as many workers as
# there are cores, one thread each (results do not depend on the thread count), the
# single-seed cases first since they are the longest. A lone run keeps every core.
jobs=$(nproc)

run_seed() {
  local scenario="$1" run="$2" seed="$3" threads="$4"
  sed "s/^seed = .*/seed = $seed/" "$scenario" > "$run.toml"
  if ! "$bin" run "$run.toml" --out "$run" --threads "$threads" > "$run.log" 2>&1; then
    echo "error: $run.toml failed; its log:" >&2
    tail -n 20 "$run.log" >&2
    return 1
  fi
  echo "${run#"$out"/}: $(tail -n 1 "$run.log")"
}

run_all() {
  local c seed seeds runs=() run threads running=0
  for c in $cases; do
    rm -rf "${out:?}/$c"
    mkdir -p "$out/$c"
    read -r -a seeds <<< "$(seeds_for "$c")"
    for seed in "${seeds[@]}"; do
      if [ "${#seeds[@]}" -eq 1 ]; then runs=("$c $seed" "${runs[@]}"); else runs+=("$c $seed"); fi
    done
  done
  threads=$(( ${#runs[@]} > 1 ? 1 : jobs ))
  for run in "${runs[@]}"; do
    read -r c seed <<< "$run"
    if [ "$running" -ge "$jobs" ]; then wait -n; running=$((running - 1)); fi
    run_seed "examples/silo-janssen/silo-$c.toml" "$out/$c/seed-$seed" "$seed" "$threads" &
    running=$((running + 1))
  done
  while [ "$running" -gt 0 ]; do wait -n; running=$((running - 1)); done
}

# Pool the runs of one case: snapshots before the descent, during it, after it; analyse each
# set as one ensemble. run_seconds: the runs' wall times added (each on one core).
analyse_case() {
  local name="$1" dir="$out/$1" seed seeds before=() relax=() after=()
  read -r -a seeds <<< "$(seeds_for "$name")"
  for seed in "${seeds[@]}"; do
    local run="$dir/seed-$seed"
    local snaps="$run/snapshots" s1 s2
    s1=$(step_of "$snaps/end_of_stage_1.h5")
    s2=$(step_of "$snaps/end_of_stage_2.h5")
    for f in "$snaps"/step_*.h5; do
      local s=${f##*/step_}
      s=$((10#${s%.h5}))
      if [ "$s" -gt "$s1" ] && [ "$s" -lt "$s2" ]; then relax+=("$f"); fi
    done
    relax+=("$snaps/end_of_stage_2.h5")
    before+=("$snaps/end_of_stage_1.h5")
    after+=("$snaps/end_of_stage_3.h5")
  done
  sed -n 's/.* \([0-9.]*\) s wall time.*/\1/p' "$dir"/seed-*.log |
    awk '{ t += $1 } END { printf "%.1f\n", t }' > "$dir/run_seconds"
  local what="walls,janssen,polarization,stress" bin_height
  bin_height=$(bin_for "$name")
  "$bin" analyze "${before[@]}" --only "$what" --wall-bin "$bin_height" \
    --out "$dir/before" 2> "$dir/before.log"
  "$bin" analyze "${relax[@]}" --only "$what" --wall-bin "$bin_height" --out "$dir/relax" \
    2> "$dir/relax.log"
  "$bin" analyze "${after[@]}" --only "$what" --wall-bin "$bin_height" \
    --out "$dir/after" 2> "$dir/after.log"
}

bash scripts/build.sh release > /dev/null
echo "== running: $cases ($jobs at a time)"
t0=$(date +%s)
run_all
echo "== all runs done in $(( $(date +%s) - t0 )) s; analysing"
for c in $cases; do analyse_case "$c"; done
/usr/bin/python3 examples/silo-janssen/report.py "$out" $cases
echo
echo "Results: $out/summary.json and $out/silo-janssen.png;"
echo "profiles: $out/CASE/relax/janssen.csv and wall_profile_*.csv; ParaView: $out/CASE/seed-*/*.pvd"
