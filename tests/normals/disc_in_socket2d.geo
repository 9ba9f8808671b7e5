// An elastic disc of radius 0.9 centred (0, -0.099), its lowest point on
// the circle of radius 0.999 about the origin: the disc rests in a rigid
// socket of that radius (tests/normals.rs). Its boundary is the group
// "rim", uniform triangles of size h.
//   gmsh -2 -format msh41 -o disc.msh tests/normals/disc_in_socket2d.geo
DefineConstant[ h = 0.03 ];
R = 0.9; cy = -0.099;
Point(1) = {0, cy, 0, h};
Point(2) = {R, cy, 0, h};
Point(3) = {0, cy + R, 0, h};
Point(4) = {-R, cy, 0, h};
Point(5) = {0, cy - R, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("rim") = {1, 2, 3, 4};
Physical Surface("disc") = {1};
