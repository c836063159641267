// Two blocks of one mesh, one above the other across a gap, for contact between bodies of a
// mesh (contact.self): the lower 0 <= x, y <= L, 0 <= z <= H, the upper the same above
// z = H + g, meshed finer so that the facing surfaces' nodes do not match.
// Parameters: L, H, g (m); h: the lower block's mesh size, the upper's 0.7 h.
// Physical groups: volume "body" (both); surfaces "bottom" (z = 0), "top" (z = 2H + g),
// "x0", "y0" (the blocks' faces x = 0 and y = 0), "lower_top" and "upper_bottom" (the faces
// across the gap).
SetFactory("OpenCASCADE");
DefineConstant[ L = 0.1, H = 0.05, g = 0.001, h = 0.025 ];
If (L <= 0 || H <= 0 || g <= 0 || h <= 0)
  Error("two_blocks.geo: need L, H, g, h > 0 (L = %g, H = %g, g = %g, h = %g)", L, H, g, h);
EndIf

Box(1) = {0, 0, 0, L, L, H};
Box(2) = {0, 0, H + g, L, L, H};

e = 1e-3 * g;
bottom() = Surface In BoundingBox{-e, -e, -e, L + e, L + e, e};
lower_top() = Surface In BoundingBox{-e, -e, H - e, L + e, L + e, H + e};
upper_bottom() = Surface In BoundingBox{-e, -e, H + g - e, L + e, L + e, H + g + e};
top() = Surface In BoundingBox{-e, -e, 2 * H + g - e, L + e, L + e, 2 * H + g + e};
x0() = Surface In BoundingBox{-e, -e, -e, e, L + e, 2 * H + g + e};
y0() = Surface In BoundingBox{-e, -e, -e, L + e, e, 2 * H + g + e};
If (#bottom() != 1 || #lower_top() != 1 || #upper_bottom() != 1 || #top() != 1 ||
    #x0() != 2 || #y0() != 2)
  Error("two_blocks.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {1, 2};
Physical Surface("bottom") = {bottom()};
Physical Surface("top") = {top()};
Physical Surface("x0") = {x0()};
Physical Surface("y0") = {y0()};
Physical Surface("lower_top") = {lower_top()};
Physical Surface("upper_bottom") = {upper_bottom()};

MeshSize{ PointsOf{ Volume{1}; } } = h;
MeshSize{ PointsOf{ Volume{2}; } } = 0.7 * h;
Mesh.MeshSizeMax = h;
