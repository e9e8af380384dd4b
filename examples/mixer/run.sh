#!/usr/bin/env bash
# The paddle mixer of mixer.toml, end to end: pour 5,000 beads around the paddle, stir one
# second at one turn per second, plot the torque on the paddle. Writes out/mixer/:
#   series.csv, grains.pvd, walls.pvd (ParaView: the paddle's triangles turn, each with its
#   force in `cell_force`), snapshots/, run.log
#   torque.png   the torque about the axis and the paddle's turning angle against time
#   torque.json  mean torque and drag force over the second half of the stirring
# Usage: examples/mixer/run.sh   (about a minute on 2 cores)
# Environment: SABLE, the executable (default build/release/bin/sable); SABLE_OUT, the
# output root (default out).
set -euo pipefail
cd "$(dirname "$0")/../.."
sable="${SABLE:-build/release/bin/sable}"
out="${SABLE_OUT:-out}/mixer"
rm -rf "$out"
mkdir -p "$out"
"$sable" run examples/mixer/mixer.toml --out "$out" 2> "$out/run.log"
/usr/bin/python3 examples/mixer/plot_torque.py "$out"
