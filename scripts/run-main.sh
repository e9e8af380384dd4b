#!/usr/bin/env bash
# Quick start, command 1: install what is missing, build, and run the main job: the silo of
# Dumont, Fortin & Ouafik (2010) by contact dynamics, its analysis against Janssen's model and
# its figure, into out/silo-janssen/ (examples/silo-janssen/run.sh; pass "full" for the DEM
# and 3D variants too).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh release
bash examples/silo-janssen/run.sh "${1:-quick}"
