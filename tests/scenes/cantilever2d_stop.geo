// A slender cantilever (2D, inches): the rectangle [0, 10] x [0, 0.5],
// uniform triangles of size H.
//   gmsh -2 -format msh41 -o tests/scenes/cantilever2d_stop.msh tests/scenes/cantilever2d_stop.geo
H = 0.06;
Point(1) = {0, 0, 0, H};
Point(2) = {10, 0, 0, H};
Point(3) = {10, 0.5, 0, H};
Point(4) = {0, 0.5, 0, H};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("underside") = {1};
Physical Curve("tip") = {2};
Physical Curve("top") = {3};
Physical Curve("root") = {4};
Physical Surface("beam") = {1};
Mesh.Algorithm = 6;
Mesh.ElementOrder = 1;
