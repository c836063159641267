// Cook's membrane: the tapered panel (0, 0), (48, 44), (48, 60), (0, 44) (mm, or any unit),
// extruded by a thickness t in z; clamped on x = 0, sheared on x = 48. With uz held on both
// faces z = 0 and z = t it is the plane-strain benchmark of nearly incompressible elements.
// Parameters (override from a deck's mesh.parameters or gmsh -setnumber):
//   h: target mesh size, t: thickness.
// Physical groups: volume "body"; surfaces "clamped" (x = 0), "loaded" (x = 48),
// "faces" (z = 0 and z = t); point "corner" (48, 60, 0), where the deflection is read.
SetFactory("OpenCASCADE");
DefineConstant[ h = 4.0, t = 1.0 ];
If (h <= 0 || t <= 0)
  Error("cook.geo: need h > 0 and t > 0 (h = %g, t = %g)", h, t);
EndIf
If (h < 0.1)
  Error("cook.geo: need h >= 0.1 (h = %g): finer meshes run past any deck's element limit", h);
EndIf

Point(1) = {0, 0, 0, h};
Point(2) = {48, 44, 0, h};
Point(3) = {48, 60, 0, h};
Point(4) = {0, 44, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, t} { Surface{1}; };

e = 1e-3;  // bounding-box tolerance, below any feature
clamped() = Surface In BoundingBox{-e, -e, -e, e, 60 + e, t + e};
loaded() = Surface In BoundingBox{48 - e, -e, -e, 48 + e, 60 + e, t + e};
faces() = Surface In BoundingBox{-e, -e, -e, 48 + e, 60 + e, e};
faces() += Surface In BoundingBox{-e, -e, t - e, 48 + e, 60 + e, t + e};
corner() = Point In BoundingBox{48 - e, 60 - e, -e, 48 + e, 60 + e, e};
If (#clamped() != 1 || #loaded() != 1 || #faces() != 2 || #corner() != 1)
  Error("cook.geo: a bounding-box selection of the boundary failed");
EndIf

Physical Volume("body") = {out[1]};
Physical Surface("clamped") = {clamped()};
Physical Surface("loaded") = {loaded()};
Physical Surface("faces") = {faces()};
Physical Point("corner") = {corner()};
Mesh.CharacteristicLengthMax = h;
