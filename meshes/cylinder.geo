// Hanging hollow cylinder with a closed inner cavity (soft actuator for cavity work).
// Axis along z; the top face z = 0 is clamped and the cylinder hangs down to z = -L.
// The cavity is a coaxial cylinder of radius R - t, closed by end walls of thickness t
// (so -L + t <= z <= -t). Units: metres.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber):
//   R: outer radius, L: length, t: wall thickness, h: target mesh size.
// Physical groups: volume "body"; surfaces "top" (z = 0), "cavity" (the closed inner
// surface; its normals point out of the body, i.e. into the cavity), "outer" (the rest).
SetFactory("OpenCASCADE");
DefineConstant[ R = 0.015, L = 0.08, t = 0.003, h = 0.003 ];
If (R <= 0 || L <= 0 || t <= 0 || 2 * t >= L || t >= R || h <= 0)
  Error("cylinder.geo: need 0 < t < R, 0 < 2 t < L, h > 0 (R = %g, L = %g, t = %g, h = %g)",
        R, L, t, h);
EndIf

Cylinder(1) = {0, 0, -L, 0, 0, L, R};
Cylinder(2) = {0, 0, -L + t, 0, 0, L - 2 * t, R - t};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

e = 1e-3 * t;  // bounding-box tolerance: above OCC's box padding, below any feature
top() = Surface In BoundingBox{-R - e, -R - e, -e, R + e, R + e, e};
cavity() = Surface In BoundingBox{-R + t - e, -R + t - e, -L + t - e, R - t + e, R - t + e, -t + e};
outer() = Boundary{ Volume{3}; };
outer() -= {top(), cavity()};
// A selection that misses its surfaces would leave a group silently empty.
If (#top() != 1 || #cavity() != 3 || #outer() != 2)
  Error("cylinder.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {3};
Physical Surface("top") = {top()};
Physical Surface("cavity") = {cavity()};
Physical Surface("outer") = {outer()};

Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{3}; } } = h;
Mesh.MeshSizeMax = h;
