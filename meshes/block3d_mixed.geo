// The block of the 3D scene (section 7.2) in three kinds of cells: its lower
// half z in (-0.5, 0) structured hexahedra (transfinite, recombined), its
// upper half unstructured tetrahedra, and the pyramids Gmsh puts on the
// quadrilaterals of the middle plane z = 0 to join them.
DefineConstant[
  n = {8, Name "n"}   // hexahedra along x (2n along y, n along z in the lower half)
];
Point(1) = {-0.5, -1, -0.5};
Point(2) = { 0.5, -1, -0.5};
Point(3) = { 0.5,  1, -0.5};
Point(4) = {-0.5,  1, -0.5};
Point(5) = {-0.5, -1,  0};
Point(6) = { 0.5, -1,  0};
Point(7) = { 0.5,  1,  0};
Point(8) = {-0.5,  1,  0};
Point(9) = {-0.5, -1,  0.5};
Point(10) = { 0.5, -1,  0.5};
Point(11) = { 0.5,  1,  0.5};
Point(12) = {-0.5,  1,  0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Line(5) = {5, 6}; Line(6) = {6, 7}; Line(7) = {7, 8}; Line(8) = {8, 5};
Line(9) = {9, 10}; Line(10) = {10, 11}; Line(11) = {11, 12}; Line(12) = {12, 9};
Line(13) = {1, 5}; Line(14) = {2, 6}; Line(15) = {3, 7}; Line(16) = {4, 8};
Line(17) = {5, 9}; Line(18) = {6, 10}; Line(19) = {7, 11}; Line(20) = {8, 12};
Curve Loop(1) = {1, 2, 3, 4};      Plane Surface(1) = {1};   // bottom z = -0.5
Curve Loop(2) = {5, 6, 7, 8};      Plane Surface(2) = {2};   // middle z = 0
Curve Loop(3) = {9, 10, 11, 12};   Plane Surface(3) = {3};   // top z = 0.5
Curve Loop(4) = {1, 14, -5, -13};  Plane Surface(4) = {4};   // lower y = -1
Curve Loop(5) = {2, 15, -6, -14};  Plane Surface(5) = {5};   // lower x = 0.5
Curve Loop(6) = {3, 16, -7, -15};  Plane Surface(6) = {6};   // lower y = 1
Curve Loop(7) = {4, 13, -8, -16};  Plane Surface(7) = {7};   // lower x = -0.5
Curve Loop(8) = {5, 18, -9, -17};  Plane Surface(8) = {8};   // upper y = -1
Curve Loop(9) = {6, 19, -10, -18}; Plane Surface(9) = {9};   // upper x = 0.5
Curve Loop(10) = {7, 20, -11, -19}; Plane Surface(10) = {10}; // upper y = 1
Curve Loop(11) = {8, 17, -12, -20}; Plane Surface(11) = {11}; // upper x = -0.5
Surface Loop(1) = {1, 2, 4, 5, 6, 7};  Volume(1) = {1};
Surface Loop(2) = {2, 3, 8, 9, 10, 11}; Volume(2) = {2};

Transfinite Curve{1, 3, 5, 7} = n + 1;
Transfinite Curve{2, 4, 6, 8} = 2 * n + 1;
Transfinite Curve{13, 14, 15, 16} = n / 2 + 1;
Transfinite Surface{1, 2, 4, 5, 6, 7};
Recombine Surface{1, 2, 4, 5, 6, 7};
Transfinite Volume{1};
Recombine Volume{1};
Mesh.CharacteristicLengthMax = 1 / n;
Mesh.CharacteristicLengthFromPoints = 0;
Mesh.Algorithm = 6;
Mesh.Algorithm3D = 1;

Physical Surface("top") = {3};
Physical Surface("bottom") = {1};
Physical Surface("sides") = {4, 5, 6, 7, 8, 9, 10, 11};
Physical Volume("body") = {1, 2};
