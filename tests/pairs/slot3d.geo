// A C-shaped block (tests/self_contact.rs): 2 x 1 in x, y with a slot
// 0.5 <= x <= 2, 0.45 <= y <= 0.55 cut from its right side, extruded 0.5
// along z. Groups: slot_top, slot_bottom (the slot's faces), top, bottom,
// left (x = 0), back (z = 0), body.
DefineConstant[ h = 0.08 ];
Point(1) = {0, 0, 0, h}; Point(2) = {2, 0, 0, h};
Point(3) = {2, 0.45, 0, h}; Point(4) = {0.5, 0.45, 0, h};
Point(5) = {0.5, 0.55, 0, h}; Point(6) = {2, 0.55, 0, h};
Point(7) = {2, 1, 0, h}; Point(8) = {0, 1, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 1};
Curve Loop(1) = {1:8};
Plane Surface(1) = {1};
out[] = Extrude {0, 0, 0.5} { Surface{1}; };
// out[0] the front, out[1] the volume, out[2..9] the sides of lines 1-8.
Physical Volume("body") = {out[1]};
Physical Surface("bottom") = {out[2]};
Physical Surface("slot_bottom") = {out[4]};
Physical Surface("slot_top") = {out[6]};
Physical Surface("top") = {out[8]};
Physical Surface("left") = {out[9]};
Physical Surface("back") = {1};
