#!/usr/bin/env python3
"""Tabulate one insertion across engines: the agreement matrix of docs/validation/agreement.md.

Reads results folders (of `needlesim run`, or the cases of a `needlesim sweep` study folder) and
prints, per folder, the axial force and its split, the lateral force, the tip deflection and the
displacement of one marker at fixed tip depths, read from forces.csv and markers.csv by linear
interpolation in depth over the insertion phase (depth increasing). Values in mN and mm.
A cell that is not a finite number, a ragged row or a table beyond 10^6 rows or 64 columns
ends the script with its file, line and column.

  scripts/agreement_table.py results/agreement_engines            # a study folder
  scripts/agreement_table.py results/a results/b --depths 5,10,20  # run folders

Convergence: --convergence takes one engine's runs on three (or more) meshes, coarse to fine, and
prints each quantity on each mesh, the observed order p of the last three and the Richardson
extrapolation of the finest value. The mesh size h is read from each run's summary.json (mpm:
grid_spacing; explicit: element_size; realtime2d/3d: block.length / (nodes_depth - 1)), or given
with --spacings. With f1, f2, f3 on h1 > h2 > h3, p solves
  (f1 - f2) / (f2 - f3) = (h1^p - h2^p) / (h2^p - h3^p)    (= r^p for a constant ratio r = h1/h2 = h2/h3)
and the extrapolated value is f3 + (f3 - f2) / ((h2/h3)^p - 1). Where the differences change sign
(an oscillating sequence) or do not shrink (p <= 0) the meshes are not in the asymptotic range: no
order, no extrapolation. The engines' formal orders lie between 1 (a node spacing or the contact's
resolution of the needle's surface) and 2 (linear elements); an observed order outside 0.5-4, or an
extrapolation of the other sign than the values, is marked pre-asymptotic, its extrapolation not
credible.
--order does the same arithmetic on numbers given as h:f (values measured elsewhere).

Windows: --windows LO:HI,... prints each folder's mean axial force, tip and shaft force and lateral
force with the tip within each window (mm; the lattices make a single row rise and fall by ~10 %).
With --placements the folders are one mesh with the path at different places in the lattice
(insertion.entry_offset): it adds their mean, its standard error s / sqrt(n) and the spread
(max - min) / mean of the axial force, the lattice's scatter that a single placement carries.

Ringing: --ringing prints, per folder, the lateral force's linear trend over the tip's depth beyond
2 mm (least squares), the period in depth of the largest Fourier component of what is left (the
rows resampled on 512 even steps) and its rms: a mode of the tissue block that the needle excites
shows as a period that grows with the square root of the mass scaling.

  scripts/agreement_table.py --convergence results/rt2_16 results/rt2_31 results/rt2_61
  scripts/agreement_table.py --order 1:258.5 0.75:230.5 0.6:195.4 0.5:170.3
  scripts/agreement_table.py --windows 2:4,4:6,6:8 --placements results/m_0 results/m_1 results/m_2
  scripts/agreement_table.py --ringing results/m_0 results/m_1    # the lateral force's trend and ringing
  scripts/agreement_table.py --self-test     # the order/extrapolation arithmetic on synthetic sequences
"""
import argparse
import csv
from array import array
import json
import math
import sys
import tempfile
from pathlib import Path


# Bounds on a table before it is read whole: a results CSV of a long run at 1 ms rows has ~10^5 rows.
MAX_ROWS = 1_000_000
MAX_COLUMNS = 64


def finite_number(cell):
    """The cell's value, or None where it is not a finite number."""
    try:
        x = float(cell)
    except ValueError:
        return None
    return x if math.isfinite(x) else None


