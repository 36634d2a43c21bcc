// mindlin3d scene (fenics_contact.meshes.mindlin3d.cap_on_block): the half y >= 0 of a spherical cap on a block.
// The cap: the part z <= H of the ball of radius R centred at (0, 0, R - overlap) (its pole, the first contact
// point, is overlap into the block), y >= 0; the block [-L, L] x [0, L] x [-D, 0] under it. Both are cut by the
// plane x = 0 (two halves each, fused: a line of nodes along the y axis of the contact surface). No node is
// shared by the cap and the block. Tetrahedra of size h_contact within contact_width of the origin, growing by
// grading per unit distance up to h_far. Open in the gmsh GUI (its parameters under "Parameters"), or mesh with
// `gmsh -3 mindlin3d.geo`; the builder sets the parameters.
// Physical names: cells "cap", "block"; facets "cap_surface" (the spherical surface), "cap_top" (z = H),
// "block_top" (z = 0), "block_bottom" (z = -D), "symmetry" (y = 0, of both bodies).
DefineConstant[ R = {1.0, Name "Parameters/R"},
                H = {0.5, Name "Parameters/H"},
                L = {1.0, Name "Parameters/L"},
                D = {0.5, Name "Parameters/D"},
                overlap = {1e-9, Name "Parameters/overlap"},
                h_contact = {0.007, Name "Parameters/h_contact"},
                h_far = {0.15, Name "Parameters/h_far"},
                contact_width = {0.1, Name "Parameters/contact_width"},
                grading = {0.25, Name "Parameters/grading"} ];
SetFactory("OpenCASCADE");
zc = R - overlap;
top = Asin((H - zc) / R);  // the latitude of the cap's top z = H
Sphere(1) = {0, 0, zc, R, -Pi / 2, top, Pi / 2};  // x >= 0, y >= 0
Sphere(2) = {0, 0, zc, R, -Pi / 2, top, Pi / 2};
Rotate {{0, 0, 1}, {0, 0, 0}, Pi / 2} { Volume{2}; }  // x <= 0, y >= 0
cap[] = BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; };
Box(3) = {-L, 0, -D, L, L, D};
Box(4) = {0, 0, -D, L, L, D};
block[] = BooleanFragments{ Volume{3}; Delete; }{ Volume{4}; Delete; };
t = 1e-6 * R;  // the boundary surfaces by their bounding boxes
ztop = zc + R * Sin(top);
cap_top[] = Surface In BoundingBox{-R - t, -t, ztop - t, R + t, R + t, ztop + t};
cap_sym[] = Surface In BoundingBox{-R - t, -t, -overlap - t, R + t, t, ztop + t};
cap_surface[] = Abs(CombinedBoundary{Volume{cap[]};});
cap_surface[] -= {cap_top[], cap_sym[]};
block_top[] = Surface In BoundingBox{-L - t, -t, -t, L + t, L + t, t};
block_bottom[] = Surface In BoundingBox{-L - t, -t, -D - t, L + t, L + t, -D + t};
block_sym[] = Surface In BoundingBox{-L - t, -t, -D - t, L + t, t, t};
Physical Surface("cap_surface", 1) = {cap_surface[]};
Physical Surface("cap_top", 2) = {cap_top[]};
Physical Surface("block_top", 3) = {block_top[]};
Physical Surface("block_bottom", 4) = {block_bottom[]};
Physical Surface("symmetry", 5) = {cap_sym[], block_sym[]};
Physical Volume("cap", 1) = {cap[]};
Physical Volume("block", 2) = {block[]};
origin = newp; Point(origin) = {0, 0, 0};  // the contact point (not in the model's mesh: the size field's centre)

Field[1] = Distance; Field[1].PointsList = {origin};
Field[2] = Threshold; Field[2].InField = 1; Field[2].SizeMin = h_contact; Field[2].SizeMax = h_far;
Field[2].DistMin = contact_width; Field[2].DistMax = contact_width + (h_far - h_contact) / grading;
Background Field = 2;
Mesh.MeshSizeExtendFromBoundary = 0;
Mesh.MeshSizeFromPoints = 0;
Mesh.MeshSizeFromCurvature = 0;
Mesh.Algorithm3D = 1;  // Delaunay: the same mesh every run (HXT's varies)
