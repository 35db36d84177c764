#!/usr/bin/env python3
"""Tabulate one insertion across engines: the agreement matrix of docs/validation/agreement.md.

Reads results folders (of `needlesim run`, or the cases of a `needlesim sweep` study folder) and
prints, per folder, the axial force and its split, the lateral force, the tip deflection and the
displacement of one marker at fixed tip depths, read from forces.csv and markers.csv by linear
interpolation in depth over the insertion phase (depth increasing). Values in mN and mm.

  scripts/agreement_table.py results/agreement_engines            # a study folder
  scripts/agreement_table.py results/a results/b --depths 5,10,20  # run folders
"""
import argparse
import csv
import json
import math
import sys
from pathlib import Path


def read_table(path):
    """Columns of a needlesim CSV (header 'name [unit]', SI) by bare name."""
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        return {}
    names = [h.split(" [")[0].strip() for h in rows[0]]
    cols = {n: [] for n in names}
    for r in rows[1:]:
        for n, v in zip(names, r):
            try:
                cols[n].append(float(v))
            except ValueError:
                cols[n].append(math.nan)
    return cols


def insertion_phase(depth):
    """Indices of the first monotone insertion: up to the deepest sample."""
    if not depth:
        return []
    deepest = max(range(len(depth)), key=lambda i: depth[i])
    return list(range(deepest + 1))


def at_depth(depth, values, d, idx):
    """values interpolated at tip depth d over the rows idx (NaN outside the range reached)."""
    for a, b in zip(idx, idx[1:]):
        da, db = depth[a], depth[b]
        if da <= d <= db and db > da:
            w = (d - da) / (db - da)
            return values[a] + w * (values[b] - values[a])
    return math.nan


def depth_of_time(forces):
    """The tip depth as a function of time (markers.csv of the real-time engines has no depth)."""
    t, d = forces.get("time", []), forces.get("depth", [])

    def f(time):
        for i in range(1, len(t)):
            if t[i - 1] <= time <= t[i]:
                w = 0.0 if t[i] == t[i - 1] else (time - t[i - 1]) / (t[i] - t[i - 1])
                return d[i - 1] + w * (d[i] - d[i - 1])
        return math.nan

    return f


def engine_label(folder):
    try:
        summary = json.loads((folder / "summary.json").read_text())
    except (OSError, ValueError) as e:
        sys.exit(f"agreement_table: {folder / 'summary.json'}: unreadable ({e})")
    sc = summary.get("scenario", {})
    engine = summary.get("engine") or sc.get("model", {}).get("engine", "?")
    if engine == "explicit":
        dim = str(sc.get("model", {}).get("explicit", {}).get("dimension", "2"))
        engine += " 3D" if dim.startswith("3") else " 2D"
    return engine, summary.get("status", "?")


def marker_series(folder, forces, marker):
    path = folder / "markers.csv"
    if not path.exists():
        return None
    m = read_table(path)
    if marker + "_ux" not in m:
        return None
    depth = m.get("depth") or [depth_of_time(forces)(t) for t in m["time"]]
    return depth, m[marker + "_ux"], m[marker + "_uy"]


def row_for(folder, depths, marker):
    forces = read_table(folder / "forces.csv")
    if "depth" not in forces or "force_total" not in forces:
        sys.exit(f"agreement_table: {folder / 'forces.csv'}: no 'depth' and 'force_total' columns "
                 "(not a needlesim forces table, or an empty one)")
    depth = forces["depth"]
    idx = insertion_phase(depth)
    engine, status = engine_label(folder)

    def mN(col):
        if col not in forces:
            return ["-"] * len(depths)
        return [f"{1e3 * at_depth(depth, forces[col], d, idx):.1f}" for d in depths]

    cut = forces.get("force_tip") or forces.get("force_cutting")
    shaft = forces.get("force_shaft") or forces.get("force_friction")
    split = "-"
    if cut and shaft:
        d = depths[-1]
        split = f"{1e3 * at_depth(depth, cut, d, idx):.1f} / {1e3 * at_depth(depth, shaft, d, idx):.1f}"
    last = depths[-1]
    lateral = mN("force_lateral")[-1]
    deflection = "-"
    if "tip_deflection" in forces:
        deflection = f"{1e3 * at_depth(depth, forces['tip_deflection'], last, idx):.3f}"
    mark = "-"
    series = marker_series(folder, forces, marker)
    if series:
        md, ux, uy = series
        midx = insertion_phase(md)
        mark = f"{1e3 * at_depth(md, ux, last, midx):.2f} / {1e3 * at_depth(md, uy, last, midx):.2f}"
    return [engine, status, " / ".join(mN("force_total")), split, lateral, deflection, mark]


def folders_of(paths):
    out = []
    for p in map(Path, paths):
        if (p / "summary.json").exists():
            out.append(p)
        elif (p / "cases").is_dir():
            out.extend(sorted(c for c in (p / "cases").iterdir() if (c / "summary.json").exists()))
        else:
            sys.exit(f"agreement_table: {p}: not a results folder or a study folder (no summary.json, no cases/)")
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("folders", nargs="+")
    ap.add_argument("--depths", default="5,10,15,20", help="tip depths in mm (default 5,10,15,20)")
    ap.add_argument("--marker", default="beside_path", help="marker name (default beside_path)")
    a = ap.parse_args()
    depths = [float(x) * 1e-3 for x in a.depths.split(",")]
    folders = folders_of(a.folders)
    dmm = "/".join(f"{d * 1e3:g}" for d in depths)
    print(f"| engine | status | axial force at {dmm} mm (mN) | tip / shaft at {depths[-1] * 1e3:g} mm (mN) "
          f"| lateral at {depths[-1] * 1e3:g} mm (mN) | tip deflection (mm) | marker {a.marker} u_x / u_y (mm) |")
    print("|---|---|---|---|---|---|---|")
    for f in folders:
        print("| " + " | ".join(row_for(f, depths, a.marker)) + " |")


if __name__ == "__main__":
    main()
