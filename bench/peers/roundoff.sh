#!/usr/bin/env bash
# One bed, many trajectories: the pour bed of one seed, settled by each code several times with
# only the round-off changed, to see how far the physics of "the same bed" moves on its own.
#
# compare.sh judges the settled bed of each code against LIGGGHTS' beds of the same seed; but
# LIGGGHTS' 1-rank and 2-rank beds of one seed are two trajectories that part on round-off, and
# the floor's share of the weight differs between them (-2.2 % for seed 12345). seeds.sh shows
# the spread over seeds (other beds); this script shows it over trajectories of ONE bed, for
# both codes, so that Sable's beds can be set against LIGGGHTS' own spread on that bed.
#
# Usage: bench/peers/roundoff.sh [SEED]        (default 12345, the peer's bed)
#   Environment: PEERS_OUT (default out/peers-roundoff), SABLE (binary), SABLE_BUILD=0 (do not
#   rebuild), JOBS (one-core runs at once, default nproc), RESUME=1 (keep finished runs),
#   NSETTLE / NSTATIC (default 50000 / 5000: compare.sh's soft bed).
#
# The trajectories. Each changes the order in which floating-point sums are made and nothing
# else: the contact law, the parameters, the time step and the neighbour skin are those of
# compare.sh's soft bed.
#   LIGGGHTS 3.8, 1 rank: its atoms are sorted in memory by spatial bin every 1000 steps
#     (atom_modify sort, default: bins of half the neighbour cutoff); a grain's pair forces are
#     summed in its neighbour list's order, which follows the atoms' order. Variants: the input
#     as is (compare.sh's 1-rank bed), no sort, a sort every 100, 250, 500, 750, 1250, 1500,
#     2000, 3000 and 5000 steps, bins of 0.75, 1.5 and 2 mm (the default bins are 1 mm, half of
#     2 r + skin: `sort 1000 0.001` gives the input's bed bit for bit).
#   LIGGGHTS 3.8, 2 ranks: the domain cut in x (compare.sh's 2-rank bed) and in y (`processors
#     1 2 1`): the ranks sum the forces on the ghost grains of their boundary in other orders.
#   Sable, 1 thread (its bed is the same for any thread count): reorder_every = "auto" (the
#     default: compare.sh's bed), 0 (never sorted) and 1-13 and 17 (the grains' slots sorted
#     by cell at other builds; the pairs, and so each grain's sum, follow the slots).
# No timing is measured (one-core runs share the machine JOBS at a time; a 2-rank run runs
# alone afterwards). Output: PEERS_OUT/CODE-VARIANT/soft/ (compare.sh's layout) and the table
# PEERS_OUT/roundoff.md (bench/peers/roundoff.py).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
repo="$(cd "$here/../.." && pwd)"
cd "$repo"
PY=/usr/bin/python3  # Debian's python, where python3-numpy lives
SABLE="${SABLE:-$repo/build/release/bin/sable}"
E=5e6
DT=1.8e-5
NSETTLE="${NSETTLE:-50000}"
NSTATIC="${NSTATIC:-5000}"
# shellcheck source=lib.sh
source "$here/lib.sh"

# The variants: NAME CODE CORES CHANGE. CHANGE, for LIGGGHTS: the line put after the input's
# `atom_modify map array`, ':' for ' ' (or "-": none; "cut-y": `processors 1 2 1`); for Sable:
# the value of reorder_every ("-": the scenario as is).
VARIANTS=(
  "liggghts-default liggghts 1 -"
  "liggghts-sort-off liggghts 1 atom_modify:sort:0:0.0"
  "liggghts-sort-500 liggghts 1 atom_modify:sort:500:0.0"
  "liggghts-sort-2000 liggghts 1 atom_modify:sort:2000:0.0"
  "liggghts-bin-1.5mm liggghts 1 atom_modify:sort:1000:0.0015"
  "liggghts-sort-250 liggghts 1 atom_modify:sort:250:0.0"
  "liggghts-sort-750 liggghts 1 atom_modify:sort:750:0.0"
  "liggghts-sort-3000 liggghts 1 atom_modify:sort:3000:0.0"
  "liggghts-sort-100 liggghts 1 atom_modify:sort:100:0.0"
  "liggghts-sort-1250 liggghts 1 atom_modify:sort:1250:0.0"
  "liggghts-sort-1500 liggghts 1 atom_modify:sort:1500:0.0"
  "liggghts-sort-5000 liggghts 1 atom_modify:sort:5000:0.0"
  "liggghts-bin-2mm liggghts 1 atom_modify:sort:1000:0.002"
  "liggghts-bin-0.75mm liggghts 1 atom_modify:sort:1000:0.00075"
  "liggghts-2ranks-x liggghts 2 -"
  "liggghts-2ranks-y liggghts 2 cut-y"
  "sable-auto sable 1 -"
  "sable-r0 sable 1 0"
  "sable-r1 sable 1 1"
  "sable-r3 sable 1 3"
  "sable-r7 sable 1 7"
  "sable-r13 sable 1 13"
  "sable-r2 sable 1 2"
  "sable-r4 sable 1 4"
  "sable-r5 sable 1 5"
  "sable-r9 sable 1 9"
  "sable-r11 sable 1 11"
  "sable-r17 sable 1 17"
  "sable-r6 sable 1 6"
  "sable-r8 sable 1 8"
  "sable-r10 sable 1 10"
  "sable-r12 sable 1 12"
)

