// Two 2D blocks 0.1 x 0.05, meshed apart (no shared nodes): the upper one
// rests on the lower one, or floats GAP above it (-setnumber gap G).
// Issue "Trust at the edges", item 2. Physical groups: lower, upper,
// bottom_lower, bottom_upper, top, left_lower, left_upper, top_lower (the
// lower block's top, for the contact pair of tests/pairs.rs).
DefineConstant[ gap = 0 ];
h = 0.01;
Point(1) = {0, 0, 0, h}; Point(2) = {0.1, 0, 0, h};
Point(3) = {0.1, 0.05, 0, h}; Point(4) = {0, 0.05, 0, h};
Point(5) = {0, 0.05 + gap, 0, h}; Point(6) = {0.1, 0.05 + gap, 0, h};
Point(7) = {0.1, 0.1 + gap, 0, h}; Point(8) = {0, 0.1 + gap, 0, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Physical Surface("lower") = {1};
Physical Surface("upper") = {2};
Physical Curve("bottom_lower") = {1};
Physical Curve("bottom_upper") = {5};
Physical Curve("top") = {7};
Physical Curve("left_lower") = {4};
Physical Curve("left_upper") = {8};
Physical Curve("top_lower") = {3};
