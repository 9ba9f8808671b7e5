// Half of a crowned steel punch (2D, metres): the section x in [0, W],
// bottom = circular arc of radius RC centred (0, RC) (lowest point at the
// origin, rising to W^2/(2 RC) at x = W), flat top y = H, vertical edge x = W.
// The edge x = 0 is a symmetry line. Mesh size HC near the lowest point of
// the arc, growing to H0 away from it.
//   gmsh -2 -format msh41 -o tests/scenes/punch2d_steel.msh tests/scenes/punch2d_steel.geo
W = 0.01;  H = 0.01;  RC = 0.2;
HC = 1.3e-4;  H0 = 1.0e-3;
yw = RC - Sqrt(RC^2 - W^2);

Point(1) = {0, 0, 0, HC};        // lowest point of the arc
Point(2) = {0, RC, 0, H0};       // centre of the arc (not meshed)
Point(3) = {W, yw, 0, H0};       // end of the arc
Point(4) = {W, H, 0, H0};
Point(5) = {0, H, 0, H0};

Circle(1) = {1, 2, 3};
Line(2) = {3, 4};
Line(3) = {4, 5};
Line(4) = {5, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};

Physical Curve("contact") = {1};
Physical Curve("side") = {2};
Physical Curve("top") = {3};
Physical Curve("symmetry") = {4};
Physical Surface("body") = {1};

// Size: HC within 4.5 mm of the lowest point, growing linearly to H0 at 9 mm.
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.0045;
Field[2].DistMax = 0.009;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.ElementOrder = 1;
