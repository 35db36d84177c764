#!/usr/bin/env python3
"""Writes the geometry readers' fuzz corpus (tests/fuzz/corpus/<target>/): small valid surfaces
(a cube, a tetrahedron) in STL ascii and binary, OBJ, PLY (ascii, both binary byte orders, with
extra properties and elements), OFF, and 2D meshes in Gmsh formats 2.2 and 4.1 (ASCII and
binary), and short .geo scripts. VTP inputs are copies of tests/mesh/data (VTK's own writer)."""
import os
import shutil
import struct

HERE = os.path.dirname(os.path.abspath(__file__))
CORPUS = os.path.join(HERE, "corpus")

CUBE = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (10, 10, 0), (0, 0, 10), (10, 0, 10), (0, 10, 10), (10, 10, 10)]
CUBE_F = [(0, 2, 1), (1, 2, 3), (4, 5, 6), (5, 7, 6), (0, 1, 4), (1, 5, 4),
          (2, 6, 3), (3, 6, 7), (0, 4, 2), (2, 4, 6), (1, 3, 5), (3, 7, 5)]
TET = [(0, 0, 0), (10, 0, 0), (0, 10, 0), (0, 0, 10)]
TET_F = [(0, 2, 1), (0, 1, 3), (0, 3, 2), (1, 2, 3)]


