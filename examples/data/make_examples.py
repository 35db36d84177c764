#!/usr/bin/env python3
"""Writes the example data files of docs/fitting.md (synthetic, reproducible).

The seeds' own measurements are not available as numbers (their tables of
fitted parameters came out empty in the extraction, figures are lost), so each
file is generated from a documented law with seed-like parameters and 1 %
Gaussian noise, with a fixed random seed. Run: python3 make_examples.py
"""
import math
import random

rng = random.Random(2026)


def noisy(v, rel=0.01):
    return v * (1.0 + rng.gauss(0.0, rel))


def write(name, header, rows, comments):
    with open(name, "w") as f:
        for c in comments:
            f.write("# " + c + "\n")
        f.write(", ".join(header) + "\n")
        for r in rows:
            f.write(", ".join(f"{x:.6g}" for x in r) + "\n")


# 1. PVA compression, seed 000 section 4.1: 18 x 30 x 30 mm sample, 5 mm at 1 mm/s.
#    Fung-Demiray (seed 000 eq 33) with mu = 2.3 kPa, gamma = 3.1; force = nominal stress x 900 mm^2.
mu, gam, h, A = 2.3e3, 3.1, 18e-3, 900e-6
rows = []
for i in range(1, 51):
    d = 5e-3 * i / 50
    lam = 1 - d / h
    cauchy = mu * (lam * lam - 1 / lam) * math.exp(gam * (lam * lam + 2 / lam - 3))
    rows.append((d * 1e3, noisy(-cauchy / lam * A)))  # compressive force, positive
write("pva_compression.csv", ["compression [mm]", "force [N]"], rows,
      ["Synthetic PVA compression like seed 000 section 4.1 (18 x 30 x 30 mm, 5 mm at 1 mm/s).",
       "Generated with Fung-Demiray mu = 2.3 kPa, gamma = 3.1 (seed 000 eq 33), 1 % noise.",
       "Fit: needlesim fit pva_compression.csv --law fung --height '18 mm' --area '900 mm^2'"])

# 2. Plastisol gel compression, seed 004 Table I: neo-Hookean C10 = 3.6 kPa, to 30 % strain
#    (seed 002 eq 10, Cauchy stress), 1 cm^3 cube.
C10 = 3.6e3
rows = []
for i in range(1, 41):
    e = 0.30 * i / 40
    lam = 1 - e
    s = 2 * C10 / lam * (lam ** 3 - 1)
    rows.append((e * 100, noisy(-s) / 1e3))
write("plastisol_compression.csv", ["compressive strain [%]", "compressive stress [kPa]"], rows,
      ["Synthetic plastisol (soft) compression like seed 004 Table I: C10 = 3.6 kPa,",
       "seed 002 eq 10 (Cauchy stress), 1 % noise. Fit: needlesim fit plastisol_compression.csv --law auto"])

# 3. Muscle relaxation, seed 001 section 2 (30 mm cube): ramp 1 s, hold 120 s,
#    elastic peak 2.0 kPa, Prony g = (0.35, 0.2), tau = (1.5 s, 30 s).
g = [(0.35, 1.5), (0.20, 30.0)]
ginf = 1 - sum(x for x, _ in g)
tr, peak = 1.0, 2.0e3
times = [tr * i / 10 for i in range(11)] + [tr + 0.05 * 1.06 ** i for i in range(1, 120)]
rows = []
for t in times:
    if t <= tr:
        s = peak / tr * (ginf * t + sum(gi * ti * (1 - math.exp(-t / ti)) for gi, ti in g))
        strain = 0.1 * t / tr
    else:
        s = peak / tr * (ginf * tr + sum(gi * ti * (math.exp(-(t - tr) / ti) - math.exp(-t / ti)) for gi, ti in g))
        strain = 0.1
    rows.append((t, strain * 100, noisy(s) / 1e3))
write("muscle_relaxation.csv", ["time [s]", "compressive strain [%]", "stress [kPa]"], rows,
      ["Synthetic stress relaxation like seed 001 section 2 (ramp to 10 % in 1 s, hold).",
       "Prony g = 0.35, 0.20; tau = 1.5 s, 30 s (QLV, seed 001 eq 3), peak elastic stress 2 kPa, 1 % noise.",
       "Fit: needlesim fit muscle_relaxation.csv --law prony"])

# 4. Gelatin insertions at four speeds, seed 003 section 5.1: phantom length 55 mm,
#    C_p = 3.791 N/m, b_p = 285.053 N s/m^2 (the seed's averages), cutting per Table 5.2,
#    puncture at 6 mm with 0.25 N, 2 mN noise.
C, b, L = 3.791, 285.053, 55e-3
for v, cut in [(2.5e-3, 0.042), (3.33e-3, 0.044), (5e-3, 0.055), (10e-3, 0.057)]:
    rows = []
    zp, Fp = 6e-3, 0.25
    for i in range(0, 351):
        z = 70e-3 * i / 350
        if z <= zp:
            f = Fp * (z / zp) ** 1.5
        elif z <= L:
            f = cut + (C + b * v) * z
        else:
            f = (C + b * v) * L
        rows.append((z / v, z * 1e3, f + rng.gauss(0, 0.002)))
    write(f"gelatin_{v * 1e3:.3g}mms.csv", ["time [s]", "depth [mm]", "force [N]"], rows,
          [f"Synthetic insertion through a 55 mm gelatin phantom at {v * 1e3:.3g} mm/s like seed 003 section 5.1.",
           "C_p = 3.791 N/m, b_p = 285.053 N s/m^2, cutting force per seed 003 Table 5.2, 2 mN noise.",
           "Fit all four: needlesim fit gelatin_*mms.csv --law friction --thickness '55 mm'"])

# 5. Seed 003 eqs 5.2-5.5 as summary rows.
write("seed003_friction_summary.csv", ["speed [mm/s]", "force [N]", "cutting force [N]", "length [mm]"],
      [(2.5, 0.244, 0.042, 55), (3.33, 0.261, 0.044, 55), (5, 0.382, 0.0549, 55), (10, 0.501, 0.106, 55)],
      ["Seed 003 eqs 5.2-5.5: F_measured = F_cut + l (C_p + b_p v), l = 55 mm.",
       "Fit: needlesim fit seed003_friction_summary.csv --law friction"])

# 6. Plastisol toughness log, seed 004 section III: 0.71 mm needle at 1.25 mm/s, L2 = 102 mm.
#    Cutting force 0.16 N gives G_c = F_cut L1 / A ~ 40 kJ/m^2 over L1 ~ 99 mm (Table I: 39.3 kJ/m^2).
k, cut, L2, v = 1.2, 0.16, 102e-3, 1.25e-3
rows = []
for i in range(0, 601):
    z = 130e-3 * i / 600
    zp = 3e-3
    if z <= zp:
        f = 0.35 * (z / zp) ** 1.5
    elif z <= L2:
        f = cut + k * z
    else:
        f = k * L2
    rows.append((z * 1e3, f + rng.gauss(0, 0.003)))
write("plastisol_toughness.csv", ["depth [mm]", "force [N]"], rows,
      ["Synthetic insertion through 102 mm of plastisol like seed 004 section III (0.71 mm needle, 1.25 mm/s).",
       "Cutting 0.16 N, shaft friction 1.2 N/m, puncture at 3 mm with 0.35 N, 3 mN noise.",
       "Fit: needlesim fit plastisol_toughness.csv --law toughness --needle-diameter '0.71 mm' --thickness '102 mm' --delta-c '0.71 mm'"])
