// A bar of two materials in series: x in [0, L1] is "stiff", x in [L1, L1 + L2] is "soft";
// square section w x w on y, z in [0, w]. For the stiffness-contrast case (E from 1e3 to
// 1e9 Pa in one body): pulled at its end, it has a closed-form piecewise-linear solution.
// Parameters: L1, L2, w, h (target mesh size).
// Physical groups: volumes "stiff", "soft"; surfaces "x0" (x = 0), "end" (x = L1 + L2),
// "y0" (y = 0), "z0" (z = 0).
SetFactory("OpenCASCADE");
DefineConstant[ L1 = 1.0, L2 = 1.0, w = 0.2, h = 0.1 ];
If (L1 <= 0 || L2 <= 0 || w <= 0 || h <= 0)
  Error("bimaterial_bar.geo: need positive L1, L2, w, h");
EndIf

Box(1) = {0, 0, 0, L1, w, w};
Box(2) = {L1, 0, 0, L2, w, w};
v() = BooleanFragments{ Volume{1, 2}; Delete; }{};  // conforming interface

e = 1e-6 * (L1 + L2);
x0() = Surface In BoundingBox{-e, -e, -e, e, w + e, w + e};
xe() = Surface In BoundingBox{L1 + L2 - e, -e, -e, L1 + L2 + e, w + e, w + e};
y0() = Surface In BoundingBox{-e, -e, -e, L1 + L2 + e, e, w + e};
z0() = Surface In BoundingBox{-e, -e, -e, L1 + L2 + e, w + e, e};
stiff() = Volume In BoundingBox{-e, -e, -e, L1 + e, w + e, w + e};
soft() = Volume In BoundingBox{L1 - e, -e, -e, L1 + L2 + e, w + e, w + e};

Physical Volume("stiff") = {stiff()};
Physical Volume("soft") = {soft()};
Physical Surface("x0") = {x0()};
Physical Surface("end") = {xe()};
Physical Surface("y0") = {y0()};
Physical Surface("z0") = {z0()};

MeshSize{ PointsOf{ Volume{:}; } } = h;
Mesh.MeshSizeMax = h;
