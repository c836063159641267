// Hanging soft pendulum with four closed cavities (hydraulic actuators) in its lower part.
// A solid cylinder of radius R, axis z, clamped at its top face z = 0 and hanging down to
// the free bottom face z = -L. Cavity k (k = 1..4) is a sector of the ring
// r1 <= r <= r2, phi degrees wide, centred on the angle (k - 1) 90 degrees from +x
// (cavity_1 on +x, cavity_2 on +y, cavity_3 on -x, cavity_4 on -y), spanning
// -L + tb <= z <= -L + tb + lc; each holds (phi / 360) pi (r2^2 - r1^2) lc.
// Filling one cavity stretches the thin outer wall on its side and adds weight there, so
// the pendulum bends across the axis; filling all four evenly extends it and lowers its
// centre of gravity (the seed paper, Section V, Fig. 6). Sectors rather than round
// channels: their flat faces and wide arcs keep the faceted cavity volumes within 0.5% of
// the closed form on the coarse default mesh (narrow round channels need many more
// elements around them). Units: metres.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber; -setnumber only
// works because they are DefineConstant):
//   R: outer radius, L: length, r1, r2: inner and outer radii of the cavities, phi: angular
//   width of each cavity in degrees (< 90), lc: cavity length, tb: wall between the
//   cavities and the bottom face, h: target mesh size.
// Physical groups: volume "body"; surfaces "top" (z = 0, clamped), "cavity_1".."cavity_4"
// (6 closed faces each; normals out of the body, i.e. into the cavity), "outer" (the rest:
// the lateral surface r = R and the bottom face z = -L); point "effector" (0, 0, -L), the
// centre of the bottom face, embedded in it so that the mesh has a node there.
// Mesh sizes (gmsh -3 -setnumber h H, defaults otherwise; nodes of the tetrahedra):
//   h = 0.0036   (default)  2,063 nodes, 7,594 tetrahedra
//   h = 0.00185             10,493 nodes
//   h = 0.00103             51,393 nodes
SetFactory("OpenCASCADE");
DefineConstant[ R = 0.015, L = 0.1, r1 = 0.005, r2 = 0.012, phi = 60, lc = 0.05, tb = 0.005,
                h = 0.0036 ];
If (R <= 0 || L <= 0 || r1 <= 0 || r2 <= r1 || phi <= 0 || lc <= 0 || tb <= 0 || h <= 0)
  Error("pendulum.geo: need R, L, r1, phi, lc, tb, h > 0 and r2 > r1 (R = %g, L = %g, r1 = %g, r2 = %g, phi = %g, lc = %g, tb = %g, h = %g)",
        R, L, r1, r2, phi, lc, tb, h);
EndIf
// Every wall at least wall_min thick: outside the cavities (R - r2), between two
// neighbouring cavities (2 r1 sin((90 - phi) / 2), at their inner corners), above them
// (L - tb - lc) and below them (tb), so that no cavity touches another one or the outer
// surface (phi < 90 degrees).
wall_min = 0.05 * R;
wall_out = R - r2;
wall_between = 2 * r1 * Sin((Pi / 2 - phi * Pi / 180) / 2);
wall_above = L - tb - lc;
If (phi >= 90 || wall_out < wall_min || wall_between < wall_min || wall_above < wall_min ||
    tb < wall_min)
  Error("pendulum.geo: a wall around the cavities is thinner than 0.05 R = %g, or phi >= 90 (outside %g, between %g, above %g, below %g; R = %g, L = %g, r1 = %g, r2 = %g, phi = %g, lc = %g, tb = %g)",
        wall_min, wall_out, wall_between, wall_above, tb, R, L, r1, r2, phi, lc, tb);
EndIf

