// A prostate-like gland with a tumour, made with Gmsh's OpenCASCADE kernel (read by
// needlesim through Gmsh's library: tissue.geometry.file, unit mm). Sizes after the adult
// prostate's typical 40 x 30 x 30 mm; the tumour a 5 mm sphere in the gland's middle third.
// x is depth from the entry plane (the perineal side), y across, z up.
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {20, 15, 15}} { Volume{1}; }
Translate {20, 0, 0} { Volume{1}; }
Sphere(2) = {22, 0, 0, 5};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
tumour() = Volume In BoundingBox {16.9, -5.1, -5.1, 27.1, 5.1, 5.1};
gland() = Volume{:};
gland() -= tumour();
Physical Volume("gland") = {gland()};
Physical Volume("tumour") = {tumour()};
// finer along the needle path (the x axis) and in and around the tumour
Field[1] = Box;
Field[1].VIn = 1.5; Field[1].VOut = 4;
Field[1].XMin = 0; Field[1].XMax = 40; Field[1].YMin = -3; Field[1].YMax = 3; Field[1].ZMin = -3; Field[1].ZMax = 3;
Field[1].Thickness = 4;
Field[2] = Ball;
Field[2].Radius = 6; Field[2].Thickness = 3; Field[2].VIn = 1.5; Field[2].VOut = 4;
Field[2].XCenter = 22; Field[2].YCenter = 0; Field[2].ZCenter = 0;
Field[3] = Min;
Field[3].FieldsList = {1, 2};
Background Field = 3;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
