// Quarter of the cylinder cross-section of the 2D Hertz scene (paper, section 7.1).
// Radius R = 8, centre (0, 8); the body is x >= 0, y <= 8 inside the circle.
// Contact happens near (0, 0) against the plane y = 0.
//
// Uniform unstructured P1 triangles of characteristic length h:
//   gmsh -2 -format msh41 -setnumber h 0.36 hertz.geo -o hertz.msh
// Optionally pin the number of contact-arc nodes (uniform spacing):
//   gmsh -2 -format msh41 -setnumber h 0.36 -setnumber n_arc 35 hertz.geo -o hertz.msh
// Q1 quadrilaterals (recombine 1: Gmsh's default Blossom recombination, all
// quadrilaterals here) or triangles mixed with quadrilaterals (recombine 2:
// the "simple" recombination, which leaves some triangles):
//   gmsh -2 -format msh41 -setnumber h 0.199 -setnumber n_arc 69 -setnumber recombine 1 hertz.geo -o q.msh
// The shipped meshes hertz_*.msh: see README.md.
DefineConstant[
  h = {0.5, Name "h"},          // characteristic length (element size)
  n_arc = {0, Name "n_arc"},    // if > 0: number of nodes on the contact arc
  recombine = {0, Name "recombine"}  // 0: triangles, 1: quadrilaterals (Blossom), 2: mixed (simple)
];
R = 8;

Point(1) = {0, 0, 0, h};   // contact point (bottom of the arc)
Point(2) = {0, R, 0, h};   // centre of the circle
Point(3) = {R, R, 0, h};   // right end of the arc

Circle(1) = {1, 2, 3};     // arc (0,0) -> (8,8)
Line(2) = {3, 2};          // top edge y = 8
Line(3) = {2, 1};          // symmetry edge x = 0

If (n_arc > 0)
  Transfinite Curve{1} = n_arc;  // equally spaced arc nodes
EndIf

Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
If (recombine > 0)
  Recombine Surface{1};
  Mesh.RecombinationAlgorithm = (recombine == 1) ? 1 : 0;
EndIf

Physical Curve("contact") = {1};
Physical Curve("symmetry") = {3};
Physical Curve("top") = {2};
Physical Surface("body") = {1};

Mesh.Algorithm = 6;        // Frontal-Delaunay
Mesh.ElementOrder = 1;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.CharacteristicLengthExtendFromBoundary = 1;
