// A crowned block (2D): x in [-3, 3], top edge y = 3, bottom edge a circular
// arc of radius RC centred (0, RC) (lowest point at the origin). Mesh size
// HC near the origin, growing to H0.
//   gmsh -2 -format msh41 -o tests/scenes/crowned2d_coulomb.msh tests/scenes/crowned2d_coulomb.geo
W = 3;  H = 3;  RC = 30;  HC = 0.02;  H0 = 0.35;
yw = RC - Sqrt(RC^2 - W^2);
Point(1) = {-W, yw, 0, H0};
Point(2) = {0, 0, 0, HC};
Point(3) = {W, yw, 0, H0};
Point(4) = {W, H, 0, H0};
Point(5) = {-W, H, 0, H0};
Point(6) = {0, RC, 0, H0};        // centre of the arc (not meshed)
Circle(1) = {1, 6, 2};
Circle(2) = {2, 6, 3};
Line(3) = {3, 4};
Line(4) = {4, 5};
Line(5) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Curve("crown") = {1, 2};
Physical Curve("sides") = {3, 5};
Physical Curve("top") = {4};
Physical Surface("block") = {1};

// HC within 0.6 of the origin, growing linearly to H0 at 2.5.
Field[1] = Distance;
Field[1].PointsList = {2};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.6;
Field[2].DistMax = 2.5;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.ElementOrder = 1;
