// The nearly incompressible block under partial compression (Reese, Wriggers and Reddy,
// Computers and Structures 75, 2000; deal.II's step-44): by symmetry a quarter of it, the cube
// [0, a]^3, pressed on the quarter [0, a/2]^2 of its top face z = a.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber): a, the edge (m);
// h, the mesh size (m).
// Physical groups: volume "body"; surfaces "symmetry_x" (x = 0), "symmetry_y" (y = 0),
// "bottom" (z = 0), "top" (z = a, the whole face: held in x and y) and "patch" (its loaded
// quarter); point "centre" (0, 0, a), the top face's centre in the whole block, where the
// compression is read.
SetFactory("OpenCASCADE");
DefineConstant[ a = 1e-3, h = 1.25e-4 ];
If (a <= 0 || h <= 0)
  Error("compressed_block.geo: need a > 0 and h > 0 (a = %g, h = %g)", a, h);
EndIf
If (h < a / 100)
  Error("compressed_block.geo: need h >= a/100 (h = %g): finer meshes run past any deck's element limit", h);
EndIf

Box(1) = {0, 0, 0, a, a, a};
Rectangle(10) = {0, 0, a, a / 2, a / 2};
BooleanFragments{ Volume{1}; Delete; }{ Surface{10}; Delete; }

e = 1e-3 * a;  // bounding-box tolerance, below any feature
symmetry_x() = Surface In BoundingBox{-e, -e, -e, e, a + e, a + e};
symmetry_y() = Surface In BoundingBox{-e, -e, -e, a + e, e, a + e};
bottom() = Surface In BoundingBox{-e, -e, -e, a + e, a + e, e};
top() = Surface In BoundingBox{-e, -e, a - e, a + e, a + e, a + e};
patch() = Surface In BoundingBox{-e, -e, a - e, a / 2 + e, a / 2 + e, a + e};
centre() = Point In BoundingBox{-e, -e, a - e, e, e, a + e};
body() = Volume In BoundingBox{-e, -e, -e, a + e, a + e, a + e};
If (#symmetry_x() != 1 || #symmetry_y() != 1 || #bottom() != 1 || #top() != 2 ||
    #patch() != 1 || #centre() != 1 || #body() != 1)
  Error("compressed_block.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {body()};
Physical Surface("symmetry_x") = {symmetry_x()};
Physical Surface("symmetry_y") = {symmetry_y()};
Physical Surface("bottom") = {bottom()};
Physical Surface("top") = {top()};
Physical Surface("patch") = {patch()};
Physical Point("centre") = {centre()};
Mesh.CharacteristicLengthMax = h;
