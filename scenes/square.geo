// The thesis's 2-D test surface: the unit square, 50 x 50 nodes, each of the
// 49 x 49 cells split into 2 triangles (2,500 vertices, 4,802 triangles).
// gmsh -2 square.geo
n = 50;
Point(1) = {0, 0, 0};
b[] = Extrude {1, 0, 0} { Point{1}; Layers{n - 1}; };
s[] = Extrude {0, 1, 0} { Curve{b[1]}; Layers{n - 1}; };
// s[0]: the curve at y = 1, s[1]: the surface, s[2], s[3]: the sides swept by
// the points at x = 1 and x = 0 (s[3] comes reversed, hence Abs)
Physical Curve("fixed", 1) = {b[1]};
Physical Curve("top", 2) = {s[0]};
Physical Curve("left", 3) = {Abs(s[3])};
Physical Curve("right", 4) = {Abs(s[2])};
Physical Surface("square", 5) = {s[1]};
