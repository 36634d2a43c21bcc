"""Parallel PETSc AIJ matrices preallocated from their own entries: from coordinate entries, and the multipliers'
Jacobian without the zero blocks of dolfinx's pattern (:func:`trimmed_matrix`).

A matrix whose rows span a whole space but whose entries sit on a contact surface (the two-body mirror
operator ``I``, the segment and collocated tangents) gets each row's exact count, not a fixed count per row:
a fixed count is allocated for every row, a few hundred MB at 1e6 dofs, and a count too small makes PETSc
reallocate while inserting (it did, for 3D segment pairs: 90 % of the Jacobian's time).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from .compat import release_free_memory

__all__ = ["KEPT_ATTRIBUTES", "aij_matrix", "trimmed_matrix", "widen"]

# The PETSc attributes a matrix keeps across :func:`widen` (MatAXPY with a new pattern gives it a new header, which
# drops them): kept.KeptJacobian's mark (the kept matrix was added into it last) and kept.BULK_PATTERN (made with the
# bulk's pattern explicit, ContactProblem.create_matrix); widening keeps the pattern.
KEPT_ATTRIBUTES = ("fc_kept_jacobian", "fc_bulk_pattern")


def aij_matrix(comm: MPI.Comm, sizes: tuple[tuple[int, int], tuple[int, int]], rows: np.ndarray, cols: np.ndarray,
               vals: np.ndarray, addv: PETSc.InsertMode = PETSc.InsertMode.ADD_VALUES) -> PETSc.Mat:
    """The assembled AIJ matrix of ``sizes = ((local rows, global rows), (local columns, global columns))``
    with this rank's entries ``vals`` at global ``(rows, cols)`` (each pair at most once per rank; rows of any
    rank). Ranks giving the same entry: summed (``addv`` ADD) or one kept (INSERT, equal values). Each row's
    owner preallocates the sum of every rank's counts for it (an upper bound). Collective."""
    (n_local, n_global), (m_local, m_global) = sizes
    rows, cols = np.asarray(rows, np.int64), np.asarray(cols, np.int64)
    order = np.lexsort((cols, rows))
    rows, cols, vals = rows[order], cols[order], np.asarray(vals, dtype=PETSc.ScalarType)[order]
    # An entry is in its row owner's diagonal block when its column is in the owner's column range (rows of any
    # rank: not this rank's range, which undercounted the owner's diagonal block and made it reallocate).
    row_start = np.concatenate([[0], np.cumsum(comm.allgather(n_local))])
    col_start = np.concatenate([[0], np.cumsum(comm.allgather(m_local))])
    urows, start, count = np.unique(rows, return_index=True, return_counts=True)
    owner = np.searchsorted(row_start, rows, side="right") - 1
    diag = ((cols >= col_start[owner]) & (cols < col_start[owner + 1])).astype(np.int64)
    nd = np.add.reduceat(diag, start) if len(start) else np.zeros(0, np.int64)
    nnz = []
    for c in (nd, count - nd):
        v = PETSc.Vec().createMPI((n_local, n_global), comm=comm)
        v.setValues(urows.astype(PETSc.IntType), c.astype(float), addv=PETSc.InsertMode.ADD_VALUES)
        v.assemble()
        nnz.append(v.array.round().astype(PETSc.IntType))
        v.destroy()
    A = PETSc.Mat().createAIJ(sizes, comm=comm)
    A.setPreallocationNNZ((np.minimum(nnz[0], m_local), np.minimum(nnz[1], m_global - m_local)))
    # PETSc forbids a new nonzero only where the count array is not empty; a rank without rows kept it allowed
    # and took another collective than the others in MatAssemblyEnd (a deadlock): the same option on every rank.
    A.setOption(PETSc.Mat.Option.NEW_NONZERO_ALLOCATION_ERR, True)
    if len(rows):
        indptr = np.append(start, len(rows)).astype(PETSc.IntType)
        A.setValuesIJV(indptr, cols.astype(PETSc.IntType), vals, addv=addv, rowmap=urows.astype(PETSc.IntType))
    A.assemble()
    return A


