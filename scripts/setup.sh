#!/usr/bin/env bash
# Install the Debian 12 packages Sable needs to build, test and run. Idempotent: installs
# only what is missing (refreshing the package index first), and does nothing otherwise.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config git
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev libhdf5-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-matplotlib clang-format
  # The fuzz targets (scripts/fuzz.sh): clang 14, its libFuzzer and sanitizer runtimes, and
  # its OpenMP runtime.
  clang libclang-rt-14-dev libomp-14-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if ((${#missing[@]})); then
  echo "setup: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -ne 0 ] && SUDO="sudo"
  $SUDO apt-get update
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends "${missing[@]}"
else
  echo "setup: all build dependencies present"
fi
