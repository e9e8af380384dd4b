#!/usr/bin/env bash
# LIGGGHTS 3.8 vs Sable on the same pour bed (20,000 spheres, see in.pour.liggghts / pour.toml):
# runs both codes alternately, REPEATS times, on 1 and 2 cores, and prints a markdown table of
# speed (particle-steps/s per phase), peak memory and the physics of the final dense bed.
#
# Usage: bench/peers/compare.sh [--stiff] [REPEATS] [NSETTLE] [NSTATIC]
#   defaults 3 50000 5000 (soft bed, E = 5e6 Pa, dt = 1.8e-5 s, the peer's benchmark A).
#   The same values may come from the environment: REPEATS=1 NSETTLE=300 NSTATIC=100 compare.sh
#   (positional arguments win). Other environment knobs:
#     STIFF=1         same as --stiff (see below)
#     CORES="1 2"     core counts to run (LIGGGHTS MPI ranks = Sable threads)
#     SABLE_BUILD=0   do not (re)build Sable's release preset first
#     SABLE=PATH      Sable binary (default build/release/bin/sable)
#     PEERS_OUT=DIR   where runs and tables go (default out/peers)
#     SEED=N          seed of the lattice jitter, the same for both codes (default 12345, the
#                     peer's): the floor's share of the weight depends on the bed's history,
#                     so judging it needs several seeds
#
# --stiff: E = 1.5e9 Pa (glass-like; LIGGGHTS needs `hard_particles yes`, already in the input),
#   dt = 1e-6 s, defaults NSETTLE = 20000, NSTATIC = 5000. Why: the Rayleigh time falls with
#   sqrt(E): 9.44e-5 s at 5e6 Pa, 5.45e-6 s at 1.5e9 Pa (r = 0.75 mm, rho = 2500, nu = 0.45).
#   The soft run uses 0.19 of it; dt = 1e-6 s is 0.18 of it, and LIGGGHTS' own check
#   (fix check/timestep/gran, thermo columns ts_check) reports 0.183 of the Rayleigh time and
#   0.018 of the Hertz time (at step 1000; the Hertz time shrinks only as v^-1/5 at impact
#   speeds of ~0.3 m/s), both under the 0.2 limit the input gives it. Settling the stiff bed takes ~0.2 s
#   of simulated time = 200,000 steps, ~15 min per LIGGGHTS 1-rank run, too long for 12+ runs; so
#   the stiff variant times the first 25,000 steps (25 ms: the lattice falls ~3 mm and its lowest
#   ~18 layers have landed and compacted, an impact-dominated mix of free grains and contacts).
#   Its phase (b) is not a settled bed: the physics rows are printed for information only.
#
# Runs go to $PEERS_OUT/{soft,stiff}/runs/rR_cC_{liggghts,sable}/ (wiped at start); the table to
# stdout and to $PEERS_OUT/compare.md (soft) or $PEERS_OUT/compare-stiff.md (stiff).
# Every run is wrapped by GNU time -v (each LIGGGHTS rank separately) for its peak memory.
# Only one simulation runs at a time; keep the machine otherwise idle while this runs.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cd "$repo"

stiff="${STIFF:-0}"
pos=()
for a in "$@"; do
  case "$a" in
    --stiff) stiff=1 ;;
    -h|--help) awk 'NR > 1 && !/^#/ {exit} NR > 1' "$here/$(basename "$0")"; exit 0 ;;
    *) pos+=("$a") ;;
  esac
done
if [ "$stiff" = 1 ]; then
  variant=stiff; E=1.5e9; DT=1e-6; def_settle=20000; def_static=5000
else
  variant=soft; E=5e6; DT=1.8e-5; def_settle=50000; def_static=5000
fi
REPEATS="${pos[0]:-${REPEATS:-3}}"
NSETTLE="${pos[1]:-${NSETTLE:-$def_settle}}"
NSTATIC="${pos[2]:-${NSTATIC:-$def_static}}"
CORES="${CORES:-1 2}"
SEED="${SEED:-12345}"
SABLE="${SABLE:-$repo/build/release/bin/sable}"
PEERS_OUT="${PEERS_OUT:-$repo/out/peers}"
# Absolute: each code runs from its own run directory, and the inputs are named from there.
mkdir -p "$PEERS_OUT"
PEERS_OUT="$(cd "$PEERS_OUT" && pwd)"
root="$PEERS_OUT/$variant"
if [ "$variant" = soft ]; then table="$PEERS_OUT/compare.md"; else table="$PEERS_OUT/compare-stiff.md"; fi
PY=/usr/bin/python3   # Debian's python, where python3-numpy lives (a pyenv python3 may lack numpy)

