// Cylinders scene (fenics_contact.meshes.two_half_disks): the right halves (x >= 0) of two disks stacked on the
// y axis, in one mesh without shared nodes: the lower disk (radius R_lower) centred at (0, R_lower), the upper
// (radius R_upper) at (0, 2 R_lower + R_upper - overlap); or the whole disks (full = 1); or the quarters that
// face each other (quarters = 1: the lower disk above its centre, the upper below its own, cut at their equators). Size h_contact within
// contact_width of the four points on the y axis where the disks touch each other and the plates, growing by
// grading per unit distance up to h_far. Open in the gmsh GUI (its parameters under "Parameters"), or mesh with
// `gmsh -2 two_disks.geo`; the builder sets the parameters.
// Physical names: cells "lower", "upper"; facets "symmetry" (x = 0, halves only), "lower_bottom", "lower_top",
// "upper_bottom", "upper_top" (each arc split at its widest point: full, the lower and upper half circles);
// quarters: "symmetry", "lower_top", "upper_bottom", "lower_equator", "upper_equator" (the cuts).
DefineConstant[ R_lower = {18.0, Name "Parameters/R_lower"},
                R_upper = {8.0, Name "Parameters/R_upper"},
                h_contact = {0.1, Name "Parameters/h_contact"},
                h_far = {2.0, Name "Parameters/h_far"},
                contact_width = {1.0, Name "Parameters/contact_width"},
                overlap = {1e-6, Name "Parameters/overlap"},
                grading = {0.25, Name "Parameters/grading"},
                full = {0, Choices {0, 1}, Name "Parameters/full"},
                quarters = {0, Choices {0, 1}, Name "Parameters/quarters"} ];
symmetry[] = {};
equators[] = {};
For i In {0:1}
  If (i == 0)
    cy = R_lower; R = R_lower;
  Else
    cy = 2 * R_lower + R_upper - overlap; R = R_upper;
  EndIf
  bottom = newp; Point(bottom) = {0, cy - R, 0};
  centre = newp; Point(centre) = {0, cy, 0};
  side = newp; Point(side) = {R, cy, 0};
  top = newp; Point(top) = {0, cy + R, 0};
  a1 = newc; Circle(a1) = {bottom, centre, side};
  a2 = newc; Circle(a2) = {side, centre, top};
  If (full)  // the left half circle too
    left = newp; Point(left) = {-R, cy, 0};
    a3 = newc; Circle(a3) = {top, centre, left};
    a0 = newc; Circle(a0) = {left, centre, bottom};
    Curve Loop(i + 1) = {a0, a1, a2, a3};
    bottoms~{i}[] = {a0, a1}; tops~{i}[] = {a2, a3};
  ElseIf (quarters)  // the lower disk's upper quarter, the upper disk's lower quarter
    e = newc; Line(e) = {centre, side};
    If (i == 0)
      s1 = newc; Line(s1) = {top, centre};
      Curve Loop(i + 1) = {e, a2, s1};
      tops~{i}[] = {a2}; bottoms~{i}[] = {};
      touch~{i}[] = {top};
    Else
      s1 = newc; Line(s1) = {centre, bottom};
      Curve Loop(i + 1) = {a1, -e, s1};
      bottoms~{i}[] = {a1}; tops~{i}[] = {};
      touch~{i}[] = {bottom};
    EndIf
    symmetry[] += {s1};
    equators[] += {e};
  Else
    s1 = newc; Line(s1) = {top, centre};
    s2 = newc; Line(s2) = {centre, bottom};
    Curve Loop(i + 1) = {a1, a2, s1, s2};
    bottoms~{i}[] = {a1}; tops~{i}[] = {a2};
    symmetry[] += {s1, s2};
  EndIf
  Plane Surface(i + 1) = {i + 1};
  If (!quarters)
    touch~{i}[] = {bottom, top};
  EndIf
EndFor
If (!full)
  Physical Curve("symmetry", 31) = {symmetry[]};
EndIf
If (quarters)
  Physical Curve("lower_top", 33) = {tops~{0}[]};
  Physical Curve("upper_bottom", 34) = {bottoms~{1}[]};
  Physical Curve("lower_equator", 36) = {equators[0]};
  Physical Curve("upper_equator", 37) = {equators[1]};
Else
  Physical Curve("lower_bottom", 32) = {bottoms~{0}[]};
  Physical Curve("lower_top", 33) = {tops~{0}[]};
  Physical Curve("upper_bottom", 34) = {bottoms~{1}[]};
  Physical Curve("upper_top", 35) = {tops~{1}[]};
EndIf
Physical Surface("lower", 1) = {1};
Physical Surface("upper", 2) = {2};

Field[1] = Distance; Field[1].PointsList = {touch~{0}[], touch~{1}[]};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = h_contact; Field[2].SizeMax = h_far;
Field[2].DistMin = contact_width; Field[2].DistMax = contact_width + (h_far - h_contact) / grading;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
