// Spring and mass (validation case 1, docs/scenes.md): a column 0.1 m wide, the spring
// [0, w] x [0, 1] under the mass [0, w] x [1, 1.05], with empty space above for the domain.
// Bodies and domain share their lines, so the mesh follows every body edge.
w = 0.1;        // column width, m (unit thickness: cross-section 0.1 m^2)
spring = 1.0;   // spring length, m
mass = 0.05;    // mass height, m
top = 1.1;      // domain top, m
lc = 0.05;      // element size, m (the scene's [mesh] size overrides it)

Point(1) = {0, 0, 0, lc};
Point(2) = {w, 0, 0, lc};
Point(3) = {w, spring, 0, lc};
Point(4) = {0, spring, 0, lc};
Point(5) = {w, spring + mass, 0, lc};
Point(6) = {0, spring + mass, 0, lc};
Point(7) = {w, top, 0, lc};
Point(8) = {0, top, 0, lc};

Line(1) = {1, 2};    // base
Line(2) = {2, 3};    // right side of the spring
Line(3) = {3, 4};    // spring / mass interface
Line(4) = {4, 1};    // left side of the spring
Line(5) = {3, 5};    // right side of the mass
Line(6) = {5, 6};    // top of the mass
Line(7) = {6, 4};    // left side of the mass
Line(8) = {5, 7};    // right side of the empty space
Line(9) = {7, 8};    // domain top
Line(10) = {8, 6};   // left side of the empty space

Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 5, 6, 7};
Plane Surface(2) = {2};
Curve Loop(3) = {-6, 8, 9, 10};
Plane Surface(3) = {3};

Physical Surface("domain") = {1, 2, 3};
Physical Surface("spring") = {1};
Physical Surface("mass") = {2};
Physical Curve("base") = {1};
Physical Curve("left") = {4, 7, 10};
Physical Curve("right") = {2, 5, 8};
Physical Curve("top") = {9};
