#!/usr/bin/env bash
# Force PDFs of Richefeu, El Youssoufi, Azema & Radjai (2009), "Force transmission in dry and
# wet granular media", end to end: prepare the samples, analyse their end states, fit the
# exponential tail, draw the PDFs. Writes out/force-pdf/:
#   CASE/                  the run (series.csv with the box's stresses, strain and solid
#                          fraction; ParaView files; snapshots/end_of_stage_*.h5)
#   CASE/analysis/         `sable analyze` of the end state (summary.json, force PDFs, fabric,
#                          coordination, stress, percolation, contacts.csv, particle_stress.csv)
#   CASE/run_seconds       wall time of the run
#   summary.json           per case: beta, fraction below the mean, P(0), z, ... (report.py)
#   force-pdf.png          normal-force PDFs f / <f> on lin-log axes with the exponential fits
# Usage: examples/force-pdf/run.sh [quick | full | CASE...]
#   quick         the dry DEM study: iso-dem then triaxial-dem (~3 minutes on one core)
#   full          every case: iso-dem, triaxial-dem, iso-cd, triaxial-cd, wet, iso-poly-cd
#                 (~30 minutes)
#   CASE          iso-dem, triaxial-dem (triaxial-dem resumes from iso-dem's end state, which
#                 must exist); wet (wet.toml: the unconfined and confined wet packings,
#                 out/force-pdf/wet/{summary.json, wet.png}); iso-cd (contact dynamics:
#                 iso-dem's end state relaxed with rigid grains, needs iso-dem), triaxial-cd
#                 (CD triaxial compression of iso-cd's end state, needs iso-cd); iso-poly-cd
#                 (the paper's S3: 1,000 polyhedra compacted by CD, iso-poly-prep.toml,
#                 then relaxed by CD, iso-poly-cd.toml; ~16 minutes); s3 (the same at the
#                 paper's 20,000 polyhedra, s3-prep.toml then s3-cd.toml: about 7 hours on
#                 one core, estimated; not in full)
# Environment: SABLE (the sable binary, default build/release/bin/sable, built if missing),
# SABLE_THREADS (OpenMP threads per run, default 1), SABLE_OUT (the output root, default out),
# SABLE_WET_RESUME (wet only: a snapshot at the end of wet.toml's stage 1 to continue from,
# instead of compacting; wet-variants.sh uses it for other preparations).
set -euo pipefail
cd "$(dirname "$0")/../.."
mode="${1:-quick}"
case "$mode" in
  quick) cases="iso-dem triaxial-dem" ;;
  full) cases="iso-dem triaxial-dem iso-cd triaxial-cd wet iso-poly-cd" ;;
  iso-dem | triaxial-dem | iso-cd | triaxial-cd | wet | iso-poly-cd | s3) cases="$*" ;;
  *)
    echo "usage: $0 [quick | full | iso-dem triaxial-dem iso-cd triaxial-cd wet iso-poly-cd s3]" >&2
    exit 2
    ;;
esac
SABLE="${SABLE:-build/release/bin/sable}"
threads="${SABLE_THREADS:-1}"
here=examples/force-pdf
out="${SABLE_OUT:-out}/force-pdf"
mkdir -p "$out"
if [ ! -x "$SABLE" ]; then bash scripts/build.sh release > /dev/null; fi

# Statistics exclude the grains within MARGIN of the walls (wall effects: layering and the
# walls' own forces): two mean diameters, <d> = 1.5 mm in every case here.
margin=0.003

# Run SCENARIO into out/force-pdf/NAME (resuming from SNAPSHOT if given), timing it.
run_scenario() {
  local name="$1" scenario="$2" resume="${3:-}" t0 t1
  local dir="$out/$name"
  rm -rf "$dir"
  mkdir -p "$dir"
  t0=$(date +%s.%N)
  local args=(run "$scenario" --out "$dir" --threads "$threads")
  # Another scenario continues the state (other walls, solver or stages): --accept-changes.
  if [ -n "$resume" ]; then args+=(--resume "$resume" --accept-changes); fi
  if ! "$SABLE" "${args[@]}" 2> "$dir/run.log"; then
    tail -5 "$dir/run.log" >&2
    exit 1
  fi
  t1=$(date +%s.%N)
  /usr/bin/python3 -c "print(round($t1 - $t0, 1))" > "$dir/run_seconds"
  grep -E "done|warning" "$dir/run.log" || true
}

# The analysis region of an end state: the box of series.csv's row at the snapshot's step
# (csv_interval divides the stages' lengths, so there is one) shrunk by the margin.
region_of() {
  local dir="$1" snap="$2" step
  step=$("$SABLE" info "$snap" | awk '$1 == "step" { print $2 }')
  awk -F, -v step="$step" -v m="$margin" '
    NR == 1 { for (k = 1; k <= NF; ++k) col[$k] = k; next }
    $col["step"] == step { last = $0 }
    END {
      if (last == "") {
        printf "series.csv has no row at the snapshot step %s\n", step > "/dev/stderr"
        exit 1
      }
      n = split(last, v, ",")
      printf "%.9g,%.9g,%.9g:%.9g,%.9g,%.9g\n",
        v[col["box_xlo_m"]] + m, v[col["box_ylo_m"]] + m, v[col["box_zlo_m"]] + m,
        v[col["box_xhi_m"]] - m, v[col["box_yhi_m"]] - m, v[col["box_zhi_m"]] - m
    }' "$dir/series.csv"
}

