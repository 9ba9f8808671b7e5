// A plate with a circular hole (2D, plane strain): the square [-2,2]^2 with
// the hole of radius 1 centred at the origin; elements of size HC on the
// hole ("seat"), growing to H0 on the outer edge ("outer").
//   gmsh -2 -format msh22 -o pin2d.msh tests/normals/pin2d.geo
SetFactory("OpenCASCADE");
HC = 0.03;  H0 = 0.25;
Rectangle(1) = {-2, -2, 0, 4, 4};
Disk(2) = {0, 0, 0, 1};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
Physical Curve("seat") = {Curve In BoundingBox{-1.01, -1.01, -0.01, 1.01, 1.01, 0.01}};
outer() = {Curve In BoundingBox{-2.01, -2.01, -0.01, -1.99, 2.01, 0.01},
           Curve In BoundingBox{1.99, -2.01, -0.01, 2.01, 2.01, 0.01},
           Curve In BoundingBox{-2.01, -2.01, -0.01, 2.01, -1.99, 0.01},
           Curve In BoundingBox{-2.01, 1.99, -0.01, 2.01, 2.01, 0.01}};
Physical Curve("outer") = {outer()};
Physical Surface("plate") = {3};
MeshSize{PointsOf{Curve{outer()};}} = H0;
MeshSize{PointsOf{Curve{Curve In BoundingBox{-1.01, -1.01, -0.01, 1.01, 1.01, 0.01}};}} = HC;
Mesh.ElementOrder = 1;
