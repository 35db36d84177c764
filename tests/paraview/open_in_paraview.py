"""Opens every field file of needlesim results folders as ParaView's File > Open does.

Run with ParaView's Python (Debian python3-paraview, scripts/bootstrap.sh):

    xvfb-run -a pvpython tests/paraview/open_in_paraview.py --png-dir PNGS RESULTS_FOLDER...

Headless machines: the Debian ParaView 5.11 build renders through X only
(--force-offscreen-rendering and pvbatch still open an X display and abort
without one), so pvpython runs against a virtual X server: xvfb-run (Debian
xvfb) as above, or the private Xvfb that field_files_test.sh starts.

For each folder: every *.xdmf opens through the default reader (OpenDataFile,
the reader the GUI picks), every time step is read (a reader error at any
step fails), every step must have points and cells, and at the last step
every vector array 3 components (any array of 2 components fails). A
displacement gets Warp By Vector (scale -1: the points are the moved ones, so
it gives the reference configuration, shown as a grey wireframe). One PNG per
folder at the last step: the tissue coloured by von Mises stress (particles as
points) and the needle in dark grey.
Exit code 1 with one line per failure.
"""
import argparse
import os
import sys
import traceback

from paraview import simple
from paraview import vtk

# Vector arrays needlesim writes (docs/results.md); any array of 2 components is a 2D vector too.
VECTOR_NAMES = ("displacement", "velocity")


def say(text):
    """One line on stdout (pvpython sends print() and tracebacks through VTK's output window,
    which ReaderErrors captures)."""
    os.write(1, (text + "\n").encode())


class ReaderErrors:
    """Collects the error messages VTK's readers report (they do not raise in Python)."""

    def __init__(self):
        self.window = vtk.vtkStringOutputWindow()
        vtk.vtkOutputWindow.SetInstance(self.window)

    def take(self):
        text = self.window.GetOutput()
        self.window = vtk.vtkStringOutputWindow()
        vtk.vtkOutputWindow.SetInstance(self.window)
        return [line for line in text.splitlines() if "ERR" in line or "Error" in line or "error" in line]


def array_names(data_information, association):
    if association == "POINTS":
        info = data_information.GetPointDataInformation()
    else:
        info = data_information.GetCellDataInformation()
    return [(info.GetArrayInformation(i).GetName(), info.GetArrayInformation(i).GetNumberOfComponents())
            for i in range(info.GetNumberOfArrays())]


def check_file(name, errors, failures):
    """Opens file `name` and reads every step; returns (reader, last time, displacement array or None,
    scalar to colour by or None), or None when it does not open."""
    try:
        reader = simple.OpenDataFile(name)
    except Exception as e:  # ParaView raises for a file its reader cannot parse
        failures.append(f"{name}: does not open: {e}")
        return None
    if reader is None:
        failures.append(f"{name}: no reader opens it")
        return None
    reader.UpdatePipelineInformation()
    steps = list(reader.TimestepValues) if reader.TimestepValues else [0.0]
    for t in steps:  # every step, the last one last
        reader.UpdatePipeline(t)
        for line in errors.take():
            failures.append(f"{name}: t = {t:g} s: {line.strip()}")
        info = reader.GetDataInformation()
        npoints, ncells = info.GetNumberOfPoints(), info.GetNumberOfCells()
        if npoints == 0 or ncells == 0:
            failures.append(f"{name}: t = {t:g} s: {npoints} points and {ncells} cells")
    say(f"{name}: reader {reader.GetXMLName()}, {len(steps)} steps, last t = {steps[-1]:g} s: "
        f"{npoints} points, {ncells} cells")
    displacement, scalar = None, None
    for association in ("POINTS", "CELLS"):
        for array, components in array_names(info, association):
            say(f"  {association.lower()[:-1]} array '{array}': {components} components")
            if (array.split(" ")[0] in VECTOR_NAMES and components != 3) or components == 2:
                failures.append(f"{name}: vector '{array}' has {components} components, not 3")
            if array.startswith("displacement") and association == "POINTS":
                displacement = array
            if scalar is None and components == 1 and array.startswith("von_mises"):
                scalar = (association, array)
    return reader, steps[-1], displacement, scalar


