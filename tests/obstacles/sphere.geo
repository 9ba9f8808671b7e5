// A sphere of radius 1 about the origin, for the mesh-obstacle tests
// (src/contact/mesh_obstacle/tests.rs): gmsh -2 -setnumber h H sphere.geo
SetFactory("OpenCASCADE");
DefineConstant[ h = 0.2 ];
Sphere(1) = {0, 0, 0, 1};
Mesh.CharacteristicLengthMin = h;
Mesh.CharacteristicLengthMax = h;
