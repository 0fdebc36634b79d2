// Test mesh: three stacked unit cubes, unstructured tets. The bottom two are
// physical volumes "soft" (10) and "hard" (20); the top one is in none, so its
// tets get the material "default". Physical groups of every dimension, one
// unnamed, and one name ("side") shared by a surface and a curve.
lc = 0.35;
Point(1) = {0, 0, 0, lc};
Point(2) = {1, 0, 0, lc};
Point(3) = {1, 1, 0, lc};
Point(4) = {0, 1, 0, lc};
Line(1) = {1, 2};
Line(2) = {2, 3};
Line(3) = {3, 4};
Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
a[] = Extrude {0, 0, 1} { Surface{1}; };
b[] = Extrude {0, 0, 1} { Surface{a[0]}; };
c[] = Extrude {0, 0, 1} { Surface{b[0]}; };
Physical Volume("soft", 10) = {a[1]};
Physical Volume("hard", 20) = {b[1]};
Physical Surface("fixed", 1) = {1};
Physical Surface("top", 2) = {c[0]};
Physical Surface("interface", 3) = {a[0]};
Physical Surface(7) = {b[0]};
Physical Surface("side", 4) = {a[2]};
Physical Curve("side", 5) = {2};
Physical Point("corner", 6) = {1};
Mesh.SaveAll = 1;
