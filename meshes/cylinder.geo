// Hollow cylinder with a closed inner cavity (soft actuator for cavity work).
// Axis along z; the face z = 0 is clamped and the free end is the face z = -L. The decks
// put gravity across the axis (along -y), so the cylinder hangs as a horizontal cantilever.
// The cavity is a cylinder of radius R - t whose axis is offset by e along y (eccentric
// when e != 0: the wall is t - |e| thick on one side and t + |e| on the other), closed by
// end walls of thickness t (so -L + t <= z <= -t). Units: metres.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber; -setnumber only
// works because they are DefineConstant):
//   R: outer radius, L: length, t: wall thickness (coaxial), e: offset of the cavity axis
//   along y (default 0), h: target mesh size.
// Physical groups: volume "body"; surfaces "top" (z = 0), "tip" (z = -L, the free end face),
// "cavity" (the closed inner surface; its normals point out of the body, i.e. into the
// cavity), "outer" (the lateral surface r = R only).
SetFactory("OpenCASCADE");
DefineConstant[ R = 0.015, L = 0.08, t = 0.003, e = 0, h = 0.003 ];
If (R <= 0 || L <= 0 || t <= 0 || 2 * t >= L || t >= R || h <= 0)
  Error("cylinder.geo: need 0 < t < R, 0 < 2 t < L, h > 0 (R = %g, L = %g, t = %g, h = %g)",
        R, L, t, h);
EndIf
// The thinnest lateral wall is t - |e|; keep at least a fifth of t so that the cavity
// never touches (or cuts) the outer surface and the thin side stays a wall.
wall_min = 0.2 * t;
If (Fabs(e) + (R - t) > R - wall_min)
  Error("cylinder.geo: cavity offset too large: |e| + (R - t) = %g must be <= R - %g = %g (thinnest wall t - |e| = %g, minimum 0.2 t = %g; e = %g, R = %g, t = %g)",
        Fabs(e) + (R - t), wall_min, R - wall_min, t - Fabs(e), wall_min, e, R, t);
EndIf

Cylinder(1) = {0, 0, -L, 0, 0, L, R};
Cylinder(2) = {0, e, -L + t, 0, 0, L - 2 * t, R - t};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

// Bounding-box tolerance: above OCC's box padding, below any feature (the thinnest wall
// t - |e| >= 0.2 t included).
tol = 1e-3 * (t - Fabs(e));
top() = Surface In BoundingBox{-R - tol, -R - tol, -tol, R + tol, R + tol, tol};
tip() = Surface In BoundingBox{-R - tol, -R - tol, -L - tol, R + tol, R + tol, -L + tol};
// The cavity box follows the offset axis; it lies strictly inside the outer surface's box
// and away from z = 0 and z = -L, so it selects the three cavity faces only.
cavity() = Surface In BoundingBox{-(R - t) - tol, e - (R - t) - tol, -L + t - tol,
                                  (R - t) + tol, e + (R - t) + tol, -t + tol};
outer() = Boundary{ Volume{3}; };
outer() -= {top(), tip(), cavity()};
// A selection that misses (or over-reaches) its surfaces would leave a group silently
// empty or wrong: the body has exactly 6 faces (2 end faces, 1 lateral, 3 of the cavity).
faces() = Boundary{ Volume{3}; };
nb = #faces();
If (#top() != 1 || #tip() != 1 || #cavity() != 3 || #outer() != 1 || nb != 6)
  Error("cylinder.geo: a bounding-box selection of the boundary failed (top %g, tip %g, cavity %g, outer %g of %g faces; expected 1, 1, 3, 1 of 6; R = %g, L = %g, t = %g, e = %g)",
        #top(), #tip(), #cavity(), #outer(), nb, R, L, t, e);
EndIf

Physical Volume("body") = {3};
Physical Surface("top") = {top()};
Physical Surface("tip") = {tip()};
Physical Surface("cavity") = {cavity()};
Physical Surface("outer") = {outer()};

Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{3}; } } = h;
Mesh.MeshSizeMax = h;
