// A unit square with a line from the middle of its left side, (0, 0.5),
// to (0.5, 0.5) embedded in its mesh (tests/pairs.rs opens it into an
// edge crack: its nodes but the tip (0.5, 0.5) doubled, the copies taken
// by the triangles above it). Groups: crack (the line), top, bottom, left
// (the left side), corner (the point (0, 0)), plate.
//   gmsh -2 -format msh22 tests/pairs/crack2d.geo
DefineConstant[ h = 0.05 ];
Point(1) = {0, 0, 0, h}; Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h}; Point(4) = {0, 1, 0, h};
Point(5) = {0, 0.5, 0, h / 2}; Point(6) = {0.5, 0.5, 0, h / 4};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 5};
Line(5) = {5, 1}; Line(6) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Line{6} In Surface{1};
Physical Surface("plate") = {1};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3};
Physical Curve("left") = {4, 5};
Physical Curve("crack") = {6};
Physical Point("corner") = {1};