def read_table(path, max_rows=MAX_ROWS):
    """Columns of a needlesim CSV (header 'name [unit]', SI) by bare name, each an array of doubles.
    A cell that is not a finite number, a row whose length is not the header's, or a table of more
    than max_rows rows or MAX_COLUMNS columns ends the script with the file, line, column and value."""
    def refuse(line, what):
        raise SystemExit(f"agreement_table: {path}:{line}: {what}")

    with open(path, newline="") as f:
        reader = csv.reader(f)
        header = next(reader, None)
        if header is None:
            return {}
        if len(header) > MAX_COLUMNS:
            refuse(1, f"{len(header)} columns; at most {MAX_COLUMNS} are read")
        names = [h.split(" [")[0].strip() for h in header]
        cols = [array("d") for _ in names]
        for line, row in enumerate(reader, start=2):
            if line - 1 > max_rows:
                refuse(line, f"more than {max_rows} rows; at most {max_rows} are read")
            if len(row) != len(names):
                refuse(line, f"{len(row)} cells where the header has {len(names)}")
            for name, col, cell in zip(names, cols, row):
                x = finite_number(cell)
                if x is None:
                    refuse(line, f"column {name}: '{cell[:40]}' is not a finite number")
                col.append(x)
    return dict(zip(names, cols))


def insertion_phase(depth):
    """Indices of the first monotone insertion: up to the deepest sample."""
    if not depth:
        return []
    deepest = max(range(len(depth)), key=lambda i: depth[i])
    return list(range(deepest + 1))


def insertion_rows(folder, column):
    """(tip depth in mm, the forces.csv column in mN, the insertion phase's row indices) of a folder."""
    path = Path(folder) / "forces.csv"
    if not path.is_file():
        raise SystemExit(f"{folder}: no forces.csv (a needlesim results folder is expected)")
    forces = read_table(path)
    depth = [d * 1e3 for d in forces.get("depth", [])]
    values = [f * 1e3 for f in forces.get(column, [])]
    if len(values) != len(depth):
        raise SystemExit(f"{folder}: forces.csv has no column {column}")
    return depth, values, insertion_phase(depth)


def window_means(folder, windows, column="force_total"):
    """Mean of a forces.csv column (mN) over the insertion rows with the tip within each (lo, hi)
    window (mm)."""
    depth, values, rows = insertion_rows(folder, column)
    means = []
    for lo, hi in windows:
        inside = [values[i] for i in rows if lo <= depth[i] <= hi]
        if not inside:
            raise SystemExit(f"{folder}: no forces.csv row with the tip {lo:g}-{hi:g} mm deep")
        means.append(sum(inside) / len(inside))
    return means


def lateral_ringing(folder, from_mm=2.0, samples=512):
    """(trend in mN/mm, period in mm, rms in mN) of the lateral force beyond from_mm of tip depth:
    the least-squares line, then the largest discrete Fourier component of the residual resampled
    on `samples` even steps, and the residual's rms."""
    depth, lateral, rows = insertion_rows(folder, "force_lateral")
    pts = [(depth[i], lateral[i]) for i in rows if depth[i] > from_mm]
    if len(pts) < 8:
        raise SystemExit(f"{folder}: fewer than 8 forces.csv rows with force_lateral beyond {from_mm:g} mm")
    n = len(pts)
    mx, my = sum(x for x, _ in pts) / n, sum(y for _, y in pts) / n
    slope = sum((x - mx) * (y - my) for x, y in pts) / sum((x - mx) ** 2 for x, _ in pts)
    res = [(x, y - my - slope * (x - mx)) for x, y in pts]
    x0, x1 = res[0][0], res[-1][0]
    even = [x0 + (x1 - x0) * k / (samples - 1) for k in range(samples)]
    xs, ys = [x for x, _ in res], [y for _, y in res]
    r = [at_depth(xs, ys, x, range(n)) for x in even]
    def power(k):
        c = sum(v * math.cos(2 * math.pi * k * i / samples) for i, v in enumerate(r))
        s = sum(v * math.sin(2 * math.pi * k * i / samples) for i, v in enumerate(r))
        return c * c + s * s
    k = max(range(1, samples // 2), key=power)
    period = (x1 - x0) * samples / ((samples - 1) * k)
    rms = math.sqrt(sum(v * v for _, v in res) / n)
    return slope, period, rms


def ringing_table(folders):
    lines = ["| folder | lateral force's trend beyond 2 mm (mN/mm) | period of its ringing (mm of tip depth) | rms about the trend (mN) |",
             "|---|---|---|---|"]
    for f in folders:
        slope, period, rms = lateral_ringing(f)
        lines.append(f"| {f} | {slope:+.2f} | {period:.2f} | {rms:.1f} |")
    return "\n".join(lines)


def mean_and_error(values):
    """(mean, standard error s / sqrt(n), spread (max - min) / |mean|) of two values or more."""
    n = len(values)
    mean = sum(values) / n
    s = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1))
    return mean, s / math.sqrt(n), (max(values) - min(values)) / abs(mean)


