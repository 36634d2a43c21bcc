// Sphere scene (fenics_contact.meshes.sphere_octant): the octant x >= 0, y >= 0, z <= R of the ball of radius R
// centred at (0, 0, R), tetrahedra of size h_contact within contact_width of the contact point (0, 0, 0), growing
// by grading per unit distance up to h_far. Open in the gmsh GUI (its parameters under "Parameters"), or mesh with
// `gmsh -3 sphere.geo`; the builder sets the parameters.
// Physical names: cells "ball"; facets "contact" (the spherical surface), "symmetry" (x = 0), "symmetry_y"
// (y = 0), "top" (z = R). plate_width > 0: also the block [0, plate_width]^2 x [-plate_depth, 0] under the ball,
// its own entities (no node shared with the ball): cells "plate", facets "plate_top" (z = 0), "plate_bottom", its
// faces x = 0 and y = 0 in "symmetry" and "symmetry_y" with the ball's; graded toward (0, 0, 0) too.
DefineConstant[ R = {1.0, Name "Parameters/R"},
                h_contact = {0.02, Name "Parameters/h_contact"},
                h_far = {0.15, Name "Parameters/h_far"},
                contact_width = {0.15, Name "Parameters/contact_width"},
                grading = {0.25, Name "Parameters/grading"},
                plate_width = {0, Name "Parameters/plate_width"},
                plate_depth = {0, Name "Parameters/plate_depth"} ];
SetFactory("OpenCASCADE");
Sphere(1) = {0, 0, R, R, -Pi / 2, 0, Pi / 2};
t = 1e-3 * R;  // the boundary surfaces by their bounding boxes
symmetry[] = Surface In BoundingBox{-t, -t, -t, t, R + t, R + t};
symmetry_y[] = Surface In BoundingBox{-t, -t, -t, R + t, t, R + t};
top[] = Surface In BoundingBox{-t, -t, R - t, R + t, R + t, R + t};
contact[] = Abs(Boundary{Volume{1};});
contact[] -= {symmetry[], symmetry_y[], top[]};
If (plate_width > 0)
  Box(2) = {0, 0, -plate_depth, plate_width, plate_width, plate_depth};
  d = plate_depth;
  symmetry[] += Surface In BoundingBox{-t, -t, -d - t, t, plate_width + t, t};
  symmetry_y[] += Surface In BoundingBox{-t, -t, -d - t, plate_width + t, t, t};
  plate_top[] = Surface In BoundingBox{-t, -t, -t, plate_width + t, plate_width + t, t};
  plate_bottom[] = Surface In BoundingBox{-t, -t, -d - t, plate_width + t, plate_width + t, -d + t};
  Physical Surface("plate_top", 5) = {plate_top[]};
  Physical Surface("plate_bottom", 6) = {plate_bottom[]};
  Physical Volume("plate", 2) = {2};
EndIf
Physical Surface("contact", 1) = {contact[]};
Physical Surface("symmetry", 2) = {symmetry[]};
Physical Surface("symmetry_y", 4) = {symmetry_y[]};
Physical Surface("top", 3) = {top[]};
Physical Volume("ball", 1) = {1};
origin = newp; Point(origin) = {0, 0, 0};  // the contact point (not in the model's mesh: the size field's centre)

Field[1] = Distance; Field[1].PointsList = {origin};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = h_contact; Field[2].SizeMax = h_far;
Field[2].DistMin = contact_width; Field[2].DistMax = contact_width + (h_far - h_contact) / grading;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm3D = 1;  // Delaunay: the same mesh every run (HXT's varies)
