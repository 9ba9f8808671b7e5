// Contact patch test in 3D (tests/pairs.rs): two blocks meshed apart (each
// with its own points: no shared nodes), the lower [0,1]^2 x [0,0.5]
// (master: its top), the upper [0,1]^2 x [0.5,1] (slave: its bottom).
// quads = 1: hexahedra, transfinite nl x nl (lower) and nu x nu (upper)
// along x and y (non-matching); else tetrahedra of sizes hl and hu.
DefineConstant[ nl = 4, nu = 3, quads = 0, hl = 0.25, hu = 0.35 ];
// One box [0,1]^2 x [z0, z0 + 0.5]: points, lines, faces from base b.
Macro "Block"
  h = (b == 0) ? hl : hu;
  Point(b + 1) = {0, 0, z0, h}; Point(b + 2) = {1, 0, z0, h};
  Point(b + 3) = {1, 1, z0, h}; Point(b + 4) = {0, 1, z0, h};
  Point(b + 5) = {0, 0, z0 + 0.5, h}; Point(b + 6) = {1, 0, z0 + 0.5, h};
  Point(b + 7) = {1, 1, z0 + 0.5, h}; Point(b + 8) = {0, 1, z0 + 0.5, h};
  Line(b + 1) = {b + 1, b + 2}; Line(b + 2) = {b + 2, b + 3};
  Line(b + 3) = {b + 3, b + 4}; Line(b + 4) = {b + 4, b + 1};
  Line(b + 5) = {b + 5, b + 6}; Line(b + 6) = {b + 6, b + 7};
  Line(b + 7) = {b + 7, b + 8}; Line(b + 8) = {b + 8, b + 5};
  Line(b + 9) = {b + 1, b + 5}; Line(b + 10) = {b + 2, b + 6};
  Line(b + 11) = {b + 3, b + 7}; Line(b + 12) = {b + 4, b + 8};
  Curve Loop(b + 1) = {b + 1, b + 2, b + 3, b + 4}; Plane Surface(b + 1) = {b + 1}; // z0
  Curve Loop(b + 2) = {b + 5, b + 6, b + 7, b + 8}; Plane Surface(b + 2) = {b + 2}; // top
  Curve Loop(b + 3) = {b + 1, b + 10, -(b + 5), -(b + 9)}; Plane Surface(b + 3) = {b + 3}; // y = 0
  Curve Loop(b + 4) = {b + 2, b + 11, -(b + 6), -(b + 10)}; Plane Surface(b + 4) = {b + 4}; // x = 1
  Curve Loop(b + 5) = {b + 3, b + 12, -(b + 7), -(b + 11)}; Plane Surface(b + 5) = {b + 5}; // y = 1
  Curve Loop(b + 6) = {b + 4, b + 9, -(b + 8), -(b + 12)}; Plane Surface(b + 6) = {b + 6}; // x = 0
  Surface Loop(b + 1) = {b + 1, b + 2, b + 3, b + 4, b + 5, b + 6};
  Volume(b + 1) = {b + 1};
  If (quads == 1)
    Transfinite Curve{b + 1, b + 2, b + 3, b + 4, b + 5, b + 6, b + 7, b + 8} = n + 1;
    Transfinite Curve{b + 9, b + 10, b + 11, b + 12} = 3;
    Transfinite Surface{b + 1, b + 2, b + 3, b + 4, b + 5, b + 6};
    Recombine Surface{b + 1, b + 2, b + 3, b + 4, b + 5, b + 6};
    Transfinite Volume{b + 1};
  EndIf
Return
b = 0; z0 = 0; n = nl; Call "Block";
b = 100; z0 = 0.5; n = nu; Call "Block";
Physical Surface("bottom") = {1};
Physical Surface("master") = {2};
Physical Surface("slave") = {101};
Physical Surface("top") = {102};
Physical Surface("y0_lower") = {3}; Physical Surface("x0_lower") = {6};
Physical Surface("y0_upper") = {103}; Physical Surface("x0_upper") = {106};
Physical Volume("lower") = {1};
Physical Volume("upper") = {101};
