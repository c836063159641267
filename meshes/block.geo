// Block 0 <= x, y, z <= H for the hydrostatic patch test (gravity along -z).
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber):
//   H: side of the block, h: target mesh size.
// Physical groups: volume "body"; surfaces "bottom" (z = 0), "top" (z = H),
// "sides" (the four faces x = 0, x = H, y = 0, y = H), and each side alone:
// "x0", "x1", "y0", "y1".
SetFactory("OpenCASCADE");
DefineConstant[ H = 1.0, h = 0.25 ];
If (H <= 0 || h <= 0)
  Error("block.geo: need H > 0 and h > 0 (H = %g, h = %g)", H, h);
EndIf

Box(1) = {0, 0, 0, H, H, H};

e = 1e-3 * H;  // bounding-box tolerance: above OCC's box padding, below any feature
bottom() = Surface In BoundingBox{-e, -e, -e, H + e, H + e, e};
top() = Surface In BoundingBox{-e, -e, H - e, H + e, H + e, H + e};
x0() = Surface In BoundingBox{-e, -e, -e, e, H + e, H + e};
x1() = Surface In BoundingBox{H - e, -e, -e, H + e, H + e, H + e};
y0() = Surface In BoundingBox{-e, -e, -e, H + e, e, H + e};
y1() = Surface In BoundingBox{-e, H - e, -e, H + e, H + e, H + e};
// A selection that misses its surfaces would leave a group silently empty.
If (#bottom() != 1 || #top() != 1 || #x0() != 1 || #x1() != 1 || #y0() != 1 || #y1() != 1)
  Error("block.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {1};
Physical Surface("bottom") = {bottom()};
Physical Surface("top") = {top()};
Physical Surface("sides") = {x0(), x1(), y0(), y1()};
Physical Surface("x0") = {x0()};
Physical Surface("x1") = {x1()};
Physical Surface("y0") = {y0()};
Physical Surface("y1") = {y1()};

MeshSize{ PointsOf{ Volume{1}; } } = h;
Mesh.MeshSizeMax = h;