def window_table(folders, windows, placements):
    """Markdown rows of each folder's window means; with placements, their mean, error and spread."""
    span = " / ".join(f"{lo:g}-{hi:g}" for lo, hi in windows)
    lines = [f"| folder | axial force (mN), the tip {span} mm deep | tip force | shaft force | lateral force |",
             "|---|---|---|---|---|"]
    columns = ("force_total", "force_tip", "force_shaft", "force_lateral")
    rows = [[window_means(f, windows, c) for c in columns] for f in folders]
    for f, r in zip(folders, rows):
        lines.append(f"| {f} | " + " | ".join(" / ".join(f"{v:.1f}" for v in col) for col in r) + " |")
    if placements and len(folders) > 1:
        stats = [[mean_and_error([r[c][w] for r in rows]) for w in range(len(windows))] for c in range(len(columns))]
        cells = [" / ".join(f"{m:.1f} +- {e:.1f}" for m, e, _ in col) for col in stats]
        lines.append(f"| mean of {len(folders)} placements +- standard error | " + " | ".join(cells) + " |")
        lines.append("| spread of the axial force (max - min) / mean | "
                     + " / ".join(f"{100 * sp:.1f} %" for _, _, sp in stats[0]) + " | | | |")
    return "\n".join(lines)


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


def quantities(folder, depths, marker):
    """The matrix's quantities of one run as numbers (mN, mm; NaN where the engine has none)."""
    forces = read_table(folder / "forces.csv")
    depth = forces.get("depth", [])
    idx = insertion_phase(depth)
    last = depths[-1]

    def at(col, d, scale=1e3):
        return scale * at_depth(depth, forces[col], d, idx) if col in forces else math.nan

    q = {f"axial at {d * 1e3:g} mm (mN)": at("force_total", d) for d in depths}
    tip = "force_tip" if "force_tip" in forces else "force_cutting"
    shaft = "force_shaft" if "force_shaft" in forces else "force_friction"
    q[f"tip at {last * 1e3:g} mm (mN)"] = at(tip, last)
    q[f"shaft at {last * 1e3:g} mm (mN)"] = at(shaft, last)
    q[f"lateral at {last * 1e3:g} mm (mN)"] = at("force_lateral", last)
    q["tip deflection (um)"] = at("tip_deflection", last, 1e6)
    series = marker_series(folder, forces, marker)
    ux = uy = math.nan
    if series:
        md, mx, my = series
        midx = insertion_phase(md)
        ux, uy = 1e3 * at_depth(md, mx, last, midx), 1e3 * at_depth(md, my, last, midx)
    q[f"{marker} u_x (mm)"], q[f"{marker} u_y (mm)"] = ux, uy
    return q


def mesh_size(folder):
    """The run's mesh size in mm: mpm grid_spacing, explicit element_size, real-time node spacing."""
    sc = json.loads((folder / "summary.json").read_text()).get("scenario", {})
    model = sc.get("model", {})
    engine = model.get("engine", "?")
    section = model.get(engine, {})

    def si(v):  # summary.json writes a quantity as "0.03 m" (SI) and a count as a number
        return float(str(v).split()[0])

    if engine == "mpm":
        return 1e3 * si(section["grid_spacing"])
    if engine == "explicit":
        return 1e3 * si(section["element_size"])
    if engine in ("realtime2d", "realtime3d"):
        return 1e3 * si(sc["tissue"]["block"]["length"]) / (si(section["nodes_depth"]) - 1)
    sys.exit(f"agreement_table: {folder}: engine {engine} has no mesh to refine")


