"""Two concentric quarter rings in one mesh, not sharing nodes at their common radius (the ``rings`` scene)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from mpi4py import MPI

from .gmshutil import _from_gmsh, _physical, _positive, gmsh

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ..domain import NamedTags

__all__ = ["concentric_rings"]

# Physical group values (private: regions are referred to by name). Cells: the inner ring (a <= r <= b) and the
# outer ring (b <= r <= c). Facets: r = a (free), r = b of the inner ring, r = b of the outer ring, r = c
# (loaded), the symmetry lines x = 0 and y = 0 of each ring.
INNER_RING, OUTER_RING = 1, 2
RINGS_INNER_FREE, RINGS_INNER_SURFACE, RINGS_OUTER_SURFACE, RINGS_LOADED = 41, 42, 43, 44
RINGS_X0_INNER, RINGS_Y0_INNER, RINGS_X0_OUTER, RINGS_Y0_OUTER = 45, 46, 47, 48
_FACETS = {RINGS_INNER_FREE: "inner_free", RINGS_INNER_SURFACE: "inner_surface",
           RINGS_OUTER_SURFACE: "outer_surface", RINGS_LOADED: "loaded", RINGS_X0_INNER: "x0_inner",
           RINGS_Y0_INNER: "y0_inner", RINGS_X0_OUTER: "x0_outer", RINGS_Y0_OUTER: "y0_outer"}


def concentric_rings(comm: MPI.Comm, a: float = 0.2, b: float = 0.6, c: float = 1.0, n_inner: int = 16,
                     n_outer: int = 12, order: int = 1) -> tuple[Mesh, NamedTags, NamedTags]:
    """Quarter (``x, y >= 0``) of two rings ``a <= r <= b`` (cells ``inner_ring``) and ``b <= r <= c``
    (``outer_ring``), two bodies of one mesh that touch along ``r = b`` without sharing nodes: ``n_inner``
    elements along the inner ring's arc ``r = b``, ``n_outer`` along the outer ring's (different counts:
    non-matching interface meshes). Unstructured triangles of about the size of the ring's interface
    elements (the other arcs and the radial sides divided uniformly at that size); geometry of ``order``
    (2: 6-node triangles whose boundary edges follow the circles at their three nodes).
    Facets: ``inner_free`` (r = a), ``inner_surface`` and ``outer_surface`` (r = b of each ring), ``loaded``
    (r = c), ``x0_inner``, ``y0_inner``, ``x0_outer``, ``y0_outer`` (the symmetry lines of each ring).
    Collective; initialises and finalises gmsh on every rank."""
    _positive(a=a, b=b, c=c)
    if not a < b < c:
        raise ValueError(f"radii must satisfy a < b < c, got a={a!r}, b={b!r}, c={c!r}")
    for name, n in (("n_inner", n_inner), ("n_outer", n_outer)):
        if int(n) != n or n < 2:
            raise ValueError(f"{name} must be an integer >= 2, got {n!r}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")

    def build() -> None:
        gmsh.model.add("rings")
        gmsh.option.setNumber("Geometry.AutoCoherence", 0)  # the rings touch: keep their points apart
        geo = gmsh.model.geo
        centre = geo.addPoint(0.0, 0.0, 0.0)
        groups = {k: [] for k in _FACETS}
        surfaces = []
        quarter = 0.5 * math.pi
        for r0, r1, n, inner in ((a, b, int(n_inner), True), (b, c, int(n_outer), False)):
            h = quarter * b / n  # element size of this ring's interface arc
            p0x, p1x, p1y, p0y = (geo.addPoint(*xy, 0.0) for xy in ((r0, 0), (r1, 0), (0, r1), (0, r0)))
            bottom, outer_arc = geo.addLine(p0x, p1x), geo.addCircleArc(p1x, centre, p1y)
            side, inner_arc = geo.addLine(p1y, p0y), geo.addCircleArc(p0y, centre, p0x)
            surfaces.append(geo.addPlaneSurface([geo.addCurveLoop([bottom, outer_arc, side, inner_arc])]))
            divisions = {bottom: (r1 - r0) / h, side: (r1 - r0) / h, outer_arc: quarter * r1 / h,
                         inner_arc: quarter * r0 / h}
            divisions[outer_arc if inner else inner_arc] = n  # the interface arc: exactly n elements
            for curve, m in divisions.items():
                geo.mesh.setTransfiniteCurve(curve, max(int(round(m)), 1) + 1)
            groups[RINGS_Y0_INNER if inner else RINGS_Y0_OUTER].append(bottom)
            groups[RINGS_X0_INNER if inner else RINGS_X0_OUTER].append(side)
            if inner:
                groups[RINGS_INNER_FREE].append(inner_arc)
                groups[RINGS_INNER_SURFACE].append(outer_arc)
            else:
                groups[RINGS_OUTER_SURFACE].append(inner_arc)
                groups[RINGS_LOADED].append(outer_arc)
        geo.synchronize()
        for tag, curves in groups.items():
            _physical(1, curves, _FACETS[tag], tag)
        _physical(2, [surfaces[0]], "inner_ring", INNER_RING)
        _physical(2, [surfaces[1]], "outer_ring", OUTER_RING)
        gmsh.option.setNumber("Mesh.Algorithm", 6)  # frontal-Delaunay: near-equilateral triangles
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(order)

    mesh, cell_tags, facet_tags = _from_gmsh(comm, build, "the concentric rings")
    mesh.name = "concentric_rings"
    return mesh, cell_tags, facet_tags
