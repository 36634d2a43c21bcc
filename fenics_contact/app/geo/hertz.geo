// Hertz scene (fenics_contact.meshes.hertz_quarter_disk): the lower-right quarter (x >= 0, y <= R) of the disk of
// radius R centred at (0, R), graded toward the contact point (0, 0); or the lower half disk (half = 1), the whole
// disk (full = 1), and optionally a plate [0, plate_width] x [-plate_depth, 0] below it (plate = 1, quarter only),
// sharing no node with the disk. Open in the gmsh GUI (its parameters under "Parameters"), or mesh with
// `gmsh -2 hertz.geo`; the builder sets the parameters and meshes it with the same result.
// Physical names: cells "disk" (and "plate"); facets "contact" (the lower arc), "symmetry" (x = 0, quarter),
// "top" (y = R), "contact_upper" (full: the upper half circle), "plate_top", "plate_bottom", "plate_symmetry".
DefineConstant[ R = {1.0, Name "Parameters/R"},
                h_contact = {0.0025, Name "Parameters/h_contact"},
                h_far = {0.1, Name "Parameters/h_far"},
                contact_width = {0.2, Name "Parameters/contact_width"},
                grading = {0.25, Name "Parameters/grading"},
                half = {0, Choices {0, 1}, Name "Parameters/half"},
                full = {0, Choices {0, 1}, Name "Parameters/full"},
                plate = {0, Choices {0, 1}, Name "Parameters/plate"},
                plate_width = {0.5, Name "Parameters/plate_width"},
                plate_depth = {0.25, Name "Parameters/plate_depth"} ];

origin = newp; Point(origin) = {0, 0, 0};
centre = newp; Point(centre) = {0, R, 0};
corner = newp; Point(corner) = {R, R, 0};
arc = newc; Circle(arc) = {origin, centre, corner};
poles[] = {origin};
If (full)
  left = newp; Point(left) = {-R, R, 0};
  pole = newp; Point(pole) = {0, 2 * R, 0};
  lower = newc; Circle(lower) = {left, centre, origin};
  up1 = newc; Circle(up1) = {corner, centre, pole};
  up2 = newc; Circle(up2) = {pole, centre, left};
  loop = 1; Curve Loop(loop) = {lower, arc, up1, up2};
  surface = 1; Plane Surface(surface) = {loop};
  Point{centre} In Surface{surface};
  Physical Curve("contact", 1) = {lower, arc};
  Physical Curve("contact_upper", 5) = {up1, up2};
  poles[] += {pole};
ElseIf (half)
  left = newp; Point(left) = {-R, R, 0};
  lower = newc; Circle(lower) = {left, centre, origin};
  top1 = newc; Line(top1) = {corner, centre};
  top2 = newc; Line(top2) = {centre, left};
  loop = 1; Curve Loop(loop) = {lower, arc, top1, top2};
  surface = 1; Plane Surface(surface) = {loop};
  Physical Curve("contact", 1) = {lower, arc};
  Physical Curve("top", 3) = {top1, top2};
Else
  top = newc; Line(top) = {corner, centre};
  symmetry = newc; Line(symmetry) = {centre, origin};
  loop = 1; Curve Loop(loop) = {arc, top, symmetry};
  surface = 1; Plane Surface(surface) = {loop};
  Physical Curve("contact", 1) = {arc};
  Physical Curve("symmetry", 2) = {symmetry};
  Physical Curve("top", 3) = {top};
EndIf
If (plate)  // its own corner points: the plate shares no node with the disk
  p0 = newp; Point(p0) = {0, 0, 0};
  p1 = newp; Point(p1) = {plate_width, 0, 0};
  p2 = newp; Point(p2) = {plate_width, -plate_depth, 0};
  p3 = newp; Point(p3) = {0, -plate_depth, 0};
  l0 = newc; Line(l0) = {p0, p1};
  l1 = newc; Line(l1) = {p1, p2};
  l2 = newc; Line(l2) = {p2, p3};
  l3 = newc; Line(l3) = {p3, p0};
  ploop = 2; Curve Loop(ploop) = {l0, l1, l2, l3};
  block = 2; Plane Surface(block) = {ploop};
  Physical Curve("plate_top", 6) = {l0};
  Physical Curve("plate_bottom", 7) = {l2};
  Physical Curve("plate_symmetry", 8) = {l3};
  Physical Surface("plate", 2) = {block};
  poles[] += {p0};
EndIf
Physical Surface("disk", 1) = {surface};

// h_contact within contact_width of the contact point(s), growing by grading per unit distance up to h_far.
Field[1] = Distance; Field[1].PointsList = {poles[]};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = h_contact; Field[2].SizeMax = h_far;
Field[2].DistMin = contact_width; Field[2].DistMax = contact_width + (h_far - h_contact) / grading;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
