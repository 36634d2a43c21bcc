// Cross-section of an O-ring in a meshed gland: the cord (the disk of diameter 1 centred at (0, 0), as oring.geo)
// and the groove body below it (the groove bottom at x = -0.5, its side walls at y = -+w/2); the builder scales by
// the cord diameter and moves the cord's centre. x is the radial, y the axial coordinate. The two bodies share no
// node: the cord touches the groove bottom at (-0.5, 0).
// Physical names: cells "cord", "groove"; facets "surface" (the cord's circle), "bottom_wall" (the groove bottom),
// "upstream_wall" (the groove's side wall y = -w/2), "side_wall" (y = w/2), "upstream_land" and "side_land" (the
// groove body's faces x = xl beside the groove, y < 0 and y > 0), "groove_fixed" (its face x = -0.5 - b),
// "housing_ends" (its faces y = -+(w/2 + land)).
// Parameters: h (the cord's mesh size and the walls'), hh (the housing's far mesh size), alpha (half-angle of the
// pressurised arc, degrees), w (the groove's width), xl (the lands' x: the groove's depth is xl + 0.5), b (the
// groove body's thickness below the groove bottom), land (the lands' length beside the groove).
DefineConstant[ h = {0.0625, Name "Parameters/h"}, hh = {0.25, Name "Parameters/hh"},
                alpha = {40.0, Name "Parameters/alpha"}, w = {1.5, Name "Parameters/w"},
                xl = {0.15, Name "Parameters/xl"}, b = {0.5, Name "Parameters/b"},
                land = {0.5, Name "Parameters/land"} ];
r = 0.5;
a = alpha * Pi / 180;
L = 0.5 * w + land;
// the cord
Point(1) = {0, 0, 0, h};
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
// the groove body
Point(11) = {-r - b, -L, 0, hh};
Point(12) = {xl, -L, 0, hh};
Point(13) = {xl, -0.5 * w, 0, h};
Point(14) = {-r, -0.5 * w, 0, h};
Point(15) = {-r, 0.5 * w, 0, h};
Point(16) = {xl, 0.5 * w, 0, h};
Point(17) = {xl, L, 0, hh};
Point(18) = {-r - b, L, 0, hh};
Line(11) = {11, 12};
Line(12) = {12, 13};
Line(13) = {13, 14};
Line(14) = {14, 15};
Line(15) = {15, 16};
Line(16) = {16, 17};
Line(17) = {17, 18};
Line(18) = {18, 11};
Curve Loop(2) = {11, 12, 13, 14, 15, 16, 17, 18};
Plane Surface(2) = {2};
// the walls near the cord carry its size h (the smallest of the points' sizes and this field)
Field[1] = Distance;
Field[1].CurvesList = {1, 2, 3, 4, 5};
Field[1].NumPointsPerCurve = 200;
Field[2] = Threshold;
Field[2].InField = 1;
Field[2].SizeMin = h;
Field[2].SizeMax = hh;
Field[2].DistMin = 0.1;
Field[2].DistMax = 0.6;
Background Field = 2;
Physical Surface("cord") = {1};
Physical Surface("groove") = {2};
Physical Curve("surface") = {1, 2, 3, 4, 5};
Physical Curve("bottom_wall") = {14};
Physical Curve("upstream_wall") = {13};
Physical Curve("side_wall") = {15};
Physical Curve("upstream_land") = {12};
Physical Curve("side_land") = {16};
Physical Curve("groove_fixed") = {18};
Physical Curve("housing_ends") = {11, 17};