def ratio_of_differences(h, p):
    """(h1^p - h2^p) / (h2^p - h3^p): what (f1 - f2) / (f2 - f3) is for f = f0 + C h^p."""
    return (h[0] ** p - h[1] ** p) / (h[1] ** p - h[2] ** p)


def observed_order(h, f):
    """(p, extrapolated, note) of the last three values f on sizes h (coarse to fine)."""
    h, f = h[-3:], f[-3:]
    if any(math.isnan(x) for x in f):
        return math.nan, math.nan, "-"
    d21, d32 = f[0] - f[1], f[1] - f[2]
    if max(abs(d21), abs(d32)) <= 1e-9 * max(abs(x) for x in f):  # equal up to rounding
        return math.nan, f[2], "constant"
    if d32 == 0.0 or d21 * d32 < 0.0:
        return math.nan, math.nan, "oscillates: not in the asymptotic range"
    target = d21 / d32
    lo, hi = 1e-3, 20.0  # the ratio grows with p; bisect for it
    if not ratio_of_differences(h, lo) <= target <= ratio_of_differences(h, hi):
        kind = "p <= 0 (the differences do not shrink)" if target < ratio_of_differences(h, lo) else "p > 20"
        return math.nan, math.nan, kind + ": not in the asymptotic range"
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if ratio_of_differences(h, mid) < target else (lo, mid)
    p = 0.5 * (lo + hi)
    extrapolated = f[2] + (f[2] - f[1]) / ((h[1] / h[2]) ** p - 1.0)
    note = "monotone"
    if not 0.5 - 1e-6 <= p <= 4.0 + 1e-6:
        note = "p outside 0.5-4: pre-asymptotic, extrapolation not credible"
    elif extrapolated * f[2] < 0.0:
        note = "the extrapolation changes sign: pre-asymptotic, not credible"
    return p, extrapolated, note


def convergence_table(sizes, rows):
    """Markdown: one line per quantity, its value on each mesh, p and the extrapolated value."""
    hs = " | ".join(f"h = {h:g} mm" for h in sizes)
    last3 = ", ".join(f"{h:g}" for h in sizes[-3:])
    out = [f"| quantity | {hs} | observed order p (h = {last3} mm) | extrapolated | |", "|---" * (len(sizes) + 4) + "|"]
    for name in rows[0]:
        f = [r[name] for r in rows]
        if all(math.isnan(x) for x in f):
            continue
        p, ext, note = observed_order(sizes, f)
        cells = " | ".join("-" if math.isnan(x) else f"{x:.4g}" for x in f)
        ps = "-" if math.isnan(p) else f"{p:.2f}"
        es = "-" if math.isnan(ext) else f"{ext:.4g}"
        out.append(f"| {name} | {cells} | {ps} | {es} | {note} |")
    return "\n".join(out)


def self_test():
    """The order and extrapolation arithmetic on sequences of known order (not a physics check)."""
    checks = []
    for h in ([2.0, 1.0, 0.5], [1.0, 0.75, 0.6], [0.7, 0.6, 0.5]):
        for p0 in (1.0, 2.0, 0.5):
            f = [5.0 + 3.0 * x ** p0 for x in h]
            p, ext, note = observed_order(h, f)
            ok = abs(p - p0) < 1e-6 and abs(ext - 5.0) < 1e-6 and note == "monotone"
            checks.append((f"f = 5 + 3 h^{p0:g} on h = {h}", ok))
    checks.append(("an oscillating sequence has no order", observed_order([1, 0.75, 0.6], [44.5, 74.5, 72.5])[2].startswith("oscillates")))
    checks.append(("an extrapolation of the other sign is marked", "not credible" in observed_order([0.75, 0.6, 0.5], [230.5, 195.4, 170.3])[2]))
    checks.append(("a sequence whose differences grow has no order", observed_order([2, 1, 0.5], [1.0, 2.0, 4.0])[2].startswith("p <= 0")))
    checks.append(("a constant sequence is its own limit", observed_order([2, 1, 0.5], [7.0, 7.0, 7.0 + 1e-14])[2] == "constant"))
    mean, err, spread = mean_and_error([54.0, 58.0, 60.0, 56.0])
    checks.append(("mean, standard error and spread of four placements",
                   abs(mean - 57.0) < 1e-12 and abs(err - math.sqrt(20.0 / 3.0) / 2.0) < 1e-12 and abs(spread - 6.0 / 57.0) < 1e-12))
    checks.append(("the window means of a linear force are its values at the windows' centres", window_self_test()))
    checks.append(("the trend, period and rms of a ringing lateral force", ringing_self_test()))
    checks.extend(bad_table_self_test())
    for name, ok in checks:
        print(("ok   " if ok else "FAIL ") + name)
    return all(ok for _, ok in checks)