# ---------------------------------------------------------------- prerequisites
sudo=""
[ "$(id -u)" -eq 0 ] || sudo="sudo"
need=()
command -v liggghts >/dev/null 2>&1 || need+=(liggghts)
command -v mpirun >/dev/null 2>&1 || need+=(openmpi-bin)
{ [ -x "$PY" ] && "$PY" -c 'import numpy' 2>/dev/null; } || need+=(python3-numpy)
[ -x /usr/bin/time ] || need+=(time)
if [ ${#need[@]} -gt 0 ]; then
  echo "installing: ${need[*]}" >&2
  $sudo apt-get update
  DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y "${need[@]}"
fi
mpiflags=(--bind-to core)
# OpenMPI refuses to start as root without this flag (containers, CI machines).
if [ "$(id -u)" -eq 0 ]; then mpiflags=(--allow-run-as-root "${mpiflags[@]}"); fi

if [ "${SABLE_BUILD:-1}" != 0 ]; then
  echo "building Sable (release preset) ..." >&2
  bash scripts/build.sh release >/dev/null
fi
[ -x "$SABLE" ] || { echo "no Sable binary at $SABLE" >&2; exit 1; }

# ---------------------------------------------------------------- inputs
rm -rf "$root/runs"
mkdir -p "$root/runs"
"$PY" "$here/gen_lattice.py" "$root/lattice20k.data" 20000 "$SEED" >/dev/null
# CSV rows on a common divisor of both stage lengths (<= 1000, LIGGGHTS' thermo interval), so
# that series.csv has a row at the end of phase (b).
gcd() { local a=$1 b=$2 t; while [ "$b" -ne 0 ]; do t=$((a % b)); a=$b; b=$t; done; echo "$a"; }
csv=$(gcd "$(gcd "$NSETTLE" "$NSTATIC")" 1000)
[ "$csv" -ge 100 ] || echo "note: csv_interval = $csv (NSETTLE and NSTATIC share no larger divisor)" >&2
sed -e "s|^dt = .*# @DT.*|dt = $DT   # @DT|" \
    -e "s|^young = .*# @YOUNG.*|young = $E   # @YOUNG|" \
    -e "s|^steps = .*# @NSETTLE.*|steps = $NSETTLE   # @NSETTLE|" \
    -e "s|^steps = .*# @NSTATIC.*|steps = $NSTATIC   # @NSTATIC|" \
    -e "s|^csv_interval = .*# @CSV.*|csv_interval = $csv   # @CSV|" \
    -e "s|^seed = .*# @SEED.*|seed = $SEED   # @SEED|" \
    "$here/pour.toml" > "$root/pour.toml"
[ "$(grep -cE '^[a-z_]+ = [0-9.e+-]+   # @[A-Z]+$' "$root/pour.toml")" -eq 6 ] || { echo "pour.toml: tagged lines missing" >&2; exit 1; }

cat > "$root/meta.txt" <<EOF
variant=$variant
E=$E
dt=$DT
nsettle=$NSETTLE
nstatic=$NSTATIC
repeats=$REPEATS
cores=$CORES
seed=$SEED
date=$(date -u '+%F %H:%M UTC')
machine=$(lscpu | sed -n 's/^Model name: *//p' | head -1), $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), load average at start $(cut -d' ' -f1-3 /proc/loadavg)
liggghts=Debian package liggghts $(dpkg-query -W -f '${Version}' liggghts 2>/dev/null || echo '?'), $(command -v liggghts)
sable=$(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD -- src apps 2>/dev/null || echo ' + uncommitted changes in src/apps'), $SABLE
command=bench/peers/compare.sh $([ "$stiff" = 1 ] && echo '--stiff ')$REPEATS $NSETTLE $NSTATIC (CORES="$CORES")
EOF

# ---------------------------------------------------------------- runs
ligvars=(-var data "$root/lattice20k.data" -var dt "$DT" -var nsettle "$NSETTLE"
         -var nstatic "$NSTATIC" -var tag bed -var E "$E")

run_liggghts() {  # REP CORES
  local d="$root/runs/r$1_c$2_liggghts" rc=0
  mkdir -p "$d/out"
  if [ "$2" -eq 1 ]; then
    (cd "$d" && /usr/bin/time -v -o mem.rank0.txt \
      liggghts -in "$here/in.pour.liggghts" -log log.liggghts "${ligvars[@]}" -var px 1 \
      > stdout.txt 2>&1) || rc=$?
  else
    # GNU time around each rank (around mpirun it would see only mpirun itself).
    (cd "$d" && mpirun "${mpiflags[@]}" -np "$2" sh -c \
      'exec /usr/bin/time -v -o "mem.rank${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-$$}}.txt" "$0" "$@"' \
      liggghts -in "$here/in.pour.liggghts" -log log.liggghts "${ligvars[@]}" -var px "$2" \
      > stdout.txt 2>&1) || rc=$?
  fi
  if [ $rc -ne 0 ]; then echo "LIGGGHTS failed (exit $rc), $d:" >&2; tail -20 "$d/stdout.txt" >&2; exit 1; fi
  grep -E '^Loop time of' "$d/log.liggghts" | head -2 | sed 's/, finish time.*//; s/^/    /' >&2
}

run_sable() {  # REP CORES
  local d="$root/runs/r$1_c$2_sable" rc=0
  mkdir -p "$d"
  /usr/bin/time -v -o "$d/mem.rank0.txt" "$SABLE" run "$root/pour.toml" --out "$d/sim" \
    --threads "$2" > "$d/stdout.txt" 2> "$d/stderr.txt" || rc=$?
  if [ $rc -ne 0 ]; then echo "Sable failed (exit $rc), $d:" >&2; tail -20 "$d/stderr.txt" >&2; exit 1; fi
  rm -rf "$d/sim/snapshots"  # not needed for the comparison (two 1-2 MB HDF5 files per run)
  grep -E "^stage '.*' done" "$d/stderr.txt" | sed 's/ (.*//; s/^/    /' >&2
}

n=0
total=$((REPEATS * $(wc -w <<< "$CORES") * 2))
t0=$(date +%s)
for rep in $(seq 1 "$REPEATS"); do
  for c in $CORES; do
    # alternate which code goes first: L S, S L, S L, L S, L S, S L, ...
    if [ $(((rep + c) % 2)) -eq 0 ]; then order="liggghts sable"; else order="sable liggghts"; fi
    for code in $order; do
      n=$((n + 1))
      echo "[$n/$total] repeat $rep, $c core(s), $code ($(($(date +%s) - t0)) s elapsed)" >&2
      "run_$code" "$rep" "$c"
    done
  done
done
echo "all runs done in $(($(date +%s) - t0)) s" >&2

"$PY" "$here/compare.py" "$root" --out "$table"
echo "table written to $table" >&2
