// A 1 x 1 x 0.1 plate (tests/condense.rs): its whole bottom face is the
// contact surface, pressed on a large ball. The contact unknowns are a
// third of the mesh's: the dense Schur block outweighs the sparse work.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.1};
Mesh.CharacteristicLengthMax = 0.05;
Physical Volume("body") = {1};
Physical Surface("bottom") = {5};
Physical Surface("top") = {6};
