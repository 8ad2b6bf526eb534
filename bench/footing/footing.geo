// A strip footing of width B = 1 m on weightless clay (bench/footing/footing.toml; docs/slope.md,
// "A footing: associated against non-associated flow"). Half model: x = 0 is the footing's centre line (a roller). The
// clay is 5 m wide and 4 m deep; the footing's half-width b = 0.5 m is a physical curve carrying
// a uniform pressure (a flexible, smooth footing); 2.5 m of empty space above the clay leave room
// for the heave beside the footing.
W = 5;     // domain width, m
D = 6.5;   // domain height, m
H = 4;     // clay depth, m
b = 0.5;   // footing half-width, m
lc = 0.25; // element size, m

Point(1) = {0, 0, 0, lc};
Point(2) = {W, 0, 0, lc};
Point(3) = {W, H, 0, lc};
Point(4) = {b, H, 0, lc};
Point(5) = {0, H, 0, lc};
Point(6) = {W, D, 0, lc};
Point(7) = {0, D, 0, lc};

Line(1) = {1, 2};  // base
Line(2) = {2, 3};  // right wall against the clay
Line(3) = {3, 4};  // free surface beside the footing
Line(4) = {4, 5};  // the footing
Line(5) = {5, 1};  // centre line under the footing
Line(6) = {3, 6};  // right wall above the clay
Line(7) = {6, 7};  // domain top
Line(8) = {7, 5};  // centre line above the clay

Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Curve Loop(2) = {-3, 6, 7, 8, -4};
Plane Surface(2) = {2};

Physical Surface("domain") = {1, 2};
Physical Surface("clay") = {1};
Physical Curve("base") = {1};
Physical Curve("left") = {5, 8};
Physical Curve("right") = {2, 6};
Physical Curve("footing") = {4};
