"""Rectangles with tagged sides (dolfinx built-in meshes)."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

from ...compat import cell_partitioner
from ...domain import NamedTags, check_tags, tag_boundary

__all__ = ["rectangle", "tag_boundary", "check_tags"]



def rectangle(
    comm: MPI.Comm,
    width: float,
    height: float,
    nx: int,
    ny: int,
    quadrilateral: bool = False,
) -> tuple[Mesh, None, NamedTags]:
    """Rectangle [0, width] x [0, height] with nx x ny cells (triangles or quadrilaterals).

    Facets: ``bottom`` (y = 0), ``right`` (x = width), ``top`` (y = height), ``left`` (x = 0).

    Returns:
        ``(mesh, None, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    cell_type = dmesh.CellType.quadrilateral if quadrilateral else dmesh.CellType.triangle
    msh = dmesh.create_rectangle(
        comm, [np.array([0.0, 0.0]), np.array([width, height])], [nx, ny], cell_type,
        partitioner=cell_partitioner())
    tol = 1e-10 * max(width, height)
    sides = (("bottom", lambda x: np.abs(x[1]) < tol), ("right", lambda x: np.abs(x[0] - width) < tol),
             ("top", lambda x: np.abs(x[1] - height) < tol), ("left", lambda x: np.abs(x[0]) < tol))
    return msh, None, tag_boundary(msh, sides)


