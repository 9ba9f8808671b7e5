// Contact patch test (tests/pairs.rs): two blocks meshed apart, their
// interface at y = 0.5 non-matching. Lower (master): [0, 1] x [0, 0.5],
// nl segments along x; upper (slave): [0, 1] x [0.5, 1], nu segments.
// quads = 1: quadrilaterals (transfinite, recombined), else triangles.
DefineConstant[ nl = 7, nu = 5, quads = 0 ];
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {1, 0.5, 0}; Point(4) = {0, 0.5, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Point(11) = {0, 0.5, 0}; Point(12) = {1, 0.5, 0}; Point(13) = {1, 1, 0}; Point(14) = {0, 1, 0};
Line(11) = {11, 12}; Line(12) = {12, 13}; Line(13) = {13, 14}; Line(14) = {14, 11};
Curve Loop(2) = {11, 12, 13, 14}; Plane Surface(2) = {2};
Transfinite Curve{1, 3} = nl + 1; Transfinite Curve{2, 4} = 5;
Transfinite Curve{11, 13} = nu + 1; Transfinite Curve{12, 14} = 4;
If (quads == 1)
  Transfinite Surface{1}; Transfinite Surface{2};
  Recombine Surface{1, 2};
EndIf
Physical Curve("bottom") = {1}; Physical Curve("master") = {3}; Physical Curve("left_lower") = {4};
Physical Curve("slave") = {11}; Physical Curve("top") = {13}; Physical Curve("left_upper") = {14};
Physical Surface("lower") = {1}; Physical Surface("upper") = {2};
