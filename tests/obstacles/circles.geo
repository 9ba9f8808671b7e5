// Two counter-clockwise circles, for the mesh-obstacle tests
// (src/contact/mesh_obstacle/tests.rs): "rim", radius 1 about the origin,
// and "other", radius 0.5 about (5, 0). gmsh -1 -setnumber h H circles.geo
DefineConstant[ h = 0.1 ];
Point(1) = {0, 0, 0, h};
Point(2) = {1, 0, 0, h};
Point(3) = {0, 1, 0, h};
Point(4) = {-1, 0, 0, h};
Point(5) = {0, -1, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Point(6) = {5, 0, 0, h};
Point(7) = {5.5, 0, 0, h};
Point(8) = {4.5, 0, 0, h};
Circle(5) = {7, 6, 8};
Circle(6) = {8, 6, 7};
Physical Curve("rim") = {1, 2, 3, 4};
Physical Curve("other") = {5, 6};
