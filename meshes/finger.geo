// Soft finger with one closed internal cavity (a gripper finger, actuated pneumatically or
// hydraulically). A slab 0 <= x <= L, -W/2 <= y <= W/2, -T/2 <= z <= T/2; the face x = 0 is
// clamped and the face x = L is the free tip. The cavity is a box along x,
// xb <= x <= xb + lc, -wc/2 <= y <= wc/2, ez - tc/2 <= z <= ez + tc/2, centred in y and
// offset by ez from the mid-plane z = 0. Units: metres.
// Why the cavity sits below the mid-plane (ez < 0 by default): inflating a closed cavity
// pushes its end walls apart and stretches the thin wall next to it, so the finger bends
// away from the cavity's side, here upwards (+z). The decks put gravity along -z: the
// liquid's weight then bends the finger down against the inflation, so a hydraulic finger
// reaches lower targets and farther horizontal ones, but not the higher ones a pneumatic
// finger reaches (the seed paper, Section V, Fig. 5). ez > 0 bends it downwards instead.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber; -setnumber only
// works because they are DefineConstant):
//   L, W, T: length (x), width (y), thickness (z) of the finger;
//   lc, wc, tc: length, width, height of the cavity; xb: wall between the base and the
//   cavity (the tip wall is L - xb - lc); ez: offset of the cavity's centre along z;
//   h: target mesh size.
// Physical groups: volume "body"; surfaces "base" (x = 0, clamped), "tip" (x = L),
// "cavity" (the 6 closed faces of the box; normals out of the body, i.e. into the cavity),
// "outer" (the 4 lateral faces y = +-W/2, z = +-T/2); point "effector" (L, 0, 0), the
// centre of the tip face, embedded in it so that the mesh has a node there.
// Mesh sizes (gmsh -3 -setnumber h H, defaults otherwise; nodes of the tetrahedra):
//   h = 0.006    (default)  364 nodes, 1,088 tetrahedra
//   h = 0.0026              1,961 nodes
//   h = 0.00135             10,488 nodes
//   h = 0.00074             51,465 nodes
SetFactory("OpenCASCADE");
DefineConstant[ L = 0.09, W = 0.018, T = 0.016, lc = 0.07, wc = 0.01, tc = 0.005,
                xb = 0.01, ez = -0.003, h = 0.006 ];
If (L <= 0 || W <= 0 || T <= 0 || lc <= 0 || wc <= 0 || tc <= 0 || xb <= 0 || h <= 0)
  Error("finger.geo: need L, W, T, lc, wc, tc, xb, h > 0 (L = %g, W = %g, T = %g, lc = %g, wc = %g, tc = %g, xb = %g, h = %g)",
        L, W, T, lc, wc, tc, xb, h);
EndIf
// Every wall around the cavity (base, tip, sides, top, bottom) at least wall_min thick, so
// that the cavity never touches (or cuts) the outer surface.
wall_min = 0.05 * T;
wall_tip = L - xb - lc;
wall_side = (W - wc) / 2;
wall_top = T / 2 - (ez + tc / 2);
wall_bottom = (ez - tc / 2) + T / 2;
If (xb < wall_min || wall_tip < wall_min || wall_side < wall_min || wall_top < wall_min ||
    wall_bottom < wall_min)
  Error("finger.geo: a wall around the cavity is thinner than 0.05 T = %g (base %g, tip %g, sides %g, top %g, bottom %g; L = %g, W = %g, T = %g, lc = %g, wc = %g, tc = %g, xb = %g, ez = %g)",
        wall_min, xb, wall_tip, wall_side, wall_top, wall_bottom, L, W, T, lc, wc, tc, xb, ez);
EndIf

Box(1) = {0, -W / 2, -T / 2, L, W, T};
Box(2) = {xb, -wc / 2, ez - tc / 2, lc, wc, tc};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

// Bounding-box tolerance: above OCC's box padding, below any feature (the thinnest wall
// is at least 0.05 T).
tol = 1e-3 * wall_min;
base() = Surface In BoundingBox{-tol, -W / 2 - tol, -T / 2 - tol, tol, W / 2 + tol, T / 2 + tol};
tip() = Surface In BoundingBox{L - tol, -W / 2 - tol, -T / 2 - tol, L + tol, W / 2 + tol,
                               T / 2 + tol};
// The cavity's box lies strictly inside the body, away from every outer face.
cavity() = Surface In BoundingBox{xb - tol, -wc / 2 - tol, ez - tc / 2 - tol, xb + lc + tol,
                                  wc / 2 + tol, ez + tc / 2 + tol};
outer() = Boundary{ Volume{3}; };
outer() -= {base(), tip(), cavity()};
// A selection that misses (or over-reaches) its surfaces would leave a group silently
// empty or wrong: the body has exactly 12 faces (6 of the slab, 6 of the cavity).
faces() = Boundary{ Volume{3}; };
nb = #faces();
If (#base() != 1 || #tip() != 1 || #cavity() != 6 || #outer() != 4 || nb != 12)
  Error("finger.geo: a bounding-box selection of the boundary failed (base %g, tip %g, cavity %g, outer %g of %g faces; expected 1, 1, 6, 4 of 12)",
        #base(), #tip(), #cavity(), #outer(), nb);
EndIf

// The effector: the centre of the tip face, a mesh node of the tip surface.
effector = newp;
Point(effector) = {L, 0, 0};
Point{effector} In Surface{tip(0)};

Physical Volume("body") = {3};
Physical Surface("base") = {base()};
Physical Surface("tip") = {tip()};
Physical Surface("cavity") = {cavity()};
Physical Surface("outer") = {outer()};
Physical Point("effector") = {effector};

Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{3}; } } = h;
MeshSize{ effector } = h;
Mesh.MeshSizeMax = h;
