# %% [markdown]
# # Insertion forces and tissue displacement from Python
#
# Runs the seed 003 gelatin experiment with the lumped model, steps the real-time
# 2D FE engine (`realtime2d`) in a loop as a haptic device would, and plots the
# force against depth and the tissue displacement with matplotlib. Run it as a
# script (`python3 examples/python/insertion_forces.py [output folder]`) or cell
# by cell in Jupyter (VS Code and JupyterLab read the `# %%` marks).
# Install the package first (docs/python.md).

# %%
import os
import pathlib
import sys

import matplotlib

if not os.environ.get("DISPLAY") and "ipykernel" not in sys.modules:
    matplotlib.use("Agg")  # no screen: write the PNG files only
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.collections import PolyCollection

import needlesim

HERE = pathlib.Path(__file__).resolve().parent if "__file__" in globals() else pathlib.Path("examples/python")
EXAMPLES = HERE.parent
OUT = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 and "ipykernel" not in sys.modules else "results/python_example")
OUT.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## A run: the lumped force model (seed 003 section 3.2)

# %%
gelatin = needlesim.load(EXAMPLES / "gelatin_18G_3mms.yaml")
run = needlesim.run(gelatin)
forces = run.tables["forces"]  # columns as NumPy arrays, units in forces.units
print(run)
print("exit force:", run.results["exit_force"])

# %% [markdown]
# ## A session: the real-time 2D FE engine stepped at 1 kHz
#
# The same motion as the engine's own run: the scenario's profile gives the depth
# (and the needle's rotations) at every step.

# %%
thesis = needlesim.load(EXAMPLES / "realtime2d" / "thesis_gelatin_18G_10mms.yaml")
thesis = thesis.with_values({"insertion.profile[0].insert.to": "40 mm"})
session = needlesim.Session(thesis)
steps = int(np.ceil(thesis.duration / session.dt - 1e-9))
depth, total, lateral = np.empty(steps), np.empty(steps), np.empty(steps)
for k in range(steps):
    m = thesis.motion_at(min((k + 1) * session.dt, thesis.duration))
    s = session.step(m.depth, rotation=m.rotation, roll=m.roll)
    depth[k], total[k], lateral[k] = s.depth, s.force_total, s.force_lateral
print(s)

# %% [markdown]
# ## Force against depth

# %%
inserting = forces["velocity"] > 0  # the profile also pauses and retracts
fig, ax = plt.subplots(figsize=(7, 4.5))
ax.plot(forces["depth"][inserting] * 1e3, forces["force_total"][inserting], label="lumped: total")
for part in ("force_stiffness", "force_cutting", "force_friction"):
    ax.plot(forces["depth"][inserting] * 1e3, forces[part][inserting], "--", lw=1,
            label="lumped: " + part.split("_")[1])
ax.plot(depth * 1e3, total, label="realtime2d session: axial")
ax.plot(depth * 1e3, lateral, ":", label="realtime2d session: lateral")
ax.set(xlabel="tip depth [mm]", ylabel="force on the needle [%s]" % forces.units["force_total"],
       title="Needle insertion into 10 wt% gelatin, 18 G (seed 003)")
ax.legend(fontsize=8)
fig.tight_layout()
fig.savefig(OUT / "force_depth.png", dpi=120)

# %% [markdown]
# ## Tissue displacement around the needle
#
# The session's mesh (node positions and displacements as arrays, quadrilateral
# cells), deformed and coloured by the displacement magnitude, with the needle.

# %%
points, u, cells = session.points, session.displacement, session.cells
moved = points + u
magnitude = np.linalg.norm(u, axis=1)[cells].mean(axis=1)
fig, ax = plt.subplots(figsize=(7, 5.5))
quads = PolyCollection(moved[cells] * 1e3, array=magnitude * 1e3, cmap="viridis", edgecolors="face")
ax.add_collection(quads)
needle = session.needle_shape(41)
ax.plot(needle[:, 0] * 1e3, needle[:, 1] * 1e3, "r-", lw=2, label="needle")
ax.autoscale_view()
ax.set_aspect("equal")
ax.set(xlabel="x, depth [mm]", ylabel="y, lateral [mm]",
       title="Tissue displacement at %.0f mm depth (realtime2d)" % (s.depth * 1e3))
fig.colorbar(quads, ax=ax, label="|u| [mm]")
ax.legend(loc="upper right", fontsize=8)
fig.tight_layout()
fig.savefig(OUT / "tissue_displacement.png", dpi=120)
print("wrote", OUT / "force_depth.png", "and", OUT / "tissue_displacement.png")
