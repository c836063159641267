// Two square bars of one mesh turned 45 degrees about their axes, so that a sharp edge (a
// ridge) of each faces the other, crossed at right angles across a gap: the lower along x,
// its upper ridge on the x axis; the upper along y, its lower ridge at z = g above the y axis.
// The ridges cross at the origin halfway between their nodes (each ridge of 2 n + 1 equal
// segments), where no node of either comes near a triangle of the other: edge against edge
// (contact.self's edge pairs, docs/contact.md).
// Parameters: L (m), the bars' length; a (m), their side; g (m), the gap; n.
// Physical groups: volume "body" (both); surfaces "lower_ends" (x = +-L/2), "upper_ends"
// (y = +-L/2), "lower_ridge" and "upper_ridge" (the two faces beside each ridge).
SetFactory("OpenCASCADE");
DefineConstant[ L = 0.06, a = 0.01, g = 0.001, n = 3 ];
If (L <= 0 || a <= 0 || g <= 0 || n < 1)
  Error("crossed_bars.geo: need L, a, g > 0 and n >= 1 (L = %g, a = %g, g = %g, n = %g)", L, a, g, n);
EndIf

r = a / Sqrt(2);  // the ridge's height above the bar's axis
Box(1) = {-L / 2, -a / 2, -a / 2, L, a, a};
Rotate {{1, 0, 0}, {0, 0, 0}, Pi / 4} { Volume{1}; }
Translate {0, 0, -r} { Volume{1}; }
Box(2) = {-a / 2, -L / 2, -a / 2, a, L, a};
Rotate {{0, 1, 0}, {0, 0, 0}, Pi / 4} { Volume{2}; }
Translate {0, 0, g + r} { Volume{2}; }

e = 1e-3 * g;
lower_ends() = Surface In BoundingBox{-L / 2 - e, -r - e, -2 * r - e, -L / 2 + e, r + e, e};
lower_ends() += Surface In BoundingBox{L / 2 - e, -r - e, -2 * r - e, L / 2 + e, r + e, e};
upper_ends() = Surface In BoundingBox{-r - e, -L / 2 - e, g - e, r + e, -L / 2 + e, g + 2 * r + e};
upper_ends() += Surface In BoundingBox{-r - e, L / 2 - e, g - e, r + e, L / 2 + e, g + 2 * r + e};
lower_ridge() = Surface In BoundingBox{-L / 2 - e, -r - e, -r - e, L / 2 + e, r + e, e};
upper_ridge() = Surface In BoundingBox{-r - e, -L / 2 - e, g - e, r + e, L / 2 + e, g + r + e};
ridges() = Curve In BoundingBox{-L / 2 - e, -e, -e, L / 2 + e, e, e};
ridges() += Curve In BoundingBox{-e, -L / 2 - e, g - e, e, L / 2 + e, g + e};
If (#lower_ends() != 2 || #upper_ends() != 2 || #lower_ridge() != 2 || #upper_ridge() != 2 ||
    #ridges() != 2)
  Error("crossed_bars.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {1, 2};
Physical Surface("lower_ends") = {lower_ends()};
Physical Surface("upper_ends") = {upper_ends()};
Physical Surface("lower_ridge") = {lower_ridge()};
Physical Surface("upper_ridge") = {upper_ridge()};

Transfinite Curve{ridges()} = 2 * n + 2;
Mesh.MeshSizeMax = L / (2 * n + 1);
