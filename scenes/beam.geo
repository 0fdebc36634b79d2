// The AMPS paper's cantilever beam: nodes on a regular 5 x 5 x h grid (unit
// spacing), i.e. 4 x 4 x (h-1) hex cells, each split into 6 tets; axis along z.
// gmsh -3 -setnumber h 16 beam.geo   (h = 4, 16, 64, 256, 1024)
If (!Exists(h)) h = 16; EndIf
Point(1) = {0, 0, 0};
Point(2) = {4, 0, 0};
Point(3) = {4, 4, 0};
Point(4) = {0, 4, 0};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 2, 3, 4} = 5;
Transfinite Surface{1} = {1, 2, 3, 4} Left;
// each layer of prisms (2 per square) is split into 3 tets by the extrusion
out[] = Extrude {0, 0, h - 1} { Surface{1}; Layers{h - 1}; };
Physical Surface("fixed", 1) = {1};
Physical Surface("tip", 2) = {out[0]};
Physical Volume("beam", 3) = {out[1]};
