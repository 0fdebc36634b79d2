// A steak-like slab for the modal bench (paper 004 sec. 6, Fig. 7 and Table 1:
// 2,976 elements in 5 domains of bone, muscle and fat): 24 x 12 x 10 = 2,880
// trilinear hexahedra of 0.01 m, five layers of two hexes along z, each its own
// physical volume (one sub-domain each):
//   fat_bottom, muscle_bottom, bone, muscle_top, fat_top
// with the paper's moduli given by meshload: bone E 9e9, muscle 3e9, fat 1e9.
// Fixed on its end face x = 0 ("fixed"), the other end "tip".
//   gmsh -3 steak.geo
Point(1) = {0, 0, 0};
l[] = Extrude {0.24, 0, 0} { Point{1}; Layers{24}; };
s[] = Extrude {0, 0.12, 0} { Curve{l[1]}; Layers{12}; Recombine; };
v1[] = Extrude {0, 0, 0.02} { Surface{s[1]}; Layers{2}; Recombine; };
v2[] = Extrude {0, 0, 0.02} { Surface{v1[0]}; Layers{2}; Recombine; };
v3[] = Extrude {0, 0, 0.02} { Surface{v2[0]}; Layers{2}; Recombine; };
v4[] = Extrude {0, 0, 0.02} { Surface{v3[0]}; Layers{2}; Recombine; };
v5[] = Extrude {0, 0, 0.02} { Surface{v4[0]}; Layers{2}; Recombine; };
// the x = 0 faces of the five layers (extrusion side 5 of each volume)
Physical Surface("fixed", 1) = {v1[5], v2[5], v3[5], v4[5], v5[5]};
Physical Surface("tip", 2) = {v1[3], v2[3], v3[3], v4[3], v5[3]};
Physical Volume("fat_bottom", 3) = {v1[1]};
Physical Volume("muscle_bottom", 4) = {v2[1]};
Physical Volume("bone", 5) = {v3[1]};
Physical Volume("muscle_top", 6) = {v4[1]};
Physical Volume("fat_top", 7) = {v5[1]};
