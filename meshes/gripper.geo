// Two-finger gripper: two soft fingers side by side, clamped to one palm at x = 0 and closing
// on what lies between their tips. Each finger is a slab 0 <= x <= L, T thick across the gap
// (y) and W high (z), the fingers' inner faces at y = +-g/2; each has a closed box cavity on
// its outer side (its centre ey farther from the gap than the finger's mid-plane), so that
// inflating it stretches the thin outer wall and bends the finger towards the other one (as
// meshes/finger.geo's cavity offset bends that finger away from its side). Units: metres.
// Parameters (override from a deck's mesh.parameters; DefineConstant):
//   L, W, T: length (x), height (z), thickness (y) of each finger; g: the gap between them;
//   lc, wc, tc: length (x), height (z), thickness (y) of each cavity; xb: wall between the
//   palm and the cavity; ey: offset of the cavity's centre from the finger's mid-plane,
//   away from the gap; h: target mesh size; ox, oy, oz: the sides (x, y, z) of a soft block
//   held between the tips, its far face ob beyond them and centred across the gap (ox = 0,
//   the default: none).
// Physical groups: volume "body" (both fingers); surfaces "base" (both x = 0 faces, the
// palm), "cavity_left" and "cavity_right" (y > 0 and y < 0; normals out of the body),
// "skin_left" and "skin_right" (every other face of each finger: the faces that may touch);
// points "tip_left" and "tip_right", the centres of the tip faces. With the block: volume
// "object" and surface "object_skin" (its faces).
SetFactory("OpenCASCADE");
DefineConstant[ L = 0.09, W = 0.018, T = 0.016, g = 0.02, lc = 0.07, wc = 0.01, tc = 0.005,
                xb = 0.01, ey = 0.003, h = 0.006, ox = 0, oy = 0.019, oz = 0.016, ob = 0.004 ];
If (L <= 0 || W <= 0 || T <= 0 || g <= 0 || lc <= 0 || wc <= 0 || tc <= 0 || xb <= 0 || h <= 0)
  Error("gripper.geo: need L, W, T, g, lc, wc, tc, xb, h > 0 (L = %g, W = %g, T = %g, g = %g, lc = %g, wc = %g, tc = %g, xb = %g, h = %g)",
        L, W, T, g, lc, wc, tc, xb, h);
EndIf
// Every wall around a cavity at least wall_min thick, so that no cavity cuts a face.
wall_min = 0.05 * T;
If (xb < wall_min || L - xb - lc < wall_min || (W - wc) / 2 < wall_min ||
    T / 2 - ey - tc / 2 < wall_min || T / 2 + ey - tc / 2 < wall_min)
  Error("gripper.geo: a wall around a cavity is thinner than 0.05 T = %g (L = %g, W = %g, T = %g, lc = %g, wc = %g, tc = %g, xb = %g, ey = %g)",
        wall_min, L, W, T, lc, wc, tc, xb, ey);
EndIf

// side = +1: the left finger (y > 0), -1: the right one.
For k In {0 : 1}
  side = 1 - 2 * k;
  y_mid = side * (g / 2 + T / 2);
  Box(10 * k + 1) = {0, y_mid - T / 2, -W / 2, L, T, W};
  Box(10 * k + 2) = {xb, y_mid + side * ey - tc / 2, -wc / 2, lc, tc, wc};
  BooleanDifference(10 * k + 3) = { Volume{10 * k + 1}; Delete; }{ Volume{10 * k + 2}; Delete; };
EndFor

tol = 1e-3 * wall_min;
For k In {0 : 1}
  side = 1 - 2 * k;
  y_mid = side * (g / 2 + T / 2);
  y0 = y_mid - T / 2;
  y1 = y_mid + T / 2;
  yc = y_mid + side * ey;
  base~{k}() = Surface In BoundingBox{-tol, y0 - tol, -W / 2 - tol, tol, y1 + tol, W / 2 + tol};
  cavity~{k}() = Surface In BoundingBox{xb - tol, yc - tc / 2 - tol, -wc / 2 - tol,
                                        xb + lc + tol, yc + tc / 2 + tol, wc / 2 + tol};
  tipface~{k}() = Surface In BoundingBox{L - tol, y0 - tol, -W / 2 - tol, L + tol, y1 + tol,
                                         W / 2 + tol};
  skin~{k}() = Boundary{ Volume{10 * k + 3}; };
  skin~{k}() -= {base~{k}(), cavity~{k}()};
  faces~{k}() = Boundary{ Volume{10 * k + 3}; };
  If (#base~{k}() != 1 || #cavity~{k}() != 6 || #tipface~{k}() != 1 || #skin~{k}() != 5 ||
      #faces~{k}() != 12)
    Error("gripper.geo: a bounding-box selection of finger %g's boundary failed (base %g, cavity %g, tip %g, skin %g of %g faces; expected 1, 6, 1, 5 of 12)",
          k, #base~{k}(), #cavity~{k}(), #tipface~{k}(), #skin~{k}(), #faces~{k}());
  EndIf
  tip~{k} = newp;
  Point(tip~{k}) = {L, y_mid, 0};
  Point{tip~{k}} In Surface{tipface~{k}(0)};
EndFor

If (ox > 0)
  If (oy >= g || ox <= ob || oz <= 0)
    Error("gripper.geo: the block must fit between the fingers and reach between them (oy = %g < g = %g, ox = %g > ob = %g, oz = %g > 0)",
          oy, g, ox, ob, oz);
  EndIf
  Box(30) = {L + ob - ox, -oy / 2, -oz / 2, ox, oy, oz};
  Physical Volume("object") = {30};
  Physical Surface("object_skin") = {Boundary{ Volume{30}; }};
  MeshSize{ PointsOf{ Volume{30}; } } = h;
EndIf

Physical Volume("body") = {3, 13};
Physical Surface("base") = {base~{0}(), base~{1}()};
Physical Surface("cavity_left") = {cavity~{0}()};
Physical Surface("cavity_right") = {cavity~{1}()};
Physical Surface("skin_left") = {skin~{0}()};
Physical Surface("skin_right") = {skin~{1}()};
Physical Point("tip_left") = {tip~{0}};
Physical Point("tip_right") = {tip~{1}};

Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{3, 13}; } } = h;
MeshSize{ tip~{0}, tip~{1} } = h;
Mesh.MeshSizeMax = h;
