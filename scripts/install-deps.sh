#!/usr/bin/env bash
# Installs the Debian 12 packages sage needs to build, test and benchmark,
# and any named as arguments (scripts/fuzz.sh adds clang's), skipping those
# already present. Run as root (or with sudo available).
set -euo pipefail

packages=(
  g++ cmake ninja-build pkg-config ca-certificates
  libeigen3-dev              # linear algebra (solver)
  libvtk9-dev                # .vtu/.vti/.png output
  libboost-program-options-dev
  nlohmann-json3-dev         # JSON model files
  libcgal-dev libgmp-dev libmpfr-dev  # exact geometry
  libgdal-dev                # GIS readers
  libocct-foundation-dev libocct-modeling-data-dev libocct-modeling-algorithms-dev
  libocct-data-exchange-dev  # CAD files (STEP, IGES, BREP) with OpenCASCADE
  libocct-ocaf-dev libocct-visualization-dev libtbb-dev  # what OCCT's CMake configuration loads
  libgtest-dev libgmock-dev  # tests
  libbenchmark-dev           # bench/
  clang-format               # format check in CI
  python3-dev pybind11-dev python3-numpy  # the Python module (python/)
  python3-shapely python3-geopandas python3-matplotlib python3-gdal  # its tests and example
  "$@"
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
