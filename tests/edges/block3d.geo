// A 3D steel block 0.1 x 0.06 x 0.05 m, for the resting-body tests (issue
// "Trust at the edges", item 1). Physical groups: body, left (x = 0),
// right (x = 0.1), front (y = 0), bottom (z = 0), top (z = 0.05).
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.1, 0.06, 0.05};
Mesh.CharacteristicLengthMax = 0.012;
Physical Volume("body") = {1};
Physical Surface("left") = {1};
Physical Surface("right") = {2};
Physical Surface("front") = {3};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
