#!/usr/bin/env bash
# Large-deformation comparison of the explicit FE engine with CalculiX (docs/validation/fe.md):
# a neo-Hookean cantilever under a dead tip shear (tip deflection ~0.35 L), the same 20x4x2 hex
# mesh, material and nodal loads in both; ccx (Debian package calculix-ccx) solves it statically
# with NLGEOM (C3D8R and C3D8I), needlesim relaxes its explicit dynamics to rest. The .inp/.dat
# files are left in $TMPDIR/needlesim_ccx_<pid>. Exit 77 (skip) when ccx is not installed.
set -euo pipefail
cd "$(dirname "$0")/.."
if ! command -v ccx > /dev/null 2>&1; then
  echo "ccx not found: apt-get install -y calculix-ccx" >&2
  exit 77
fi
BUILD=${BUILD:-build/release}
cmake --build "$BUILD" -j2 --target test_explicit > /dev/null
"$BUILD/tests/test_explicit" --gtest_filter='ExplicitCalculix.*' --gtest_color=no
