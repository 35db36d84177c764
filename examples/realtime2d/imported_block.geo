// A 60 x 40 mm section of gelatin with a 5 mm stiffer disc (a tumour's section) beside the needle
// path, as Gmsh's unstructured triangles (read by needlesim through Gmsh's library:
// tissue.geometry.file, unit mm), finer along the path and around the disc. x is depth from the
// entry face, y across; the path runs along y = 0.
SetFactory("OpenCASCADE");
Rectangle(1) = {0, -20, 0, 60, 40};
Disk(2) = {35, 4, 0, 5};
BooleanFragments{ Surface{1}; Delete; }{ Surface{2}; Delete; }
tumour() = Surface In BoundingBox {29.9, -1.1, -1, 40.1, 9.1, 1};
gel() = Surface{:};
gel() -= tumour();
Physical Surface("gel") = {gel()};
Physical Surface("tumour") = {tumour()};
Field[1] = Box;
Field[1].VIn = 1; Field[1].VOut = 3;
Field[1].XMin = 0; Field[1].XMax = 60; Field[1].YMin = -3; Field[1].YMax = 3;
Field[1].Thickness = 6;
Field[2] = Ball;
Field[2].Radius = 6; Field[2].Thickness = 3; Field[2].VIn = 1; Field[2].VOut = 3;
Field[2].XCenter = 35; Field[2].YCenter = 4;
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = 3;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
