// Liver-lobe-like test organ for surgical_sim, in millimetres (about 150 x 100 x 60 mm).
// A large right lobe (flattened ellipsoid) fused with a thinner left lobe, then tetrahedralised.
// Regenerate with:  gmsh liver_lobe.geo -3 -format msh41 -o liver_lobe.msh
SetFactory("OpenCASCADE");

// Right lobe: semi-axes 50 x 50 x 30 mm, centred at x = -20 mm.
Sphere(1) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {50, 50, 30}} { Volume{1}; }
Translate {-20, 0, 0} { Volume{1}; }

// Left lobe: semi-axes 45 x 35 x 18 mm, centred at x = +28 mm, lifted and shifted in y.
Sphere(2) = {0, 0, 0, 1};
Dilate {{0, 0, 0}, {45, 35, 18}} { Volume{2}; }
Translate {28, 8, 6} { Volume{2}; }

BooleanUnion(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

Physical Volume("tissue", 1) = {3};

Mesh.MeshSizeMin = 5;
Mesh.MeshSizeMax = 7;
Mesh.MeshSizeFromCurvature = 12;
Mesh.Algorithm3D = 1;        // Delaunay
Mesh.Optimize = 1;
Mesh.MshFileVersion = 4.1;
Mesh.Binary = 0;
