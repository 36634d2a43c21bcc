// Cross-section of an O-ring cord: the disk of diameter 1 centred at (0, 0) (the builder scales and moves it).
// Open in the gmsh GUI, or mesh with `gmsh -2 oring.geo`. Physical names: "cord" (the surface), "surface" (the
// circle). The points at the angles -90 +- alpha (degrees from the +x axis) are vertices: the ends of the arc the
// fluid pressure acts on (the scene tags it).
// Parameters: h (the mesh size), alpha (half-angle of the pressurised arc, degrees).
DefineConstant[ h = {0.0625, Name "Parameters/h"}, alpha = {40.0, Name "Parameters/alpha"} ];
r = 0.5;
a = alpha * Pi / 180;
Point(1) = {0, 0, 0, h};  // the centre: not a vertex of the mesh
Point(2) = {r, 0, 0, h};
Point(3) = {0, r, 0, h};
Point(4) = {-r, 0, 0, h};
Point(5) = {-r * Sin(a), -r * Cos(a), 0, h};
Point(6) = {r * Sin(a), -r * Cos(a), 0, h};
Circle(1) = {2, 1, 3};
Circle(2) = {3, 1, 4};
Circle(3) = {4, 1, 5};
Circle(4) = {5, 1, 6};
Circle(5) = {6, 1, 2};
Curve Loop(1) = {1, 2, 3, 4, 5};
Plane Surface(1) = {1};
Physical Surface("cord") = {1};
Physical Curve("surface") = {1, 2, 3, 4, 5};
