// A punch pressed on a base, two boxes meshed apart (tests/pairs.rs):
// base [0, 1] x [0, 1] x [0, 0.4] (mesh size 0.09), punch [0.2, 0.8] x
// [0.15, 0.85] x [0.4, 0.7] (0.06) on it; their facing faces non-matching.
// On 2 ranks METIS puts the punch's bottom and the base's top on different
// ranks.
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.4};
Box(2) = {0.2, 0.15, 0.4, 0.6, 0.7, 0.3};
Physical Volume("base") = {1};
Physical Volume("punch") = {2};
Physical Surface("bottom") = {5};
Physical Surface("btop") = {6};
Physical Surface("pbot") = {11};
Physical Surface("ptop") = {12};
MeshSize{ PointsOf{ Volume{1}; } } = 0.09;
MeshSize{ PointsOf{ Volume{2}; } } = 0.06;
