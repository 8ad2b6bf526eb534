// A two-layer undrained clay slope: Griffiths and Lane (1999), "Slope stability analysis by
// finite elements", Geotechnique 49(3):387-403, the slope on a foundation layer of another
// strength (their example of an undrained clay slope on a weak or strong foundation; code_aster
// validation test ssnp507, manual V6.03.507). A 2:1 slope (26.57 degrees) of height H over a
// foundation layer as deep as the slope is high (depth factor D = 2). Two bodies: `slope`
// (the clay above the toe's level) and `foundation` (the layer under it and beyond the toe),
// sharing the line between them. The domain is 2 m higher than the crest.
H = 10;                // slope height, m
crest = 2 * H;         // crest width from the left wall, m
toe = crest + 2 * H;   // x of the toe (2:1 slope), m
W = toe + 3 * H;       // domain width, m
lc = 1.0;              // element size, m (scene: mesh.size)

Point(1) = {0, 0, 0, lc};
Point(2) = {W, 0, 0, lc};
Point(3) = {W, H, 0, lc};
Point(4) = {toe, H, 0, lc};
Point(5) = {crest, 2 * H, 0, lc};
Point(6) = {0, 2 * H, 0, lc};
Point(7) = {0, H, 0, lc};
Point(8) = {W, 2 * H + 2, 0, lc};
Point(9) = {0, 2 * H + 2, 0, lc};

Line(1) = {1, 2};   // base
Line(2) = {2, 3};   // right wall against the foundation
Line(3) = {3, 4};   // foundation surface beyond the toe
Line(4) = {4, 5};   // slope face
Line(5) = {5, 6};   // crest
Line(6) = {6, 7};   // left wall against the slope layer
Line(7) = {7, 1};   // left wall against the foundation
Line(8) = {7, 4};   // the slope layer on the foundation
Line(9) = {3, 8};   // right wall above the foundation
Line(10) = {8, 9};  // domain top
Line(11) = {9, 6};  // left wall above the crest

Curve Loop(1) = {1, 2, 3, -8, 7};
Plane Surface(1) = {1};
Curve Loop(2) = {8, 4, 5, 6};
Plane Surface(2) = {2};
Curve Loop(3) = {9, 10, 11, -5, -4, -3};
Plane Surface(3) = {3};

Physical Surface("domain") = {1, 2, 3};
Physical Surface("foundation") = {1};
Physical Surface("slope") = {2};
Physical Curve("base") = {1};
Physical Curve("left") = {6, 7, 11};
Physical Curve("right") = {2, 9};
Physical Curve("top") = {10};
