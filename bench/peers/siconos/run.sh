#!/usr/bin/env bash
# Sable's `fc3d` solver vs Siconos numerics (NSGS and a handful of other solvers) on the
# frictional-contact problems of ../shared/data/fc3d and fc2d, at tolerances 1e-4 and 1e-6.
# Every answer, Sable's and Siconos', is judged by one error routine (siconos_fc.c, indep_error).
#
# Usage: bench/peers/siconos/run.sh [REPEATS]      (default 3)
#   Environment knobs:
#     SABLE=PATH     Sable binary (default /tmp/sable-bench, copied from build/release/bin/sable
#                    if missing, so that a rebuild of the checkout does not change it mid-run)
#     WORK=DIR       scratch: the driver's build, Sable's reactions (default /tmp/siconos-bench)
#     TIMEOUT=S      wall-clock limit of one solve, Siconos or Sable (default 60)
#     DATA=DIR       problem root holding fc3d/ and fc2d/ (default ../shared/data beside the repository)
#     PROBLEMS=GLOB  only problem files whose name matches, extglob (default: all)
#     INPROC=K       solves of one problem in one process, Sable and Siconos alike (default 10):
#                    the first is the cold time, the median of the others the warm time;
#                    further solves only while the process's solves took < 0.1 s in all
# Writes results.md (the tables) and raw.tsv (one line per run) next to this script.
set -euo pipefail
shopt -s extglob  # PROBLEMS may be an extended glob: '@(Rover*|NESpheres*)'

here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../../.." && pwd)
REPEATS=${1:-${REPEATS:-3}}
SABLE=${SABLE:-/tmp/sable-bench}
WORK=${WORK:-/tmp/siconos-bench}
TIMEOUT=${TIMEOUT:-60}
DATA=${DATA:-$root/../shared/data}
PROBLEMS=${PROBLEMS:-*}
INPROC=${INPROC:-10}
PY=/usr/bin/python3
TOLS="1e-4 1e-6"
# Candidates for "Siconos best"; NSGS is one of them. The 2D ones are all fc2d offers
# besides the legacy Latin/projection variants that the 4.4 driver does not expose by id.
SOLVERS_3D="NSGS NSN_AC NSN_AC_TEST NSN_FB NSN_NM PROX ADMM"
SOLVERS_2D="NSGS CPG LEMKE ENUM"

"$here/setup.sh" >/dev/null
started=$(date -u '+%Y-%m-%d %H:%M UTC')
load_start=$(cut -d' ' -f1-3 /proc/loadavg)
mkdir -p "$WORK"
: >"$WORK/load.samples"
if [ ! -x "$SABLE" ]; then cp "$root/build/release/bin/sable" "$SABLE"; fi

# The driver: one C file, Siconos' headers include each other by bare name.
driver=$WORK/siconos_fc
gcc -O2 -std=c11 -D_POSIX_C_SOURCE=199309L -Wall -Wextra \
  -I/usr/include/siconos -I/usr/include/siconos/numerics \
  -o "$driver" "$here/siconos_fc.c" -lsiconos_numerics -lm

siconos_version=$(dpkg -s libsiconos-numerics7 | sed -n 's/^Version: //p')
raw=$here/raw.tsv
printf 'problem\tdim\tcontacts\ttol\tcode\tsolver\trepeat\tstatus\tinfo\titerations\tseconds\tself_error\tindep_error\twarm_seconds\tsolves\n' >"$raw"

# One row of raw.tsv. status: ok | timeout (S s) | crash (rc N) | exit N (Sable) | unreadable
# (Siconos cannot read the file: no independent error for anyone on it)
row() { local IFS=$'\t'; echo "$*" >>"$raw"; }

# The problem list, and what Siconos' reader makes of each one.
declare -A dim nc
files=()
for f in "$DATA"/fc3d/*.dat "$DATA"/fc3d/*.hdf5 "$DATA"/fc2d/*.dat; do
  # shellcheck disable=SC2254  # PROBLEMS is a pattern on purpose
  case "$(basename "$f")" in $PROBLEMS) ;; *) continue ;; esac
  files+=("$f")
  if info=$("$driver" "$f" --info 2>/dev/null); then
    read -r _ "dim[$f]" "nc[$f]" _ <<<"$info"
  else
    dim[$f]=""  # Siconos' reader aborts (FCLIB .hdf5: this build has no FCLIB)
    # its contact count from Sable (one sweep; Sable exits 1 as it stops short: expected)
    nc[$f]=$({ timeout "$TIMEOUT" "$SABLE" fc3d "$f" --max-iterations 1 --newton-iterations 0 \
      2>/dev/null || true; } | sed -n 's/^ *contacts *//p')
  fi
done

