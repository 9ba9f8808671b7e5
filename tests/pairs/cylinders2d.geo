// Two elastic cylinders touching at the origin (tests/pairs.rs), quarter
// models (symmetry about x = 0): the lower of radius r1 centred (0, -r1),
// held on its cut y = -r1 (master: its arc); the upper of radius r2
// centred (0, r2), pressed down on its cut y = r2 (slave: its arc).
// hc: the mesh size at the contact, hf: far from it.
DefineConstant[ r1 = 8, r2 = 4, hc = 0.04, hf = 0.5 ];
Point(1) = {0, -r1, 0, hf}; Point(2) = {r1, -r1, 0, hf}; Point(3) = {0, 0, 0, hc};
Line(1) = {1, 2}; Circle(2) = {2, 1, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
Point(11) = {0, r2, 0, hf}; Point(12) = {0, 0, 0, hc}; Point(13) = {r2, r2, 0, hf};
Line(11) = {11, 12}; Circle(12) = {12, 11, 13}; Line(13) = {13, 11};
Curve Loop(2) = {11, 12, 13}; Plane Surface(2) = {2};
Physical Curve("base") = {1}; Physical Curve("master") = {2}; Physical Curve("sym_lower") = {3};
Physical Curve("sym_upper") = {11}; Physical Curve("slave") = {12}; Physical Curve("top") = {13};
Physical Surface("lower") = {1}; Physical Surface("upper") = {2};
