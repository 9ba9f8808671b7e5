// Lower half of a ball of radius R centred (0, 0, R) (3D, millimetres): its
// flat face z = R on top, its lowest point at the origin. The plane z = ZC
// splits it in two volumes, so that the spherical cap below ZC is a
// surface of its own (group "cap", the contact candidates). Tetrahedra of
// size HC near the origin, growing to H0.
//   gmsh -3 -format msh41 -o tests/scenes/hemisphere3d_coulomb.msh tests/scenes/hemisphere3d_coulomb.geo
SetFactory("OpenCASCADE");
R = 10;  ZC = 0.6;  HC = 0.13;  H0 = 2.5;
Sphere(1) = {0, 0, R, R, -Pi/2, 0, 2*Pi};
Rectangle(10) = {-2*R, -2*R, ZC, 4*R, 4*R};
BooleanFragments{ Volume{1}; Delete; }{ Surface{10}; Delete; }
// The part of the rectangle outside the ball is not part of the body.
Recursive Delete { Surface{Surface In BoundingBox{-2*R-1, -2*R-1, ZC-1e-6, 2*R+1, 2*R+1, ZC+1e-6}}; }
// The cap: the one surface below ZC that reaches z = 0.
cap() = {};
low() = Surface In BoundingBox{-R-1, -R-1, -1, R+1, R+1, ZC+1e-6};
For i In {0 : #low()-1}
  bb() = BoundingBox Surface{low(i)};
  If (bb(2) < 1e-6)
    cap() += low(i);
  EndIf
EndFor
Physical Surface("cap") = {cap()};
Physical Surface("top") = {Surface In BoundingBox{-R-1, -R-1, R-1e-6, R+1, R+1, R+1e-6}};
Physical Volume("ball") = {Volume{:}};

// HC within 1.1 of the origin, growing linearly to H0 at 5.
Field[1] = MathEval;
Field[1].F = Sprintf("%g + (%g) * Max(0, Min(1, (Sqrt(x^2 + y^2 + z^2) - 1.1) / 3.9))", HC, H0 - HC);
Background Field = 1;
Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;
Mesh.ElementOrder = 1;
