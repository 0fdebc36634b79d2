// A curved thin sheet (meshload --membrane): the patch of the sphere of
// radius R through the corners of the unit square, bounded by the 4 great
// circles above the square's sides (a shallow dome, height 2 - sqrt(3.5) =
// 0.129 at the centre), N x N nodes in transfinite triangles.
// gmsh -2 -setnumber N 21 dome.geo
If (!Exists(N))
  N = 21;
EndIf
R = 2;
zc = -Sqrt(R * R - 0.5);
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 1, 0};
Point(4) = {0, 1, 0};
Point(5) = {0.5, 0.5, zc};
Circle(1) = {1, 5, 2};
Circle(2) = {2, 5, 3};
Circle(3) = {3, 5, 4};
Circle(4) = {4, 5, 1};
Curve Loop(1) = {1, 2, 3, 4};
Surface(1) = {1} In Sphere {5};
Transfinite Curve{1, 2, 3, 4} = N;
Transfinite Surface{1};
Physical Curve("front", 1) = {1};
Physical Curve("right", 2) = {2};
Physical Curve("back", 3) = {3};
Physical Curve("left", 4) = {4};
Physical Surface("dome", 5) = {1};
