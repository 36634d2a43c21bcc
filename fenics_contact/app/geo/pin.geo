// Pin scene (fenics_contact.meshes.pin_plate): the right half (x >= 0) of a plate 0 <= x <= half_width,
// -below <= y <= above with a hole of radius R centred at the origin, graded toward the hole. Open in the gmsh
// GUI (its parameters under "Parameters"), or mesh with `gmsh -2 pin.geo`; the builder sets the parameters.
// Physical names: cells "plate"; facets "contact" (the half hole), "symmetry" (x = 0), "top" (y = above),
// "free" (y = -below and x = half_width).
DefineConstant[ R = {1.0, Name "Parameters/R"},
                half_width = {5.0, Name "Parameters/half_width"},
                below = {5.0, Name "Parameters/below"},
                above = {5.0, Name "Parameters/above"},
                h_contact = {0.02, Name "Parameters/h_contact"},
                h_far = {0.5, Name "Parameters/h_far"},
                band = {0.1, Name "Parameters/band"},
                grading = {0.25, Name "Parameters/grading"} ];

Point(1) = {0, 0, 0};  // the hole's centre
Point(2) = {0, -below, 0};
Point(3) = {half_width, -below, 0};
Point(4) = {half_width, above, 0};
Point(5) = {0, above, 0};
Point(6) = {0, R, 0};
Point(7) = {R, 0, 0};
Point(8) = {0, -R, 0};
Line(1) = {2, 3};  // bottom
Line(2) = {3, 4};  // right
Line(3) = {4, 5};  // top
Line(4) = {5, 6};  // symmetry, above the hole
Circle(5) = {6, 1, 7};
Circle(6) = {7, 1, 8};
Line(7) = {8, 2};  // symmetry, below the hole
Curve Loop(1) = {1, 2, 3, 4, 5, 6, 7};
Plane Surface(1) = {1};
Physical Curve("contact", 1) = {5, 6};
Physical Curve("symmetry", 2) = {4, 7};
Physical Curve("top", 3) = {3};
Physical Curve("free", 4) = {1, 2};
Physical Surface("plate", 1) = {1};

// h_contact within band of the hole (the exact distance: a Distance field samples the curve), growing by grading
// per unit distance up to h_far.
Field[1] = MathEval; Field[1].F = Sprintf("Sqrt(x*x + y*y) - %.17g", R);
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = h_contact; Field[2].SizeMax = h_far;
Field[2].DistMin = band; Field[2].DistMax = band + (h_far - h_contact) / grading;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
