// The rigid ball of tests/normals' plate (radius 1, centre (0,0,-1)) as a
// triangulated surface, for `-obstacle mesh` against `-obstacle ball`
// (tests/surface_obstacle.rs): triangles of size HC within 0.3 of its top
// (0,0,0), where the plate touches it, growing to H0; with reverse = 1 its
// triangles face inward (a spherical cavity, by their orientation alone).
//   gmsh -2 -format msh41 -o ball_below.msh tests/obstacles/ball_below.geo
SetFactory("OpenCASCADE");
DefineConstant[ HC = 0.01, H0 = 0.2, reverse = 0 ];
Sphere(1) = {0, 0, -1, 1};
Physical Surface("ball") = {1};
If (reverse)
  Reverse Surface{1};
EndIf
top() = Point In BoundingBox{-0.01, -0.01, -0.01, 0.01, 0.01, 0.01};
Field[1] = Distance;
Field[1].PointsList = {top(0)};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.3;
Field[2].DistMax = 1;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
