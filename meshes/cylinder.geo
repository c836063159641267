// Hollow cylinder with a closed inner cavity (soft actuator for cavity work).
// Axis along z; the face z = 0 is clamped and the free end is the face z = -L. The decks
// put gravity across the axis (along -y), so the cylinder hangs as a horizontal cantilever.
// The cavity is a cylinder of radius R - t whose axis is offset by e along y (eccentric
// when e != 0: the wall is t - |e| thick on one side and t + |e| on the other), closed by
// end walls of thickness t (so -L + t <= z <= -t). Units: metres.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber; -setnumber only
// works because they are DefineConstant):
//   R: outer radius, L: length, t: wall thickness (coaxial), e: offset of the cavity axis
//   along y (default 0), h: target mesh size, split: 0 (default) or 1 (below).
// Physical groups: volume "body"; surfaces "top" (z = 0), "tip" (z = -L, the free end face),
// "cavity" (the closed inner surface; its normals point out of the body, i.e. into the
// cavity), "outer" (the lateral surface r = R only).
// split = 1 cuts the body by the plane y = e (through the cavity axis) into two volume
// groups, "body_upper" (y > e, the wall t + |e| thick when e < 0) and "body_lower" (y < e),
// meshed conformingly across the cut, for two materials; there is then no "body" group.
// The surface groups are the same surfaces, each cut in two by the plane (the cavity stays
// closed). split = 0 leaves the geometry and the mesh exactly as without the parameter.
SetFactory("OpenCASCADE");
DefineConstant[ R = 0.015, L = 0.08, t = 0.003, e = 0, h = 0.003, split = 0 ];
If (R <= 0 || L <= 0 || t <= 0 || 2 * t >= L || t >= R || h <= 0)
  Error("cylinder.geo: need 0 < t < R, 0 < 2 t < L, h > 0 (R = %g, L = %g, t = %g, h = %g)",
        R, L, t, h);
EndIf
If (split != 0 && split != 1)
  Error("cylinder.geo: split must be 0 (one volume group, body) or 1 (body_upper and body_lower, cut at y = e), got %g",
        split);
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
body() = {3};
If (split == 1)
  // A box over y > e, larger than the body in x and z (no coincident or tangent faces),
  // fragments the body; the pieces of the box outside the body (around it, and the upper
  // half of the cavity) are deleted.
  Box(4) = {-2 * R, e, -2 * L, 4 * R, 2 * R, 3 * L};
  pieces() = BooleanFragments{ Volume{3}; Delete; }{ Volume{4}; Delete; };
  inside() = Volume In BoundingBox{-R - tol, -R - tol, -L - tol, R + tol, R + tol, tol};
  hole() = Volume In BoundingBox{-(R - t) - tol, e - tol, -L + t - tol,
                                 (R - t) + tol, e + (R - t) + tol, -t + tol};
  junk() = pieces();
  junk() -= inside();
  junk() += hole();
  Recursive Delete{ Volume{junk()}; }
  upper() = Volume In BoundingBox{-R - tol, e - tol, -L - tol, R + tol, R + tol, tol};
  lower() = Volume In BoundingBox{-R - tol, -R - tol, -L - tol, R + tol, e + tol, tol};
  If (#pieces() != 4 || #hole() != 1 || #upper() != 1 || #lower() != 1)
    Error("cylinder.geo: split: cutting the body at y = e failed (%g pieces, cavity half %g, upper %g, lower %g; expected 4, 1, 1, 1; R = %g, L = %g, t = %g, e = %g)",
          #pieces(), #hole(), #upper(), #lower(), R, L, t, e);
  EndIf
  body() = {upper(), lower()};
EndIf

top() = Surface In BoundingBox{-R - tol, -R - tol, -tol, R + tol, R + tol, tol};
tip() = Surface In BoundingBox{-R - tol, -R - tol, -L - tol, R + tol, R + tol, -L + tol};
// The cavity box follows the offset axis; it lies strictly inside the outer surface's box
// and away from z = 0 and z = -L, so it selects the three cavity faces only (and with
// split, the cut plane's faces are not selected: they reach the outer surface).
cavity() = Surface In BoundingBox{-(R - t) - tol, e - (R - t) - tol, -L + t - tol,
                                  (R - t) + tol, e + (R - t) + tol, -t + tol};
outer() = CombinedBoundary{ Volume{body()}; };
outer() -= {top(), tip(), cavity()};
// A selection that misses (or over-reaches) its surfaces would leave a group silently
// empty or wrong: the body has exactly 6 faces (2 end faces, 1 lateral, 3 of the cavity).
// split cuts each in two, and the outer lateral face of the piece that holds its seam
// (x = R, y = 0; every piece but when e = 0) once more, so 5 k + 1 or 5 k + 2 faces.
faces() = CombinedBoundary{ Volume{body()}; };
nb = #faces();
k = 1 + split;
outer_max = (split == 1 && e != 0) ? k + 1 : k;
If (#top() != k || #tip() != k || #cavity() != 3 * k || #outer() < k || #outer() > outer_max || nb != 5 * k + #outer())
  Error("cylinder.geo: a bounding-box selection of the boundary failed (top %g, tip %g, cavity %g, outer %g of %g faces; expected %g, %g, %g, %g to %g of 5 k + outer; R = %g, L = %g, t = %g, e = %g, split = %g)",
        #top(), #tip(), #cavity(), #outer(), nb, k, k, 3 * k, k, outer_max, R, L, t, e, split);
EndIf

If (split == 1)
  Physical Volume("body_upper") = {upper()};
  Physical Volume("body_lower") = {lower()};
Else
  Physical Volume("body") = {3};
EndIf
Physical Surface("top") = {top()};
Physical Surface("tip") = {tip()};
Physical Surface("cavity") = {cavity()};
Physical Surface("outer") = {outer()};

Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{body()}; } } = h;
Mesh.MeshSizeMax = h;
