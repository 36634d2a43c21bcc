"""Two concentric quarter rings in one mesh, not sharing nodes at their common radius (the ``rings`` scene)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

from .gmshutil import _from_gmsh, _load_geo, _positive, geo_path, gmsh

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

__all__ = ["concentric_rings"]


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
    The geometry: ``geo/rings.geo``. Collective; initialises and finalises gmsh on every rank."""
    _positive(a=a, b=b, c=c)
    if not a < b < c:
        raise ValueError(f"radii must satisfy a < b < c, got a={a!r}, b={b!r}, c={c!r}")
    for name, n in (("n_inner", n_inner), ("n_outer", n_outer)):
        if int(n) != n or n < 2:
            raise ValueError(f"{name} must be an integer >= 2, got {n!r}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")

    path = geo_path("rings")  # a missing source: a clear error on every rank

    def build() -> None:
        gmsh.model.add("rings")
        _load_geo(path, a=a / c, b=b / c, c=1.0, n_inner=int(n_inner), n_outer=int(n_outer))
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(order)

    mesh, cell_tags, facet_tags = _from_gmsh(comm, build, "the concentric rings", scale=c)
    mesh.name = "concentric_rings"
    return mesh, cell_tags, facet_tags
