#!/usr/bin/env bash
# The physics of the pour bed over many seeds, LIGGGHTS 3.8 against Sable: is Sable's settled bed
# a bed LIGGGHTS could have made? The floor's share of the weight is set by how much friction the
# side walls happen to carry when the bed comes to rest, a draw that changes with any round-off
# (LIGGGHTS on 1 and on 2 ranks gives two different beds), so one bed per code is one draw and
# a 3 % bound on it is a bet. This script makes the distribution of each code and compares them.
#
# Usage: bench/peers/seeds.sh [SEED ...]     (default: 12345 1 2 3 4 5 6 7 8 9 10 11)
#   For each seed (the lattice jitter, the same for both codes; 12345 is the peer's bed): LIGGGHTS
#   on 1 and on 2 MPI ranks (two beds: the ranks sum forces in other orders) and Sable on 1 thread
#   (its bed does not depend on the thread count: DemBasics.ThreadCountDoesNotChangeABit).
#   Environment: JOBS (one-core runs at once, default nproc), PEERS_OUT (default
#   out/peers-seeds), SABLE, SABLE_BUILD=0 (do not rebuild), NSETTLE / NSTATIC (default
#   50000 / 5000, compare.sh's soft bed), RANKS (LIGGGHTS rank counts, default "1 2"),
#   RESUME=1 (keep the runs that finished, run only the others).
# The one-core runs share the machine, JOBS at a time; a run on several ranks runs alone
# afterwards (MPI ranks wait by spinning: two such runs on two cores take 4-5 times as long).
# Timing is NOT measured here; bench/peers/compare.sh does that.
# Output: PEERS_OUT/seed-S/soft/ (compare.sh's layout, one repeat) and the table
# PEERS_OUT/seeds.md (bench/peers/seeds.py).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cd "$repo"
PY=/usr/bin/python3   # Debian's python, where python3-numpy lives
SABLE="${SABLE:-$repo/build/release/bin/sable}"
E=5e6
DT=1.8e-5
NSETTLE="${NSETTLE:-50000}"
NSTATIC="${NSTATIC:-5000}"
# shellcheck source=lib.sh
source "$here/lib.sh"

# Worker mode (one run; called by xargs below): --job ROOT CODE CORES
if [ "${1:-}" = --job ]; then
  root=$2 code=$3 cores=$4
  d="$root/runs/r1_c${cores}_$code"
  t0=$(date +%s)
  if [ "${RESUME:-0}" = 1 ] && peers_run_finished "$d" "$code"; then exit 0; fi
  rm -rf "$d"
  if [ "$code" = liggghts ]; then
    # One-rank runs share the cores with others, so no binding; root needs OpenMPI's consent.
    flags=(--bind-to "${MPI_BIND:-none}")
    [ "$(id -u)" -ne 0 ] || flags=(--allow-run-as-root "${flags[@]}")
    peers_run_liggghts "$root" "$d" "$cores" "$E" "$DT" "$NSETTLE" "$NSTATIC" "${flags[@]}"
  else
    peers_run_sable "$root" "$d" "$cores"
  fi
  echo "  done: $(basename "$(dirname "$root")") $code on $cores core(s), $(($(date +%s) - t0)) s" >&2
  exit 0
fi

seeds=("$@")
[ ${#seeds[@]} -gt 0 ] || seeds=(12345 1 2 3 4 5 6 7 8 9 10 11)
for s in "${seeds[@]}"; do
  [[ "$s" =~ ^[0-9]+$ ]] || { echo "seeds.sh: seed '$s' is not a non-negative integer" >&2; exit 2; }
done
JOBS="${JOBS:-$(nproc)}"
RANKS="${RANKS:-1 2}"
PEERS_OUT="${PEERS_OUT:-$repo/out/peers-seeds}"
mkdir -p "$PEERS_OUT"
PEERS_OUT="$(cd "$PEERS_OUT" && pwd)"

peers_need_tools
if [ "${SABLE_BUILD:-1}" != 0 ]; then
  echo "building Sable (release preset) ..." >&2
  bash scripts/build.sh release >/dev/null
fi
[ -x "$SABLE" ] || { echo "no Sable binary at $SABLE" >&2; exit 1; }

jobs_file="$PEERS_OUT/jobs.txt"
: > "$jobs_file"
for s in "${seeds[@]}"; do
  root="$PEERS_OUT/seed-$s/soft"
  [ "${RESUME:-0}" = 1 ] || rm -rf "$root/runs"
  mkdir -p "$root/runs"
  peers_inputs "$root" "$s" "$E" "$DT" "$NSETTLE" "$NSTATIC"
  cat > "$root/meta.txt" <<META
variant=soft
E=$E
dt=$DT
nsettle=$NSETTLE
nstatic=$NSTATIC
repeats=1
seed=$s
date=$(date -u '+%F %H:%M UTC')
liggghts=Debian package liggghts $(dpkg-query -W -f '${Version}' liggghts 2>/dev/null || echo '?')
sable=$(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD -- src apps 2>/dev/null || echo ' + uncommitted changes in src/apps')
META
  for r in $RANKS; do echo "$root liggghts $r" >> "$jobs_file"; done
  echo "$root sable 1" >> "$jobs_file"
done
# One-core runs in a pool, the longest (LIGGGHTS) first so that the pool ends together; then
# the multi-rank runs, one at a time, each bound to its cores.
sort -k2,2 -k3,3n -s "$jobs_file" -o "$jobs_file"
export RESUME="${RESUME:-0}"
echo "$(wc -l < "$jobs_file") runs for ${#seeds[@]} seed(s) ..." >&2
t0=$(date +%s)
failed=0
awk '$3 == 1' "$jobs_file" | xargs -P "$JOBS" -L 1 bash "$here/seeds.sh" --job || failed=1
echo "one-core runs done in $(($(date +%s) - t0)) s" >&2
awk '$3 > 1' "$jobs_file" | MPI_BIND=core xargs -P 1 -L 1 bash "$here/seeds.sh" --job || failed=1
echo "all runs done in $(($(date +%s) - t0)) s" >&2

roots=()
for s in "${seeds[@]}"; do roots+=("$PEERS_OUT/seed-$s/soft"); done
"$PY" "$here/seeds.py" "${roots[@]}" --out "$PEERS_OUT/seeds.md"
echo "table written to $PEERS_OUT/seeds.md" >&2
[ "$failed" -eq 0 ] || { echo "some runs failed: their rows in the table say why" >&2; exit 1; }
