// An elastic ball on an elastic block (tests/pairs.rs), a quarter model
// (symmetry planes x = 0 and y = 0): the ball of radius r centred (0, 0, r)
// cut at z = r (its lower half; slave: its sphere), the block [0, l]^2 x
// [-l/2, 0] (master: its top), touching at the origin. hc: the mesh size
// within dc of the contact, hf: far from it.
SetFactory("OpenCASCADE");
DefineConstant[ r = 1, l = 1.5, hc = 0.03, hf = 0.25, dc = 0.2 ];
Sphere(1) = {0, 0, r, r};
Box(2) = {0, 0, 0, r, r, r};
BooleanIntersection(3) = { Volume{1}; Delete; }{ Volume{2}; Delete; };
Box(4) = {0, 0, -l / 2, l, l, l / 2};
e = 1e-6;
ball() = Boundary{ Volume{3}; };
top() = Surface In BoundingBox{-e, -e, r - e, r + e, r + e, r + e};
x0() = Surface In BoundingBox{-e, -e, -e, e, r + e, r + e};
y0() = Surface In BoundingBox{-e, -e, -e, r + e, e, r + e};
sphere() = ball();
sphere() -= {top(), x0(), y0()};
Physical Surface("slave") = {sphere()};
Physical Surface("top") = {top()};
Physical Surface("x0_ball") = {x0()};
Physical Surface("y0_ball") = {y0()};
Physical Surface("master") = Surface In BoundingBox{-e, -e, -e, l + e, l + e, e};
Physical Surface("base") = Surface In BoundingBox{-e, -e, -l / 2 - e, l + e, l + e, -l / 2 + e};
Physical Surface("x0_block") = Surface In BoundingBox{-e, -e, -l / 2 - e, e, l + e, e};
Physical Surface("y0_block") = Surface In BoundingBox{-e, -e, -l / 2 - e, l + e, e, e};
Physical Volume("ball") = {3};
Physical Volume("block") = {4};
origin() = Point In BoundingBox{-e, -e, -e, e, e, e};
Field[1] = Distance; Field[1].PointsList = {origin()};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = hc; Field[2].SizeMax = hf;
Field[2].DistMin = dc; Field[2].DistMax = 4 * dc;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0; Mesh.MeshSizeFromPoints = 0; Mesh.MeshSizeFromCurvature = 0;
