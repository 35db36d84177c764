"""Shows chosen regions (a tumour, a layer) of a run inside the tissue, in their deformed shape.

Run with ParaView's Python (Debian python3-paraview and xvfb, scripts/bootstrap.sh); Debian's
ParaView renders through X only, so on a machine without a display run it under xvfb-run:

    xvfb-run -a pvpython scripts/paraview/show_regions.py RESULTS_FOLDER --png tumour.png

RESULTS_FOLDER is the folder of `needlesim run` on a scenario with a field_interval: the mpm
particles (particles.xdmf, a `region` per point) or another engine's tissue mesh (tissue.xdmf, a
`region` per cell), and needle.xdmf. `region` numbers the layers of tissue.layers from 0, then the
inclusions of tissue.inclusions (docs/results.md "Field files"; the names are in the .h5 file).
At the last field step (or --time), the points moved by Warp By Vector (displacement): the
regions --regions LO HI (default 1 and up: all but the first layer, the tumour of a one-layer
tissue) in red, the rest of the tissue faint grey, the needle dark grey, seen from the side and above.
Exit code 1 with a message when the folder has no tissue series or it has no region array.
"""
import argparse
import os
import sys

from paraview import simple


def say(text):
    """One line on stdout (pvpython's print() goes through VTK's output window)."""
    os.write(1, (text + "\n").encode())


def open_tissue(folder):
    """(reader, association of `region`) of the folder's particles or tissue series, or None."""
    for name, association in (("particles.xdmf", "POINTS"), ("tissue.xdmf", "CELLS")):
        path = os.path.join(folder, name)
        if os.path.isfile(path):
            return simple.OpenDataFile(path), association, path
    return None


def show_as(display, association, colour, opacity=1.0):
    display.SetRepresentationType("Points" if association == "POINTS" else "Surface")
    display.PointSize = 4
    display.ColorArrayName = ["POINTS", ""]
    display.AmbientColor = display.DiffuseColor = colour
    display.Opacity = opacity


def show(folder, png, regions, time):
    view = simple.CreateRenderView()  # before any data is read: Debian's 5.11 aborts otherwise
    view.ViewSize = [900, 700]
    view.OrientationAxesVisibility = 1
    opened = open_tissue(folder)
    if opened is None:
        say(f"{folder}: no particles.xdmf or tissue.xdmf (run a scenario with a field_interval)")
        return 1
    tissue, association, path = opened
    tissue.UpdatePipelineInformation()
    steps = list(tissue.TimestepValues) if tissue.TimestepValues else [0.0]
    view.ViewTime = steps[-1] if time is None else time
    tissue.UpdatePipeline(view.ViewTime)
    arrays = tissue.PointData if association == "POINTS" else tissue.CellData
    if "region" not in arrays.keys():
        say(f"{path}: no {association.lower()[:-1]} array 'region' (written by needlesim)")
        return 1
    deformed = simple.WarpByVector(Input=tissue, Vectors=["POINTS", "displacement"], ScaleFactor=1.0)
    chosen = simple.Threshold(Input=deformed, Scalars=[association, "region"],
                              LowerThreshold=regions[0], UpperThreshold=regions[1])
    show_as(simple.Show(deformed, view), association, [0.7, 0.7, 0.7], 0.15)
    show_as(simple.Show(chosen, view), association, [0.85, 0.1, 0.1])
    needle_file = os.path.join(folder, "needle.xdmf")
    if os.path.isfile(needle_file):
        needle = simple.Show(simple.OpenDataFile(needle_file), view)
        needle.ColorArrayName = ["POINTS", ""]
        needle.AmbientColor = needle.DiffuseColor = [0.15, 0.15, 0.15]

    chosen.UpdatePipeline(view.ViewTime)
    info = chosen.GetDataInformation()
    count = info.GetNumberOfPoints() if association == "POINTS" else info.GetNumberOfCells()
    b = deformed.GetDataInformation().GetBounds()
    focal = [0.5 * (b[2 * i] + b[2 * i + 1]) for i in range(3)]
    view.CameraFocalPoint = focal
    view.CameraPosition = [focal[0] - 0.5, focal[1] - 1.0, focal[2] + 0.6]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera(b)
    simple.SaveScreenshot(png, view, ImageResolution=[900, 700])
    what = "points" if association == "POINTS" else "cells"
    say(f"{png}: written (t = {view.ViewTime:g} s, {count} {what} in regions {regions[0]} to {regions[1]})")
    simple.Delete(view)
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="needlesim results folder")
    parser.add_argument("--png", default="regions.png", help="picture to write (default %(default)s)")
    parser.add_argument("--regions", type=int, nargs=2, default=[1, 255], metavar=("LO", "HI"),
                        help="the regions to show, LO to HI (default 1 255)")
    parser.add_argument("--time", type=float, default=None, help="field time in s (default: the last step)")
    args = parser.parse_args()
    return show(args.folder, args.png, args.regions, args.time)


if __name__ == "__main__":
    sys.exit(main())