def trimmed_matrix(W, field: int, keep: Sequence) -> PETSc.Mat:
    """A matrix for the Jacobian of the mixed unknown on ``W`` whose field ``field`` (the displacement) is the
    only one the bodies couple, the other a surface multiplier: the pairs of ``field``'s dofs of every cell, every
    entry of the compiled forms ``keep`` (the contact terms: their cells' whole blocks) and the diagonal, with
    dolfinx's local-to-global map. dolfinx's own pattern couples every pair of a cell's dofs, the multiplier's too:
    4 times the bodies' entries in 3D (P1 x P1 vector), all zero off the contact. Insertions outside the pattern
    (the bodies' zero blocks) are dropped (``MAT_NEW_NONZERO_LOCATIONS`` false: set it again after anything that
    rebuilds the matrix). Collective."""
    import dolfinx.fem.petsc as fem_petsc
    from scipy import sparse

    from .compat import cell_dofs

    comm = W.mesh.comm
    imap = W.dofmap.index_map
    n, N = imap.size_local, imap.size_global  # a mixed space: block size 1
    n_all = n + imap.num_ghosts
    to_global = np.asarray(imap.local_to_global(np.arange(n_all, dtype=np.int32)), np.int64)
    start = int(to_global[0]) if n else 0
    # the cells this rank owns (each cell once over the ranks); rows of any rank: aij_matrix sends them
    dofs = cell_dofs(W.sub(field))[:W.mesh.topology.index_map(W.mesh.topology.dim).size_local]
    # int32 counts: scipy's product drops a sum that wraps to 0 (int8: 256 cells sharing a pair)
    C = sparse.csr_matrix((np.ones(dofs.size, np.int32), dofs.ravel(), np.arange(0, dofs.size + 1, dofs.shape[1])),
                          shape=(len(dofs), n_all))
    pairs = (C.T @ C).tocoo()
    del C, dofs
    rows, cols = [to_global[pairs.row]], [to_global[pairs.col]]
    del pairs
    for form in keep:  # assembled: dolfinx inserts each cell's whole block, zeros too (an unassembled one is empty)
        M = fem_petsc.assemble_matrix(form)
        M.assemble()
        indptr, cc, _ = M.getValuesCSR()
        rows.append(start + np.repeat(np.arange(n, dtype=np.int64), np.diff(indptr)))
        cols.append(np.asarray(cc, np.int64))
        M.destroy()
    rows.append(np.arange(start, start + n, dtype=np.int64))
    cols.append(rows[-1])
    key = np.unique(np.concatenate(rows) * N + np.concatenate(cols))
    del rows, cols
    A = aij_matrix(comm, ((n, N), (n, N)), key // N, key % N, np.zeros(len(key)))
    lgmap = PETSc.LGMap().create(to_global.astype(PETSc.IntType), comm=comm)
    A.setLGMap(lgmap, lgmap)
    A.setOption(PETSc.Mat.Option.NEW_NONZERO_LOCATIONS, False)
    return A


def widen(A: PETSc.Mat, C: PETSc.Mat) -> None:
    """``A += C`` with ``C``'s nonzero pattern joined to ``A``'s (``MatAXPY``, ``DIFFERENT_NONZERO_PATTERN``), ``A``
    keeping its near-nullspace (GAMG's rigid-body modes) and :data:`KEPT_ATTRIBUTES`, which the new header drops.
    Collective."""
    release_free_memory()  # the temporaries' freed pages back to the system before A's copy is allocated
    near = A.getNearNullSpace()
    kept = {name: A.getAttr(name) for name in KEPT_ATTRIBUTES}
    A.axpy(1.0, C, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
    if near is not None and near.handle:
        A.setNearNullSpace(near)
    for name, value in kept.items():
        if value is not None:
            A.setAttr(name, value)
