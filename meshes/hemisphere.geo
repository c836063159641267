// A quarter of a solid hemisphere for Hertz contact: the ball x^2 + y^2 + z^2 <= R^2 cut to
// x >= 0, y >= 0, z <= 0, its flat face z = 0 on top and its pole (0, 0, -R) at the bottom,
// where it touches a plane below. The mesh is refined towards the pole: size hc within rc of
// it, growing to h at 3 rc. Units: metres.
// Parameters (override from a deck's mesh.parameters; DefineConstant): R, h, hc, rc.
// Physical groups: volume "body"; surfaces "top" (z = 0), "x0" (x = 0), "y0" (y = 0), "ball"
// (the curved surface, the one that may touch); point "pole".
SetFactory("OpenCASCADE");
DefineConstant[ R = 0.01, h = 0.002, hc = 0.0001, rc = 0.001 ];
If (R <= 0 || h <= 0 || hc <= 0 || rc <= 0 || hc > h)
  Error("hemisphere.geo: need R, h, hc, rc > 0 and hc <= h (R = %g, h = %g, hc = %g, rc = %g)",
        R, h, hc, rc);
EndIf
Sphere(1) = {0, 0, 0, R};
Box(2) = {0, 0, -R, R, R, R};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
tol = 1e-3 * R;  // above OCC's bounding-box padding, below any feature
top() = Surface In BoundingBox{-tol, -tol, -tol, R + tol, R + tol, tol};
x0() = Surface In BoundingBox{-tol, -tol, -R - tol, tol, R + tol, tol};
y0() = Surface In BoundingBox{-tol, -tol, -R - tol, R + tol, tol, tol};
ball() = Boundary{ Volume{3}; };
ball() -= {top(), x0(), y0()};
If (#top() != 1 || #x0() != 1 || #y0() != 1 || #ball() != 1)
  Error("hemisphere.geo: a bounding-box selection failed (top %g, x0 %g, y0 %g, ball %g)",
        #top(), #x0(), #y0(), #ball());
EndIf
pole() = Point In BoundingBox{-tol, -tol, -R - tol, tol, tol, -R + tol};
Physical Volume("body") = {3};
Physical Surface("top") = {top()};
Physical Surface("x0") = {x0()};
Physical Surface("y0") = {y0()};
Physical Surface("ball") = {ball()};
Physical Point("pole") = {pole(0)};

Field[1] = Distance;
Field[1].PointsList = {pole(0)};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = hc;
Field[2].SizeMax = h;
Field[2].DistMin = rc;
Field[2].DistMax = 3 * rc;
Background Field = 2;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeExtendFromBoundary = 0;