def write(target, name, data):
    os.makedirs(os.path.join(CORPUS, target), exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    with open(os.path.join(CORPUS, target, name), mode) as f:
        f.write(data)


def fmt(x):
    return ("%g" % x)


def stl_ascii(v, f, name):
    s = "solid %s\n" % name
    for t in f:
        s += "  facet normal 0 0 0\n    outer loop\n"
        for i in t:
            s += "      vertex %s %s %s\n" % tuple(fmt(c) for c in v[i])
        s += "    endloop\n  endfacet\n"
    return s + "endsolid %s\n" % name


def stl_binary(v, f, header=b"binary STL written for the fuzz corpus"):
    b = header.ljust(80, b" ") + struct.pack("<I", len(f))
    for t in f:
        b += struct.pack("<3f", 0, 0, 0)
        for i in t:
            b += struct.pack("<3f", *v[i])
        b += struct.pack("<H", 0)
    return b


def ply(v, f, form, extra=False):
    endian = {"binary_little_endian": "<", "binary_big_endian": ">"}.get(form)
    head = "ply\nformat %s 1.0\ncomment fuzz corpus\nelement vertex %d\n" % (form, len(v))
    head += "property float x\nproperty float y\nproperty float z\n"
    if extra:
        head += "property uchar red\nproperty uchar green\nproperty uchar blue\n"
    head += "element face %d\nproperty list uchar int vertex_indices\n" % len(f)
    if extra:
        head += "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
    head += "end_header\n"
    if endian is None:
        s = head
        for p in v:
            s += " ".join(fmt(c) for c in p) + (" 255 0 0" if extra else "") + "\n"
        for t in f:
            s += "3 " + " ".join(str(i) for i in t) + "\n"
        if extra:
            s += "0 1\n"
        return s
    b = head.encode()
    for p in v:
        b += struct.pack(endian + "3f", *p) + (struct.pack("3B", 255, 0, 0) if extra else b"")
    for t in f:
        b += struct.pack(endian + "B3i", 3, *t)
    if extra:
        b += struct.pack(endian + "2i", 0, 1)
    return b


def off(v, f, quads=False):
    s = "OFF\n# fuzz corpus\n%d %d 0\n" % (len(v), len(f))
    for p in v:
        s += " ".join(fmt(c) for c in p) + "\n"
    for t in f:
        s += "%d %s\n" % (len(t), " ".join(str(i) for i in t))
    return s


def obj(v, f):
    s = "# fuzz corpus\no body\n"
    for p in v:
        s += "v %s\n" % " ".join(fmt(c) for c in p)
    for t in f:
        s += "f %s\n" % " ".join("%d/%d/%d" % (i + 1, 1, 1) for i in t)
    return s


# A 20 x 20 square of four triangles around its centre, groups gel (1) and tumour (2).
SQ = [(0, -10, 0), (20, -10, 0), (20, 10, 0), (0, 10, 0), (10, 0, 0)]
SQ_E = [((0, 1, 4), 1), ((1, 2, 4), 1), ((2, 3, 4), 1), ((3, 0, 4), 2)]
NAMES = '$PhysicalNames\n2\n2 1 "gel"\n2 2 "tumour"\n$EndPhysicalNames\n'


def msh2(binary):
    head = "$MeshFormat\n2.2 %d 8\n" % binary
    if not binary:
        s = head + "$EndMeshFormat\n" + NAMES + "$Nodes\n%d\n" % len(SQ)
        s += "".join("%d %s\n" % (i + 1, " ".join(fmt(c) for c in p)) for i, p in enumerate(SQ))
        s += "$EndNodes\n$Elements\n%d\n" % len(SQ_E)
        s += "".join("%d 2 2 %d %d %s\n" % (e + 1, g, g, " ".join(str(n + 1) for n in t)) for e, (t, g) in enumerate(SQ_E))
        return s + "$EndElements\n"
    b = head.encode() + struct.pack("<i", 1) + b"\n$EndMeshFormat\n" + NAMES.encode()
    b += b"$Nodes\n%d\n" % len(SQ)
    for i, p in enumerate(SQ):
        b += struct.pack("<i3d", i + 1, *p)
    b += b"\n$EndNodes\n$Elements\n%d\n" % len(SQ_E)
    b += struct.pack("<3i", 2, len(SQ_E), 2)
    for e, (t, g) in enumerate(SQ_E):
        b += struct.pack("<6i", e + 1, g, g, *(n + 1 for n in t))
    return b + b"\n$EndElements\n"


def msh4(binary):
    # entities: one surface per group (tags 1 and 2), physical tags 1 and 2
    head = "$MeshFormat\n4.1 %d 8\n" % binary
    groups = {1: [e for e in SQ_E if e[1] == 1], 2: [e for e in SQ_E if e[1] == 2]}
    if not binary:
        s = head + "$EndMeshFormat\n" + NAMES
        s += "$Entities\n0 0 2 0\n"
        for g in (1, 2):
            s += "%d 0 -10 0 20 10 0 1 %d 0\n" % (g, g)
        s += "$EndEntities\n$Nodes\n1 %d 1 %d\n2 1 0 %d\n" % (len(SQ), len(SQ), len(SQ))
        s += "".join("%d\n" % (i + 1) for i in range(len(SQ)))
        s += "".join("%s\n" % " ".join(fmt(c) for c in p) for p in SQ)
        s += "$EndNodes\n$Elements\n2 %d 1 %d\n" % (len(SQ_E), len(SQ_E))
        e = 1
        for g in (1, 2):
            s += "2 %d 2 %d\n" % (g, len(groups[g]))
            for t, _ in groups[g]:
                s += "%d %s\n" % (e, " ".join(str(n + 1) for n in t))
                e += 1
        return s + "$EndElements\n"
    b = head.encode() + struct.pack("<i", 1) + b"\n$EndMeshFormat\n" + NAMES.encode()
    b += b"$Entities\n" + struct.pack("<4Q", 0, 0, 2, 0)
    for g in (1, 2):
        b += struct.pack("<i6dQi Q", g, 0, -10, 0, 20, 10, 0, 1, g, 0)
    b += b"\n$EndEntities\n$Nodes\n" + struct.pack("<4Q", 1, len(SQ), 1, len(SQ))
    b += struct.pack("<3iQ", 2, 1, 0, len(SQ))
    b += b"".join(struct.pack("<Q", i + 1) for i in range(len(SQ)))
    b += b"".join(struct.pack("<3d", *p) for p in SQ)
    b += b"\n$EndNodes\n$Elements\n" + struct.pack("<4Q", 2, len(SQ_E), 1, len(SQ_E))
    e = 1
    for g in (1, 2):
        b += struct.pack("<3iQ", 2, g, 2, len(groups[g]))
        for t, _ in groups[g]:
            b += struct.pack("<4Q", e, *(n + 1 for n in t))
            e += 1
    return b + b"\n$EndElements\n"


GEO_SQUARE = """// a 10 x 10 square
Point(1) = {0, 0, 0, 2}; Point(2) = {10, 0, 0, 2}; Point(3) = {10, 10, 0, 2}; Point(4) = {0, 10, 0, 2};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("gel", 5) = {1};
"""
GEO_LAYERS = """// two layers
lc = 2.5;
Point(1) = {0, -10, 0, lc}; Point(2) = {5, -10, 0, lc}; Point(3) = {20, -10, 0, lc};
Point(4) = {20, 10, 0, lc}; Point(5) = {5, 10, 0, lc}; Point(6) = {0, 10, 0, lc};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5}; Line(5) = {5, 6}; Line(6) = {6, 1};
Line(7) = {2, 5};
Curve Loop(1) = {1, 7, 5, 6}; Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, -7}; Plane Surface(2) = {2};
Physical Surface("skin") = {1};
Physical Surface("muscle") = {2};
"""


def main():
    write("stl_ascii", "cube.stl", stl_ascii(CUBE, CUBE_F, "cube"))
    write("stl_ascii", "tet.stl", stl_ascii(TET, TET_F, "tet"))
    write("stl_ascii", "two_solids.stl", stl_ascii(TET, TET_F[:2], "a") + stl_ascii(TET, TET_F[2:], "b"))
    write("stl_binary", "cube.stl", stl_binary(CUBE, CUBE_F))
    write("stl_binary", "tet.stl", stl_binary(TET, TET_F, b"solid but binary"))
    write("obj", "cube.obj", obj(CUBE, CUBE_F))
    write("obj", "tet.obj", "v 0 0 0\nv 10 0 0\nv 0 10 0\nv 0 0 10\nf 1 3 2\nf 1 2 4\nf -4 -1 -2\nf 2 3 4\n")
    write("ply", "cube_ascii.ply", ply(CUBE, CUBE_F, "ascii"))
    write("ply", "tet_ascii_extra.ply", ply(TET, TET_F, "ascii", extra=True))
    write("ply", "cube_le.ply", ply(CUBE, CUBE_F, "binary_little_endian"))
    write("ply", "tet_be_extra.ply", ply(TET, TET_F, "binary_big_endian", extra=True))
    write("off", "cube.off", off(CUBE, CUBE_F))
    write("off", "tet.off", off(TET, TET_F))
    write("off", "cube_quads.off", off(CUBE, [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]))
    for name in ("tet_ascii", "tet_binary", "tet_binary_zlib", "tet_appended_raw", "tet_appended_zlib_u64",
                 "tet_appended_base64"):
        os.makedirs(os.path.join(CORPUS, "vtp"), exist_ok=True)
        shutil.copy(os.path.join(HERE, "..", "mesh", "data", name + ".vtp"), os.path.join(CORPUS, "vtp", name + ".vtp"))
    write("msh2", "square_ascii.msh", msh2(0))
    write("msh2", "square_binary.msh", msh2(1))
    write("msh4", "square_ascii.msh", msh4(0))
    write("msh4", "square_binary.msh", msh4(1))
    write("geo", "square.geo", GEO_SQUARE)
    write("geo", "layers.geo", GEO_LAYERS)


if __name__ == "__main__":
    main()
