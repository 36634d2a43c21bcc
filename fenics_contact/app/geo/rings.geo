// Rings scene (fenics_contact.meshes.rings.concentric_rings): the quarter (x, y >= 0) of two concentric rings
// a <= r <= b and b <= r <= c, two bodies that touch along r = b without sharing nodes: n_inner elements along
// the inner ring's arc r = b, n_outer along the outer ring's (non-matching interface meshes); the other arcs and
// the radial sides divided uniformly at about the size of the ring's interface elements. Open in the gmsh GUI
// (its parameters under "Parameters"), or mesh with `gmsh -2 rings.geo`; the builder sets the parameters and the
// geometry order.
// Physical names: cells "inner_ring", "outer_ring"; facets "inner_free" (r = a), "inner_surface" and
// "outer_surface" (r = b of each ring), "loaded" (r = c), "x0_inner", "y0_inner", "x0_outer", "y0_outer".
DefineConstant[ a = {0.2, Name "Parameters/a"},
                b = {0.6, Name "Parameters/b"},
                c = {1.0, Name "Parameters/c"},
                n_inner = {16, Name "Parameters/n_inner"},
                n_outer = {12, Name "Parameters/n_outer"} ];
Geometry.AutoCoherence = 0;  // the rings touch: keep their points apart
quarter = 0.5 * Pi;
Point(1) = {0, 0, 0};
// the inner ring: points 2-5, curves 1-4 (bottom, outer arc, side, inner arc)
h = quarter * b / n_inner;  // the size of its interface elements
Point(2) = {a, 0, 0}; Point(3) = {b, 0, 0}; Point(4) = {0, b, 0}; Point(5) = {0, a, 0};
Line(1) = {2, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 5}; Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4}; Plane Surface(1) = {1};
Transfinite Curve{1, 3} = Max(Round((b - a) / h), 1) + 1;
Transfinite Curve{2} = n_inner + 1;  // the interface arc: exactly n_inner elements
Transfinite Curve{4} = Max(Round(quarter * a / h), 1) + 1;
// the outer ring: points 6-9, curves 5-8
h = quarter * b / n_outer;
Point(6) = {b, 0, 0}; Point(7) = {c, 0, 0}; Point(8) = {0, c, 0}; Point(9) = {0, b, 0};
Line(5) = {6, 7}; Circle(6) = {7, 1, 8}; Line(7) = {8, 9}; Circle(8) = {9, 1, 6};
Curve Loop(2) = {5, 6, 7, 8}; Plane Surface(2) = {2};
Transfinite Curve{5, 7} = Max(Round((c - b) / h), 1) + 1;
Transfinite Curve{6} = Max(Round(quarter * c / h), 1) + 1;
Transfinite Curve{8} = n_outer + 1;
Physical Curve("inner_free", 41) = {4};
Physical Curve("inner_surface", 42) = {2};
Physical Curve("outer_surface", 43) = {8};
Physical Curve("loaded", 44) = {6};
Physical Curve("x0_inner", 45) = {3};
Physical Curve("y0_inner", 46) = {1};
Physical Curve("x0_outer", 47) = {7};
Physical Curve("y0_outer", 48) = {5};
Physical Surface("inner_ring", 1) = {1};
Physical Surface("outer_ring", 2) = {2};
Mesh.Algorithm = 6;  // frontal-Delaunay: near-equilateral triangles
