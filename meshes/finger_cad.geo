// The soft finger of meshes/finger_cad.step (a CAD model in millimetres; how it was made:
// finger_cad_make.geo) as a hydrosoft mesh: docs/tutorial_cad.md walks through this file.
// Physical groups, picked by bounding boxes of the imported shape, not by the tags the CAD
// export happened to give its faces (they change whenever the model is edited):
//   volume "body"; surfaces "base" (the end face at the smallest x, clamped), "tip" (the
//   end face at the largest x), "cavity" (every face of the closed inner cavity), "outer"
//   (the rest of the outside); point "effector", the centre of the tip face.
// Parameters (a deck's mesh.parameters or gmsh -setnumber):
//   h: target mesh size (m); h = 0.004 (default): 1,009 nodes, 3,468 tetrahedra (P1);
//   h = 0.0026: 2,197 nodes.
//   wall: less than the thinnest wall between the cavity and the outside (m): the cavity
//   is every face inside the shape's bounding box shrunk by `wall` on each side.
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.004, wall = 0.001 ];
If (h <= 0 || wall <= 0)
  Error("finger_cad.geo: need h, wall > 0 (h = %g, wall = %g)", h, wall);
EndIf

// STEP files carry their unit; OpenCASCADE reads them in millimetres. hydrosoft works in SI
// units: scale by 1e-3 on import.
Geometry.OCCScaling = 0.001;
v() = ShapeFromFile("finger_cad.step");
If (#v() != 1)
  Error("finger_cad.geo: finger_cad.step holds %g volumes, expected one", #v());
EndIf

// bb() = {xmin, ymin, zmin, xmax, ymax, zmax}, padded by OpenCASCADE by about 1e-7.
bb() = BoundingBox Volume{v(0)};
tol = 1e-6;
base() = Surface In BoundingBox{bb(0) - tol, bb(1) - tol, bb(2) - tol,
                                bb(0) + tol, bb(4) + tol, bb(5) + tol};
tip() = Surface In BoundingBox{bb(3) - tol, bb(1) - tol, bb(2) - tol,
                               bb(3) + tol, bb(4) + tol, bb(5) + tol};
cavity() = Surface In BoundingBox{bb(0) + wall, bb(1) + wall, bb(2) + wall,
                                  bb(3) - wall, bb(4) - wall, bb(5) - wall};
faces() = Boundary{ Volume{v(0)}; };
outer() = faces();
outer() -= {base(), tip(), cavity()};
// A selection that misses or over-reaches would leave a group silently wrong. This model has
// 20 faces: two flat ends, 8 around the outside (4 flat, 4 rounded), 10 around the cavity
// (4 flat, 4 rounded, 2 ends). Change these counts with the CAD model.
If (#base() != 1 || #tip() != 1 || #cavity() != 10 || #outer() != 8 || #faces() != 20)
  Error("finger_cad.geo: a bounding-box selection failed (base %g, tip %g, cavity %g, outer %g of %g faces; expected 1, 1, 10, 8 of 20)",
        #base(), #tip(), #cavity(), #outer(), #faces());
EndIf

// The effector: the centre of the flat tip face, made a node of its mesh. Its x is that of a
// corner of the face (the box is padded); y and z the middle of the (symmetric) padding.
tip_corners() = Boundary{ Curve{ Abs(Boundary{ Surface{tip(0)}; }) }; };
corner() = Point{ Abs(tip_corners(0)) };
effector = newp;
Point(effector) = {corner(0), (bb(1) + bb(4)) / 2, (bb(2) + bb(5)) / 2};
Point{effector} In Surface{tip(0)};

Physical Volume("body") = {v(0)};
Physical Surface("base") = {base()};
Physical Surface("tip") = {tip()};
Physical Surface("cavity") = {cavity()};
Physical Surface("outer") = {outer()};
Physical Point("effector") = {effector};

// One size everywhere: the rounded edges (r 3 and 1.5 mm) are faceted at h rather than
// refined by curvature, which would multiply the nodes near the cavity's edges.
Mesh.MeshSizeFromCurvature = 0;
MeshSize{ PointsOf{ Volume{v(0)}; } } = h;
MeshSize{ effector } = h;
Mesh.MeshSizeMax = h;