def write_synthetic_forces(folder, columns, step_mm, count, values):
    """forces.csv in folder: `count` rows `step_mm` apart in depth at 5 mm/s, then `values(depth in mm)`
    under the header's `columns`."""
    lines = ["time [s],depth [m]," + columns]
    for i in range(count):
        d = step_mm * i
        lines.append(f"{d / 5:.4f},{d * 1e-3:.6e}," + values(d))
    (Path(folder) / "forces.csv").write_text("\n".join(lines) + "\n")


def window_self_test():
    """A force of 7 mN/mm (tip 2 mN, lateral -1 mN) read over the windows 2-4 and 6-8 mm."""
    with tempfile.TemporaryDirectory() as tmp:
        write_synthetic_forces(tmp, "force_total [N],force_tip [N],force_shaft [N],force_lateral [N]", 0.1, 101,
                               lambda d: f"{7 * d * 1e-3:.6e},2e-3,{(7 * d - 2) * 1e-3:.6e},-1e-3")
        windows = [(2.0, 4.0), (6.0, 8.0)]
        ok = all(abs(m - e) < 1e-9 for m, e in zip(window_means(tmp, windows), [21.0, 49.0]))
        ok = ok and all(abs(m - e) < 1e-9 for m, e in zip(window_means(tmp, windows, "force_shaft"), [19.0, 47.0]))
        table = window_table([Path(tmp), Path(tmp)], windows, True)
        return ok and "21.0 +- 0.0 / 49.0 +- 0.0" in table and "-1.0" in table


def ringing_self_test():
    """A lateral force of 3 mN/mm plus 5 mN sin(2 pi d / 1.5 mm), sampled every 0.01 mm to 8 mm (over
    the 4 periods from 2 mm the sine correlates with depth: the line takes 0.21 mN/mm of it)."""
    with tempfile.TemporaryDirectory() as tmp:
        write_synthetic_forces(tmp, "force_lateral [N]", 0.01, 801,
                               lambda d: f"{(3 * d + 5 * math.sin(2 * math.pi * d / 1.5)) * 1e-3:.9e}")
        slope, period, rms = lateral_ringing(tmp)
        return abs(slope - 3.0) < 0.3 and abs(period - 1.5) < 0.05 and abs(rms - 5 / math.sqrt(2)) < 0.2


def refusal_of(text, max_rows=MAX_ROWS):
    """The message with which read_table refuses a forces.csv holding text (None: read)."""
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "forces.csv"
        path.write_text(text)
        try:
            read_table(path, max_rows)
        except SystemExit as e:
            return str(e)
    return None


def bad_table_self_test():
    """Tables that are refused with their line and column, and one that is read."""
    head = "time [s],depth [m],force_total [N]\n"
    cases = [("a NaN cell is refused with its line and column", head + "0,0,0\n0.1,1e-3,nan\n", ":3: column force_total"),
             ("an empty cell is refused", head + "0,,0\n", ":2: column depth"),
             ("a short row is refused", head + "0,0\n", ":2: 2 cells where the header has 3"),
             ("a table beyond the row bound is refused", head + "0,0,0\n" * 4, "more than 3 rows")]
    checks = [(name, (refusal_of(text, 3) or "").find(expected) >= 0) for name, text, expected in cases]
    checks.append(("a well-formed table is read", refusal_of(head + "0,0,0\n0.1,1e-3,2e-3\n") is None))
    return checks


