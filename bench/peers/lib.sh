# shellcheck shell=bash
# Shared by bench/peers/compare.sh (timing) and bench/peers/seeds.sh (the beds' physics over
# seeds): the peer's inputs for one seed and one run of each code. Source it; it defines
# functions only. Callers set: here (this folder), PY (a python3 with numpy), SABLE (binary).
: "${here:?bench/peers/lib.sh: the caller must set here}" "${PY:?bench/peers/lib.sh: the caller must set PY}"

# peers_need_tools: install LIGGGHTS, OpenMPI, numpy and GNU time if any is missing.
peers_need_tools() {
  local sudo="" need=()
  [ "$(id -u)" -eq 0 ] || sudo="sudo"
  command -v liggghts >/dev/null 2>&1 || need+=(liggghts)
  command -v mpirun >/dev/null 2>&1 || need+=(openmpi-bin)
  { [ -x "$PY" ] && "$PY" -c 'import numpy' 2>/dev/null; } || need+=(python3-numpy)
  [ -x /usr/bin/time ] || need+=(time)
  if [ ${#need[@]} -gt 0 ]; then
    echo "installing: ${need[*]}" >&2
    $sudo apt-get update
    DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y "${need[@]}"
  fi
}

# peers_inputs ROOT SEED E DT NSETTLE NSTATIC: the lattice (ROOT/lattice20k.data) and Sable's
# scenario (ROOT/pour.toml) for one seed, both codes starting from the same positions.
peers_inputs() {
  local root=$1 seed=$2 E=$3 dt=$4 nsettle=$5 nstatic=$6 csv
  mkdir -p "$root"
  "$PY" "$here/gen_lattice.py" "$root/lattice20k.data" 20000 "$seed" >/dev/null
  # CSV rows on a common divisor of both stage lengths (<= 1000, LIGGGHTS' thermo interval), so
  # that series.csv has a row at the end of phase (b).
  csv=$(peers_gcd "$(peers_gcd "$nsettle" "$nstatic")" 1000)
  [ "$csv" -ge 100 ] || echo "note: csv_interval = $csv (NSETTLE and NSTATIC share no larger divisor)" >&2
  sed -e "s|^dt = .*# @DT.*|dt = $dt   # @DT|" \
      -e "s|^young = .*# @YOUNG.*|young = $E   # @YOUNG|" \
      -e "s|^steps = .*# @NSETTLE.*|steps = $nsettle   # @NSETTLE|" \
      -e "s|^steps = .*# @NSTATIC.*|steps = $nstatic   # @NSTATIC|" \
      -e "s|^csv_interval = .*# @CSV.*|csv_interval = $csv   # @CSV|" \
      -e "s|^seed = .*# @SEED.*|seed = $seed   # @SEED|" \
      "$here/pour.toml" > "$root/pour.toml"
  if [ "$(grep -cE '^[a-z_]+ = [0-9.e+-]+   # @[A-Z]+$' "$root/pour.toml")" -ne 6 ]; then
    echo "$here/pour.toml: the six lines tagged # @NAME are not all there" >&2
    return 1
  fi
}

peers_gcd() { local a=$1 b=$2 t; while [ "$b" -ne 0 ]; do t=$((a % b)); a=$b; b=$t; done; echo "$a"; }

# peers_run_liggghts ROOT DIR CORES E DT NSETTLE NSTATIC [MPI flags...]: one LIGGGHTS run in DIR
# (log.liggghts, out/bed.dump, mem.rank*.txt), GNU time around each rank for its peak memory.
# The input is $here/in.pour.liggghts, or PEERS_LIGGGHTS_IN when set (roundoff.sh's variants).
peers_run_liggghts() {
  local root=$1 d=$2 cores=$3 rc=0 input="${PEERS_LIGGGHTS_IN:-$here/in.pour.liggghts}"
  local vars=(-var data "$root/lattice20k.data" -var dt "$5" -var nsettle "$6" -var nstatic "$7"
              -var tag bed -var E "$4" -var px "$cores")
  shift 7
  mkdir -p "$d/out"
  if [ "$cores" -eq 1 ]; then
    (cd "$d" && /usr/bin/time -v -o mem.rank0.txt \
      liggghts -in "$input" -log log.liggghts "${vars[@]}" > stdout.txt 2>&1) || rc=$?
  else
    # GNU time around each rank (around mpirun it would see only mpirun itself).
    (cd "$d" && mpirun "$@" -np "$cores" sh -c \
      'exec /usr/bin/time -v -o "mem.rank${OMPI_COMM_WORLD_RANK:-${PMI_RANK:-$$}}.txt" "$0" "$@"' \
      liggghts -in "$input" -log log.liggghts "${vars[@]}" > stdout.txt 2>&1) || rc=$?
  fi
  if [ $rc -ne 0 ]; then echo "LIGGGHTS failed (exit $rc), $d:" >&2; tail -20 "$d/stdout.txt" >&2; return 1; fi
}

# peers_run_sable ROOT DIR CORES: one Sable run of ROOT/pour.toml in DIR (sim/, stderr.txt,
# mem.rank0.txt).
peers_run_sable() {
  local root=$1 d=$2 cores=$3 rc=0
  mkdir -p "$d"
  /usr/bin/time -v -o "$d/mem.rank0.txt" "$SABLE" run "$root/pour.toml" --out "$d/sim" \
    --threads "$cores" > "$d/stdout.txt" 2> "$d/stderr.txt" || rc=$?
  if [ $rc -ne 0 ]; then echo "Sable failed (exit $rc), $d:" >&2; tail -20 "$d/stderr.txt" >&2; return 1; fi
  rm -rf "$d/sim/snapshots"  # not needed for the comparison (two 1-2 MB HDF5 files per run)
}

# peers_run_finished DIR CODE: the run in DIR got to its end (its final bed is written); for
# RESUME=1 in seeds.sh and roundoff.sh.
peers_run_finished() {
  if [ "$2" = liggghts ]; then
    grep -q FINAL_DUMP_WRITTEN "$1/log.liggghts" 2>/dev/null && [ -s "$1/out/bed.dump" ]
  else
    grep -q "state hash" "$1/stderr.txt" 2>/dev/null
  fi
}
