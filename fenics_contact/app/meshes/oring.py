"""The cross-section of an O-ring cord (the ``oring`` scene): gmsh, a disk."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from mpi4py import MPI

from .gmshutil import _from_gmsh, _load_geo, _positive, geo_path, gmsh

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

__all__ = ["cord_section"]


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
