#!/usr/bin/env bash
# Installs Siconos' numerics library (headers + shared library) from Debian's apt registry,
# if it is not already installed. Nothing is downloaded from anywhere else.
set -euo pipefail

pkg=libsiconos-numerics-dev
if dpkg -s "$pkg" >/dev/null 2>&1; then
  echo "$pkg already installed: $(dpkg -s "$pkg" | sed -n 's/^Version: //p')"
  exit 0
fi
sudo=""
if [ "$(id -u)" -ne 0 ]; then sudo=sudo; fi
$sudo apt-get update
# The -dev package pulls in libsiconos-numerics7 (the library) and its BLAS/LAPACK deps.
$sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y "$pkg"
# A compiler and cmake are needed to build the driver; Debian's build-essential has both
# gcc and g++ (cmake is not needed: run.sh compiles with one gcc line).
command -v cc >/dev/null || $sudo env DEBIAN_FRONTEND=noninteractive apt-get install -y build-essential
echo "installed $pkg $(dpkg -s "$pkg" | sed -n 's/^Version: //p')"
