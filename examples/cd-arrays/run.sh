#!/usr/bin/env bash
# Run the regular-array examples with the contact-dynamics solver and draw each force network
# (out/cd-arrays/NAME/force_network.png). Run from the repository root after a build.
# Environment: SABLE_OUT, the output root (default out).
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${SABLE_OUT:-out}/cd-arrays"
mkdir -p "$out"
for f in examples/cd-arrays/*.toml; do
  name=$(basename "$f" .toml)
  if ! ./build/release/bin/sable run "$f" --out "$out/$name" --overwrite > "$out/$name.log" 2>&1; then
    tail -5 "$out/$name.log" >&2
    exit 1
  fi
  grep -E "done|warning" "$out/$name.log" || true
  /usr/bin/python3 scripts/plot_force_network.py "$out/$name"
done
