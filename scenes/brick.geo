// A 1 x 1 x 2 brick of N x N x 2N cubic cells, each split into 6 tets by
// extrusion; fixed at z = 0, loaded at z = 2.
// gmsh -3 -setnumber N 8 brick.geo   (N = 4, 8, 12, 16, 20: (N+1)^2 (2N+1) nodes)
If (!Exists(N)) N = 8; EndIf
Point(1) = {0, 0, 0};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{N}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{N}; };
v[] = Extrude {0, 0, 2} { Surface{s[1]}; Layers{2 * N}; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("top", 2) = {v[0]};
Physical Volume("brick", 3) = {v[1]};
