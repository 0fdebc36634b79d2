// A 1 x 1 x 2 brick of N x N x 2N cubic trilinear hexahedra (the hex twin of
// brick.geo, for the hex8 tests); fixed at z = 0, loaded at z = 2.
// gmsh -3 -setnumber N 4 hexbrick.geo   ((N+1)^2 (2N+1) nodes, 2 N^3 hexes)
If (!Exists(N)) N = 4; EndIf
Point(1) = {0, 0, 0};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{N}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{N}; Recombine; };
v[] = Extrude {0, 0, 2} { Surface{s[1]}; Layers{2 * N}; Recombine; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("top", 2) = {v[0]};
Physical Volume("brick", 3) = {v[1]};
