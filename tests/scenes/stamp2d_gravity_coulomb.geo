// stamp2d_gravity_coulomb: a half-disc stamp (radius 3, flat face up),
// refined near its lowest point. Physical groups: body, top, arc.
SetFactory("OpenCASCADE");
Disk(1) = {0, 3, 0, 3};
Rectangle(2) = {-4, 3, 0, 8, 4};
BooleanDifference(3) = { Surface{1}; Delete; }{ Surface{2}; Delete; };
Mesh.CharacteristicLengthMax = 0.15;
Mesh.CharacteristicLengthMin = 0.04;
Field[1] = Box; Field[1].VIn = 0.04; Field[1].VOut = 0.15; Field[1].XMin = -1.2; Field[1].XMax = 1.2; Field[1].YMin = -0.1; Field[1].YMax = 0.6;
Background Field = 1;
Physical Surface("body") = {3};
top() = Curve In BoundingBox{-3.1, 2.9, -1, 3.1, 3.1, 1};
arc() = Curve In BoundingBox{-3.1, -0.1, -1, 3.1, 3.01, 1};
arc() -= top();
Physical Curve("top") = {top()};
Physical Curve("arc") = {arc()};