def parse_order_values(items):
    try:
        pairs = [tuple(float(x) for x in it.split(":")) for it in items]
    except ValueError:
        sys.exit("agreement_table: --order takes h:f pairs, e.g. 1:258.5 0.75:230.5 0.6:195.4")
    if len(pairs) < 3 or any(len(pr) != 2 for pr in pairs):
        sys.exit("agreement_table: --order takes at least three h:f pairs, coarse to fine")
    return [pr[0] for pr in pairs], [pr[1] for pr in pairs]


def parse_windows(text):
    try:
        windows = [tuple(float(x) for x in w.split(":")) for w in text.split(",")]
    except ValueError:
        sys.exit(f"agreement_table: --windows {text}: expected LO:HI,... in mm, e.g. 2:4,4:6,6:8")
    if any(len(w) != 2 or not w[0] < w[1] for w in windows):
        sys.exit(f"agreement_table: --windows {text}: each window LO:HI with LO < HI (mm)")
    return windows


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
    ap.add_argument("folders", nargs="*")
    ap.add_argument("--depths", default="5,10,15,20", help="tip depths in mm (default 5,10,15,20)")
    ap.add_argument("--marker", default="beside_path", help="marker name (default beside_path)")
    ap.add_argument("--convergence", action="store_true", help="the folders are one engine on meshes coarse to fine")
    ap.add_argument("--spacings", help="mesh sizes in mm, one per folder (default: from each summary.json)")
    ap.add_argument("--order", nargs="+", metavar="H:F", help="observed order and extrapolation of the values given")
    ap.add_argument("--windows", help="LO:HI,... tip depths in mm: each folder's mean forces over each window")
    ap.add_argument("--placements", action="store_true",
                    help="with --windows: the folders are one mesh, the path at different places in the lattice")
    ap.add_argument("--ringing", action="store_true",
                    help="each folder's lateral force: its trend, the period and rms of what rings about it")
    ap.add_argument("--self-test", action="store_true", help="check the order arithmetic on synthetic sequences")
    a = ap.parse_args()
    if a.self_test:
        sys.exit(0 if self_test() else 1)
    if a.order:
        h, f = parse_order_values(a.order)
        p, ext, note = observed_order(h, f)
        print(f"p = {p:.3g}, extrapolated {ext:.4g} ({note})")
        return
    if not a.folders:
        ap.error("give results folders (or --order, --self-test)")
    folders = folders_of(a.folders)
    if a.windows:
        print(window_table(folders, parse_windows(a.windows), a.placements))
        return
    if a.ringing:
        print(ringing_table(folders))
        return
    depths = [float(x) * 1e-3 for x in a.depths.split(",")]
    if a.convergence:
        convergence(a, folders, depths)
        return
    dmm = "/".join(f"{d * 1e3:g}" for d in depths)
    print(f"| engine | status | axial force at {dmm} mm (mN) | tip / shaft at {depths[-1] * 1e3:g} mm (mN) "
          f"| lateral at {depths[-1] * 1e3:g} mm (mN) | tip deflection (mm) | marker {a.marker} u_x / u_y (mm) |")
    print("|---|---|---|---|---|---|---|")
    for f in folders:
        print("| " + " | ".join(row_for(f, depths, a.marker)) + " |")


def convergence(a, folders, depths):
    if len(folders) < 3:
        sys.exit("agreement_table: --convergence needs three results folders or more, coarse to fine")
    sizes = [float(x) for x in a.spacings.split(",")] if a.spacings else [mesh_size(f) for f in folders]
    if len(sizes) != len(folders) or any(x <= y for x, y in zip(sizes, sizes[1:])):
        sys.exit(f"agreement_table: mesh sizes {sizes} mm: one per folder, decreasing (coarse to fine)")
    print(convergence_table(sizes, [quantities(f, depths, a.marker) for f in folders]))

if __name__ == "__main__":
    main()
