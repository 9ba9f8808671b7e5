// Elastic block of the 3D scene (paper, section 7.2): the box
// (-0.5, 0.5) x (-1, 1) x (-0.5, 0.5). The top face z = 0.5 is displaced by
// (0, 0, -0.2); the bottom face z = -0.5 is the contact surface, pressed onto
// a rigid half-ball of radius 0.5 centred at (-0.3, 0, -1).
//
// Unstructured P1 tetrahedra. The element size varies linearly in z, from
// h_bottom on the bottom face to h on the top face (uniform h by default):
//   gmsh -3 -bin -format msh41 -setnumber h 0.1 block3d.geo -o block3d.msh
//   gmsh -3 -bin -format msh41 -setnumber h 0.09317 -setnumber h_bottom 0.10329 block3d.geo -o block3d_2357.msh
// The shipped meshes block3d_*.msh: see README.md.
DefineConstant[
  h = {0.1, Name "h"},               // element size on the top face (everywhere if h_bottom <= 0)
  h_bottom = {0, Name "h_bottom"}    // if > 0: element size on the bottom (contact) face
];
hb = h;
If (h_bottom > 0)
  hb = h_bottom;
EndIf

Point(1) = {-0.5, -1, -0.5};
Point(2) = { 0.5, -1, -0.5};
Point(3) = { 0.5,  1, -0.5};
Point(4) = {-0.5,  1, -0.5};
Point(5) = {-0.5, -1,  0.5};
Point(6) = { 0.5, -1,  0.5};
Point(7) = { 0.5,  1,  0.5};
Point(8) = {-0.5,  1,  0.5};

Line(1) = {1, 2};  Line(2) = {2, 3};  Line(3) = {3, 4};  Line(4) = {4, 1};    // bottom edges
Line(5) = {5, 6};  Line(6) = {6, 7};  Line(7) = {7, 8};  Line(8) = {8, 5};    // top edges
Line(9) = {1, 5};  Line(10) = {2, 6}; Line(11) = {3, 7}; Line(12) = {4, 8};   // vertical edges

Curve Loop(1) = {1, 2, 3, 4};     Plane Surface(1) = {1};   // bottom, z = -0.5
Curve Loop(2) = {5, 6, 7, 8};     Plane Surface(2) = {2};   // top, z = 0.5
Curve Loop(3) = {1, 10, -5, -9};  Plane Surface(3) = {3};   // y = -1
Curve Loop(4) = {2, 11, -6, -10}; Plane Surface(4) = {4};   // x = 0.5
Curve Loop(5) = {3, 12, -7, -11}; Plane Surface(5) = {5};   // y = 1
Curve Loop(6) = {4, 9, -8, -12};  Plane Surface(6) = {6};   // x = -0.5
Surface Loop(1) = {1, 2, 3, 4, 5, 6};
Volume(1) = {1};

Physical Surface("top") = {2};
Physical Surface("bottom") = {1};
Physical Surface("sides") = {3, 4, 5, 6};
Physical Volume("body") = {1};

// Size field: hb at z = -0.5, h at z = 0.5, linear in between.
Field[1] = MathEval;
Field[1].F = Sprintf("%.10g + (%.10g) * (z + 0.5)", hb, h - hb);
Background Field = 1;

Mesh.CharacteristicLengthExtendFromBoundary = 0;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.Algorithm = 6;        // Frontal-Delaunay (surfaces)
Mesh.Algorithm3D = 1;      // Delaunay
Mesh.ElementOrder = 1;
