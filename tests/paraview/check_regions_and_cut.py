"""Checks, in ParaView's Python, what a user needs to see the inside of the tissue:

    pvpython tests/paraview/check_regions_and_cut.py MPM_INCLUSION_FOLDER CUT_PNG REGIONS_PNG \
        [REALTIME3D_FOLDER [IMPORTED_FOLDER]]

- the mpm particles of MPM_INCLUSION_FOLDER (tests/paraview/scenarios/mpm_inclusion.yaml: one
  layer, region 0, and a sphere of radius 1.5 mm centred 4 mm deep on the axis, region 1) carry
  an integer point array `region` that marks every point well inside the sphere with 1 and
  every point well outside it with 0;
- the tets of REALTIME3D_FOLDER (tests/paraview/scenarios/realtime3d.yaml: a sphere of radius
  8 mm centred 15 mm deep on the axis, region 1) carry an integer cell array `region`: 1 for
  every tet whose centroid (the reference points) lies inside the sphere, 0 for the others,
  and some of each; a Threshold on it from 1 to 1 keeps exactly those tets;
- the triangles of IMPORTED_FOLDER (examples/realtime2d/imported_block.yaml: the disc is the
  mesh's group of inclusion 0, region 1) carry the mesh's regions: the disc's triangles 1 (the
  disc of radius 5 mm centred 4 mm beside the path, 35 mm deep: imported_block.geo), the others 0;
- CUT_PNG (scripts/paraview/show_realtime3d.py on a realtime3d run) shows more than a uniform
  surface: over 30 distinct colours of at least 20 pixels each in its middle (the central half
  in width and height, where the tissue is framed; the colour legend lies outside it). Lines
  (the outline, the needle) add many colours of a few pixels each through antialiasing, an
  empty or uniform view fewer than 10 of 20 pixels.
- REGIONS_PNG (scripts/paraview/show_regions.py on MPM_INCLUSION_FOLDER) shows the inclusion's
  points in red: over 500 red pixels (the axes' red x arrow has fewer than 100).
Exit code 1 with one line per failure.
"""
import os
import sys

from paraview import simple
from vtkmodules.vtkIOImage import vtkPNGReader

CENTRE, RADIUS, SPACING = (4e-3, 0.0, 0.0), 1.5e-3, 0.5e-3  # the scenario's inclusion and particle spacing
TET_CENTRE, TET_RADIUS = (15e-3, 0.0, 0.0), 8e-3  # the realtime3d scenario's inclusion
MIN_COLOURS, MIN_PIXELS = 30, 20
MIN_RED = 500


def say(text):
    os.write(1, (text + "\n").encode())


def check_regions(folder, failures):
    reader = simple.OpenDataFile(os.path.join(folder, "particles.xdmf"))
    reader.UpdatePipelineInformation()
    reader.UpdatePipeline(reader.TimestepValues[0] if reader.TimestepValues else 0.0)  # reference positions
    data = simple.servermanager.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    region = data.GetPointData().GetArray("region")
    if region is None:
        failures.append(f"{folder}/particles.xdmf: no point array 'region'")
        return
    if region.GetDataTypeAsString() in ("float", "double"):
        failures.append(f"{folder}/particles.xdmf: 'region' is {region.GetDataTypeAsString()}, not an integer")
    inside = 0
    for p in range(data.GetNumberOfPoints()):
        x = data.GetPoint(p)
        r = sum((x[i] - CENTRE[i]) ** 2 for i in range(3)) ** 0.5
        value = region.GetValue(p)
        if r < RADIUS - SPACING and value != 1:
            failures.append(f"point {p} at {r * 1e3:.2f} mm from the inclusion's centre has region {value}, not 1")
        elif r > RADIUS + SPACING and value != 0:
            failures.append(f"point {p} at {r * 1e3:.2f} mm from the inclusion's centre has region {value}, not 0")
        inside += value == 1
    say(f"{folder}/particles.xdmf: {inside} of {data.GetNumberOfPoints()} points in region 1")
    if inside == 0:
        failures.append(f"{folder}/particles.xdmf: no point in region 1 (the inclusion)")


