// A block (2D) for the tests of several obstacles (tests/obstacles.rs):
// [-1,1] x [0,1], its top edge split at the point "mid" (0,1), which the
// tests hold in x (the block's symmetry line); groups bottom, top, sides.
//   gmsh -2 -format msh22 -o multi_block2d.msh tests/obstacles/multi_block2d.geo
h = 0.04;
Point(1) = {-1, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {1, 1, 0, h};
Point(4) = {0, 1, 0, h};
Point(5) = {-1, 1, 0, h};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1};
Physical Curve("top") = {3, 4};
Physical Curve("sides") = {2, 5};
Physical Point("mid") = {4};
Physical Surface("block") = {1};