def warp_to_reference(name, reader, displacement, time, errors, failures):
    """Warp By Vector by -displacement: the points are the moved ones, so this gives the reference
    configuration. Fails when the filter reports an error or loses points."""
    warp = simple.WarpByVector(Input=reader, Vectors=["POINTS", displacement], ScaleFactor=-1.0)
    warp.UpdatePipeline(time)
    for line in errors.take():
        failures.append(f"{name}: Warp By Vector: {line.strip()}")
    if warp.GetDataInformation().GetNumberOfPoints() != reader.GetDataInformation().GetNumberOfPoints():
        failures.append(f"{name}: Warp By Vector gives {warp.GetDataInformation().GetNumberOfPoints()} points")
    return warp


def show_file(view, name, reader, warp, scalar):
    """The needle dark grey; the tissue coloured by its von Mises stress over its reference
    configuration (wireframe); particles as points."""
    display = simple.Show(reader, view)
    if name.startswith("needle"):
        display.ColorArrayName = ["POINTS", ""]
        display.DiffuseColor = [0.15, 0.15, 0.15]
        display.AmbientColor = [0.15, 0.15, 0.15]
        display.LineWidth = 3.0
        return
    if scalar is not None:
        simple.ColorBy(display, scalar)
        display.RescaleTransferFunctionToDataRange(False, True)
        display.SetScalarBarVisibility(view, True)
    if name.startswith("particles"):
        display.SetRepresentationType("Points")
        display.PointSize = 3
    elif warp is not None:
        reference = simple.Show(warp, view)
        reference.SetRepresentationType("Wireframe")
        reference.ColorArrayName = ["POINTS", ""]
        reference.AmbientColor = reference.DiffuseColor = [0.6, 0.6, 0.6]


def frame_tissue(view, bounds):
    """The camera on the tissue with a margin (the needle reaches out of the picture): a 2D
    series (z = 0) seen down z, a 3D one from the side and above."""
    simple.ResetCamera(view)
    if bounds is None:
        return
    flat = bounds[4] == 0.0 and bounds[5] == 0.0
    if not flat:
        view.CameraPosition = [c + d for c, d in zip(view.CameraFocalPoint, [-0.9, -1.0, 0.6])]
        view.CameraViewUp = [0.0, 0.0, 1.0]
    margin = [0.4 * (bounds[2 * i + 1] - bounds[2 * i]) for i in range(3)]
    view.ResetCamera([bounds[k] + (margin[k // 2] if k % 2 else -margin[k // 2]) for k in range(6)])


def render_folder(folder, png_dir, failures):
    errors = ReaderErrors()
    files = sorted(f for f in os.listdir(folder) if f.endswith(".xdmf"))
    if not files:
        failures.append(f"{folder}: no .xdmf field file")
        return
    opened = []
    for f in files:
        result = check_file(os.path.join(folder, f), errors, failures)
        if result is not None:
            opened.append((f,) + result)
    if not opened:
        return
    end = max(time for _, _, time, _, _ in opened)
    view = simple.CreateRenderView()
    view.ViewSize = [800, 600]
    view.OrientationAxesVisibility = 1
    view.ViewTime = end
    tissue = None  # bounds of everything but the needle
    for f, reader, time, displacement, scalar in opened:
        warp = None
        if displacement is not None:
            warp = warp_to_reference(f, reader, displacement, time, errors, failures)
        show_file(view, f, reader, warp, scalar)
        if not f.startswith("needle"):
            tissue = reader.GetDataInformation().GetBounds()
    frame_tissue(view, tissue)
    png = os.path.join(png_dir, os.path.basename(os.path.normpath(folder)) + ".png")
    simple.SaveScreenshot(png, view, ImageResolution=[800, 600])
    say(f"{png}: written (t = {end:g} s)")
    for line in errors.take():
        failures.append(f"{folder}: rendering: {line.strip()}")
    simple.Delete(view)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--png-dir", required=True, help="folder for one PNG per results folder")
    parser.add_argument("folders", nargs="+", help="needlesim results folders")
    args = parser.parse_args()
    os.makedirs(args.png_dir, exist_ok=True)
    failures = []
    for folder in args.folders:
        try:
            render_folder(folder, args.png_dir, failures)
        except Exception:  # its traceback would go to the captured output window
            failures.append(f"{folder}: {traceback.format_exc()}")
    for f in failures:
        say(f"FAIL: {f}")
    say(f"{len(args.folders)} folders, {len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