# Worker mode (one run; called by xargs below): --job SEED NAME CODE CORES CHANGE
if [ "${1:-}" = --job ]; then
  seed=$2 name=$3 code=$4 cores=$5 change=${6//:/ }
  root="$PEERS_OUT/$name/soft"
  d="$root/runs/r1_c${cores}_$code"
  if [ "${RESUME:-0}" = 1 ] && peers_run_finished "$d" "$code"; then exit 0; fi
  rm -rf "$d"
  mkdir -p "$root/runs"
  peers_inputs "$root" "$seed" "$E" "$DT" "$NSETTLE" "$NSTATIC"
  if [ "$code" = liggghts ]; then
    input="$root/in.pour.liggghts"
    # shellcheck disable=SC2016  # ${px} is LIGGGHTS' own variable, kept as it is
    case "$change" in
      -) cp "$here/in.pour.liggghts" "$input" ;;
      cut-y) sed 's/^processors      ${px} 1 1$/processors      1 ${px} 1/' \
               "$here/in.pour.liggghts" > "$input" ;;
      *) sed "s/^atom_modify     map array$/&\n$change/" "$here/in.pour.liggghts" > "$input" ;;
    esac
    if [ "$change" != - ] && cmp -s "$input" "$here/in.pour.liggghts"; then
      echo "roundoff.sh: $name: the change '$change' did not apply to in.pour.liggghts" >&2
      exit 1
    fi
    flags=(--bind-to "${MPI_BIND:-none}")
    [ "$(id -u)" -ne 0 ] || flags=(--allow-run-as-root "${flags[@]}")
    PEERS_LIGGGHTS_IN="$input" peers_run_liggghts "$root" "$d" "$cores" "$E" "$DT" "$NSETTLE" \
      "$NSTATIC" "${flags[@]}"
  else
    if [ "$change" != - ]; then  # into [simulation], before its (first) seed line
      sed -i "0,/^seed = /s//reorder_every = $change\n&/" "$root/pour.toml"
      grep -q "^reorder_every = $change$" "$root/pour.toml" ||
        { echo "roundoff.sh: $name: reorder_every did not go into $root/pour.toml" >&2; exit 1; }
    fi
    peers_run_sable "$root" "$d" "$cores"
  fi
  echo "  done: $name, $(date -u +%T)" >&2
  exit 0
fi

SEED="${1:-12345}"
[[ "$SEED" =~ ^[0-9]+$ ]] || { echo "roundoff.sh: seed '$SEED' is not a non-negative integer" >&2; exit 2; }
JOBS="${JOBS:-$(nproc)}"
PEERS_OUT="${PEERS_OUT:-$repo/out/peers-roundoff}"
mkdir -p "$PEERS_OUT"
PEERS_OUT="$(cd "$PEERS_OUT" && pwd)"
export PEERS_OUT SABLE RESUME="${RESUME:-0}" NSETTLE NSTATIC

peers_need_tools
if [ "${SABLE_BUILD:-1}" != 0 ]; then
  echo "building Sable (release preset) ..." >&2
  bash scripts/build.sh release >/dev/null
fi
[ -x "$SABLE" ] || { echo "no Sable binary at $SABLE" >&2; exit 1; }
cat > "$PEERS_OUT/meta.txt" <<META
seed=$SEED
E=$E
dt=$DT
nsettle=$NSETTLE
nstatic=$NSTATIC
date=$(date -u '+%F %H:%M UTC')
liggghts=Debian package liggghts $(dpkg-query -W -f '${Version}' liggghts 2>/dev/null || echo '?')
sable=$(git rev-parse --short HEAD 2>/dev/null || echo '?')$(git diff --quiet HEAD -- src apps 2>/dev/null || echo ' + uncommitted changes in src/apps'), $SABLE
META

jobs=()
for v in "${VARIANTS[@]}"; do jobs+=("$SEED $v"); done
echo "${#jobs[@]} runs of seed $SEED ..." >&2
t0=$(date +%s)
failed=0
# The one-core runs in a pool, LIGGGHTS' (the longest) first; then the 2-rank runs one at a time.
printf '%s\n' "${jobs[@]}" | awk '$4 == 1' | xargs -P "$JOBS" -L 1 bash "$here/roundoff.sh" --job ||
  failed=1
printf '%s\n' "${jobs[@]}" | awk '$4 > 1' | MPI_BIND=core xargs -P 1 -L 1 bash "$here/roundoff.sh" --job ||
  failed=1
echo "all runs done in $(($(date +%s) - t0)) s" >&2
roots=()
for v in "${VARIANTS[@]}"; do roots+=("$PEERS_OUT/${v%% *}/soft"); done
"$PY" "$here/roundoff.py" "${roots[@]}" --meta "$PEERS_OUT/meta.txt" --out "$PEERS_OUT/roundoff.md" ||
  failed=1
echo "table written to $PEERS_OUT/roundoff.md" >&2
[ "$failed" -eq 0 ] || { echo "some runs failed: the table says which" >&2; exit 1; }
