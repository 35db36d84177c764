#!/usr/bin/python3
"""Writes the VTK XML PolyData surfaces (.vtp) of tests/mesh/test_gmsh_reader.cpp
(GmshSurfaces.VtpSurfacesInEveryEncodingAreRead) with VTK's own writer, in every encoding the
reader handles. Not run by CI: the files it writes are committed. Run it again with
    /usr/bin/python3 tests/mesh/data/make_vtp.py
(VTK from Debian's python3-paraview or `pip install vtk`).

tet_*.vtp:    the tetrahedron (0,0,0), (10,0,0), (0,10,0), (0,0,10), faces outward (Float64 points,
              four triangles).
sphere_*.vtp: vtkSphereSource (radius 1, theta and phi resolution 8; Float32 points).
Encodings: ascii, binary (inline base64, uncompressed), binary_zlib, appended_raw,
appended_zlib (VTK's default), appended_base64 (uncompressed), appended_base64_zlib, and
binary_zlib_u64 / appended_zlib_u64 (header_type UInt64); v10_* copies of appended_zlib and
binary marked version="1.0" as VTK 9.1 and later write them (this VTK writes version="0.1"; the
layout of PolyData is the same).
"""
import os
import re

from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkFiltersSources import vtkSphereSource
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter
from vtkmodules.util.vtkConstants import VTK_DOUBLE

HERE = os.path.dirname(os.path.abspath(__file__))


def tetrahedron():
    points = vtkPoints()
    points.SetDataType(VTK_DOUBLE)
    for p in [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]:
        points.InsertNextPoint(p)
    polys = vtkCellArray()
    for f in [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]:
        polys.InsertNextCell(3, f)
    surface = vtkPolyData()
    surface.SetPoints(points)
    surface.SetPolys(polys)
    return surface


def sphere():
    source = vtkSphereSource()
    source.SetRadius(1.0)
    source.SetThetaResolution(8)
    source.SetPhiResolution(8)
    source.Update()
    return source.GetOutput()


ENCODINGS = {  # name: (data mode, compressed, base64 appended, UInt64 header)
    "ascii": ("ascii", False, False, False),
    "binary": ("binary", False, False, False),
    "binary_zlib": ("binary", True, False, False),
    "binary_zlib_u64": ("binary", True, False, True),
    "appended_raw": ("appended", False, False, False),
    "appended_zlib": ("appended", True, False, False),
    "appended_zlib_u64": ("appended", True, False, True),
    "appended_base64": ("appended", False, True, False),
    "appended_base64_zlib": ("appended", True, True, False),
}


def write(surface, path, mode, compressed, base64, uint64):
    w = vtkXMLPolyDataWriter()
    w.SetInputData(surface)
    w.SetFileName(path)
    {"ascii": w.SetDataModeToAscii, "binary": w.SetDataModeToBinary, "appended": w.SetDataModeToAppended}[mode]()
    if compressed:
        w.SetCompressorTypeToZLib()
    else:
        w.SetCompressorTypeToNone()
    w.SetEncodeAppendedData(base64)
    if uint64:
        w.SetHeaderTypeToUInt64()
    else:
        w.SetHeaderTypeToUInt32()
    w.SetByteOrderToLittleEndian()
    assert w.Write() == 1, path


def version10(source, target):
    with open(os.path.join(HERE, source), "rb") as f:
        data = f.read()
    data = re.sub(rb'version="[0-9.]+"', b'version="1.0"', data, count=1)
    with open(os.path.join(HERE, target), "wb") as f:
        f.write(data)


for shape, surface in [("tet", tetrahedron()), ("sphere", sphere())]:
    for name, spec in ENCODINGS.items():
        write(surface, os.path.join(HERE, f"{shape}_{name}.vtp"), *spec)
    version10(f"{shape}_appended_zlib.vtp", f"{shape}_v10_appended_zlib.vtp")
    version10(f"{shape}_binary.vtp", f"{shape}_v10_binary.vtp")
