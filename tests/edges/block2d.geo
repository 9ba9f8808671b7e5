// A 2D steel block 0.1 x 0.05 m, for the resting-body tests (issue "Trust
// at the edges", item 1). Physical groups: body, bottom, right, top, left.
Point(1) = {0, 0, 0, 0.005};
Point(2) = {0.1, 0, 0, 0.005};
Point(3) = {0.1, 0.05, 0, 0.005};
Point(4) = {0, 0.05, 0, 0.005};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Physical Surface("body") = {1};
Physical Curve("bottom") = {1};
Physical Curve("right") = {2};
Physical Curve("top") = {3};
Physical Curve("left") = {4};
