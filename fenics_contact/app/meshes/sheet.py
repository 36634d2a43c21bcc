"""Sheet wrapped over a cylinder (structured quadrilaterals, optionally 9-node) for the sheet scene."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

from .gmshutil import _from_gmsh, _load_geo, _positive, geo_path, gmsh

__all__ = ["sheet_over_cylinder"]


def sheet_over_cylinder(comm: MPI.Comm, R: float = 3.0, thickness: float = 1.0, leg: float = 2.0,
                        n_arc: int = 24, n_thick: int = 2, n_leg: int = 8, order: int = 2,
                        cylinder: tuple[float, int, int] | None = None) -> tuple[Mesh, NamedTags, NamedTags]:
    """Right half of a sheet wrapped over the top of a cylinder of radius ``R`` (centre at the origin).

    A quarter annulus ``R <= r <= R + thickness``, ``0 <= theta <= 90 deg`` (``theta`` from the x axis),
    continued by a vertical leg ``R <= x <= R + thickness``, ``-leg <= y <= 0``. Structured
    quadrilaterals: ``n_arc`` along the arc, ``n_leg`` along the leg, ``n_thick`` through the
    thickness; geometry of ``order`` (2: 9-node quadrilaterals whose edges follow the circles
    exactly at their three nodes). Facets: ``contact`` (inner arc and inner side of the leg),
    ``symmetry`` (x = 0), ``end`` (y = -leg); cells ``sheet``.

    ``cylinder = (R_in, n_cyl, n_rad)``: the mesh also holds the right half of the hollow cylinder
    ``R_in <= r <= R`` (cells ``cylinder``), ``n_cyl`` elements along
    each of its two quarter arcs, ``n_rad`` through its wall; facets ``cylinder_surface`` (its outer arc
    ``r = R``), ``cylinder_fixed`` (``r = R_in``), ``symmetry`` (its two segments on ``x = 0``). The two bodies
    touch along ``r = R`` but share no node (``n_cyl != n_arc``: non-matching interface meshes).
    The geometry: ``geo/sheet.geo``. Initialises and finalises gmsh (on every rank).
    """
    _positive(R=R, thickness=thickness, leg=leg)
    for name, value in (("n_arc", n_arc), ("n_thick", n_thick), ("n_leg", n_leg)):
        if int(value) < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if cylinder is not None and not (0 < cylinder[0] < R and int(cylinder[1]) >= 1 and int(cylinder[2]) >= 1):
        raise ValueError(f"cylinder must be (R_in in (0, R), n_cyl >= 1, n_rad >= 1), got {cylinder!r}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    path = geo_path("sheet")  # a missing source: a clear error on every rank

    def build() -> None:
        gmsh.model.add("sheet")
        R_in, n_cyl, n_rad = cylinder if cylinder is not None else (R / 3, 18, 3)
        _load_geo(path, R=1.0, thickness=thickness / R, leg=leg / R, n_arc=int(n_arc), n_thick=int(n_thick),
                  n_leg=int(n_leg), cylinder=int(cylinder is not None), R_in=R_in / R, n_cyl=int(n_cyl),
                  n_rad=int(n_rad))
        gmsh.option.setNumber("Mesh.ElementOrder", 1)  # the geometry order set below, as for the other builders
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(order)

    mesh, cell_tags, facet_tags = _from_gmsh(comm, build, "the sheet", scale=R)
    mesh.name = "sheet"
    return mesh, cell_tags, facet_tags
