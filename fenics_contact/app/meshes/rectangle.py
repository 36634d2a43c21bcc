"""Rectangles with tagged sides (dolfinx built-in meshes)."""
from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

from ...compat import cell_partitioner
from ...domain import NamedTags, check_tags

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


def tag_boundary(msh: Mesh, sides: Sequence[tuple[str, Callable[[np.ndarray], np.ndarray]]]) -> NamedTags:
    """Named tags of the boundary facets: ``(name, where)`` pairs, ``where(x)`` true on the facet's vertices
    (``x`` of shape (3, n)); a facet matched by several pairs is tagged once per pair."""
    fdim = msh.topology.dim - 1
    indices, values = [], []
    names = {name: i + 1 for i, (name, _) in enumerate(sides)}
    for name, where in sides:
        tag = names[name]
        facets = dmesh.locate_entities_boundary(msh, fdim, where)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    index = np.concatenate(indices).astype(np.int32)
    order = np.argsort(index)
    facet_tags = dmesh.meshtags(msh, fdim, index[order], np.concatenate(values)[order])
    facet_tags.name = "facet_tags"
    return NamedTags(facet_tags, names)


