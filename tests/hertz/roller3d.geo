// A roller lying on its side (tests/hertz.rs, line contact in 3D): a
// cylinder of radius 1, its axis along y at height 1, the part x >= 0 and
// below the axis (a quarter of the section, symmetry plane x = 0),
// extruded over 0 <= y <= len. Groups: contact (the arc), top (the cut
// z = 1), sym (x = 0), end (y = 0), far (y = len), body.
// hc: the mesh size along the contact line, h elsewhere.
DefineConstant[ hc = 0.03, h = 0.1, len = 2 ];
Point(1) = {0, 0, 1, h};
Point(2) = {0, 0, 0, hc};
Point(3) = {1, 0, 1, h};
Point(4) = {0.3, 0, 1 - Sqrt(1 - 0.09), hc};
Circle(1) = {2, 1, 4};
Circle(2) = {4, 1, 3};
Line(3) = {3, 1};
Line(4) = {1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
out[] = Extrude {0, len, 0} { Surface{1}; };
// out[0] the far end, out[1] the volume, out[2..5] the sides of curves 1-4.
Physical Volume("body") = {out[1]};
Physical Surface("contact") = {out[2], out[3]};
Physical Surface("top") = {out[4]};
Physical Surface("sym") = {out[5]};
Physical Surface("end") = {1};
Physical Surface("far") = {out[0]};
