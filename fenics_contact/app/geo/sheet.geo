// Sheet scene (fenics_contact.meshes.sheet_over_cylinder): the right half of a sheet wrapped over the top of a
// cylinder of radius R (centre at the origin): the quarter annulus R <= r <= R + thickness continued by a vertical
// leg of length leg; structured quadrilaterals (n_arc along the arc, n_leg along the leg, n_thick through the
// thickness). cylinder = 1: also the right half of the hollow cylinder R_in <= r <= R (n_cyl elements per quarter
// arc, n_rad through its wall), touching the sheet along r = R without sharing a node. Open in the gmsh GUI (its
// parameters under "Parameters"), or mesh with `gmsh -2 sheet.geo`; the builder sets the parameters and the
// geometry order (9-node quadrilaterals).
// Physical names: cells "sheet" (and "cylinder"); facets "contact" (the sheet's inner arc and leg side),
// "symmetry" (x = 0), "end" (y = -leg), "cylinder_surface" (r = R), "cylinder_fixed" (r = R_in).
DefineConstant[ R = {3.0, Name "Parameters/R"},
                thickness = {1.0, Name "Parameters/thickness"},
                leg = {2.0, Name "Parameters/leg"},
                n_arc = {24, Name "Parameters/n_arc"},
                n_thick = {2, Name "Parameters/n_thick"},
                n_leg = {8, Name "Parameters/n_leg"},
                cylinder = {1, Choices {0, 1}, Name "Parameters/cylinder"},
                R_in = {1.0, Name "Parameters/R_in"},
                n_cyl = {18, Name "Parameters/n_cyl"},
                n_rad = {3, Name "Parameters/n_rad"} ];
Geometry.AutoCoherence = 0;  // the two bodies touch: keep their points apart
Ro = R + thickness;
Point(1) = {0, 0, 0};
Point(2) = {0, R, 0};
Point(3) = {R, 0, 0};
Point(4) = {0, Ro, 0};
Point(5) = {Ro, 0, 0};
Point(6) = {R, -leg, 0};
Point(7) = {Ro, -leg, 0};
Circle(1) = {2, 1, 3};  // the sheet's inner arc
Circle(2) = {4, 1, 5};  // outer arc
Line(3) = {2, 4};  // symmetry
Line(4) = {3, 5};  // between the arc and the leg
Line(5) = {6, 7};  // the end
Line(6) = {3, 6};  // the leg's inner side
Line(7) = {5, 7};  // the leg's outer side
Curve Loop(1) = {1, 4, -2, -3};
Plane Surface(1) = {1};
Curve Loop(2) = {6, 5, -7, -4};
Plane Surface(2) = {2};
Transfinite Curve{1, 2} = n_arc + 1;
Transfinite Curve{3, 4, 5} = n_thick + 1;
Transfinite Curve{6, 7} = n_leg + 1;
Transfinite Surface{1, 2};
Recombine Surface{1, 2};
symmetry[] = {3};
If (cylinder)
  Point(8) = {0, R_in, 0};
  Point(9) = {R_in, 0, 0};
  Point(10) = {0, -R_in, 0};
  Point(11) = {0, R, 0};
  Point(12) = {R, 0, 0};
  Point(13) = {0, -R, 0};
  Circle(8) = {8, 1, 9};
  Circle(9) = {9, 1, 10};
  Circle(10) = {11, 1, 12};
  Circle(11) = {12, 1, 13};
  Line(12) = {8, 11};
  Line(13) = {10, 13};
  Line(14) = {9, 12};
  Curve Loop(3) = {8, 14, -10, -12};
  Plane Surface(3) = {3};
  Curve Loop(4) = {9, 13, -11, -14};
  Plane Surface(4) = {4};
  Transfinite Curve{8, 9, 10, 11} = n_cyl + 1;
  Transfinite Curve{12, 13, 14} = n_rad + 1;
  Transfinite Surface{3, 4};
  Recombine Surface{3, 4};
  Physical Curve("cylinder_surface", 5) = {10, 11};
  Physical Curve("cylinder_fixed", 6) = {8, 9};
  Physical Surface("cylinder", 2) = {3, 4};
  symmetry[] += {12, 13};
EndIf
Physical Curve("contact", 1) = {1, 6};
Physical Curve("symmetry", 2) = {symmetry[]};
Physical Curve("end", 4) = {5};
Physical Surface("sheet", 1) = {1, 2};
Mesh.ElementOrder = 2;
