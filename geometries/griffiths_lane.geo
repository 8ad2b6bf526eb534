// Griffiths and Lane (1999), "Slope stability analysis by finite elements", Geotechnique
// 49(3):387-403, example 1: a homogeneous 2:1 slope (26.57 degrees) of height H = 10 m with no
// foundation layer (depth factor D = 1: the base is at the toe's level), a crest 1.2 H wide
// against the left boundary and 2 H of base beyond the toe. The domain is the 52 m x 12 m
// rectangle; soil and empty space share the crest and slope-face lines.
H = 10;              // slope height, m
crest = 1.2 * H;     // crest width from the left wall, m
toe = crest + 2 * H; // x of the toe (2:1 slope), m
W = toe + 2 * H;     // domain width, m
D = H + 2;           // domain height, m
lc = 1.0;            // element size, m (scene: mesh.size)

Point(1) = {0, 0, 0, lc};
Point(2) = {toe, 0, 0, lc};
Point(3) = {W, 0, 0, lc};
Point(4) = {W, D, 0, lc};
Point(5) = {0, D, 0, lc};
Point(6) = {0, H, 0, lc};
Point(7) = {crest, H, 0, lc};

Line(1) = {1, 2};  // base under the slope
Line(2) = {2, 3};  // base beyond the toe
Line(3) = {3, 4};  // right wall
Line(4) = {4, 5};  // domain top
Line(5) = {5, 6};  // left wall above the crest
Line(6) = {6, 1};  // left wall against the soil
Line(7) = {6, 7};  // crest
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
