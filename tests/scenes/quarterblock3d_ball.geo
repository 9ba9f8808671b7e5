// A quarter of a square block (3D): the box [0,1] x [0,1] x [0,0.8]; the
// faces x = 0 and y = 0 are symmetry planes of the whole block. Tetrahedra
// of size HC near the corner (0,0,0), where the block touches the ball,
// growing to H0 away from it.
//   gmsh -3 -format msh41 -o tests/scenes/quarterblock3d_ball.msh tests/scenes/quarterblock3d_ball.geo
SetFactory("OpenCASCADE");
HC = 0.035;  H0 = 0.2;
Box(1) = {0, 0, 0, 1, 1, 0.8};
Physical Surface("symx") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 0.01, 1.01, 0.81}};
Physical Surface("symy") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 0.01, 0.81}};
Physical Surface("bottom") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 1.01, 0.01}};
Physical Surface("top") = {Surface In BoundingBox{-0.01, -0.01, 0.79, 1.01, 1.01, 0.81}};
Physical Surface("free") = {Surface In BoundingBox{0.99, -0.01, -0.01, 1.01, 1.01, 0.81},
                            Surface In BoundingBox{-0.01, 0.99, -0.01, 1.01, 1.01, 0.81}};
Physical Volume("block") = {1};

// HC within 0.35 of the corner, growing linearly to H0 at 1.
corner() = Point In BoundingBox{-0.01, -0.01, -0.01, 0.01, 0.01, 0.01};
Field[1] = Distance;
Field[1].PointsList = {corner(0)};
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = HC;
Field[2].SizeMax = H0;
Field[2].DistMin = 0.35;
Field[2].DistMax = 1;
Background Field = 2;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.ElementOrder = 1;
