// A thick disc (3D): the cylinder of radius 1 around the z axis, z in
// [0, 0.5]; bottom face z = 0 ("bottom"), top face z = 0.5 ("top"), the
// lateral surface "side". Tetrahedra of size HB on the bottom face,
// growing linearly to HT on the top face.
//   gmsh -3 -format msh41 -o tests/scenes/disc3d_halfball_coulomb.msh tests/scenes/disc3d_halfball_coulomb.geo
SetFactory("OpenCASCADE");
HB = 0.065;  HT = 0.16;
Cylinder(1) = {0, 0, 0, 0, 0, 0.5, 1};
bot() = Surface In BoundingBox{-1.1, -1.1, -0.01, 1.1, 1.1, 0.01};
top() = Surface In BoundingBox{-1.1, -1.1, 0.49, 1.1, 1.1, 0.51};
side() = Surface In BoundingBox{-1.1, -1.1, -0.01, 1.1, 1.1, 0.51};
side() -= bot();
side() -= top();
Physical Surface("bottom") = {bot()};
Physical Surface("top") = {top()};
Physical Surface("side") = {side()};
Physical Volume("disc") = {1};
Field[1] = MathEval;
Field[1].F = Sprintf("%g + (%g) * z / 0.5", HB, HT - HB);
Background Field = 1;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.ElementOrder = 1;