# Analyse the end state SNAPSHOT of case NAME. The CLI's force PDF and coordination use every
# contact; report.py restricts them to the region with contacts.csv (polarization) and the
# grains' positions (particle_stress.csv).
analyze_end() {
  local name="$1" snap="$2" region
  region=$(region_of "$out/$name" "$snap")
  echo "$region" > "$out/$name/region"
  if ! "$SABLE" analyze "$snap" --only forces,coordination,stress,percolation,fabric,polarization,particle-stress \
    --region "$region" --plot --out "$out/$name/analysis" 2> "$out/$name/analysis.log"; then
    tail -5 "$out/$name/analysis.log" >&2
    exit 1
  fi
}

# --- one function per case ----------------------------------------------------------------

case_iso_dem() {
  run_scenario iso-dem "$here/iso-dem.toml"
  analyze_end iso-dem "$out/iso-dem/snapshots/end_of_stage_1.h5"
}

# A case that continues another's end state: NAME SCENARIO START_SNAPSHOT END_STAGE NEEDS.
resumed_case() {
  local name="$1" scenario="$2" start="$3" stage="$4" needs="$5"
  if [ ! -f "$start" ]; then
    echo "$name starts from $start: run $needs first" >&2
    exit 2
  fi
  run_scenario "$name" "$scenario" "$start"
  analyze_end "$name" "$out/$name/snapshots/end_of_stage_$stage.h5"
}

case_triaxial_dem() {
  resumed_case triaxial-dem "$here/triaxial-dem.toml" \
    "$out/iso-dem/snapshots/end_of_stage_1.h5" 2 iso-dem
}

# The CD cases: iso-cd relaxes iso-dem's end state with contact dynamics (rigid grains, CD
# wall bodies at p_m) until equilibrium (stage 2 of iso-cd.toml); triaxial-cd compresses that
# state by CD (stage 3 of triaxial-cd.toml).
case_iso_cd() {
  resumed_case iso-cd "$here/iso-cd.toml" "$out/iso-dem/snapshots/end_of_stage_1.h5" 2 iso-dem
}

case_triaxial_cd() {
  resumed_case triaxial-cd "$here/triaxial-cd.toml" \
    "$out/iso-cd/snapshots/end_of_stage_2.h5" 3 iso-cd
}

# The polyhedra (the paper's S3): a packing compacted by CD with a short NLGS
# (iso-poly-prep.toml), then relaxed by CD with a longer one (iso-poly-cd.toml), analysed.
# The margin: two diameters of the sphere of a grain's mean volume, <d_v> = 0.87 mm (solid
# fraction 0.537 of the final 8.6 mm box over 1,000 grains), not of its bounding sphere: the
# hulls hold about a fifth of their bounding spheres' volume, and 3 mm would leave a bulk of
# 2.6 mm (35 contacts).
case_iso_poly_cd() {
  local margin=0.00175
  run_scenario iso-poly-prep "$here/iso-poly-prep.toml"
  resumed_case iso-poly-cd "$here/iso-poly-cd.toml" \
    "$out/iso-poly-prep/snapshots/end_of_stage_1.h5" 2 iso-poly-prep
}

# S3 at the paper's size: the same two scenarios with 20,000 grains (the same grains, so the
# same margin).
case_s3() {
  local margin=0.00175
  run_scenario s3-prep "$here/s3-prep.toml"
  resumed_case s3-cd "$here/s3-cd.toml" "$out/s3-prep/snapshots/end_of_stage_1.h5" 2 s3-prep
}

# The wet study (wet.toml): one run, the unconfined state at the end of stage 3 (0 Pa, S6) and
# the confined one at the end of stage 4 (100 Pa, S7), each analysed with f0 = kappa R_max as
# the reference force; wet_report.py writes wet/summary.json and wet/wet.png.
case_wet() {
  run_scenario wet "$here/wet.toml" "${SABLE_WET_RESUME:-}"
  local f0 label snap
  f0=$(/usr/bin/python3 -c "import math; print(2 * math.pi * 0.0728 * 1.0e-3)")
  for label in 0pa 100pa; do
    snap="$out/wet/snapshots/end_of_stage_$([ "$label" = 0pa ] && echo 3 || echo 4).h5"
    region=$(region_of "$out/wet" "$snap")
    echo "$region" > "$out/wet/region-$label"
    if ! "$SABLE" analyze "$snap" --only forces,coordination,particle-stress,percolation,polarization \
      --region "$region" --reference-force "$f0" --plot --out "$out/wet/analysis-$label" \
      2> "$out/wet/analysis-$label.log"; then
      tail -5 "$out/wet/analysis-$label.log" >&2
      exit 1
    fi
  done
  /usr/bin/python3 "$here/wet_report.py" "$out"
}

for c in $cases; do
  echo "== $c"
  "case_${c//-/_}"
done
/usr/bin/python3 "$here/report.py" "$out" $cases
echo
echo "Results: $out/summary.json and $out/force-pdf.png; per case: $out/CASE/analysis/"
