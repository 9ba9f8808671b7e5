// A block with a line embedded inside it (tests/bad_input.rs): "mid" is no
// boundary of the body, each of its segments a face of two triangles.
Point(1) = {0, 0, 0, 0.05}; Point(2) = {1, 0, 0, 0.05};
Point(3) = {1, 0.3, 0, 0.05}; Point(4) = {0, 0.3, 0, 0.05};
Point(5) = {0.2, 0.15, 0, 0.05}; Point(6) = {0.8, 0.15, 0, 0.05};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Line{5} In Surface{1};
Physical Curve("bottom") = {1}; Physical Curve("top") = {3};
Physical Curve("mid") = {5}; Physical Surface("body") = {1};
