"""Shows the material points of chosen regions (a tumour, a layer) of an mpm run inside the tissue.

Run with ParaView's Python (Debian python3-paraview and xvfb, scripts/bootstrap.sh); Debian's
ParaView renders through X only, so on a machine without a display run it under xvfb-run:

    xvfb-run -a pvpython scripts/paraview/show_regions.py RESULTS_FOLDER --png tumour.png

RESULTS_FOLDER is the folder of `needlesim run` on an mpm scenario with a field_interval
(particles.xdmf, needle.xdmf). `region [1]` numbers the layers of tissue.layers from 0, then the
inclusions of tissue.inclusions (docs/results.md "Field files"; the names are in particles.h5).
At the last field step (or --time): the particles of regions --regions LO HI (default 1 and up:
all but the first layer, the tumour of a one-layer tissue) as red points, the other particles
as faint grey points, the needle dark grey, seen from the side and above.
Exit code 1 with a message when the folder has no particle series or it has no region array.
"""
import argparse
import os
import sys

from paraview import simple


def say(text):
    """One line on stdout (pvpython's print() goes through VTK's output window)."""
    os.write(1, (text + "\n").encode())


def show(folder, png, regions, time):
    particles_file = os.path.join(folder, "particles.xdmf")
    if not os.path.isfile(particles_file):
        say(f"{folder}: no particles.xdmf (run an mpm scenario with model.mpm.field_interval)")
        return 1
    view = simple.CreateRenderView()  # before any data is read: Debian's 5.11 aborts otherwise
    view.ViewSize = [900, 700]
    view.OrientationAxesVisibility = 1
    particles = simple.OpenDataFile(particles_file)
    particles.UpdatePipelineInformation()
    steps = list(particles.TimestepValues) if particles.TimestepValues else [0.0]
    view.ViewTime = steps[-1] if time is None else time
    particles.UpdatePipeline(view.ViewTime)
    if "region [1]" not in particles.PointData.keys():
        say(f"{particles_file}: no point array 'region [1]' (written by needlesim's mpm engine)")
        return 1
    chosen = simple.Threshold(Input=particles, Scalars=["POINTS", "region [1]"],
                              LowerThreshold=regions[0], UpperThreshold=regions[1])
    rest = simple.Show(particles, view)
    rest.SetRepresentationType("Points")
    rest.ColorArrayName = ["POINTS", ""]
    rest.Opacity = 0.15
    shown = simple.Show(chosen, view)
    shown.SetRepresentationType("Points")
    shown.PointSize = 4
    shown.ColorArrayName = ["POINTS", ""]
    shown.AmbientColor = shown.DiffuseColor = [0.85, 0.1, 0.1]
    needle_file = os.path.join(folder, "needle.xdmf")
    if os.path.isfile(needle_file):
        needle = simple.Show(simple.OpenDataFile(needle_file), view)
        needle.ColorArrayName = ["POINTS", ""]
        needle.AmbientColor = needle.DiffuseColor = [0.15, 0.15, 0.15]

    chosen.UpdatePipeline(view.ViewTime)
    count = chosen.GetDataInformation().GetNumberOfPoints()
    b = particles.GetDataInformation().GetBounds()
    focal = [0.5 * (b[2 * i] + b[2 * i + 1]) for i in range(3)]
    view.CameraFocalPoint = focal
    view.CameraPosition = [focal[0] - 0.5, focal[1] - 1.0, focal[2] + 0.6]
    view.CameraViewUp = [0.0, 0.0, 1.0]
    view.ResetCamera(b)
    simple.SaveScreenshot(png, view, ImageResolution=[900, 700])
    say(f"{png}: written (t = {view.ViewTime:g} s, {count} points in regions {regions[0]} to {regions[1]})")
    simple.Delete(view)
    return 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", help="needlesim results folder of an mpm run")
    parser.add_argument("--png", default="regions.png", help="picture to write (default %(default)s)")
    parser.add_argument("--regions", type=int, nargs=2, default=[1, 255], metavar=("LO", "HI"),
                        help="the regions to show, LO to HI (default 1 255)")
    parser.add_argument("--time", type=float, default=None, help="field time in s (default: the last step)")
    args = parser.parse_args()
    return show(args.folder, args.png, args.regions, args.time)


if __name__ == "__main__":
    sys.exit(main())
