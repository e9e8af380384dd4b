#!/usr/bin/env bash
# Run the regular-array examples with the contact-dynamics solver and draw each force network
# (out/cd-arrays/NAME/force_network.png). Run from the repository root after a build.
set -euo pipefail
cd "$(dirname "$0")/../.."
for f in examples/cd-arrays/*.toml; do
  name=$(basename "$f" .toml)
  ./build/release/bin/sable run "$f" --overwrite 2>&1 | grep -E "done|warning" || true
  /usr/bin/python3 scripts/plot_force_network.py "out/cd-arrays/$name"
done
