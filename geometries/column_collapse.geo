// Granular column collapse (validation case 4, docs/column.md). A column L0 long and
// H0 = a L0 high stands against a wall (x = 0) on a rough base (y = 0) and is released at t = 0.
// The aspect ratio a and the column length L0 are gmsh parameters: the scene sets them with
// [mesh.parameters] (a = 3 is `--set mesh.parameters.a=3`); the gmsh GUI shows them under
// "Parameters". The domain is sized from a: it reaches three times Lube et al.'s (2005) runout
// past the column, and a little above it. Column and empty space share two lines, so the mesh
// follows the column's outline.
DefineConstant[ a = {0.5, Min 0.1, Max 20, Name "Parameters/a"} ];    // aspect ratio H0 / L0
DefineConstant[ L0 = {0.2, Min 0.01, Max 10, Name "Parameters/L0"} ];  // column length, m
// The domain reaches `reach` times Lube's runout past the column (a material that runs further,
// such as the aluminium rods of rods_collapse.toml, asks for more room).
DefineConstant[ reach = {3, Min 1, Max 20, Name "Parameters/reach"} ];
lc = 0.005;       // element size, m (5 mm triangles)
H0 = a * L0;      // column height, m
// Lube et al. (2005), 2D: (L_inf - L0) / L0 = 1.2 a for small a, 1.9 a^(2/3) for large a.
If (a < 2.3)
  spread = 1.2 * a;
Else
  spread = 1.9 * a^(2 / 3);
EndIf
W = L0 * (1 + reach * spread) + 30 * lc;   // domain length, m: `reach` times the law's runout
D = 1.1 * H0 + 10 * lc;                // domain height, m

Point(1) = {0, 0, 0, lc};
Point(2) = {L0, 0, 0, lc};
Point(3) = {W, 0, 0, lc};
Point(4) = {W, D, 0, lc};
Point(5) = {0, D, 0, lc};
Point(6) = {0, H0, 0, lc};
Point(7) = {L0, H0, 0, lc};

Line(1) = {1, 2};  // base under the column
Line(2) = {2, 3};  // base beyond the column
Line(3) = {3, 4};  // far end
Line(4) = {4, 5};  // domain top
Line(5) = {5, 6};  // wall above the column
Line(6) = {6, 1};  // wall against the column
Line(7) = {6, 7};  // column top
Line(8) = {7, 2};  // column face, the side that is released

Curve Loop(1) = {1, -8, -7, 6};
Plane Surface(1) = {1};
Curve Loop(2) = {2, 3, 4, 5, 7, 8};
Plane Surface(2) = {2};

Physical Surface("domain") = {1, 2};
Physical Surface("column") = {1};
Physical Curve("base") = {1, 2};
Physical Curve("wall") = {5, 6};
Physical Curve("far_end") = {3};
Physical Curve("top") = {4};
