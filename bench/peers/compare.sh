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

# shellcheck source=lib.sh
source "$here/lib.sh"

# ---------------------------------------------------------------- prerequisites
peers_need_tools
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
peers_inputs "$root" "$SEED" "$E" "$DT" "$NSETTLE" "$NSTATIC"

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
run_liggghts() {  # REP CORES
  local d="$root/runs/r$1_c$2_liggghts"
  peers_run_liggghts "$root" "$d" "$2" "$E" "$DT" "$NSETTLE" "$NSTATIC" "${mpiflags[@]}" || exit 1
  grep -E '^Loop time of' "$d/log.liggghts" | head -2 | sed 's/, finish time.*//; s/^/    /' >&2
}

run_sable() {  # REP CORES
  local d="$root/runs/r$1_c$2_sable"
  peers_run_sable "$root" "$d" "$2" || exit 1
  grep -E "^stage '.*' done" "$d/stderr.txt" | sed 's/ (.*//; s/^/    /' >&2
}

n=0
total=$((REPEATS * $(wc -w <<< "$CORES") * 2))
t0=$(date +%s)
for rep in $(seq 1 "$REPEATS"); do
  # A snake through the core counts, so that every comparison the targets make is between runs
  # back to back: repeat 1 runs L1 S1 S2 L2, repeat 2 L2 S2 S1 L1, and so on (L = LIGGGHTS,
  # S = Sable, the digit the cores). Each code's speed at one core count is timed next to the
  # other's, and Sable's two threads next to its one thread: the VM's speed drifts by 10-50 %
  # over minutes, and in the order used before this one (L1 S1 S2 L2, then
  # S1 L1 L2 S2) every other repeat had S1 and S2 two LIGGGHTS runs apart.
  # Who goes first at a core count alternates between repeats.
  seq_cores=$CORES
  [ $((rep % 2)) -eq 0 ] && seq_cores=$(tr ' ' '\n' <<< "$CORES" | grep . | tac | tr '\n' ' ')
  i=0
  for c in $seq_cores; do
    if [ $((i % 2)) -eq 0 ]; then order="liggghts sable"; else order="sable liggghts"; fi
    i=$((i + 1))
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