def check_cell_regions(folder, failures):
    reader = simple.OpenDataFile(os.path.join(folder, "tissue.xdmf"))
    reader.UpdatePipelineInformation()
    reader.UpdatePipeline(reader.TimestepValues[-1] if reader.TimestepValues else 0.0)
    data = simple.servermanager.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    region = data.GetCellData().GetArray("region")
    if region is None or region.GetDataTypeAsString() in ("float", "double"):
        failures.append(f"{folder}/tissue.xdmf: no integer cell array 'region'")
        return
    inside = 0
    for c in range(data.GetNumberOfCells()):
        ids = data.GetCell(c).GetPointIds()
        centroid = [sum(data.GetPoint(ids.GetId(k))[i] for k in range(4)) / 4 for i in range(3)]
        r = sum((centroid[i] - TET_CENTRE[i]) ** 2 for i in range(3)) ** 0.5
        expected = 1 if r <= TET_RADIUS else 0
        if region.GetValue(c) != expected:
            failures.append(f"{folder}/tissue.xdmf: tet {c} at {r * 1e3:.2f} mm from the sphere's centre has region "
                            f"{region.GetValue(c)}, not {expected}")
        inside += expected
    tumour = simple.Threshold(Input=reader, Scalars=["CELLS", "region"], LowerThreshold=1, UpperThreshold=1)
    tumour.UpdatePipeline(reader.TimestepValues[-1] if reader.TimestepValues else 0.0)
    kept = tumour.GetDataInformation().GetNumberOfCells()
    say(f"{folder}/tissue.xdmf: {inside} of {data.GetNumberOfCells()} tets in region 1, Threshold keeps {kept}")
    if inside == 0 or inside == data.GetNumberOfCells() or kept != inside:
        failures.append(f"{folder}/tissue.xdmf: {inside} tets in the sphere, Threshold on region 1 keeps {kept}")


def check_imported_regions(folder, failures):
    reader = simple.OpenDataFile(os.path.join(folder, "tissue.xdmf"))
    reader.UpdatePipeline(0.0)
    data = simple.servermanager.Fetch(reader)
    if data.IsA("vtkMultiBlockDataSet"):
        data = data.GetBlock(0)
    region = data.GetCellData().GetArray("region")
    if region is None:
        failures.append(f"{folder}/tissue.xdmf: no cell array 'region'")
        return
    counts = {}
    for c in range(data.GetNumberOfCells()):
        counts[region.GetValue(c)] = counts.get(region.GetValue(c), 0) + 1
    say(f"{folder}/tissue.xdmf: cells per region {dict(sorted(counts.items()))}")
    if sorted(counts) != [0, 1]:
        failures.append(f"{folder}/tissue.xdmf: regions {sorted(counts)}, not the gel 0 and the disc 1")


def read_png(png, failures):
    if not os.path.isfile(png):
        failures.append(f"{png}: not written")
        return None
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    return reader.GetOutput()


def check_red(png, failures):
    image = read_png(png, failures)
    if image is None:
        return
    pixels = image.GetPointData().GetScalars()
    red = 0
    for i in range(pixels.GetNumberOfTuples()):
        r, g, b = (pixels.GetComponent(i, c) for c in range(3))
        red += r > 150 and g < 80 and b < 80
    say(f"{png}: {red} red pixels")
    if red <= MIN_RED:
        failures.append(f"{png}: {red} red pixels, at most {MIN_RED}: the inclusion is not shown")


def check_picture(png, failures):
    image = read_png(png, failures)
    if image is None:
        return
    width, height, _ = image.GetDimensions()
    pixels = image.GetPointData().GetScalars()
    comps = min(pixels.GetNumberOfComponents(), 3)
    colours = {}
    for row in range(height // 4, 3 * height // 4):
        for column in range(width // 4, 3 * width // 4):
            i = row * width + column
            colour = tuple(int(pixels.GetComponent(i, c)) for c in range(comps))
            colours[colour] = colours.get(colour, 0) + 1
    areas = sum(1 for count in colours.values() if count >= MIN_PIXELS)
    say(f"{png}: {areas} distinct colours of at least {MIN_PIXELS} pixels in the middle")
    if areas <= MIN_COLOURS:
        failures.append(f"{png}: {areas} distinct colours of at least {MIN_PIXELS} pixels in the middle, "
                        f"at most {MIN_COLOURS}: a uniform picture")


def main():
    failures = []
    check_regions(sys.argv[1], failures)
    check_picture(sys.argv[2], failures)
    check_red(sys.argv[3], failures)
    if len(sys.argv) > 4:
        check_cell_regions(sys.argv[4], failures)
    if len(sys.argv) > 5:
        check_imported_regions(sys.argv[5], failures)
    for f in failures[:20]:
        say(f"FAIL: {f}")
    say(f"{len(failures)} failures")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
