// Box sliding on an inclined surface (validation case 2, docs/scenes.md). Points are given in
// slope coordinates (s down the slope, n normal to it, up) and rotated by the inclination:
// x = s cos(a) + n sin(a), y = -s sin(a) + n cos(a). The surface is a slab 0.1 m thick with
// a wall at its lower end; the box sits near its upper end. Bodies and domain share lines,
// so the mesh follows every body edge.
// With the parameter level = 1 the points are not rotated: the slab lies level along the
// domain's base, an axis-aligned rectangle, and the scene tilts gravity instead
// (box_incline_level.toml, which the grid pattern and B-splines can run).
DefineConstant[ level = {0, Min 0, Max 1, Name "Parameters/level"} ];
a = 30 * Pi / 180 * (1 - level);  // rotation of the geometry: the inclination, or none
ca = Cos(a);
sa = Sin(a);
L = 1.6;     // surface length, m (1.2 m of sliding in 1 s at mu = 0.3 needs more than 1 m)
t = 0.1;     // surface thickness, m
ww = 0.05;   // wall thickness, m
hw = 0.1;    // wall height above the surface, m
s0 = 0.05;   // box's upper face, m from the surface's upper end
bl = 0.15;   // box length along the slope, m
bh = 0.1;    // box height, m
H = 0.3;     // domain height above the surface, m
lc = 0.025;  // element size, m

s[] = {0, L, L, L - ww, L - ww, s0 + bl, s0, 0, s0, s0 + bl, L, 0};
n[] = {-t, -t, hw, hw, 0, 0, 0, 0, bh, bh, H, H};
For i In {0 : 11}
  Point(i + 1) = {s[i] * ca + n[i] * sa, -s[i] * sa + n[i] * ca, 0, lc};
EndFor

Line(1) = {1, 2};    // underside of the surface
Line(2) = {2, 3};    // lower end of the surface and outer face of the wall
Line(3) = {3, 4};    // top of the wall
Line(4) = {4, 5};    // inner face of the wall
Line(5) = {5, 6};    // surface between the box and the wall
Line(6) = {6, 7};    // surface under the box
Line(7) = {7, 8};    // surface above the box
Line(8) = {8, 1};    // upper end of the surface
Line(9) = {7, 9};    // upper face of the box
Line(10) = {9, 10};  // top of the box
Line(11) = {10, 6};  // lower face of the box
Line(12) = {3, 11};  // domain, lower end
Line(13) = {11, 12}; // domain, top
Line(14) = {12, 8};  // domain, upper end

Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7, 8};
Plane Surface(1) = {1};
Curve Loop(2) = {-6, -11, -10, -9};
Plane Surface(2) = {2};
Curve Loop(3) = {-7, 9, 10, 11, -5, -4, -3, 12, 13, 14};
Plane Surface(3) = {3};

Physical Surface("domain") = {1, 2, 3};
Physical Surface("surface") = {1};
Physical Surface("box") = {2};
Physical Curve("underside") = {1};
Physical Curve("ends") = {2, 8, 12, 14};
Physical Curve("top") = {13};
