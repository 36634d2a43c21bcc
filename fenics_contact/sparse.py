"""Parallel PETSc AIJ matrices from coordinate entries, preallocated from the entries themselves.

A matrix whose rows span a whole space but whose entries sit on a contact surface (the two-body mirror
operator ``I``, the segment and collocated tangents) gets each row's exact count, not a fixed count per row:
a fixed count is allocated for every row, a few hundred MB at 1e6 dofs, and a count too small makes PETSc
reallocate while inserting (it did, for 3D segment pairs: 90 % of the Jacobian's time).
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["aij_matrix"]


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
