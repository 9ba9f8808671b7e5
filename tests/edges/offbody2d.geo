// A block with groups off the body (tests/edges.rs): "helper" is a line
// meshed apart from the block, "lid" its top plus that line, "pin" a
// physical point on a geometry point no triangle uses. Gmsh writes their
// elements; options that name them are refused.
Point(1) = {0, 0, 0, 0.1}; Point(2) = {1, 0, 0, 0.1};
Point(3) = {1, 0.5, 0, 0.1}; Point(4) = {0, 0.5, 0, 0.1};
Point(5) = {0, 1, 0, 0.1}; Point(6) = {1, 1, 0, 0.1};
Point(7) = {2, 2, 0, 0.1};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Physical Surface("body") = {1};
Physical Curve("bottom") = {1}; Physical Curve("top") = {3};
Physical Curve("left") = {4};
Physical Curve("helper") = {5}; Physical Curve("lid") = {3, 5};
Physical Point("pin") = {7};
