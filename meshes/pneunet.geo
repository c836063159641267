// A PneuNet-style bending actuator: a row of chambers joined by a channel into one cavity,
// on a stiffer strain-limiting layer; clamped at x = 0. Inflating the chambers stretches the
// soft top more than the layer, so the actuator bends towards the layer's side.
// Physical groups: volumes "body" (the chambers' soft silicone) and "layer" (the
// strain-limiting bottom layer); surfaces "base" (the clamped end, x = 0), "tip" (x = L),
// "cavity" (every wall of the chambers and the channel), "slots" (the walls and floors of the
// slots between the chamber blocks, which press on each other when the chambers bulge:
// self-contact); point "effector", the centre of the tip face.
// Parameters (a deck's mesh.parameters or gmsh -setnumber), lengths in m:
//   h: mesh size; chambers: how many; pitch: their spacing along x.
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.004, chambers = 6, pitch = 0.014 ];
If (h <= 0 || chambers < 1 || pitch <= 0.006)
  Error("pneunet.geo: need h > 0, chambers >= 1, pitch > 6 mm (h = %g, chambers = %g, pitch = %g)",
        h, chambers, pitch);
EndIf
head = 0.008;            // solid clamped length before the first chamber
L = 2 * head + chambers * pitch;
W = 0.020;               // width (y)
H = 0.018;               // height (z) above the layer's bottom
layer = 0.003;           // strain-limiting layer, z in [0, layer]
wall = 0.0015;           // chamber walls
slot = 0.002;            // gap between neighbouring chamber blocks, from z = slot_floor up
slot_floor = 0.0075;
channel_z0 = 0.004; channel_z1 = 0.006; channel_w = 0.004;

layer_v = newv; Box(layer_v) = {0, -W / 2, 0, L, W, layer};
body_v = newv; Box(body_v) = {0, -W / 2, layer, L, W, H - layer};
For k In {1 : chambers - 1}
  s = newv;
  Box(s) = {head + k * pitch - slot / 2, -W / 2, slot_floor, slot, W, H - slot_floor};
  cut() = BooleanDifference{ Volume{body_v}; Delete; }{ Volume{s}; Delete; };
  body_v = cut(0);
EndFor
cav = newv;
Box(cav) = {head + pitch / 2, -channel_w / 2, channel_z0, (chambers - 1) * pitch, channel_w,
            channel_z1 - channel_z0};
For k In {0 : chambers - 1}
  c = newv;
  x0 = head + k * pitch + slot / 2 + wall;
  Box(c) = {x0, -W / 2 + wall, channel_z0, pitch - slot - 2 * wall, W - 2 * wall,
            H - wall - channel_z0};
  joined() = BooleanUnion{ Volume{cav}; Delete; }{ Volume{c}; Delete; };
  cav = joined(0);
EndFor
cut() = BooleanDifference{ Volume{body_v}; Delete; }{ Volume{cav}; Delete; };
body_v = cut(0);
v() = BooleanFragments{ Volume{body_v, layer_v}; Delete; }{};
If (#v() != 2)
  Error("pneunet.geo: expected two volumes (body, layer), got %g", #v());
EndIf

tol = 1e-6;
bottom() = Volume In BoundingBox{-tol, -W / 2 - tol, -tol, L + tol, W / 2 + tol, layer + tol};
top() = Volume In BoundingBox{-tol, -W / 2 - tol, layer - tol, L + tol, W / 2 + tol, H + tol};
base() = Surface In BoundingBox{-tol, -W / 2 - tol, -tol, tol, W / 2 + tol, H + tol};
tip() = Surface In BoundingBox{L - tol, -W / 2 - tol, -tol, L + tol, W / 2 + tol, H + tol};
cavity() = Surface In BoundingBox{head - tol, -W / 2 + wall - tol, channel_z0 - tol,
                                  L - head + tol, W / 2 - wall + tol, H - wall + tol};
If (#bottom() != 1 || #top() != 1 || #base() != 2 || #tip() != 2 || #cavity() < 6 * chambers)
  Error("pneunet.geo: a bounding-box selection failed (layer %g, body %g, base %g, tip %g, cavity %g faces)",
        #bottom(), #top(), #base(), #tip(), #cavity());
EndIf
slots() = {};
For k In {1 : chambers - 1}
  slots() += Surface In BoundingBox{head + k * pitch - slot / 2 - tol, -W / 2 - tol,
                                    slot_floor - tol, head + k * pitch + slot / 2 + tol,
                                    W / 2 + tol, H + tol};
EndFor
If (#slots() != 3 * (chambers - 1))
  Error("pneunet.geo: expected 3 faces a slot, got %g for %g slots", #slots(), chambers - 1);
EndIf
effector = newp;
Point(effector) = {L, 0, H / 2};
tip_top() = Surface In BoundingBox{L - tol, -W / 2 - tol, layer - tol, L + tol, W / 2 + tol, H + tol};
Point{effector} In Surface{tip_top(0)};

Physical Volume("body") = {top()};
Physical Volume("layer") = {bottom()};
Physical Surface("base") = {base()};
Physical Surface("tip") = {tip()};
Physical Surface("cavity") = {cavity()};
If (chambers > 1)
  Physical Surface("slots") = {slots()};
EndIf
Physical Point("effector") = {effector};
Mesh.MeshSizeFromCurvature = 0;
Mesh.MeshSizeMax = h;
