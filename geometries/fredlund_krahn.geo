// Fredlund and Krahn (1977), "Comparison of slope stability methods of analysis", Can. Geotech.
// J. 14(3):429-439, the example slope in metres (1 ft = 0.3048 m): a 2H:1V slope 40 ft
// (12.192 m) high, its crest 60 ft (18.288 m) wide against the left boundary, 30 ft (9.144 m) of
// ground beyond the toe, on bedrock 20 ft (6.096 m) below the toe (the fixed base). The domain
// adds 2 m of empty space above the crest; soil and empty space share the ground lines.
ft = 0.3048;
H = 40 * ft;          // slope height
crest = 60 * ft;      // crest width from the left wall
toe = crest + 2 * H;  // x of the toe (2:1 slope)
W = toe + 30 * ft;    // domain width
base = 20 * ft;       // depth of the toe above the bedrock
D = base + H + 2;     // domain height
lc = 1.0;             // element size, m (scene: mesh.size)

Point(1) = {0, 0, 0, lc};
Point(2) = {W, 0, 0, lc};
Point(3) = {W, base, 0, lc};
Point(4) = {W, D, 0, lc};
Point(5) = {0, D, 0, lc};
Point(6) = {0, base + H, 0, lc};
Point(7) = {crest, base + H, 0, lc};
Point(8) = {toe, base, 0, lc};

Line(1) = {1, 2};  // bedrock (base)
Line(2) = {2, 3};  // right wall against the soil
Line(3) = {3, 4};  // right wall above the toe ground
Line(4) = {4, 5};  // domain top
Line(5) = {5, 6};  // left wall above the crest
Line(6) = {6, 1};  // left wall against the soil
Line(7) = {6, 7};  // crest
Line(8) = {7, 8};  // slope face
Line(9) = {8, 3};  // ground beyond the toe

Curve Loop(1) = {1, 2, -9, -8, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {9, 3, 4, 5, 7, 8};
Plane Surface(2) = {2};

Physical Surface("domain") = {1, 2};
Physical Surface("soil") = {1};
Physical Curve("base") = {1};
Physical Curve("left") = {5, 6};
Physical Curve("right") = {2, 3};
Physical Curve("top") = {4};
