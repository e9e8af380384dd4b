#!/usr/bin/env bash
# Configure and build one CMake preset (default: release) with all cores. The release build
# also makes `import sable` work for /usr/bin/python3: a sable.pth in the system's
# site-packages names build/release/python (docs/python.md; a user without write access there
# gets the PYTHONPATH line to use instead).
set -euo pipefail
cd "$(dirname "$0")/.."
preset="${1:-release}"
cmake --preset "$preset" >/dev/null
cmake --build --preset "$preset" -j "$(nproc)"
if [ "$preset" = release ] && [ -d build/release/python/sable ]; then
  site=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
  module_dir="$(pwd)/build/release/python"
  if mkdir -p "$site" 2>/dev/null && echo "$module_dir" > "$site/sable.pth" 2>/dev/null; then
    echo "build: import sable finds $module_dir (through $site/sable.pth)"
  else
    echo "build: for import sable, export PYTHONPATH=$module_dir"
  fi
fi
