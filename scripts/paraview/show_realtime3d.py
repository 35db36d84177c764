"""Cuts a realtime3d tissue open along the needle path and saves a picture of its displacement.

Run with ParaView's Python (Debian python3-paraview and xvfb, scripts/bootstrap.sh); Debian's
ParaView renders through X only, so on a machine without a display run it under xvfb-run:

    xvfb-run -a pvpython scripts/paraview/show_realtime3d.py RESULTS_FOLDER --png cut.png

RESULTS_FOLDER is the folder of `needlesim run` on a realtime3d scenario with a field_interval
(tissue.xdmf, needle.xdmf; docs/results.md "Field files"). At the last field step (or --time):
the tissue, deformed by Warp By Vector (its points are the reference ones), is clipped by the
plane that holds the needle's centre line and the vertical (z) axis, its cut face coloured by
the magnitude of `displacement` (in mm; the array is in m), the far half kept
and seen face-on, the uncut block as a grey outline and the needle as a dark tube. The same
steps in the ParaView GUI: docs/results.md "Seeing inside a realtime3d tissue".
Exit code 1 with a message when the folder has no tissue series.
"""
import argparse
import os
import sys

from paraview import simple


def say(text):
    """One line on stdout (pvpython's print() goes through VTK's output window)."""
    os.write(1, (text + "\n").encode())


def needle_line(needle, time):
    """Start and end point of the needle's centre line at `time` (None without a needle series)."""
    if needle is None:
        return None
    needle.UpdatePipeline(time)
    data = simple.servermanager.Fetch(needle)
    if data.GetNumberOfPoints() < 2:
        return None
    return data.GetPoint(0), data.GetPoint(data.GetNumberOfPoints() - 1)


def cut_plane(tissue_bounds, line):
    """Origin and normal of the plane through the needle line and the z axis (without a needle:
    the tissue's mid-plane y = const)."""
    centre = [0.5 * (tissue_bounds[2 * i] + tissue_bounds[2 * i + 1]) for i in range(3)]
    if line is None:
        return centre, [0.0, 1.0, 0.0]
    a, b = line
    d = [b[i] - a[i] for i in range(3)]
    normal = [d[1], -d[0], 0.0]  # d x z
    length = (normal[0] ** 2 + normal[1] ** 2) ** 0.5
    if length < 1e-12 * max(1.0, sum(x * x for x in d) ** 0.5):  # a vertical needle
        return list(b), [0.0, 1.0, 0.0]
    return list(b), [n / length for n in normal]


def show(folder, png, time):
    tissue_file = os.path.join(folder, "tissue.xdmf")
    if not os.path.isfile(tissue_file):
        say(f"{folder}: no tissue.xdmf (run a realtime3d scenario with model.realtime3d.field_interval)")
        return 1
    view = simple.CreateRenderView()  # before any data is fetched: Debian's 5.11 aborts otherwise
    tissue = simple.OpenDataFile(tissue_file)
    needle_file = os.path.join(folder, "needle.xdmf")
    needle = simple.OpenDataFile(needle_file) if os.path.isfile(needle_file) else None
    tissue.UpdatePipelineInformation()
    steps = list(tissue.TimestepValues) if tissue.TimestepValues else [0.0]
    t = steps[-1] if time is None else time
    tissue.UpdatePipeline(t)
    bounds = tissue.GetDataInformation().GetBounds()
    origin, normal = cut_plane(bounds, needle_line(needle, t))

    # the deformed shape, its displacement magnitude in mm (the array is in metres)
    deformed = simple.WarpByVector(Input=tissue, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
    mm = simple.Calculator(Input=deformed, AttributeType="Point Data", ResultArrayName="|displacement| [mm]",
                           Function="1000*mag(displacement)")
    clip = simple.Clip(Input=mm, ClipType="Plane")
    clip.ClipType.Origin = origin
    clip.ClipType.Normal = normal
    clip.Invert = 0  # keep the half the normal points into: the camera looks at its cut face

    view.ViewSize = [900, 700]
    view.ViewTime = t
    view.OrientationAxesVisibility = 1
    cut = simple.Show(clip, view)
    simple.ColorBy(cut, ("POINTS", "|displacement| [mm]"))
    cut.RescaleTransferFunctionToDataRange(False, True)
    lut = simple.GetColorTransferFunction("|displacement| [mm]")
    lut.ApplyPreset("Viridis (matplotlib)", True)
    cut.SetScalarBarVisibility(view, True)
    outline = simple.Show(simple.Outline(Input=tissue), view)
    outline.AmbientColor = outline.DiffuseColor = [0.5, 0.5, 0.5]
    if needle is not None:
        tube = simple.Show(simple.Tube(Input=simple.ExtractSurface(Input=needle), Radius=0.006 * max(bounds[1] - bounds[0], 1e-9)), view)
        tube.ColorArrayName = ["POINTS", ""]
        tube.AmbientColor = tube.DiffuseColor = [0.15, 0.15, 0.15]

    # face-on to the cut face, from the side the clip removed, framing the tissue (not the needle)
    focal = [0.5 * (bounds[2 * i] + bounds[2 * i + 1]) for i in range(3)]
    view.CameraFocalPoint = focal
    view.CameraPosition = [focal[i] - normal[i] for i in range(3)]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.CameraParallelProjection = 1
    margin = [0.1 * (bounds[2 * i + 1] - bounds[2 * i]) for i in range(3)]
    view.ResetCamera([bounds[k] + (margin[k // 2] if k % 2 else -margin[k // 2]) for k in range(6)])
    simple.SaveScreenshot(png, view, ImageResolution=[900, 700])
    say(f"{png}: written (t = {t:g} s, cut through {', '.join(f'{x:.4g}' for x in origin)} m, "
        f"normal {', '.join(f'{x:.3g}' for x in normal)})")
    simple.Delete(view)
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="needlesim results folder of a realtime3d run")
    parser.add_argument("--png", default="realtime3d_cut.png", help="picture to write (default %(default)s)")
    parser.add_argument("--time", type=float, default=None, help="field time in s (default: the last step)")
    args = parser.parse_args()
    return show(args.folder, args.png, args.time)


if __name__ == "__main__":
    sys.exit(main())
