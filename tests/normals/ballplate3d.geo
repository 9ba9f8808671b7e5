// A quarter of a thick plate (3D) pressed onto a rigid ball: the box
// [0,1] x [0,1] x [0,1]; the faces x = 0 and y = 0 are symmetry planes,
// the ball touches the bottom face at the corner (0,0,0). Tetrahedra of
// size HC within 0.2 of that corner, growing to H0 at 1.
//   gmsh -3 -format msh41 -o ballplate3d.msh tests/normals/ballplate3d.geo
SetFactory("OpenCASCADE");
HC = 0.02;  H0 = 0.25;
Box(1) = {0, 0, 0, 1, 1, 1};
Physical Surface("symx") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 0.01, 1.01, 1.01}};
Physical Surface("symy") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 0.01, 1.01}};
Physical Surface("bottom") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 1.01, 0.01}};
Physical Surface("top") = {Surface In BoundingBox{-0.01, -0.01, 0.99, 1.01, 1.01, 1.01}};
Physical Volume("plate") = {1};
corner() = Point In BoundingBox{-0.01, -0.01, -0.01, 0.01, 0.01, 0.01};
Field[1] = Distance;
Field[1].PointsList = {corner(0)};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.2;
Field[2].DistMax = 1;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.ElementOrder = 1;
