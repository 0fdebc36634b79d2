// Test mesh: three stacked slabs on the unit square, 4 x 4 hexahedra per
// layer: "bottom" (2 layers, z 0..0.45), "middle" (one layer, z 0.45..0.55:
// every node of it lies on an interface with a neighbour slab) and "upper"
// (2 layers, z 0.55..1). Fixed at z = 0 ("fixed"), the free top "top".
Point(1) = {0, 0, 0};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{4}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{4}; Recombine; };
v1[] = Extrude {0, 0, 0.45} { Surface{s[1]}; Layers{2}; Recombine; };
v2[] = Extrude {0, 0, 0.1} { Surface{v1[0]}; Layers{1}; Recombine; };
v3[] = Extrude {0, 0, 0.45} { Surface{v2[0]}; Layers{2}; Recombine; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("top", 2) = {v3[0]};
Physical Volume("bottom", 3) = {v1[1]};
Physical Volume("middle", 4) = {v2[1]};
Physical Volume("upper", 5) = {v3[1]};
