#!/usr/bin/env bash
# Installs the Debian packages needlesim needs to build, test and run
# (libgmsh-dev: imported meshes, Gmsh scripts and surfaces, tissue.geometry; zlib1g-dev: compressed
# VTK XML surfaces, .vtp; libseccomp-dev: the sandbox Gmsh runs in)
# (python3-paraview, xvfb, libgl1-mesa-dri, python3-meshio, python3-h5py: the field-file test,
# tests/paraview).
# (libcpp-httplib-dev, libjs-three: `needlesim serve`, its page's 3D view; chromium, python3-websocket:
# the real-browser test, tests/browser).
# (libsuitesparse-dev, libopenblas0-serial: CHOLMOD, the supernodal Cholesky of the real-time
# tissues' set-up, on an optimised BLAS instead of the reference one).
# Safe to run again: it asks apt only for what is missing.
set -euo pipefail
PKGS=(
  cmake g++ make ninja-build ccache pkg-config
  libeigen3-dev libyaml-cpp-dev libcli11-dev libfmt-dev nlohmann-json3-dev
  libhdf5-dev libgtest-dev libbenchmark-dev
  libjs-chart.js
  libopenmpi-dev openmpi-bin
  pybind11-dev python3-dev
  python3-numpy python3-pytest python3-h5py python3-matplotlib
  python3-venv python3-pip python3-setuptools python3-wheel
  calculix-ccx
  libgmsh-dev zlib1g-dev libseccomp-dev libsuitesparse-dev libopenblas0-serial
  python3-paraview xvfb libgl1-mesa-dri python3-meshio python3-h5py
  libcpp-httplib-dev libjs-three
  chromium python3-websocket
)
missing=()
for p in "${PKGS[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "bootstrap: all ${#PKGS[@]} Debian packages present"
  exit 0
fi
echo "bootstrap: installing ${missing[*]}"
SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
