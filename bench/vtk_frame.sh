#!/usr/bin/env bash
# VTK frame benchmark: the time to write one frame (grains, contacts, walls) of the
# 20,000-grain pour bed and its size, in each encoding of [output] vtk_format (binary, zlib,
# ascii; io/vtk_xml.hpp), REPEATS repetitions of BM_VtkFrame (bench/micro/bench_io.cpp).
# Usage: bench/vtk_frame.sh [SNAPSHOT] [REPEATS]
# Without SNAPSHOT it first runs examples/pour.toml (VTK off; minutes) and takes its last
# snapshot, the settled, dense bed. Builds the release preset first.
set -euo pipefail
cd "$(dirname "$0")/.."
snapshot="${1:-}"
repeats="${2:-5}"
bash scripts/build.sh release >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if [ -z "$snapshot" ]; then
  sed -e 's/^vtk_interval = .*/vtk_interval = 0/' examples/pour.toml > "$work/pour.toml"
  ./build/release/bin/sable run "$work/pour.toml" --out "$work/out" > "$work/log.txt" 2>&1 ||
    { cat "$work/log.txt"; exit 1; }
  snapshot=$(ls "$work"/out/snapshots/end_of_stage_*.h5 | sort | tail -1)
fi
echo "machine: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; $(date -u +%F); $snapshot"
TMPDIR="$work" SABLE_BENCH_SNAPSHOT="$snapshot" ./build/release/bench/sable_micro_bench \
  --benchmark_filter=BM_VtkFrame --benchmark_repetitions="$repeats" \
  --benchmark_report_aggregates_only=true
