// A box whose volume is in no physical group (tests/edges.rs): Gmsh then
// writes only the boundary groups' triangles, no tetrahedron.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.5};
Physical Surface("bottom") = {5};
If (top)
  Physical Surface("top") = {6};
EndIf
Mesh.CharacteristicLengthMax = 0.25;
