// Two rigid discs of radius 0.45 under the block of multi_block2d.geo,
// centred (-0.5, -0.45) and (0.5, -0.45) (each touching its bottom at
// x = -+0.5), as closed counter-clockwise curves in one file, for
// `-obstacle mesh` (tests/surface_obstacle.rs); with reverse_right = 1 the
// right disc is clockwise (a cavity, by its orientation alone).
//   gmsh -1 -format msh41 -setnumber reverse_right 1 -o two_discs.msh tests/obstacles/two_discs.geo
DefineConstant[ h = 0.02, reverse_right = 0 ];
R = 0.45;
For k In {0:1}
  cx = -0.5 + k; cy = -R;
  c = newp; Point(c) = {cx, cy, 0, h};
  p1 = newp; Point(p1) = {cx + R, cy, 0, h};
  p2 = newp; Point(p2) = {cx, cy + R, 0, h};
  p3 = newp; Point(p3) = {cx - R, cy, 0, h};
  p4 = newp; Point(p4) = {cx, cy - R, 0, h};
  a1 = newl; Circle(a1) = {p1, c, p2};
  a2 = newl; Circle(a2) = {p2, c, p3};
  a3 = newl; Circle(a3) = {p3, c, p4};
  a4 = newl; Circle(a4) = {p4, c, p1};
  arcs~{k}[] = {a1, a2, a3, a4};
EndFor
Physical Curve("discs") = {arcs~{0}[], arcs~{1}[]};
If (reverse_right)
  Reverse Curve{arcs~{1}[]};
EndIf
