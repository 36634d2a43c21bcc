"""Structured meshes: grid triangles and tetrahedra, layer grading, and the tagging every structured builder does
(cells by body, exterior facets with their midpoints and body), used by the meshes of two bodies without a shared
node (``ironing``, ``mindlin``, ``wedges``, the stacked blocks) and of one body (``tube``, ``horseshoe``). Collective
where a mesh is made."""
from __future__ import annotations

from typing import Callable, Mapping

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...domain import NamedTags

__all__ = ["grid_triangles", "kuhn_tetrahedra", "layer_fractions", "grid", "two_bodies", "exterior_facets",
           "facet_tags"]


def grid_triangles(idx: np.ndarray) -> np.ndarray:
    """The triangles of the structured grid of node numbers ``idx`` (shape (n, m)): each quad ``(i, j)`` split
    along its diagonal ``(i, j)``-``(i + 1, j + 1)``; first all the lower triangles, then all the upper ones."""
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def kuhn_tetrahedra(idx: np.ndarray) -> np.ndarray:
    """The 6 tetrahedra of each hexahedron of the structured grid of node numbers ``idx`` (shape (l, m, n)),
    along its main diagonal (Kuhn's subdivision: conforming across faces), shape (l - 1, m - 1, n - 1, 6, 4)."""
    shape = [s - 1 for s in idx.shape]
    corner = {(i, j, k): idx[i:i + shape[0], j:j + shape[1], k:k + shape[2]]
              for i in (0, 1) for j in (0, 1) for k in (0, 1)}
    tets = []
    for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
        p, path = [0, 0, 0], [corner[(0, 0, 0)]]
        for ax in perm:
            p[ax] = 1
            path.append(corner[tuple(p)])
        tets.append(np.stack(path, -1))
    return np.stack(tets, -2)


def layer_fractions(length: float, h: float, n: int) -> np.ndarray:
    """Fractions ``(k / n)^p``, ``k = 0..n``, of ``n`` layers over ``length`` graded so that the first one is
    about ``h`` thick (``p = log(length / h) / log(n)``, at least 1: uniform when ``n h >= length``)."""
    p = max(1.0, np.log(length / h) / np.log(n))
    return (np.arange(n + 1) / n) ** p


def grid(bottom: np.ndarray, top: np.ndarray, s: np.ndarray, offset: int) -> tuple[np.ndarray, np.ndarray]:
    """Nodes between the curves ``bottom`` and ``top`` (same number of points, joined column by column) at the
    fractions ``s`` (0 at the bottom), and the triangles of the structured grid (global numbers from ``offset``)."""
    x = bottom[:, None, :] + (top - bottom)[:, None, :] * s[None, :, None]
    idx = np.arange(x.shape[0] * x.shape[1]).reshape(x.shape[:2]) + offset
    return x.reshape(-1, 2), grid_triangles(idx)


def two_bodies(comm: MPI.Comm, x: np.ndarray, cells: np.ndarray, name: str, second: Callable[[np.ndarray], np.ndarray],
               names: tuple[str, str], cell_names: Mapping[str, int]
               ) -> tuple[dmesh.Mesh, NamedTags, np.ndarray, np.ndarray, np.ndarray]:
    """The triangle mesh ``name`` of the nodes ``x`` and ``cells`` held on rank 0 (distributed), its cells tagged
    ``names[1]`` where ``second(midpoints)`` is true, else ``names[0]`` (values from ``cell_names``). Returns the
    mesh, the cell tags, the exterior facets (local indices), their midpoints and whether each is on the second
    body. Collective."""
    from ...compat import create_mesh

    if comm.rank != 0:
        x, cells = np.zeros((0, 2)), np.zeros((0, 3), np.int64)
    msh = create_mesh(comm, cells, x, "triangle")
    msh.name = name
    tdim, fdim = 2, 1
    msh.topology.create_connectivity(tdim, 0)
    ncell = msh.topology.index_map(tdim).size_local + msh.topology.index_map(tdim).num_ghosts
    body = second(dmesh.compute_midpoints(msh, tdim, np.arange(ncell, dtype=np.int32)))
    cell_tags = dmesh.meshtags(msh, tdim, np.arange(ncell, dtype=np.int32),
                               np.where(body, cell_names[names[1]], cell_names[names[0]]).astype(np.int32))
    msh.topology.create_connectivity(fdim, tdim)
    facets = dmesh.exterior_facet_indices(msh.topology)
    f2c = msh.topology.connectivity(fdim, tdim)
    on_second = np.array([body[f2c.links(f)[0]] for f in facets], dtype=bool)
    return msh, NamedTags(cell_tags, cell_names), facets, dmesh.compute_midpoints(msh, fdim, facets), on_second


def exterior_facets(msh: dmesh.Mesh) -> tuple[np.ndarray, np.ndarray]:
    """The exterior facets of ``msh`` (local indices) and their midpoints (shape (n, 3))."""
    fdim = msh.topology.dim - 1
    msh.topology.create_connectivity(fdim, msh.topology.dim)
    facets = dmesh.exterior_facet_indices(msh.topology)
    return facets, dmesh.compute_midpoints(msh, fdim, facets)


def facet_tags(msh: dmesh.Mesh, facets: np.ndarray, values: np.ndarray, names: Mapping[str, int]) -> NamedTags:
    """The facet tags ``facet_tags``: ``values`` on ``facets``, those with value 0 left out."""
    keep = values > 0
    tags = dmesh.meshtags(msh, msh.topology.dim - 1, facets[keep].astype(np.int32), values[keep])
    tags.name = "facet_tags"
    return NamedTags(tags, names)
