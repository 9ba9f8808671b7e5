// The rigid pin of tests/normals/pin2d.geo (a disc of radius 0.999 about
// the origin) as a closed counter-clockwise curve of segments of size h,
// for `-obstacle mesh` in 2D (tests/surface_obstacle.rs); with reverse = 1
// the curve is clockwise (a cavity, by its orientation alone).
//   gmsh -1 -format msh41 -setnumber h 0.01 -o pin_disc.msh tests/obstacles/pin_disc.geo
DefineConstant[ h = 0.01, reverse = 0 ];
R = 0.999;
Point(1) = {0, 0, 0, h};
Point(2) = {R, 0, 0, h};
Point(3) = {0, R, 0, h};
Point(4) = {-R, 0, 0, h};
Point(5) = {0, -R, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 2};
Physical Curve("pin") = {1, 2, 3, 4};
If (reverse)
  Reverse Curve{1, 2, 3, 4};
EndIf
