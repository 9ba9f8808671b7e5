// A 3D steel cantilever 0.2 x 0.02 x 0.02 m, clamped at x = 0, pressed onto
// a plane below its bottom face (issue "Trust at the edges", items 3 and 4).
// Physical groups: body, root (x = 0), tip (x = 0.2), bottom, top.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 0.2, 0.02, 0.02};
Mesh.CharacteristicLengthMax = 0.005;
Physical Volume("body") = {1};
Physical Surface("root") = {1};
Physical Surface("tip") = {2};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
