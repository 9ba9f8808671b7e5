// 2D Hertz scene (paper, section 7.1), refined near the contact point for a
// low-load test (half contact width b ~ 0.68).
// Quarter of the cylinder cross-section: radius R = 8, centre (0, 8); the body
// is x >= 0, y <= 8 inside the circle. Contact near (0, 0) against y = 0.
//
// Element size h_min within distance d_min of (0, 0), growing linearly to
// h_max at distance d_max and beyond:
//   gmsh -2 -format msh41 hertz_lowload.geo -o hertz_lowload.msh
DefineConstant[
  h_min = {0.01, Name "h_min"},
  h_max = {0.4, Name "h_max"},
  d_min = {1.25, Name "d_min"},
  d_max = {5.0, Name "d_max"}
];
R = 8;

Point(1) = {0, 0, 0, h_max};   // contact point (bottom of the arc)
Point(2) = {0, R, 0, h_max};   // centre of the circle
Point(3) = {R, R, 0, h_max};   // right end of the arc

Circle(1) = {1, 2, 3};         // arc (0,0) -> (8,8)
Line(2) = {3, 2};              // top edge y = 8
Line(3) = {2, 1};              // symmetry edge x = 0

Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};

Physical Curve("contact") = {1};
Physical Curve("symmetry") = {3};
Physical Curve("top") = {2};
Physical Surface("body") = {1};

Field[1] = Distance;
Field[1].PointsList = {1};

Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h_min;
Field[2].SizeMax = h_max;
Field[2].DistMin = d_min;
Field[2].DistMax = d_max;

Background Field = 2;

Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;            // Frontal-Delaunay
Mesh.ElementOrder = 1;
