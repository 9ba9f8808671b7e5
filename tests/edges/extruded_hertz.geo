// The section of meshes/hertz.geo (the quarter cylinder R = 8, the same
// mesh at the same h and recombine) extruded along z by L in nl layers:
// prisms from its triangles, hexahedra from its quadrilaterals. Held at
// u_z = 0 on `front` (z = 0) and `back` (z = L), it is the 2D section in
// plane strain (tests/q1.rs::extruded_section_in_plane_strain_equals_2d).
DefineConstant[
  h = {0.5, Name "h"},
  recombine = {0, Name "recombine"},
  L = {2, Name "L"},
  nl = {3, Name "nl"}
];
R = 8;
Point(1) = {0, 0, 0, h}; Point(2) = {0, R, 0, h}; Point(3) = {R, R, 0, h};
Circle(1) = {1, 2, 3}; Line(2) = {3, 2}; Line(3) = {2, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
If (recombine > 0)
  Recombine Surface{1};
  Mesh.RecombinationAlgorithm = (recombine == 1) ? 1 : 0;
EndIf
Mesh.Algorithm = 6;
Mesh.CharacteristicLengthFromCurvature = 0;
Mesh.CharacteristicLengthExtendFromBoundary = 1;
out[] = Extrude {0, 0, L} { Surface{1}; Layers{nl}; Recombine; };
// out[0]: the face at z = L; out[1]: the volume; out[2..4]: the faces swept
// by the arc, the top edge and the symmetry edge.
Physical Volume("body") = {out[1]};
Physical Surface("contact") = {out[2]};
Physical Surface("top") = {out[3]};
Physical Surface("symmetry") = {out[4]};
Physical Surface("front") = {1};
Physical Surface("back") = {out[0]};
