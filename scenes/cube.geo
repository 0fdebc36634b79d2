// The cube of paper 004 (Yang et al., CAGD 2016, sec. 6, Fig. 8 and Table 1):
// 22 x 22 x 22 trilinear hexahedra (10,648 elements, 23^3 = 12,167 nodes),
// two sub-domains of 11 layers each: "hard" (z < 0.5, blue in Fig. 8,
// E = 6.0e9) and "soft" (z > 0.5, yellow, E = 1.0e9). The paper gives only
// the moduli (in Pa) and the grid; side 1 (m), nu and rho are meshload's
// defaults unless given. Fixed at z = 0 ("fixed"), the free top "top".
//   gmsh -3 cube.geo   (-setnumber N 4: the same cube of N^3 hexes, N even,
//   the small twin the modal tests use)
//   meshload cube.msh --material hard:E=6e9 --material soft:E=1e9 --fix fixed
If (!Exists(N)) N = 22; EndIf
Point(1) = {0, 0, 0};
l[] = Extrude {1, 0, 0} { Point{1}; Layers{N}; };
s[] = Extrude {0, 1, 0} { Curve{l[1]}; Layers{N}; Recombine; };
v1[] = Extrude {0, 0, 0.5} { Surface{s[1]}; Layers{N / 2}; Recombine; };
v2[] = Extrude {0, 0, 0.5} { Surface{v1[0]}; Layers{N / 2}; Recombine; };
Physical Surface("fixed", 1) = {s[1]};
Physical Surface("top", 2) = {v2[0]};
Physical Volume("hard", 3) = {v1[1]};
Physical Volume("soft", 4) = {v2[1]};
