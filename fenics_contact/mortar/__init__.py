"""Segment-to-segment (mortar-type) integration of two-body contact: segments (2D) and triangles (3D).

Pointwise two-body contact (:mod:`twobody`, nodal or Gauss points) sends the forces of the slave points to
the master vertices through master shape functions that have kinks inside a slave facet: the rule is not
exact, the uniform-pressure state is not a discrete equilibrium and the patch test fails on non-matching
meshes. Here every slave facet is cut into the parts whose points project inside one master facet, each
integrated with its own rule, so the constant-pressure state is reproduced to round-off. The parts, one job
each:

- :mod:`~.dual`: forward-mode dual numbers (the element's exact tangent through the law's formula);
- :mod:`~.clipping`: the overlap of a slave and a projected master triangle (3D);
- :mod:`~.element`: residual and tangent of slave/master facet pairs;
- :mod:`~.pairs`: the slave/master facet pairs with an overlap;
- :mod:`~.surface`: :class:`SegmentSurface`, composed of these and of the nodal state of :mod:`twobody`;
- :mod:`~.cell_stress`: a P1 triangle's traction ``P N`` and its derivatives, from the material;
- :mod:`~.nitsche_element`: Nitsche's segment element (2D: the slave cell's stress terms);
- :mod:`~.nitsche_surface`: :class:`NitscheSegmentSurface`, Nitsche's method on :class:`SegmentSurface`.
"""
from .clipping import (
    MAX_VERTICES,
    SLAVE_LINES,
    clip_arrays,
    clip_polygons,
    intersect_values,
    master_lines,
    polygon_area,
    polygon_areas,
)
from .dual import DUAL_OPS, Dual, dual_exp, dual_max, dual_min, dual_sqrt
from .element import SEGMENT_RULE, TRIANGLE_RULE, segment_element, triangle_element
from .nitsche_surface import NitscheSegmentSurface
from .pairs import overlap, pair_segments, pair_triangles
from .surface import SegmentSurface

# The names tests/test_mortar.py imports.
_SLAVE_LINES, _intersect_values, _master_lines = SLAVE_LINES, intersect_values, master_lines

__all__ = [
    "SEGMENT_RULE", "TRIANGLE_RULE", "Dual", "dual_max", "dual_min", "dual_exp", "dual_sqrt", "DUAL_OPS",
    "segment_element", "SLAVE_LINES", "MAX_VERTICES", "master_lines", "clip_arrays", "clip_polygons",
    "intersect_values", "polygon_area", "polygon_areas", "triangle_element", "overlap", "pair_segments",
    "pair_triangles", "SegmentSurface", "NitscheSegmentSurface"
]
