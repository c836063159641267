// Makes meshes/finger_cad.step, the CAD model of docs/tutorial_cad.md, with gmsh's
// OpenCASCADE kernel, in millimetres as CAD tools write it:
//   gmsh -0 meshes/finger_cad_make.geo -o meshes/finger_cad.step
// A soft finger 90 x 18 x 16 mm along x, its four long edges rounded (r 3 mm), with a closed
// cavity 70 x 10 x 5 mm (3.5 ml, long edges rounded, r 1.5 mm), 10 mm from either end,
// its centre 3 mm below the mid-plane (the box finger of meshes/finger.geo, rounded).
// Nothing here is read by hydrosoft: meshes/finger_cad.geo reads the STEP file only.
SetFactory("OpenCASCADE");
L = 90; W = 18; T = 16; r = 3;                      // the finger
lc = 70; wc = 10; tc = 5; xb = 10; ez = -3; rc = 1.5;  // the cavity
e = 0.01;                                           // selection tolerance (mm)
Box(1) = {0, -W / 2, -T / 2, L, W, T};
Box(2) = {xb, -wc / 2, ez - tc / 2, lc, wc, tc};
// The four edges along x of each box, at its corners (+-y, +-z).
finger_edges() = {};
cavity_edges() = {};
For i In {0:3}
  sy = 2 * (i % 2) - 1;
  sz = 2 * Floor(i / 2) - 1;
  y = sy * W / 2; z = sz * T / 2;
  finger_edges() += Curve In BoundingBox{-e, y - e, z - e, L + e, y + e, z + e};
  y = sy * wc / 2; z = ez + sz * tc / 2;
  cavity_edges() += Curve In BoundingBox{xb - e, y - e, z - e, xb + lc + e, y + e, z + e};
EndFor
If (#finger_edges() != 4 || #cavity_edges() != 4)
  Error("finger_cad_make.geo: %g finger and %g cavity edges selected, expected 4 and 4",
        #finger_edges(), #cavity_edges());
EndIf
finger() = Fillet{1}{finger_edges()}{r};
cavity() = Fillet{2}{cavity_edges()}{rc};
finger_body = newv;
BooleanDifference(finger_body) = { Volume{finger(0)}; Delete; }{ Volume{cavity(0)}; Delete; };
