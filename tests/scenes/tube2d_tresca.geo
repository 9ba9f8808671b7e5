// Quarter of a thick tube's cross-section (2D): the annulus between radii
// RI and RO around (0, RO), quarter x >= 0, y <= RO. Its outer arc touches
// the floor near the origin. Mesh size HC near the origin, H0 far from it.
//   gmsh -2 -format msh41 -o tests/scenes/tube2d_tresca.msh tests/scenes/tube2d_tresca.geo
RO = 8;  RI = 4;  HC = 0.025;  H0 = 0.5;
Point(1) = {0, 0, 0, HC};          // bottom of the outer arc
Point(2) = {0, RO, 0, H0};         // centre
Point(3) = {RO, RO, 0, H0};        // end of the outer arc
Point(4) = {RI, RO, 0, H0};        // end of the inner arc
Point(5) = {0, RO - RI, 0, H0};    // bottom of the inner arc
Circle(1) = {1, 2, 3};             // outer arc: contact surface
Line(2) = {3, 4};                  // top edge y = RO: loaded
Circle(3) = {4, 2, 5};             // inner arc: free
Line(4) = {5, 1};                  // symmetry edge x = 0
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Curve("outer") = {1};
Physical Curve("top") = {2};
Physical Curve("inner") = {3};
Physical Curve("symmetry") = {4};
Physical Surface("tube") = {1};

// HC within 0.8 of the origin, growing linearly to H0 at 4.
Field[1] = Distance;
Field[1].PointsList = {1};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.8;
Field[2].DistMax = 4;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.ElementOrder = 1;
