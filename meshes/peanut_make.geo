// Makes meshes/peanut.stl, the rigid object of input/finger_press_peanut.yaml: two balls of
// radius 7 mm whose centres are 12 mm apart along x, fused (a non-convex surface with a saddle
// between the lobes), tessellated at 0.5 to 0.8 mm, in metres:
//   gmsh -2 meshes/peanut_make.geo -format stl -bin -o meshes/peanut.stl
// Nothing here is read by hydrosoft: the deck reads the STL file only.
SetFactory("OpenCASCADE");
r = 0.007; gap = 0.012; x0 = 0.062; z0 = -0.0155;
Sphere(1) = {x0, 0, z0, r};
Sphere(2) = {x0 + gap, 0, z0, r};
BooleanUnion{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Mesh.MeshSizeMin = 0.0005;
Mesh.MeshSizeMax = 0.0008;
