"""Rigid-body modes as the near-nullspace of algebraic multigrid: of the whole mesh, or one set per body.

A mesh may hold several bodies (connected components of its cells: two-body
contact meshes both bodies in one mesh, without shared vertices). The
penalty or multiplier coupling ties the bodies only through the contact zone,
so each body's own rigid motion is nearly free of energy, and per-body modes
(3 per body in 2D, 6 in 3D, each zero on the other bodies) are the exact
near-nullspace. Measured on the 3D two-body sphere-on-block (21,237 dofs,
GMRES + GAMG, ``scripts/gamg_bodies.py``): 78 Krylov iterations per Newton
step against 100 with the whole mesh's 6 modes, but 1.4 x the time per
Newton iteration and 1.5 x the peak memory (GAMG gives every aggregate a
coarse dof per vector, also for the vectors that vanish on it: 12 coarse dofs
per aggregate, 4 x the coarse operators' entries; at 1.2e5 dofs a serial
run peaked at 3.6 GB, the union's at 1.05 GB earlier). So the solver sets the whole mesh's modes; ``per_body`` is
here for the measurement and for preconditioners that drop vanishing vectors.

Bodies are found in parallel: connected components of the local cells
(``scipy.sparse.csgraph``), merged across ranks through the shared vertices
(their global numbers), numbered in the lexicographic order of their lowest
vertex (coordinates): the same on every rank whatever the partition. Collective.
"""
from __future__ import annotations

import numpy as np
from petsc4py import PETSc
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .compat import cell_dofs, entities_to_geometry

__all__ = ["cell_bodies", "rigid_body_modes"]


def cell_bodies(mesh) -> tuple[np.ndarray, int]:
    """The body of each local cell (owned and ghost): ``(labels, number of bodies)``; a body is a connected
    component of the mesh (cells joined through shared vertices). Collective."""
    comm = mesh.comm
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim, 0)
    mesh.topology.create_connectivity(0, tdim)  # the vertices' geometry nodes (dolfinx 0.9 wants it)
    c2v = mesh.topology.connectivity(tdim, 0)
    cmap, vmap = mesh.topology.index_map(tdim), mesh.topology.index_map(0)
    n_cells = cmap.size_local + cmap.num_ghosts
    n_vert = vmap.size_local + vmap.num_ghosts
    offsets, verts = np.asarray(c2v.offsets), np.asarray(c2v.array)
    cell_of = np.repeat(np.arange(n_cells), np.diff(offsets)[:n_cells])
    verts = verts[: offsets[n_cells]]
    # Local components of the bipartite cell-vertex graph (cells 0..n_cells-1, vertices after them).
    graph = coo_matrix((np.ones(len(verts)), (cell_of, n_cells + verts)), shape=(n_cells + n_vert,) * 2)
    n_local, label = connected_components(graph, directed=False)
    vlabel = label[n_cells:]
    gv = np.asarray(vmap.local_to_global(np.arange(n_vert, dtype=np.int32)), dtype=np.int64)
    # Each local component's lowest vertex (lexicographic in x, y, z): the bodies' partition-independent order.
    gdim = mesh.geometry.dim
    xv = mesh.geometry.x[entities_to_geometry(mesh, 0, np.arange(n_vert, dtype=np.int32)).ravel(), :gdim]
    first_of = np.lexsort((*xv.T[::-1], vlabel))
    first_of = first_of[np.r_[True, vlabel[first_of][1:] != vlabel[first_of][:-1]]]
    low = np.zeros((n_local, gdim))
    low[vlabel[first_of]] = xv[first_of]
    # Ghost vertices link a local component to the owner's component of the same vertex.
    ghosts = np.arange(vmap.size_local, n_vert)
    asked = comm.allgather(gv[ghosts])
    owned_lo = vmap.local_range[0]
    answers = []  # for each rank, the owner's component (rank, component) of each of its ghost vertices
    for g in asked:
        mine = (g >= owned_lo) & (g < owned_lo + vmap.size_local)
        answers.append((np.flatnonzero(mine), vlabel[(g[mine] - owned_lo).astype(np.int64)]))
    replies = comm.alltoall(answers)  # replies[r]: (indices into my ghosts, rank r's component of each)
    offsets_c = np.concatenate([[0], np.cumsum(comm.allgather(n_local))])
    rows, cols = [], []
    for r, (idx, comp) in enumerate(replies):
        rows.append(offsets_c[comm.rank] + vlabel[ghosts[idx]])
        cols.append(offsets_c[r] + comp)
    edges = comm.allgather((np.concatenate(rows).astype(np.int64), np.concatenate(cols).astype(np.int64)))
    lows = np.concatenate(comm.allgather(low)).reshape(-1, gdim)
    n_all = int(offsets_c[-1])
    i = np.concatenate([e[0] for e in edges])
    j = np.concatenate([e[1] for e in edges])
    n_bodies, body = connected_components(coo_matrix((np.ones(len(i)), (i, j)), shape=(n_all, n_all)),
                                          directed=False)
    # Number the bodies by their lowest vertex (partition independent).
    order = np.lexsort((*lows.T[::-1], body))
    heads = order[np.r_[True, body[order][1:] != body[order][:-1]]]  # each body's lowest component
    rank_of = np.empty(n_bodies, np.int64)
    rank_of[body[heads[np.lexsort(lows[heads].T[::-1])]]] = np.arange(n_bodies)
    mine = rank_of[body[offsets_c[comm.rank]: offsets_c[comm.rank + 1]]]
    return mine[label[:n_cells]], n_bodies


def rigid_body_modes(V, per_body: bool = False) -> PETSc.NullSpace:
    """The rigid-body modes of the vector space ``V`` (3 in 2D, 6 in 3D; rotations about the origin),
    orthonormalised, as a PETSc near-nullspace for algebraic multigrid: one set for the whole mesh, or
    (``per_body``) one set per body of the mesh, each zero off its body (:func:`cell_bodies`). Collective."""
    comm = V.mesh.comm
    gdim = V.mesh.geometry.dim
    bs = V.dofmap.index_map_bs
    x = V.tabulate_dof_coordinates()[:, :gdim]
    n_local = V.dofmap.index_map.size_local
    n_nodes = len(x)
    if per_body:
        labels, n_bodies = cell_bodies(V.mesh)
        node_body = np.full(n_nodes, -1, np.int64)
        dofs = cell_dofs(V)
        node_body[dofs.ravel()] = np.repeat(labels[: len(dofs)], dofs.shape[1])  # a node's cells share its body
    else:
        node_body, n_bodies = np.zeros(n_nodes, np.int64), 1
    rotations = [(0, 1)] if gdim == 2 else [(0, 1), (1, 2), (2, 0)]
    vecs = []
    for b in range(n_bodies):
        on = (node_body == b)[:n_local]
        modes = np.zeros((gdim + len(rotations), n_local, bs))
        for i in range(gdim):  # translations
            modes[i, on, i] = 1.0
        for k, (i, j) in enumerate(rotations):  # rotation in the (i, j) plane
            modes[gdim + k, on, i] = -x[:n_local][on, j]
            modes[gdim + k, on, j] = x[:n_local][on, i]
        for m in modes:  # Gram-Schmidt on the owned entries
            v = PETSc.Vec().createWithArray(m.ravel().copy(), comm=comm)
            for w in vecs:
                v.axpy(-v.dot(w), w)
            v.normalize()
            vecs.append(v)
    return PETSc.NullSpace().create(vectors=vecs, comm=comm)

