// Benchmark body with one fine cavity: a cube of side 2 b (centred at the origin) holding a
// spherical cavity of radius a at its centre. The cavity surface is meshed finely (size hc,
// ~100k triangles with the defaults) and the size grows with the distance from it to ho at
// the outer faces (a distance + threshold size field), so the volume mesh stays moderate.
// Units: metres. Override with gmsh -setnumber NAME VALUE (the parameters are DefineConstant).
//   a: cavity radius, b: half side of the cube, hc: mesh size on the cavity,
//   ho: mesh size far from it, grow: distance over which the size grows from hc to ho.
// Physical groups: volume "body"; surfaces "cavity" (the sphere; normals out of the body,
// i.e. into the cavity), "fixed" (the bottom face z = -b), "outer" (the other five faces).
SetFactory("OpenCASCADE");
DefineConstant[ a = 0.02, b = 0.05, hc = 3.4e-4, ho = 0.01, grow = 0.01 ];
If (a <= 0 || b <= a || hc <= 0 || ho < hc || grow <= 0)
  Error("sphere_cavity.geo: need 0 < a < b, 0 < hc <= ho, grow > 0 (a = %g, b = %g, hc = %g, ho = %g, grow = %g)",
        a, b, hc, ho, grow);
EndIf

Box(1) = {-b, -b, -b, 2 * b, 2 * b, 2 * b};
Sphere(2) = {0, 0, 0, a};
BooleanDifference(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };

tol = 1e-3 * (b - a);
fixed() = Surface In BoundingBox{-b - tol, -b - tol, -b - tol, b + tol, b + tol, -b + tol};
cavity() = Surface In BoundingBox{-a - tol, -a - tol, -a - tol, a + tol, a + tol, a + tol};
outer() = Boundary{ Volume{3}; };
outer() -= {fixed(), cavity()};
If (#fixed() != 1 || #cavity() != 1 || #outer() != 5)
  Error("sphere_cavity.geo: a bounding-box selection of the boundary failed (fixed %g, cavity %g, outer %g; expected 1, 1, 5)",
        #fixed(), #cavity(), #outer());
EndIf

Physical Volume("body") = {3};
Physical Surface("cavity") = {cavity()};
Physical Surface("fixed") = {fixed()};
Physical Surface("outer") = {outer()};

// Size: hc on the cavity, growing linearly with the distance from it to ho at distance
// grow. The distance to a sphere is exact in closed form (a sampled distance field would
// leave the size uneven on the cavity).
Field[1] = MathEval;
Field[1].F = Sprintf("min(%.17g, %.17g + %.17g * max(0, sqrt(x * x + y * y + z * z) - %.17g))",
                     ho, hc, (ho - hc) / grow, a);
Background Field = 1;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
