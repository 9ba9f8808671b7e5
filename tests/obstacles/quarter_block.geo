// A quarter block, 0.5 x 0.5 x 0.3, its bottom at z = 1 (the top of a
// sphere of radius 1 about the origin, tests/obstacles/sphere.geo), with its
// symmetry planes x = 0 and y = 0 (tests/surface_obstacle.rs).
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.04 ];
Box(1) = {0, 0, 1, 0.5, 0.5, 0.3};
e = 1e-6;
Physical Surface("bottom") = Surface In BoundingBox{-e, -e, 1 - e, 0.5 + e, 0.5 + e, 1 + e};
Physical Surface("top") = Surface In BoundingBox{-e, -e, 1.3 - e, 0.5 + e, 0.5 + e, 1.3 + e};
Physical Surface("x0") = Surface In BoundingBox{-e, -e, 1 - e, e, 0.5 + e, 1.3 + e};
Physical Surface("y0") = Surface In BoundingBox{-e, -e, 1 - e, 0.5 + e, e, 1.3 + e};
Physical Volume("block") = {1};
Mesh.CharacteristicLengthMax = h;
