// One eighth of a thick-walled sphere, inner radius a, outer radius b (x, y, z >= 0).
// Used by the Lame (linear) and neo-Hookean inflation decks.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber):
//   a: inner radius, b: outer radius, h: target mesh size.
// Physical groups: volume "body"; surfaces "inner" (r = a), "outer" (r = b),
// "symmetry_x" (x = 0), "symmetry_y" (y = 0), "symmetry_z" (z = 0).
SetFactory("OpenCASCADE");
DefineConstant[ a = 1.0, b = 2.0, h = 0.25 ];
If (a <= 0 || b <= a || h <= 0)
  Error("lame_sphere.geo: need 0 < a < b and h > 0 (a = %g, b = %g, h = %g)", a, b, h);
EndIf
// A far smaller inner sphere is below what OpenCASCADE and the mesher resolve: gmsh then ran
// without end (a = 1e-30) instead of failing.
If (a < 1e-3 * b)
  Error("lame_sphere.geo: need a >= b / 1000 (a = %g, b = %g)", a, b);
EndIf

// Sphere(tag) = {centre, radius, polar angle from, polar angle to, azimuth}:
// latitude 0..pi/2 (z >= 0) and azimuth 0..pi/2 (x, y >= 0) is the first octant.
Sphere(1) = {0, 0, 0, b, 0, Pi / 2, Pi / 2};
Sphere(2) = {0, 0, 0, a, 0, Pi / 2, Pi / 2};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

e = 1e-3 * a;  // bounding-box tolerance: above OCC's box padding, below any feature
sx() = Surface In BoundingBox{-e, -e, -e, e, b + e, b + e};
sy() = Surface In BoundingBox{-e, -e, -e, b + e, e, b + e};
sz() = Surface In BoundingBox{-e, -e, -e, b + e, b + e, e};
inner() = Surface In BoundingBox{-e, -e, -e, a + e, a + e, a + e};
outer() = Boundary{ Volume{3}; };
outer() -= {sx(), sy(), sz(), inner()};
// A selection that misses its surfaces would leave a group silently empty.
If (#sx() != 1 || #sy() != 1 || #sz() != 1 || #inner() != 1 || #outer() != 1)
  Error("lame_sphere.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {3};
Physical Surface("inner") = {inner()};
Physical Surface("outer") = {outer()};
Physical Surface("symmetry_x") = {sx()};
Physical Surface("symmetry_y") = {sy()};
Physical Surface("symmetry_z") = {sz()};

Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 1;
MeshSize{ PointsOf{ Volume{3}; } } = h;
Mesh.MeshSizeMax = h;
