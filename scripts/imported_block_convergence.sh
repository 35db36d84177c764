#!/usr/bin/env bash
# The explicit engine's 2D block, generated (split-quad triangles) and imported (Gmsh's
# unstructured triangles of the same size), at several element sizes: the mean force over the
# second half of a 10 mm insertion and their difference (docs/models/explicit.md "Imported meshes").
#
#   scripts/imported_block_convergence.sh [NEEDLESIM] [SIZES_MM...]     (default 0.5 0.35 0.25)
#   TOLERANCE_PERCENT=6 scripts/... NEEDLESIM 0.35   exits 1 when a difference exceeds it (CTest)
# Runs take about 10 s (0.5 mm) to 3 min (0.25 mm) each on one core.
set -euo pipefail
here="$(cd "$(dirname "$0")/.." && pwd)"
needlesim=${1:-$here/build/release/apps/needlesim/needlesim}
shift || true
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(0.5 0.35 0.25)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

scenario() {  # tissue line, element size
  cat <<YAML
name: block_convergence
tissue:
  $1
  material: {law: neo-hookean, C10: 3.6 kPa, nu: 0.45, density: 1000 kg/m^3}
  friction: {coefficient: 0.3}
needle: {outer_diameter: 2 mm, length: 40 mm, bevel_angle: 45 deg, tip: bevel, youngs_modulus: 200 GPa}
insertion:
  start_depth: -0.5 mm
  profile:
    - insert: {to: 10 mm, speed: 10 mm/s}
model:
  engine: explicit
  explicit: {dimension: 2d, element: tri3, element_size: $2 mm, max_element_size: $2 mm, core_width: 20 mm,
             mass_scaling: 15, tip_friction: 0}
output: {interval: 10 ms}
YAML
}

for h in "${sizes[@]}"; do
  cat > "$work/block_$h.geo" <<GEO
L = 20; W = 20;
Point(1) = {0, -W/2, 0}; Point(2) = {L, -W/2, 0}; Point(3) = {L, W/2, 0}; Point(4) = {0, W/2, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Mesh.MeshSizeMax = $h; Mesh.MeshSizeMin = $h;
Physical Surface("gel") = {1};
GEO
  scenario "block: {length: 20 mm, width: 20 mm, height: 20 mm}" "$h" > "$work/generated_$h.yaml"
  scenario "geometry: {file: block_$h.geo, unit: mm}" "$h" > "$work/imported_$h.yaml"
  for kind in generated imported; do
    "$needlesim" run -q "$work/${kind}_$h.yaml" -o "$work/r_${kind}_$h"
  done
done

python3 - "$work" "${sizes[@]}" <<'PY'
import csv, os, sys
failed = False
work, sizes = sys.argv[1], sys.argv[2:]
def second_half_mean(folder):
    rows = list(csv.reader(open(f"{folder}/forces.csv")))
    depth, force = rows[0].index("depth [m]"), rows[0].index("force_total [N]")
    values = [float(r[force]) for r in rows[1:] if float(r[depth]) > 5e-3]
    return sum(values) / len(values)
print("| element size | generated tri3 | imported unstructured tri3 | difference |")
print("|---|---|---|---|")
for h in sizes:
    g, u = (second_half_mean(f"{work}/r_{k}_{h}") for k in ("generated", "imported"))
    print(f"| {h} mm | {1e3 * g:.1f} mN | {1e3 * u:.1f} mN | {100 * (u / g - 1):+.1f} % |")
    limit = os.environ.get("TOLERANCE_PERCENT")
    if limit and abs(100 * (u / g - 1)) > float(limit):
        print(f"{h} mm: the imported and generated blocks differ by more than {limit} %")
        failed = True
sys.exit(1 if failed else 0)
PY
