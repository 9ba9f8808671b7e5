// The block of the 3D scene (section 7.2) extruded from its bottom face:
// the face z = -0.5 is meshed with triangles and quadrilaterals (Gmsh's
// "simple" recombination of a Frontal-Delaunay mesh leaves some triangles),
// then extruded in nz layers to z = 0.5, giving prisms over the triangles
// and hexahedra over the quadrilaterals.
DefineConstant[
  h = {0.125, Name "h"},   // element size on the bottom face
  nz = {8, Name "nz"}      // layers
];
Point(1) = {-0.5, -1, -0.5, h};
Point(2) = { 0.5, -1, -0.5, h};
Point(3) = { 0.5,  1, -0.5, h};
Point(4) = {-0.5,  1, -0.5, h};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Recombine Surface{1};
Mesh.RecombinationAlgorithm = 0;   // simple: leaves triangles
Mesh.Algorithm = 6;
out[] = Extrude {0, 0, 1} { Surface{1}; Layers{nz}; Recombine; };
Physical Surface("bottom") = {1};
Physical Surface("top") = {out[0]};
Physical Surface("sides") = {out[2], out[3], out[4], out[5]};
Physical Volume("body") = {out[1]};
