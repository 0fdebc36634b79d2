// The thesis's 2-D test surface: the unit square, 50 x 50 nodes, each of the
// 49 x 49 cells split into 2 triangles (2,500 vertices, 4,802 triangles).
n = 50;
Point(1) = {0, 0, 0};
Point(2) = {1, 0, 0};
Point(3) = {1, 1, 0};
Point(4) = {0, 1, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = n;
Transfinite Surface{1} = {1, 2, 3, 4} Left;
Physical Curve("fixed", 1) = {1};
Physical Curve("right", 2) = {2};
Physical Curve("top", 3) = {3};
Physical Curve("left", 4) = {4};
Physical Surface("square", 5) = {1};
