#!/usr/bin/env bash
# Quick start, command 1: install what is missing, build, and run the main job:
# examples/pour.toml (20,000 spheres poured and settled), writing ParaView files and a CSV
# into out/pour/.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
./build/release/bin/sable run examples/pour.toml --out out/pour "$@"
echo
echo "Open out/pour/grains.pvd (and contacts.pvd, walls.pvd) in ParaView;"
echo "the time series (kinetic energy, coordination, wall forces) is out/pour/series.csv."
