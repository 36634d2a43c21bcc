"""Rectangles with tagged sides (dolfinx built-in meshes) and the facet-tag check."""
from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh
    from dolfinx.mesh import MeshTagsMetaClass as MeshTags

from ..compat import cell_partitioner
from .tags import BOTTOM, LEFT, RECT_TOP, RIGHT

__all__ = ["rectangle", "tag_boundary", "check_tags"]


def rectangle(
    comm: MPI.Comm,
    width: float,
    height: float,
    nx: int,
    ny: int,
    quadrilateral: bool = False,
) -> tuple[Mesh, None, MeshTags]:
    """Rectangle [0, width] x [0, height] with nx x ny cells (triangles or quadrilaterals).

    Facet tags: BOTTOM (y = 0), RIGHT (x = width), RECT_TOP (y = height), LEFT (x = 0).

    Returns:
        ``(mesh, None, facet_tags)``.
    """
    cell_type = dmesh.CellType.quadrilateral if quadrilateral else dmesh.CellType.triangle
    msh = dmesh.create_rectangle(
        comm, [np.array([0.0, 0.0]), np.array([width, height])], [nx, ny], cell_type,
        partitioner=cell_partitioner())
    tol = 1e-10 * max(width, height)
    sides = ((BOTTOM, lambda x: np.abs(x[1]) < tol), (RIGHT, lambda x: np.abs(x[0] - width) < tol),
             (RECT_TOP, lambda x: np.abs(x[1] - height) < tol), (LEFT, lambda x: np.abs(x[0]) < tol))
    facet_tags = tag_boundary(msh, sides)
    return msh, None, facet_tags


def tag_boundary(msh: Mesh, sides: Sequence[tuple[int, Callable[[np.ndarray], np.ndarray]]]) -> MeshTags:
    """Facet tags of the boundary facets: ``(tag, where)`` pairs, ``where(x)`` true on the facet's vertices
    (``x`` of shape (3, n)); a facet matched by several pairs is tagged once per pair."""
    fdim = msh.topology.dim - 1
    indices, values = [], []
    for tag, where in sides:
        facets = dmesh.locate_entities_boundary(msh, fdim, where)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    index = np.concatenate(indices).astype(np.int32)
    order = np.argsort(index)
    facet_tags = dmesh.meshtags(msh, fdim, index[order], np.concatenate(values)[order])
    facet_tags.name = "facet_tags"
    return facet_tags


def check_tags(facet_tags: MeshTags, tags: Mapping[str, int],
               comm: MPI.Comm) -> None:
    """Raise ValueError if a tag of ``tags`` (name -> value) marks no facet on any rank."""
    local = np.asarray(facet_tags.values)
    present = sorted(set().union(*comm.allgather(set(np.unique(local).tolist()))))
    for name, value in tags.items():
        if comm.allreduce(int(np.count_nonzero(local == value)), op=MPI.SUM) == 0:
            raise ValueError(f"facet tag {name!r}={value} is absent from the mesh; "
                             f"tags present: {present}")
