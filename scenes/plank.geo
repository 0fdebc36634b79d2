// A cantilever plank 2 x 1 x 10 (x, y, z), fixed at z = 0: its two bending
// modes are well apart (the thin direction y first), for the dynamics tests
// (tests/dyn_physics.test: the period of the tip oscillation).
// gmsh -3 plank.geo   (4 x 2 x 10 cells, 6 tets each; 165 nodes)
Point(1) = {0, 0, 0};
l[] = Extrude {2, 0, 0} { Point{1}; Layers{4}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{2}; };
v[] = Extrude {0, 0, 10} { Surface{s[1]}; Layers{10}; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("tip", 2) = {v[0]};
Physical Volume("plank", 3) = {v[1]};