Cylinder(1) = {0, 0, -L, 0, 0, L, R};
// Cavity k: the sector of the ring r1 <= r <= r2 between the angles theta_k -+ phi / 2.
For k In {1 : 4}
  theta[k] = (k - 1) * Pi / 2;
  Cylinder(10 * k + 1) = {0, 0, -L + tb, 0, 0, lc, r2, phi * Pi / 180};
  Cylinder(10 * k + 2) = {0, 0, -L + tb, 0, 0, lc, r1};
  BooleanDifference(1 + k) = { Volume{10 * k + 1}; Delete; }{ Volume{10 * k + 2}; Delete; };
  Rotate{ {0, 0, 1}, {0, 0, 0}, theta[k] - phi * Pi / 360 } { Volume{1 + k}; }
EndFor
BooleanDifference(6) = { Volume{1}; Delete; }{ Volume{2 : 5}; Delete; };

// Bounding-box tolerance: above OCC's box padding, below any feature (the thinnest wall
// is at least 0.05 R).
tol = 1e-3 * wall_min;
top() = Surface In BoundingBox{-R - tol, -R - tol, -tol, R + tol, R + tol, tol};
// Each cavity's box (the bounding box of its sector: its corners and the point of its
// outer arc on its axis, as phi < 90 degrees) lies strictly inside the body; it may
// overlap a neighbour's box but holds none of its faces whole (the face counts below check
// this).
half = phi * Pi / 360;
For k In {1 : 4}
  xs() = {r1 * Cos(theta[k] - half), r1 * Cos(theta[k] + half), r2 * Cos(theta[k] - half),
          r2 * Cos(theta[k] + half), r2 * Cos(theta[k])};
  ys() = {r1 * Sin(theta[k] - half), r1 * Sin(theta[k] + half), r2 * Sin(theta[k] - half),
          r2 * Sin(theta[k] + half), r2 * Sin(theta[k])};
  x0 = xs(0); x1 = xs(0); y0 = ys(0); y1 = ys(0);
  For i In {1 : 4}
    x0 = Min(x0, xs(i)); x1 = Max(x1, xs(i)); y0 = Min(y0, ys(i)); y1 = Max(y1, ys(i));
  EndFor
  cav~{k}() = Surface In BoundingBox{x0 - tol, y0 - tol, -L + tb - tol, x1 + tol, y1 + tol,
                                      -L + tb + lc + tol};
EndFor
outer() = Boundary{ Volume{6}; };
outer() -= {top(), cav_1(), cav_2(), cav_3(), cav_4()};
// A selection that misses (or over-reaches) its surfaces would leave a group silently
// empty or wrong: the body has exactly 27 faces (top, bottom, lateral, 6 per cavity).
faces() = Boundary{ Volume{6}; };
nb = #faces();
If (#top() != 1 || #cav_1() != 6 || #cav_2() != 6 || #cav_3() != 6 || #cav_4() != 6 ||
    #outer() != 2 || nb != 27)
  Error("pendulum.geo: a bounding-box selection of the boundary failed (top %g, cavities %g %g %g %g, outer %g of %g faces; expected 1, 6 each, 2 of 27)",
        #top(), #cav_1(), #cav_2(), #cav_3(), #cav_4(), #outer(), nb);
EndIf
bottom() = Surface In BoundingBox{-R - tol, -R - tol, -L - tol, R + tol, R + tol, -L + tol};
If (#bottom() != 1)
  Error("pendulum.geo: the bottom face was not found (%g faces at z = -L)", #bottom());
EndIf

// The effector: the centre of the bottom face, a mesh node of that surface.
effector = newp;
Point(effector) = {0, 0, -L};
Point{effector} In Surface{bottom(0)};

Physical Volume("body") = {6};
Physical Surface("top") = {top()};
Physical Surface("cavity_1") = {cav_1()};
Physical Surface("cavity_2") = {cav_2()};
Physical Surface("cavity_3") = {cav_3()};
Physical Surface("cavity_4") = {cav_4()};
Physical Surface("outer") = {outer()};
Physical Point("effector") = {effector};

Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{6}; } } = h;
MeshSize{ effector } = h;
Mesh.MeshSizeMax = h;
