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
every vector array 3 components (any array of 2 components fails). Every
tissue file (not the needle) carries an integer `region` per cell (per point for
the particles). A file with a `displacement` keeps its reference points at every
step (the first step's points at the last one), and Warp By Vector (scale 1)
gives reference + displacement, a deformed shape that differs from the reference
(shown as a grey wireframe over the reference coloured by von Mises stress). One
PNG per folder at the last step: the tissue (particles as points) and the needle
in dark grey.
Exit code 1 with one line per failure.
"""
import argparse
import os
import sys
import traceback

import numpy
from paraview import simple
from paraview import vtk
from vtkmodules.util.numpy_support import vtk_to_numpy

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
    """Opens file `name` and reads every step; returns (reader, times, displacement array or None,
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
            if array == "displacement" and association == "POINTS":
                displacement = array
            if scalar is None and components == 1 and array.startswith("von_mises"):
                scalar = (association, array)
    if not os.path.basename(name).startswith("needle"):
        check_region(name, fetch(reader, steps[-1]), failures)
        if displacement is None:
            failures.append(f"{name}: no point array 'displacement'")
    return reader, steps, displacement, scalar


def fetch(proxy, time):
    """The dataset `proxy` gives at `time` (the first block of a multiblock)."""
    data = simple.servermanager.Fetch(simple.ForceTime(Input=proxy, ForcedTime=time, IgnorePipelineTime=1))
    return data.GetBlock(0) if data.IsA("vtkMultiBlockDataSet") else data


def check_region(name, data, failures):
    """A tissue file's integer `region` id on every cell (every point of the particles)."""
    particles = os.path.basename(name).startswith("particles")
    arrays = data.GetPointData() if particles else data.GetCellData()
    region = arrays.GetArray("region")
    where = "point" if particles else "cell"
    if region is None:
        failures.append(f"{name}: no {where} array 'region'")
        return
    values = vtk_to_numpy(region)
    if region.GetDataTypeAsString() in ("float", "double") or len(values) == 0 or values.min() < 0:
        failures.append(f"{name}: '{where} region' is {region.GetDataTypeAsString()} from {values.min()}, not an id >= 0")
    say(f"  region ids {sorted(set(values.tolist()))}")


def warp_to_deformed(name, reader, displacement, steps, errors, failures):
    """Warp By Vector (scale 1) of the reference points by the displacement: the points of the last step
    are the first step's (the reference), and the warped points are reference + displacement, which
    moved (max |u| > 0). Fails when the filter reports an error or the points differ."""
    first, last = fetch(reader, steps[0]), fetch(reader, steps[-1])
    reference = vtk_to_numpy(first.GetPoints().GetData())
    points = vtk_to_numpy(last.GetPoints().GetData())
    u = vtk_to_numpy(last.GetPointData().GetArray(displacement))
    size = float(numpy.abs(reference).max())
    if points.shape != reference.shape or numpy.abs(points - reference).max() > 1e-12 * size:
        failures.append(f"{name}: the points of t = {steps[-1]:g} s are not the reference points of t = {steps[0]:g} s")
    if numpy.abs(u).max() == 0.0:
        failures.append(f"{name}: zero displacement at t = {steps[-1]:g} s: Warp By Vector shows nothing")
    warp = simple.WarpByVector(Input=reader, Vectors=["POINTS", displacement], ScaleFactor=1.0)
    warp.UpdatePipeline(steps[-1])
    for line in errors.take():
        failures.append(f"{name}: Warp By Vector: {line.strip()}")
    warped = vtk_to_numpy(fetch(warp, steps[-1]).GetPoints().GetData())
    if warped.shape != points.shape or numpy.abs(warped - (points + u)).max() > 1e-9 * size:
        failures.append(f"{name}: Warp By Vector does not give reference + displacement")
    else:
        say(f"  Warp By Vector: deformed shape, max |u| = {numpy.linalg.norm(u, axis=1).max():.3g} m")
    return warp


def show_file(view, name, reader, warp, scalar):
    """The needle dark grey; the tissue coloured by its von Mises stress on its reference
    configuration, the deformed one (Warp By Vector) over it as a grey wireframe; particles as points."""
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
        deformed = simple.Show(warp, view)
        deformed.SetRepresentationType("Wireframe")
        deformed.ColorArrayName = ["POINTS", ""]
        deformed.AmbientColor = deformed.DiffuseColor = [0.6, 0.6, 0.6]


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
    end = max(steps[-1] for _, _, steps, _, _ in opened)
    view = simple.CreateRenderView()
    view.ViewSize = [800, 600]
    view.OrientationAxesVisibility = 1
    view.ViewTime = end
    tissue = None  # bounds of everything but the needle
    for f, reader, steps, displacement, scalar in opened:
        warp = None
        if displacement is not None:
            warp = warp_to_deformed(f, reader, displacement, steps, errors, failures)
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
