// The AMPS paper's cantilever beam: nodes on a regular 5 x 5 x h grid (unit
// spacing, exact integer coordinates), i.e. 4 x 4 x (h-1) cubic cells, each
// split into 6 tets by extrusion; axis along z, fixed at z = 0.
// gmsh -3 -setnumber h 16 beam.geo   (h = 4, 16, 64, 256, 1024: 25 h nodes)
If (!Exists(h)) h = 16; EndIf
Point(1) = {0, 0, 0};
l[] = Extrude {4, 0, 0} { Point{1}; Layers{4}; };
s[] = Extrude {0, 4, 0} { Curve{l[1]}; Layers{4}; };
v[] = Extrude {0, 0, h - 1} { Surface{s[1]}; Layers{h - 1}; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("tip", 2) = {v[0]};
Physical Volume("beam", 3) = {v[1]};
