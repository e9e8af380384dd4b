#!/usr/bin/env bash
# The rotating cylinder of Guillard, Forterre & Pouliquen (2015) at reduced scale
# (docs/examples.md, "Rotating cylinder"). Each case: make_scenario.py writes the scenario, the
# grains are poured around the cylinder at rest, the cylinder turns; analyze_run.py then writes
# the drag per half-turn, the turning-frame fields and the figures, study.py the depth plots.
#
#   examples/rotating-cylinder/run.sh quick   L = 10 d, h/L = 1, E = 5 MPa, 2 turns at the
#                                             inertial number 0.016 (the paper's largest)
#   examples/rotating-cylinder/run.sh depths  the quick case at h/L = 0.5, 1, 2, 3 (E = 5 MPa,
#                                             2 turns at I = 0.016 each: ~25-45 min per case on
#                                             one core, docs/examples.md)
#   examples/rotating-cylinder/run.sh stiff   the same four depths with E = 40 MPa (E* = 1.1e6),
#                                             32 snapshots per turn
#   examples/rotating-cylinder/run.sh facets  h/L = 2, E = 5 MPa with 128 facets round the
#                                             cylinder instead of 32
#   examples/rotating-cylinder/run.sh full    the study: depths, stiff and facets, each case in
#                                             its own directory under full/
#
# `run.sh MODE CASE...` runs only the named cases of MODE (e.g. `run.sh stiff h3_E4e7`) and
# leaves the study's plots to a run without names.
# Resumable: a case whose run.log says `done:` is only analysed again; a case with snapshots
# resumes from its newest one (`sable run --resume`); its scenario.toml is kept as written.
# CHUNK_SECONDS=S stops each `sable run` after S seconds of wall time with SIGINT (the run
# writes snapshots/interrupted_step_N.h5) and the script then exits 75: run it again to go on.
# Writes $SABLE_OUT/rotating-cylinder/{quick,depths,full}/CASE/ (run/, run.log, figures, summary.json)
# and the study's study.json and fig3/fig6a/fig6b figures. Two threads per run (THREADS=2).
# Environment: SABLE (default build/release/bin/sable), SABLE_OUT (default out), THREADS,
# CHUNK_SECONDS.
set -euo pipefail
cd "$(dirname "$0")/../.."
here=examples/rotating-cylinder
sable="${SABLE:-build/release/bin/sable}"
threads="${THREADS:-2}"
chunk="${CHUNK_SECONDS:-0}"
mode="${1:-}"
only=("${@:2}")
case "$mode" in
  quick | depths | stiff | facets | full) ;;
  *)
    echo "usage: $0 quick|depths|stiff|facets|full   (see the header of $0)" >&2
    exit 2
    ;;
esac
if [[ ! -x "$sable" ]]; then
  echo "$0: no executable $sable (build first: cmake --preset release && cmake --build --preset release, or set SABLE)" >&2
  exit 2
fi
if ! [[ "$chunk" =~ ^[0-9]+$ ]]; then
  echo "$0: CHUNK_SECONDS='$chunk' is not a whole number of seconds" >&2
  exit 2
fi
root="${SABLE_OUT:-out}/rotating-cylinder/$mode"
mkdir -p "$root"

# run_case NAME MAKE_SCENARIO_ARGS...: write (once), run or resume, analyse.
run_case() {
  local name="$1"
  shift
  if [[ ${#only[@]} -gt 0 && ! " ${only[*]} " =~ " $name " ]]; then
    return 0
  fi
  local dir="$root/$name"
  mkdir -p "$dir"
  if [[ ! -f "$dir/scenario.toml" && "${1:-}" == --copy ]]; then
    # A committed scenario (and its settings), as make_scenario.py wrote it.
    cp "$here/$2.toml" "$dir/scenario.toml"
    cp "$here/$2.json" "$dir/scenario.json"
  elif [[ ! -f "$dir/scenario.toml" ]]; then
    /usr/bin/python3 "$here/make_scenario.py" "$dir/scenario.toml" --out-dir "$dir/run" "$@" \
      > /dev/null
  fi
  if ! grep -q '^done:' "$dir/run.log" 2> /dev/null; then
    local args=("$dir/scenario.toml" --out "$dir/run" --threads "$threads")
    local newest=""
    if [[ -d "$dir/run/snapshots" ]]; then
      newest="$(ls -t "$dir/run/snapshots/"*.h5 2> /dev/null | head -n 1 || true)"
    fi
    if [[ -n "$newest" ]]; then
      echo "$name: resuming from $newest" >&2
      args+=(--resume "$newest" --overwrite)
    else
      echo "$name: starting" >&2
      args+=(--overwrite)
    fi
    local start=$SECONDS rc=0
    if [[ "$chunk" -gt 0 ]]; then
      timeout -s INT "$chunk" "$sable" run "${args[@]}" >> "$dir/run.log" 2>&1 || rc=$?
    else
      "$sable" run "${args[@]}" >> "$dir/run.log" 2>&1 || rc=$?
    fi
    echo "$name: sable run exit $rc after $((SECONDS - start)) s" | tee -a "$dir/wall_time.log" >&2
    if [[ $rc -eq 130 || $rc -eq 124 ]]; then
      echo "$name: stopped after its chunk; run $0 $mode again to resume" >&2
      exit 75
    elif [[ $rc -ne 0 ]]; then
      echo "$name: sable run failed (exit $rc), see $dir/run.log" >&2
      exit 1
    fi
  fi
  /usr/bin/python3 "$here/analyze_run.py" "$dir" --sable "$sable" > "$dir/analysis.log"
  echo "$name: analysed ($dir/summary.json)" >&2
}

# Every case of the study turns twice at the inertial number 0.016 (the paper's largest, the
# rate set from each case's planned depth) with dt = 0.3 Rayleigh time (docs/examples.md).
study_case() {  # study_case DEPTH YOUNG [FACETS [SNAPSHOTS_PER_TURN]]
  local facets="${3:-32}" snaps="${4:-16}" name="h$1_E$2"
  [[ "$facets" != 32 ]] && name="${name}_f${facets}"
  run_case "$name" --length-d 10 --depth "$1" --young "$2" --turns 2 --dt-fraction 0.3 \
    --inertial 0.016 --facets "$facets" --snapshots-per-turn "$snaps"
}
if [[ "$mode" == quick ]]; then
  # quick.toml: make_scenario.py --length-d 10 --depth 1 --young 5e6 --turns 2
  #   --inertial 0.016 --dt-fraction 0.3 (its header)
  run_case h1.0_E5e6 --copy quick
fi
if [[ "$mode" == depths || "$mode" == full ]]; then
  for depth in 0.5 1 2 3; do study_case "$depth" 5e6; done
fi
if [[ "$mode" == stiff || "$mode" == full ]]; then
  for depth in 0.5 1 2 3; do study_case "$depth" 4e7 32 32; done
fi
if [[ "$mode" == facets || "$mode" == full ]]; then
  study_case 2 5e6 128 32
fi
if [[ ${#only[@]} -eq 0 ]]; then
  /usr/bin/python3 "$here/study.py" "$root"
fi
