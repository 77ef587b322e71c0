#!/usr/bin/env bash
# Installs the Debian packages pbf builds with. Safe to run repeatedly.
# Runs apt-get as root (directly, or through sudo when available).
# Usage: scripts/install_deps.sh [--clang]
#   --clang: also clang and LLVM's OpenMP runtime, for the fuzzers
#            (scripts/fuzz.sh) and the ThreadSanitizer build (scripts/tsan.sh).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libgtest-dev libgmock-dev libbenchmark-dev
  nlohmann-json3-dev libcli11-dev libfmt-dev libhwy-dev
  libopenvdb-dev libtbb-dev libtinyobjloader-dev libboost-iostreams-dev zlib1g-dev
  # rigid bodies: contacts and dynamics (double-precision build, bullet-float64.pc)
  libbullet-dev
  # pbf_render (PBF_BUILD_VIEWER): viewer, headless EGL rendering, images, video, viewer test
  libglfw3-dev libepoxy-dev libimgui-dev libglm-dev libstb-dev
  libegl-dev libegl-mesa0 libgl1 libglx-mesa0 libgl1-mesa-dri ffmpeg xvfb xauth
  # the Python module (PBF_BUILD_PYTHON), its tests, and `pip install .` offline in a venv
  pybind11-dev python3-dev python3-numpy python3-pytest
  python3-venv python3-pip python3-setuptools python3-wheel
  # client tests (tests/clients, docs/clients.md): runs opened headless in ParaView (pvpython)
  # and Blender (the add-on in blender/, Alembic export). Measured on the 2-core machine:
  # paraview + python3-paraview 116 packages, 741 MB, 200 s; blender then 33 more, 331 MB, 65 s.
  # Not libvtk9-dev: it depends on python3-vtk9, which python3-paraview conflicts with.
  paraview python3-paraview blender
  # distributed runs (PBF_MPI, docs/distributed.md): mpirun -np N pbf run ...
  libopenmpi-dev openmpi-bin
  # parallel H5Part frames (PBF_HDF5, docs/distributed.md): HDF5 built with Open MPI.
  # Measured on the 2-core machine with its runtime already there (ParaView brings
  # it): 8 packages, 16 MB, 10 s.
  libhdf5-openmpi-dev
  # the GPU backend's CPU build (cuda-on-cpu) where no CUDA toolkit is installed:
  # Thrust 1.17 and CUB (with the toolkit, its CCCL is used and these are built
  # against too, tests/backend/gpu/device_thrust_versions_test.cpp)
  libthrust-dev libcub-dev
  # plots of `pbf plot`, `pbf run` and `pbf validate` (scripts/pbf_plot.py, run with /usr/bin/python3)
  python3-matplotlib
)
if [ "${1:-}" = "--clang" ]; then packages+=(clang libomp-dev); fi

# The USD client test's reader (tests/clients/usd, CTest clients.usd): the npm
# package tinyusdz (TinyUSDZ built to WebAssembly; no USD library is packaged
# for Debian), pinned in tests/clients/usd/package-lock.json. Installed where
# node and npm are present (Node is not one of the Debian packages above);
# without them the test is skipped with a message.
install_usd_reader() {
  local dir
  dir="$(cd "$(dirname "$0")/.." && pwd)/tests/clients/usd"
  if ! command -v node > /dev/null || ! command -v npm > /dev/null; then
    echo "install_deps: no node/npm on the PATH: the USD client test (clients.usd) will be skipped"
    return 0
  fi
  if npm ls --prefix "$dir" tinyusdz@0.9.0-rc10 > /dev/null 2>&1; then
    echo "install_deps: tinyusdz 0.9.0-rc10 already installed in $dir"
    return 0
  fi
  echo "install_deps: npm ci in $dir (tinyusdz 0.9.0-rc10)"
  if ! (cd "$dir" && npm ci --no-audit --no-fund); then
    echo "install_deps: warning: npm ci failed: the USD client test (clients.usd) will be skipped"
  fi
}

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install_deps: all ${#packages[@]} packages already installed"
  install_usd_reader
  exit 0
fi
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install_deps: installing ${missing[*]}"
$SUDO apt-get update -q
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${missing[@]}"
install_usd_reader
