// Writes kidney.stl and cyst.stl, the closed surfaces of kidney_surfaces_explicit.yaml, as a
// segmentation of CT or MRI would give them (run: gmsh make_kidney_surfaces.geo -0; needlesim
// refuses it as a tissue geometry, since it saves files). A kidney-like ellipsoid of
// 44 x 30 x 26 mm (a child's kidney, kept small for a quick run) and a 4 mm cyst in it; millimetres.
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {22, 15, 13}} { Volume{1}; }
Translate {22, 0, 0} { Volume{1}; }
Mesh.MeshSizeMax = 4;
Mesh 2;
Save "kidney.stl";
Delete All;
SetFactory("OpenCASCADE");
Sphere(2) = {18, 1.5, 0, 4};
Mesh.MeshSizeMax = 2;
Mesh 2;
Save "cyst.stl";