[ ${#files[@]} -gt 0 ] || { echo "run.sh: no problem file matches PROBLEMS=$PROBLEMS" >&2; exit 1; }

# Pairs (problem|solver|tol) that timed out or crashed are not run again: one line says so.
declare -A skip

for ((rep = 1; rep <= REPEATS; rep++)); do
  for f in "${files[@]}"; do
    name=$(basename "$f")
    echo "repeat $rep/$REPEATS  $name" >&2
    cut -d' ' -f1 /proc/loadavg >>"$WORK/load.samples" # how busy the machine was, for the record
    for tol in $TOLS; do
      # --- Sable: its own iteration count and solve time; the judge re-reads its reactions.
      out=$WORK/sable.out reac=$WORK/sable.reactions
      rm -f "$reac"
      set +e
      timeout "$TIMEOUT" "$SABLE" fc3d "$f" --tolerance "$tol" --reactions "$reac" \
        --repeat "$INPROC" >"$out" 2>&1
      rc=$?
      set -e
      iters=$(sed -n 's/^ *iterations *//p' "$out" | tr '\t' ' ')
      secs=$(sed -n 's/^ *time *\([0-9.eE+-]*\) s$/\1/p' "$out")
      self=$(sed -n 's/^ *residual *//p' "$out")
      # "warm time   0.000002 s (median of 9 more solves)": absent after a single solve
      warm=$(sed -n 's/^ *warm time *\([0-9.eE+-]*\) s.*/\1/p' "$out")
      solves=$(sed -n 's/^ *warm time .*median of \([0-9]*\) more.*/\1/p' "$out")
      solves=$((${solves:-0} + 1))
      # Sable exits 1 when it stops short of the tolerance but still reports and writes its
      # answer: that is a finished run (the judge says "not converged"), not a failure.
      status=ok indep=""
      [ -n "$secs" ] || status="exit $rc"
      [ $rc -eq 124 ] && status="timeout (${TIMEOUT} s)"
      if [ -n "${dim[$f]}" ] && [ -s "$reac" ]; then
        indep=$("$driver" "$f" --reactions "$reac" | sed -n 's/^REACTIONS //p')
      fi
      row "$name" "${dim[$f]:-3}" "${nc[$f]}" "$tol" sable sable "$rep" "$status" "$rc" \
        "$iters" "$secs" "$self" "$indep" "${warm:-0}" "$solves"

      # --- Siconos: every candidate solver, one process per solve.
      if [ -z "${dim[$f]}" ]; then
        row "$name" 3 "${nc[$f]}" "$tol" siconos all "$rep" unreadable "" "" "" "" ""
        continue
      fi
      if [ "${dim[$f]}" = 2 ]; then solvers=$SOLVERS_2D; else solvers=$SOLVERS_3D; fi
      for s in $solvers; do
        key="$f|$s|$tol"
        [ -z "${skip[$key]:-}" ] || continue
        set +e
        timeout "$TIMEOUT" "$driver" "$f" --solver "$s" --tol "$tol" --repeat "$INPROC" \
          >"$WORK/siconos.out" 2>&1
        rc=$?
        set -e
        res=$(grep '^RESULT ' "$WORK/siconos.out" || true) # Siconos may print more lines
        if [ $rc -eq 0 ] && [ -n "$res" ]; then
          read -r _ _ _ info iters secs self indep warm solves <<<"$res"
          row "$name" "${dim[$f]}" "${nc[$f]}" "$tol" siconos "$s" "$rep" ok "$info" \
            "$iters" "$secs" "$self" "$indep" "$warm" "$solves"
        else
          status="crash (rc $rc)"
          [ $rc -eq 124 ] && status="timeout (${TIMEOUT} s)"
          row "$name" "${dim[$f]}" "${nc[$f]}" "$tol" siconos "$s" "$rep" "$status" "" "" "" "" ""
          skip[$key]=1
          # a solver too slow for 1e-4 is slower still for 1e-6: do not wait for it twice
          [ $rc -eq 124 ] && [ "$tol" = 1e-4 ] && skip["$f|$s|1e-6"]=1
        fi
      done
    done
  done
done

cmd="bench/peers/siconos/run.sh $REPEATS"
[ "$INPROC" = 10 ] || cmd="INPROC=$INPROC $cmd"
[ "$TIMEOUT" = 60 ] || cmd="TIMEOUT=$TIMEOUT $cmd"
[ "$PROBLEMS" = "*" ] || cmd="PROBLEMS='$PROBLEMS' $cmd"
"$PY" "$here/table.py" "$raw" "$here/results.md" \
  --machine "$(nproc) cores, $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo | head -1)" \
  --date "$started to $(date -u '+%H:%M UTC')" \
  --load "$load_start; $(cut -d' ' -f1-3 /proc/loadavg) (1-min load at each problem's start: \
min $(sort -g "$WORK/load.samples" | head -1), max $(sort -g "$WORK/load.samples" | tail -1))" \
  --siconos "libsiconos-numerics7 $siconos_version (Debian)" \
  --sable "$("$SABLE" --version), binary $SABLE (sha256 $(sha256sum "$SABLE" | cut -c1-12), \
$(stat -c %y "$SABLE" | cut -c1-16))" \
  --command "$cmd" --repeats "$REPEATS" --timeout "$TIMEOUT" --inproc "$INPROC"
cat "$here/results.md"
