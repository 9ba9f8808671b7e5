// Half a thick plate (3D) on a rigid ball, for Mindlin's stick zone under
// a tangential load along x (tests/history.rs): the box [-1,1] x [0,1] x
// [0,1], the face y = 0 a symmetry plane ("symy"), the ball touching the
// bottom face at the origin. Tetrahedra of size HC within 0.25 of the
// origin, growing to H0.
//   gmsh -3 -format msh41 -o halfplate3d.msh tests/obstacles/halfplate3d.geo
SetFactory("OpenCASCADE");
DefineConstant[ HC = 0.025, H0 = 0.3 ];
Box(1) = {-1, 0, 0, 2, 1, 1};
Physical Surface("symy") = {Surface In BoundingBox{-1.01, -0.01, -0.01, 1.01, 0.01, 1.01}};
Physical Surface("bottom") = {Surface In BoundingBox{-1.01, -0.01, -0.01, 1.01, 1.01, 0.01}};
Physical Surface("top") = {Surface In BoundingBox{-1.01, -0.01, 0.99, 1.01, 1.01, 1.01}};
Physical Volume("plate") = {1};
Point(100) = {0, 0, 0, HC};
Field[1] = Distance;
Field[1].PointsList = {100};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.25;
Field[2].DistMax = 1;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
