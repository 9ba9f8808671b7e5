// A ring (outer radius 1, inner 0.6, centre (0, 1)) resting on the plane
// y = 0: tests/friction.rs, a friction-held body under its own weight.
// No Dirichlet condition: contact along n holds it vertically, friction
// alone sideways and in rolling, with no tangential load at all.
SetFactory("OpenCASCADE");
Disk(1) = {0, 1.0, 0, 1.0};
Disk(2) = {0, 1.0, 0, 0.6};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
bnd() = Boundary{ Surface{3}; };
Mesh.CharacteristicLengthMax = 0.05;
Physical Surface("body") = {3};
Physical Curve("outer") = {bnd(0)};
Physical Curve("inner") = {bnd(1)};
