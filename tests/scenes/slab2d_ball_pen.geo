// Aluminium slab (2D, millimetres): the rectangle [-20, 20] x [0, 5]. Mesh
// size 0.1 near the bottom (contact) edge for |x| < 5, growing to 0.8.
//   gmsh -2 -format msh22 -o tests/scenes/slab2d_ball_pen.msh tests/scenes/slab2d_ball_pen.geo
L = 20;  T = 5;  HC = 0.1;  H0 = 0.8;
Point(1) = {-L, 0, 0, H0};
Point(2) = { L, 0, 0, H0};
Point(3) = { L, T, 0, H0};
Point(4) = {-L, T, 0, H0};
Point(5) = {-5, 0, 0, HC};
Point(6) = { 5, 0, 0, HC};
Line(1) = {1, 5};
Line(5) = {5, 6};
Line(6) = {6, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 5, 6, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("bottom") = {1, 5, 6};
Physical Curve("sides") = {2, 4};
Physical Curve("top") = {3};
Physical Surface("slab") = {1};

// HC in the box |x| < 5, y < 1, growing to H0 over a 4 mm band around it.
Field[1] = Box;
Field[1].VIn = HC;
Field[1].VOut = H0;
Field[1].XMin = -5;
Field[1].XMax = 5;
Field[1].YMin = -1;
Field[1].YMax = 1;
Field[1].Thickness = 4;
Background Field = 1;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.Algorithm = 6;
Mesh.ElementOrder = 1;
