#!/usr/bin/env python3
"""mpm's finest grids against explicit 3D's limit on the reduced reference (docs/validation/agreement.md).

Runs examples/agreement/reduced.yaml through explicit 3D on cores of 0.5 / 0.35 / 0.25 mm elements
and through mpm (its defaults: CFEMP, parting `tip`) on grids of 0.375 and 0.25 mm (points at half
the spacing), takes each run's mean axial force with the tip 6-8 mm deep and checks two things:

- mpm on the 0.25 mm grid against explicit's Richardson limit of its three cores, within
  d_p / (4 R) + GCI. CFEMP resolves the needle's outline within the eq 22 gap of a point's centre,
  so each lip's opening, and the wall pressure with it, is uncertain by about d_p / (4 R) (4.9 % at
  0.125 mm points on the 0.635 mm radius); the limit is uncertain by the grid convergence index of
  explicit's finest core, GCI = 1.25 |f_3 - f_2| / ((r^p - 1) |f_3|) (Roache; 1.25: three meshes).
- mpm's change from the 0.375 mm to the 0.25 mm grid within the two lattices' uncertainty of the
  lips' opening, (d_p1 + d_p2) / (4 R) = 12.3 %.
About 10 min on two free cores.

  scripts/agreement_reduced_finest.py --binary build/release/apps/needlesim/needlesim --workdir /tmp/arf
  scripts/agreement_reduced_finest.py --self-test   # the checks on synthetic forces
"""
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from agreement_full_reference import arguments, run_scenarios, variant, window_means  # noqa: E402
from agreement_table import observed_order  # noqa: E402

RADIUS_MM = 0.635                       # reduced.yaml: outer_diameter 1.27 mm
EXPLICIT_CORES_MM = (0.5, 0.35, 0.25)   # model.explicit.element_size
MPM_GRIDS_MM = (0.375, 0.25)            # model.mpm.grid_spacing; particle_spacing half of it
WINDOW_MM = (6.0, 8.0)                  # the tip's depth; the far face is 4 mm ahead
GCI_SAFETY = 1.25


def scenarios(reduced):
    """{name: scenario text} of the five runs."""
    text = variant(Path(reduced).read_text(), [("outer_diameter: 1.27 mm", "outer_diameter: 1.27 mm")], "reduced.yaml")
    runs = {}
    for h in EXPLICIT_CORES_MM:
        runs[f"explicit_{h:g}"] = variant(text, [("engine: mpm", "engine: explicit"),
                                                 ("    element_size: 0.5 mm", f"    element_size: {h:g} mm")], "reduced.yaml")
    for h in MPM_GRIDS_MM:
        runs[f"mpm_{h:g}"] = variant(text, [("    grid_spacing: 0.5 mm", f"    grid_spacing: {h:g} mm"),
                                            ("    particle_spacing: 0.25 mm", f"    particle_spacing: {h / 2:g} mm")],
                                    "reduced.yaml")
    return runs


def window_mean(folder):
    """Mean axial force (mN) over the insertion rows with the tip within WINDOW_MM."""
    return window_means(folder, [WINDOW_MM])[0]


def explicit_limit(means):
    """(limit, GCI of the finest core as a fraction, order) of explicit's means on EXPLICIT_CORES_MM."""
    p, limit, note = observed_order(list(EXPLICIT_CORES_MM), means)
    if p != p:  # NaN: no order
        raise SystemExit(f"explicit 3D's cores {means} mN give no observed order ({note})")
    return limit, GCI_SAFETY * abs(limit - means[-1]) / abs(means[-1]), p


def check(explicit_means, mpm_means):
    """Prints the comparison; True when both checks hold."""
    limit, gci, p = explicit_limit(explicit_means)
    coarse, fine = mpm_means
    dp_coarse, dp_fine = (h / 2 for h in MPM_GRIDS_MM)
    agree_tol = dp_fine / (4 * RADIUS_MM) + gci
    change_tol = (dp_coarse + dp_fine) / (4 * RADIUS_MM)
    agree, change = fine / limit - 1.0, fine / coarse - 1.0
    cores = " / ".join(f"{m:.1f}" for m in explicit_means)
    print(f"explicit 3D, cores {EXPLICIT_CORES_MM} mm: {cores} mN; order {p:.2f}, limit {limit:.1f} mN, GCI {100 * gci:.1f} %")
    print(f"mpm, grids {MPM_GRIDS_MM} mm: {coarse:.1f} / {fine:.1f} mN")
    print(f"mpm 0.25 mm grid / explicit's limit - 1: {100 * agree:+.1f} % (allowed {100 * agree_tol:.1f} %)")
    print(f"mpm 0.375 -> 0.25 mm grid: {100 * change:+.1f} % (allowed {100 * change_tol:.1f} %)")
    ok = abs(agree) <= agree_tol and abs(change) <= change_tol
    print("both hold" if ok else "NOT both within their tolerances")
    return ok


def self_test():
    """explicit's cores on f = 60 - 40 h (mN, h in mm): order 1, limit 60, GCI 1.25 x 10 / 50 = 25 %."""
    explicit = [60.0 - 40.0 * h for h in EXPLICIT_CORES_MM]
    limit, gci, p = explicit_limit(explicit)
    assert abs(p - 1.0) < 1e-6 and abs(limit - 60.0) < 1e-6 and abs(gci - 0.25) < 1e-9, (p, limit, gci)
    assert check(explicit, [60.0 * 1.29] * 2)        # +29 % of the limit: within 4.9 + 25 %
    assert not check(explicit, [80.0, 60.0 * 1.31])   # +31 %: outside
    assert not check(explicit, [45.0, 58.0])          # a change of 29 % between the grids
    with tempfile.TemporaryDirectory() as tmp:        # the window mean of a linear force: its value at 7 mm
        folder = Path(tmp)
        rows = ["time [s],depth [m],force_total [N]"] + [f"{i},{i * 1e-4:.6e},{i * 1e-3:.6e}" for i in range(101)]
        (folder / "forces.csv").write_text("\n".join(rows) + "\n")
        assert abs(window_mean(folder) - 70.0) < 1e-9, window_mean(folder)
    print("self-test passed")


def main():
    a = arguments(__doc__, "--reduced", "reduced.yaml").parse_args()
    if a.self_test:
        self_test()
        return 0
    workdir = a.workdir or Path(tempfile.mkdtemp(prefix="agreement_reduced_finest_"))
    folders = run_scenarios(a.binary, scenarios(a.reduced), workdir, "reduced")
    explicit = [window_mean(folders[f"explicit_{h:g}"]) for h in EXPLICIT_CORES_MM]
    mpm = [window_mean(folders[f"mpm_{h:g}"]) for h in MPM_GRIDS_MM]
    return 0 if check(explicit, mpm) else 1


if __name__ == "__main__":
    sys.exit(main())
