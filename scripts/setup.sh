#!/usr/bin/env bash
# Install the Debian 12 packages Sable needs to build, test and run. Idempotent: installs
# only what is missing (refreshing the package index first), and does nothing otherwise.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config git
  libeigen3-dev libtomlplusplus-dev libcli11-dev libfmt-dev libhdf5-dev
  # zlib-compressed VTK output (io/vtk_xml.hpp).
  zlib1g-dev
  # MPI domain decomposition (src/sable/mpi, optional at configure time) and its tests; HDF5's
  # MPI flavour writes a decomposed run's snapshots collectively (the MPI build uses it).
  libopenmpi-dev openmpi-bin libhdf5-openmpi-dev
  # The Python module (apps/python, python/sable; docs/python.md).
  pybind11-dev python3-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  python3 python3-numpy python3-matplotlib clang-format clang-tidy
  # examples/silo-janssen/wall_contacts.py reads snapshots from Python.
  python3-h5py
  # The sanitizer builds, the fuzz targets and ThreadSanitizer (docs/reliability.md): clang,
  # its sanitizer and libFuzzer runtimes (only recommended by clang, and this script skips
  # recommendations), LLVM's libomp with Archer.
  clang libclang-rt-dev libomp-dev
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
