"""The cross-section of an O-ring cord (the ``oring`` scene): gmsh, a disk; alone, or in a meshed gland."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from mpi4py import MPI

from .gmshutil import _from_gmsh, _load_geo, _positive, geo_path, gmsh

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

__all__ = ["cord_section", "gland_section"]


def cord_section(comm: MPI.Comm, d: float, center: tuple[float, float], h: float,
                 alpha: float) -> tuple[Mesh, NamedTags, NamedTags]:
    """The disk of diameter ``d`` centred at ``center``: triangles of size ``h``; the points at ``-90 +- alpha``
    degrees from the ``+x`` axis are vertices (the ends of the pressurised arc). Cells ``cord``, facets ``surface``
    (the circle). The geometry: ``geo/oring.geo``. Collective; initialises and finalises gmsh on every rank."""
    _positive(d=d, h=h)
    if not 0.0 < alpha < 90.0:
        raise ValueError(f"alpha must be in (0, 90) degrees, got {alpha!r}")
    path = geo_path("oring")  # a missing source: a clear error on every rank

    def build() -> None:
        gmsh.model.add("oring")
        _load_geo(path, h=h / d, alpha=float(alpha))
        gmsh.model.mesh.generate(2)

    mesh, cells, facets = _from_gmsh(comm, build, "the O-ring cord", scale=d)
    mesh.geometry.x[:, :2] += np.asarray(center, dtype=float)
    mesh.name = "cord_section"
    return mesh, cells, facets


def gland_section(comm: MPI.Comm, d: float, center: tuple[float, float], h: float, alpha: float, w: float,
                  land_x: float, thickness: float | None = None,
                  h_housing: float | None = None) -> tuple[Mesh, NamedTags, NamedTags]:
    """The cord of :func:`cord_section` in a meshed groove body (its bottom at ``center[0] - d/2``, side walls at
    ``z = +-w/2``, lands at ``r = land_x`` reaching ``d/2`` beyond the side walls, ``thickness`` thick below the
    bottom, default ``d/2``); the two share no node. Triangles of size ``h`` on the cord and the walls near it,
    ``h_housing`` (default ``4 h``, at most ``d/4``) far from it. Cells ``cord``, ``groove``; facets ``surface``
    (the cord's circle), ``bottom_wall``, ``upstream_wall`` (``z = -w/2``), ``side_wall`` (``z = w/2``),
    ``upstream_land`` and ``side_land`` (the lands beside them), ``groove_fixed`` (the groove body's face away from
    the cord), ``housing_ends``. The geometry: ``geo/gland.geo``. Collective; initialises and finalises gmsh on every
    rank."""
    thickness = 0.5 * d if thickness is None else thickness
    h_housing = min(4 * h, 0.25 * d) if h_housing is None else h_housing
    _positive(d=d, h=h, w=w, thickness=thickness, h_housing=h_housing)
    if not 0.0 < alpha < 90.0:
        raise ValueError(f"alpha must be in (0, 90) degrees, got {alpha!r}")
    if w <= d:
        raise ValueError(f"w must be above d = {d:g} (the cord fits the groove), got {w!r}")
    xl = (land_x - center[0]) / d
    if not -0.5 < xl < 0.5:
        raise ValueError(f"land_x must be between the groove bottom {center[0] - 0.5 * d:g} and the cord's top "
                         f"{center[0] + 0.5 * d:g}, got {land_x!r}")
    path = geo_path("gland")

    def build() -> None:
        gmsh.model.add("gland")
        _load_geo(path, h=h / d, hh=max(h_housing, h) / d, alpha=float(alpha), w=w / d, xl=xl,
                  b=thickness / d, land=0.5)
        gmsh.model.mesh.generate(2)

    mesh, cells, facets = _from_gmsh(comm, build, "the O-ring in its gland", scale=d)
    mesh.geometry.x[:, :2] += np.asarray(center, dtype=float)
    mesh.name = "gland_section"
    return mesh, cells, facets
