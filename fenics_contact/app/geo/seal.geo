// Seal scene (fenics_contact.meshes.seal_section, seal_s_section, seal_wave_section): the cross-section of a
// seal between the plates y = 0 and y = gap, a band of thickness R_out - R_in, structured quadrilaterals of size
// about h. shape = 0: the U (right half: one annular sector centred at (0, R_out), its outer arc touching y = 0);
// 1: the S (two sectors of opposite curvature joined tangentially, point-symmetric about (0, gap/2)); 2: the wave
// (right half: the crown sector centred at (0, gap - R_out) and a hump). See fenics_contact/meshes/seal.py for the
// geometry. Open in the gmsh GUI (its parameters under "Parameters"), or mesh with `gmsh -2 seal.geo`.
// Physical names: cells "seal"; facets "boundary" (the arcs and ends), "symmetry" (x = 0; U and wave).
DefineConstant[ shape = {0, Choices {0 = "U", 1 = "S", 2 = "wave"}, Name "Parameters/shape"},
                R_out = {10.0, Name "Parameters/R_out"},
                R_in = {9.0, Name "Parameters/R_in"},
                gap = {7.0, Name "Parameters/gap"},
                h = {0.25, Name "Parameters/h"} ];
Ro = R_out; Ri = R_in;
symmetry[] = {};
If (shape == 0)
  phi = Acos((Ro - gap) / Ri);  // the half-angle of the sector, from its bottom
  Point(1) = {0, Ro, 0};  // the centre
  Point(2) = {0, Ro - Ro, 0};
  Point(3) = {0, Ro - Ri, 0};
  Point(4) = {0 + Ro * Sin(phi), Ro - Ro * Cos(phi), 0};
  Point(5) = {0 + Ri * Sin(phi), Ro - Ri * Cos(phi), 0};
  Circle(1) = {2, 1, 4};  // outer arc
  Line(2) = {4, 5};  // end
  Circle(3) = {5, 1, 3};  // inner arc
  Line(4) = {3, 2};  // symmetry
  Curve Loop(1) = {1, 2, 3, 4};
  Plane Surface(1) = {1};
  n_t = Max(2, Round((Ro - Ri) / h));
  n_l = Max(4, Round(0.5 * (Ro + Ri) * phi / h));
  Transfinite Curve{1, 3} = n_l + 1;
  Transfinite Curve{2, 4} = n_t + 1;
  Transfinite Surface{1};
  Recombine Surface{1};
  boundary[] = {1, 2, 3}; symmetry[] = {4}; surfaces[] = {1};
Else
  dy = Ro - gap / 2; dd = (Ro + Ri) / 2;
  dx = Sqrt(dd^2 - dy^2);
  beta = Atan2(dy, dx);  // the junction's direction from the first centre
  If (shape == 1)
    c1x = -dx; c1y = gap / 2 - dy; c2x = dx; c2y = gap / 2 + dy; end = Pi - beta;
  Else
    c1x = 0.0; c1y = gap / 2 - dy; c2x = dx + dx; c2y = gap / 2 + dy; end = 2 * Pi - beta;
  EndIf
  Point(1) = {c1x, c1y, 0};
  Point(2) = {c2x, c2y, 0};
  If (shape == 1)
    Point(3) = {c1x + Ro * Cos(beta), c1y + Ro * Sin(beta), 0};  // j_up
    Point(4) = {c1x + Ri * Cos(beta), c1y + Ri * Sin(beta), 0};  // j_low
    Point(5) = {0.0, gap / 2, 0};  // the centre of symmetry
    Point(6) = {c1x + Ro * Cos(end), c1y + Ro * Sin(end), 0};
    Point(7) = {c1x + Ri * Cos(end), c1y + Ri * Sin(end), 0};
    Point(8) = {c2x + Ro * Cos(end + Pi), c2y + Ro * Sin(end + Pi), 0};
    Point(9) = {c2x + Ri * Cos(end + Pi), c2y + Ri * Sin(end + Pi), 0};
    n_t = Max(2, 2 * Round((Ro - Ri) / h / 2));
    n_l = Max(4, Round(0.5 * (Ro + Ri) * (end - beta) / h));
    Circle(1) = {3, 1, 6}; Line(2) = {6, 7}; Circle(3) = {7, 1, 4};
    Line(4) = {4, 5}; Line(5) = {5, 3};
    Circle(6) = {4, 2, 8}; Line(7) = {8, 9}; Circle(8) = {9, 2, 3};
    Curve Loop(1) = {1, 2, 3, 4, 5}; Plane Surface(1) = {1};
    Curve Loop(2) = {6, 7, 8, -5, -4}; Plane Surface(2) = {2};
    Transfinite Curve{1, 3, 6, 8} = n_l + 1;
    Transfinite Curve{2, 7} = n_t + 1;
    Transfinite Curve{4, 5} = Floor(n_t / 2) + 1;
    Transfinite Surface{1} = {3, 6, 7, 4};
    Transfinite Surface{2} = {4, 8, 9, 3};
    boundary[] = {1, 2, 3, 6, 7, 8};
  Else
    Point(3) = {c1x + Ro * Cos(Pi / 2), c1y + Ro * Sin(Pi / 2), 0};  // top_out
    Point(4) = {c1x + Ri * Cos(Pi / 2), c1y + Ri * Sin(Pi / 2), 0};  // top_in
    Point(5) = {c1x + Ro * Cos(beta), c1y + Ro * Sin(beta), 0};  // j_up
    Point(6) = {c1x + Ri * Cos(beta), c1y + Ri * Sin(beta), 0};  // j_low
    Point(7) = {c2x + Ro * Cos(end), c2y + Ro * Sin(end), 0};
    Point(8) = {c2x + Ri * Cos(end), c2y + Ri * Sin(end), 0};
    n_t = Max(2, Round((Ro - Ri) / h));
    n_1 = Max(2, Round(0.5 * (Ro + Ri) * (Pi / 2 - beta) / h));
    n_2 = Max(4, 2 * Round(0.25 * (Ro + Ri) * (Pi - 2 * beta) / h));  // even: a vertex at the hump's bottom
    Line(1) = {4, 3}; Circle(2) = {3, 1, 5}; Circle(3) = {6, 1, 4};
    Line(4) = {5, 6};
    Circle(5) = {6, 2, 7}; Line(6) = {7, 8}; Circle(7) = {8, 2, 5};
    Curve Loop(1) = {1, 2, 4, 3}; Plane Surface(1) = {1};
    Curve Loop(2) = {5, 6, 7, 4}; Plane Surface(2) = {2};
    Transfinite Curve{2, 3} = n_1 + 1;
    Transfinite Curve{5, 7} = n_2 + 1;
    Transfinite Curve{1, 4, 6} = n_t + 1;
    Transfinite Surface{1} = {4, 3, 5, 6};
    Transfinite Surface{2} = {6, 7, 8, 5};
    boundary[] = {2, 3, 5, 6, 7}; symmetry[] = {1};
  EndIf
  Recombine Surface{1, 2};
  surfaces[] = {1, 2};
EndIf
Physical Curve("boundary", 31) = {boundary[]};
If (#symmetry[])
  Physical Curve("symmetry", 32) = {symmetry[]};
EndIf
Physical Surface("seal", 33) = {surfaces[]};
