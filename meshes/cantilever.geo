// Slender cantilever: a box beam along +x from x = 0 to x = L, square section h x h
// centred on the x axis (-h/2 <= y, z <= h/2). Gravity decks load it along -z.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber):
//   L: length, h: side of the section, n: elements across the section
//   (target mesh size h / n, so about n L / h elements along the beam).
// Physical groups: volume "body"; surfaces "clamped" (x = 0), "tip" (x = L),
// "top" (z = h/2), "bottom" (z = -h/2).
SetFactory("OpenCASCADE");
DefineConstant[ L = 1.0, h = 0.05, n = 2 ];
If (L <= 0 || h <= 0 || n < 1)
  Error("cantilever.geo: need L > 0, h > 0 and n >= 1 (L = %g, h = %g, n = %g)", L, h, n);
EndIf

Box(1) = {0, -h / 2, -h / 2, L, h, h};

e = 1e-3 * h;  // bounding-box tolerance: above OCC's box padding, below any feature
clamped() = Surface In BoundingBox{-e, -h, -h, e, h, h};
tip() = Surface In BoundingBox{L - e, -h, -h, L + e, h, h};
top() = Surface In BoundingBox{-e, -h, h / 2 - e, L + e, h, h / 2 + e};
bottom() = Surface In BoundingBox{-e, -h, -h / 2 - e, L + e, h, -h / 2 + e};
// A selection that misses its surfaces would leave a group silently empty.
If (#clamped() != 1 || #tip() != 1 || #top() != 1 || #bottom() != 1)
  Error("cantilever.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {1};
Physical Surface("clamped") = {clamped()};
Physical Surface("tip") = {tip()};
Physical Surface("top") = {top()};
Physical Surface("bottom") = {bottom()};

MeshSize{ PointsOf{ Volume{1}; } } = h / n;
Mesh.MeshSizeMax = h / n;
