// A slice of a block (3D) pressed onto a rigid cylinder whose axis is y:
// the box [0,1] x [0,0.1] x [0,1]; x = 0 is a symmetry plane and the faces
// y = 0, y = 0.1 ("sides") hold uy = 0 (plane strain). The cylinder
// touches the bottom face along the line x = 0, z = 0. Tetrahedra of size
// HC within 0.2 of that line, growing to H0 at 1.
//   gmsh -3 -format msh41 -o cylblock3d.msh tests/normals/cylblock3d.geo
SetFactory("OpenCASCADE");
HC = 0.02;  H0 = 0.2;
Box(1) = {0, 0, 0, 1, 0.1, 1};
Physical Surface("symx") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 0.01, 0.11, 1.01}};
Physical Surface("sides") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 0.01, 1.01},
                             Surface In BoundingBox{-0.01, 0.09, -0.01, 1.01, 0.11, 1.01}};
Physical Surface("bottom") = {Surface In BoundingBox{-0.01, -0.01, -0.01, 1.01, 0.11, 0.01}};
Physical Surface("top") = {Surface In BoundingBox{-0.01, -0.01, 0.99, 1.01, 0.11, 1.01}};
Physical Volume("block") = {1};
line() = Curve In BoundingBox{-0.01, -0.01, -0.01, 0.01, 0.11, 0.01};
Field[1] = Distance;
Field[1].CurvesList = {line()};
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
