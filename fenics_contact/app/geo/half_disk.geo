// Lower half of a disk of radius R centred at (0, R): the user's-own-mesh example of the README.
// Open in the gmsh GUI, or mesh with `gmsh -2 half_disk.geo`; read with fenics_contact.read_gmsh.
// Physical names: "disk" (the surface), "contact" (the lower arc), "top" (the diameter y = R).
DefineConstant[ R = {1.0, Name "Parameters/R (radius)"},
                h = {0.1, Name "Parameters/h (size away from the contact)"},
                h_contact = {0.002, Name "Parameters/h_contact (size at the contact point)"} ];
Point(1) = {0, R, 0, h};
Point(2) = {-R, R, 0, h};
Point(3) = {0, 0, 0, h_contact};
Point(4) = {R, R, 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Line(3) = {4, 2};
Curve Loop(1) = {1, 2, 3};
Plane Surface(1) = {1};
// h_contact within 0.05 R of the contact point, growing to h at 0.6 R.
Field[1] = Distance; Field[1].PointsList = {3};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = h_contact; Field[2].SizeMax = h;
Field[2].DistMin = 0.05 * R; Field[2].DistMax = 0.6 * R;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Physical Surface("disk") = {1};
Physical Curve("contact") = {1, 2};
Physical Curve("top") = {3};
