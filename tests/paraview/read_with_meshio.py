"""Reads every field file of needlesim results folders with meshio and h5py.

    python3 tests/paraview/read_with_meshio.py RESULTS_FOLDER...

(Debian python3-meshio and python3-h5py: run with /usr/bin/python3.) For each
*.xdmf: meshio's XDMF TimeSeriesReader reads the mesh and every step; the mesh
must have points with 3 coordinates and cells, every point array one row per
point, every displacement or velocity 3 components. Every dataset of the HDF5
file beside it must carry a string attribute `units`, and every XDMF array
name must end in that unit ("von_mises [Pa]") but `displacement` and the integer
`region`, whose names are bare. Exit code 1 with one line per failure.
"""
import os
import sys

import h5py
import meshio

VECTOR_NAMES = ("displacement", "velocity")
BARE_NAMES = ("displacement", "region")  # their units are in the datasets' attribute only


def check_units(h5_path, failures):
    """Every dataset has a non-empty `units` attribute; returns {dataset path: unit}."""
    units = {}

    def visit(path, item):
        if isinstance(item, h5py.Dataset):
            unit = item.attrs.get("units")
            if isinstance(unit, bytes):
                unit = unit.decode()
            if not unit:
                failures.append(f"{h5_path}:/{path}: no units attribute")
            units["/" + path] = unit

    with h5py.File(h5_path, "r") as f:
        f.visititems(visit)
    return units


def check_series(xdmf, failures):
    name = xdmf
    units = check_units(os.path.splitext(xdmf)[0] + ".h5", failures)
    with meshio.xdmf.TimeSeriesReader(xdmf) as reader:
        points, cells = reader.read_points_cells()
        ncells = sum(len(block.data) for block in cells)
        if points.ndim != 2 or points.shape[1] != 3 or len(points) == 0 or ncells == 0:
            failures.append(f"{name}: mesh of points {points.shape} and {ncells} cells")
        for k in range(reader.num_steps):
            t, point_data, cell_data = reader.read_data(k)
            for array, values in point_data.items():
                if len(values) != len(points):
                    failures.append(f"{name}: step {k}: '{array}' has {len(values)} rows for {len(points)} points")
            for array, values in list(point_data.items()) + list(cell_data.items()):
                base, _, unit = array.partition(" [")
                if base in VECTOR_NAMES:
                    shape = values.shape if hasattr(values, "shape") else values[0].shape
                    if len(shape) != 2 or shape[1] != 3:
                        failures.append(f"{name}: step {k}: vector '{array}' of shape {shape}, not n x 3")
                stored = {u for path, u in units.items() if path.endswith("/" + base)}
                if base in BARE_NAMES:
                    if unit or not stored:
                        failures.append(f"{name}: '{array}' is not the bare name of its datasets {sorted(stored)}")
                elif not unit.endswith("]") or stored != {unit[:-1]}:
                    failures.append(f"{name}: '{array}' does not name the unit of its datasets {sorted(stored)}")
        print(f"{name}: {len(points)} points, {ncells} cells ({', '.join(b.type for b in cells)}), "
              f"{reader.num_steps} steps, last t = {t:g} s, arrays {sorted(point_data) + sorted(cell_data)}")


def main():
    failures = []
    for folder in sys.argv[1:]:
        files = sorted(f for f in os.listdir(folder) if f.endswith(".xdmf"))
        if not files:
            failures.append(f"{folder}: no .xdmf field file")
        for f in files:
            try:
                check_series(os.path.join(folder, f), failures)
            except Exception as e:  # meshio raises ReadError and others for what it cannot read
                failures.append(f"{os.path.join(folder, f)}: meshio: {type(e).__name__}: {e}")
    failures = list(dict.fromkeys(failures))  # a defect of every step once
    for f in failures:
        print(f"FAIL: {f}")
    print(f"{len(sys.argv) - 1} folders, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
