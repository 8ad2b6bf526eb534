// Slope failure under self-weight (validation case 3, docs/scenes.md). A sand slope 5 m high
// at 50 degrees (steeper than its friction angle of 30 degrees, so it fails) stands on a fixed
// base, its crest plateau reaching the left wall; 13.8 m of flat base downhill of the toe
// leave room for the runout. The domain is the 24 m x 7 m rectangle; soil and empty space
// share the crest and slope-face lines, so the mesh follows the slope's outline.
W = 24;           // domain width, m
D = 7;            // domain height, m
h = 5;            // slope height, m
crest = 6;        // crest plateau width from the left wall, m
beta = 50 * Pi / 180;     // slope angle
toe = crest + h / Tan(beta);  // x of the toe, 10.195 m
lc = 0.25;        // element size, m

Point(1) = {0, 0, 0, lc};
Point(2) = {toe, 0, 0, lc};
Point(3) = {W, 0, 0, lc};
Point(4) = {W, D, 0, lc};
Point(5) = {0, D, 0, lc};
Point(6) = {0, h, 0, lc};
Point(7) = {crest, h, 0, lc};

Line(1) = {1, 2};  // base under the slope
Line(2) = {2, 3};  // base downhill of the toe
Line(3) = {3, 4};  // right wall
Line(4) = {4, 5};  // domain top
Line(5) = {5, 6};  // left wall above the crest
Line(6) = {6, 1};  // left wall against the soil
Line(7) = {6, 7};  // crest plateau
Line(8) = {7, 2};  // slope face

Curve Loop(1) = {1, -8, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, 5, 7, 8};
Plane Surface(2) = {2};

Physical Surface("domain") = {1, 2};
Physical Surface("soil") = {1};
Physical Curve("base") = {1, 2};
Physical Curve("left") = {5, 6};
Physical Curve("right") = {3};
Physical Curve("top") = {4};
