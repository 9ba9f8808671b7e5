// The 2D block of block2d.geo with its left and right edges meshed alike
// (Gmsh's Periodic Curve: a $Periodic section in the file), which the
// program does not tie: the run says so. Physical groups: body, bottom,
// top, left, right.
h = 0.01;
Point(1) = {0, 0, 0, h}; Point(2) = {0.1, 0, 0, h};
Point(3) = {0.1, 0.05, 0, h}; Point(4) = {0, 0.05, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Periodic Curve {2} = {-4} Translate {0.1, 0, 0};
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
