// A sand slope on a weak clay layer, with a surcharge on its crest (docs/layered.md). The sand
// is 5 m high with a 45 degree face; under it, and on beyond the toe, a weak layer 1 m thick
// lies on a rough, fixed base. The crest carries a strip load (a road) between x = 2 m and
// x = 5 m: the physical curve `road`. Two bodies, `sand` and `weak`, share the line between
// them, and the empty space above shares the crest, the face and the layer's free surface.
lc = 0.25;      // element size, m (scene: mesh.size)

Point(1) = {0, 0, 0, lc};
Point(2) = {24, 0, 0, lc};
Point(3) = {24, 1, 0, lc};
Point(4) = {11, 1, 0, lc};   // toe
Point(5) = {6, 6, 0, lc};    // crest edge
Point(6) = {5, 6, 0, lc};    // road, downhill end
Point(7) = {2, 6, 0, lc};    // road, uphill end
Point(8) = {0, 6, 0, lc};
Point(9) = {0, 1, 0, lc};
Point(10) = {24, 8, 0, lc};
Point(11) = {0, 8, 0, lc};

Line(1) = {1, 2};    // base
Line(2) = {2, 3};    // right wall against the weak layer
Line(3) = {3, 4};    // weak layer's surface beyond the toe
Line(4) = {4, 5};    // slope face
Line(5) = {5, 6};    // crest
Line(6) = {6, 7};    // crest under the road
Line(7) = {7, 8};    // crest
Line(8) = {8, 9};    // left wall against the sand
Line(9) = {9, 1};    // left wall against the weak layer
Line(10) = {9, 4};   // the sand on the weak layer
Line(11) = {3, 10};  // right wall above the layer
Line(12) = {10, 11}; // domain top
Line(13) = {11, 8};  // left wall above the crest

Curve Loop(1) = {1, 2, 3, -10, 9};
Plane Surface(1) = {1};
Curve Loop(2) = {10, 4, 5, 6, 7, 8};
Plane Surface(2) = {2};
Curve Loop(3) = {11, 12, 13, -7, -6, -5, -4, -3};
Plane Surface(3) = {3};

Physical Surface("domain") = {1, 2, 3};
Physical Surface("weak") = {1};
Physical Surface("sand") = {2};
Physical Curve("base") = {1};
Physical Curve("left") = {8, 9, 13};
Physical Curve("right") = {2, 11};
Physical Curve("top") = {12};
Physical Curve("road") = {6};
