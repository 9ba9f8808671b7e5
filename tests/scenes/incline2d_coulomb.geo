// A concrete block (2D, metres): the rectangle [0, 4] x [0, 1]. Mesh size
// HB along the bottom (contact) edge, growing to HT at the top.
//   gmsh -2 -format msh41 -o tests/scenes/incline2d_coulomb.msh tests/scenes/incline2d_coulomb.geo
HB = 0.025;  HT = 0.08;
Point(1) = {0, 0, 0, HB};
Point(2) = {4, 0, 0, HB};
Point(3) = {4, 1, 0, HT};
Point(4) = {0, 1, 0, HT};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("base") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Surface("block") = {1};
Mesh.Algorithm = 6;
Mesh.ElementOrder = 1;
