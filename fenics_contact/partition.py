"""A partition of a mesh's cells over the ranks that splits the cells at the contact surfaces evenly too.

A graph partitioner balances the cells, and so the bulk's assembly and linear solve, but knows nothing of the
contact: the cells at a small contact patch usually all go to one rank, which then assembles, pairs and searches
the whole contact while the others wait (mindlin3d with friction at 5e5 dofs on 2 ranks: one rank ~20 s idle at
the contact's assemblies in a 220 s solve). :func:`balanced_owners` cuts the cells by planes (recursive
bisection) whose direction is turned, within the plane of the contact cells' two largest spreads, until one
plane splits both the cells and the contact cells in the ratio of the ranks on either side; the mesh is then
distributed again with those owners (:func:`~fenics_contact.compat.model_to_mesh`'s ``owners``).
"""
from __future__ import annotations

import numpy as np

__all__ = ["balanced_owners"]

# Directions tried per cut (over half a turn) before the best bracket is refined by bisection
_ANGLES, _REFINE = 36, 12


def balanced_owners(mesh, facet_tags, values, nparts: int | None = None) -> np.ndarray | None:
    """The rank of each cell of ``mesh`` (by its input index: ``mesh.topology.original_cell_index``) that balances
    the cells and, as far as one plane per cut can, the cells with a facet among ``facet_tags`` of ``values``. On
    rank 0 (None on the other ranks, for one part, or where no cell has such a facet). Collective.

    Args:
        mesh: the mesh, distributed any way.
        facet_tags: its facet tags (dolfinx ``MeshTags``).
        values: the tag values of the contact surfaces.
        nparts: the number of parts (default: the mesh's ranks).

    Returns:
        ``owners`` (int32, one per input cell) on rank 0, else None.
    """
    from dolfinx import mesh as dmesh

    comm = mesh.comm
    nparts = comm.size if nparts is None else nparts
    tdim = mesh.topology.dim
    n_owned = mesh.topology.index_map(tdim).size_local
    mesh.topology.create_connectivity(tdim - 1, tdim)
    f_to_c = mesh.topology.connectivity(tdim - 1, tdim)
    facets = facet_tags.indices[np.isin(facet_tags.values, np.asarray(values))]
    near = np.zeros(n_owned, bool)
    for f in facets:
        cells = f_to_c.links(f)
        near[cells[cells < n_owned]] = True
    X = dmesh.compute_midpoints(mesh, tdim, np.arange(n_owned, dtype=np.int32))
    index = mesh.topology.original_cell_index
    index = np.asarray(index[0] if isinstance(index, list) else index)[:n_owned]
    gathered = comm.gather((index, X, near), root=0)
    if nparts == 1 or comm.rank != 0:
        return None
    index = np.concatenate([g[0] for g in gathered])
    X = np.concatenate([g[1] for g in gathered])
    near = np.concatenate([g[2] for g in gathered])
    if not near.any():
        return None
    owners = np.empty(len(index), np.int32)
    _bisect(X, near, np.arange(len(index)), 0, nparts, owners)
    result = np.empty_like(owners)
    result[index] = owners  # by input index
    return result


def _bisect(X: np.ndarray, near: np.ndarray, ids: np.ndarray, first: int, parts: int, owners: np.ndarray) -> None:
    """Give the cells ``ids`` the ranks ``first, ..., first + parts - 1``: cut in two by the plane of
    :func:`_direction` (``parts // 2`` ranks below it), each side cut again."""
    if parts == 1:
        owners[ids] = first
        return
    below = parts // 2
    k = int(round(len(ids) * below / parts))
    s = X[ids] @ _direction(X[ids], near[ids], below / parts, k)
    order = np.argsort(s, kind="stable")
    _bisect(X, near, ids[order[:k]], first, below, owners)
    _bisect(X, near, ids[order[k:]], first + below, parts - below, owners)


def _direction(X: np.ndarray, near: np.ndarray, fraction: float, k: int) -> np.ndarray:
    """The unit normal of a plane that leaves ``k`` of the cells at ``X`` below it and as close as it can to
    ``fraction`` of the ``near`` ones: turned in the plane of the near cells' two largest spreads (their surface's
    tangents; a half turn changes the sign of the excess, so a root exists where ``fraction`` is 1/2). Without
    near cells: the axis of the cells' largest extent."""
    if k <= 0 or k >= len(X) or not near.any():
        return np.eye(X.shape[1])[np.argmax(np.ptp(X, axis=0))]
    Y = X[near] - X[near].mean(axis=0)
    if len(Y) > 1:
        e = np.linalg.svd(Y, full_matrices=False)[2]
        e1, e2 = e[0], e[1] if len(e) > 1 else np.roll(e[0], 1)
    else:
        e1, e2 = np.eye(X.shape[1])[:2]
    total = near.sum()

    def excess(theta: float) -> float:
        d = np.cos(theta) * e1 + np.sin(theta) * e2
        s = X @ d
        cut = np.partition(s, k - 1)[k - 1]  # the k-th smallest: the cells at or below it go below
        return float(np.count_nonzero(near & (s <= cut))) / total - fraction

    thetas = list(np.linspace(0.0, np.pi, _ANGLES + 1))  # both ends: a half turn apart
    values = [excess(t) for t in thetas]
    for i in range(_ANGLES):  # the first sign change between neighbours, refined by bisection
        a, b, fa = thetas[i], thetas[i + 1], values[i]
        if fa * values[i + 1] > 0:
            continue
        for _ in range(_REFINE):
            m = 0.5 * (a + b)
            fm = excess(m)
            thetas.append(m)
            values.append(fm)
            if fa * fm <= 0:
                b = m
            else:
                a, fa = m, fm
        break
    best = int(np.argmin(np.abs(values)))
    theta = thetas[best]
    return np.cos(theta) * e1 + np.sin(theta) * e2
