"""Matrices from coordinate entries (the two-body mirror operator, the segment and collocated tangents): the
entries every rank gives, summed or inserted, in a matrix preallocated from them (PETSc never reallocates), its
rows sized by its own entries rather than a fixed count per row."""
import numpy as np
import pytest
from mpi4py import MPI
from petsc4py import PETSc

from fenics_contact.sparse import aij_matrix


def _dense(A: PETSc.Mat) -> np.ndarray:
    """The whole matrix on every rank."""
    lo, hi = A.getOwnershipRange()
    rows = np.zeros((A.getSize()[0], A.getSize()[1]))
    for i in range(lo, hi):
        cols, vals = A.getRow(i)
        rows[i, cols] = vals
    return A.comm.tompi4py().allreduce(rows)


@pytest.mark.parametrize("mode", ["add", "insert"])
def test_entries_of_every_rank(mode):
    comm = MPI.COMM_WORLD
    n_local, m_local = 7 + comm.rank, 5 + 2 * comm.rank  # rectangular, uneven row and column ownership
    N, M = comm.allreduce(n_local), comm.allreduce(m_local)
    rng = np.random.default_rng(3)  # the same on every rank: each rank takes a share, any row
    rows, cols = rng.integers(0, N, 60), rng.integers(0, M, 60)
    key = np.unique(rows * M + cols)
    rows, cols = key // M, key % M
    vals = 1.0 + rng.random(len(rows))
    # every rank gives every entry, in its own order (as ghost slave facets do): summed, or kept once
    addv = PETSc.InsertMode.ADD_VALUES if mode == "add" else PETSc.InsertMode.INSERT_VALUES
    order = rng.permutation(len(rows)) if comm.rank else np.arange(len(rows))
    A = aij_matrix(comm, ((n_local, N), (m_local, M)), rows[order], cols[order], vals[order], addv=addv)
    expected = np.zeros((N, M))
    expected[rows, cols] = vals * (comm.size if mode == "add" else 1)
    assert np.array_equal(_dense(A), expected)
    info = A.getInfo()  # summed over ranks
    assert info["mallocs"] == 0  # the preallocation held every entry
    # rows without entries cost nothing: allocated at most the entries given on all ranks
    assert info["nz_allocated"] <= comm.size * len(rows)
    A.destroy()


def test_no_entries():
    comm = MPI.COMM_WORLD
    A = aij_matrix(comm, ((4, 4 * comm.size), (3, 3 * comm.size)), np.zeros(0), np.zeros(0), np.zeros(0))
    assert A.getSize() == (4 * comm.size, 3 * comm.size) and A.norm() == 0.0
    A.destroy()


def test_entries_given_only_by_other_ranks():
    """Each rank gives only entries of rows another rank owns (as a slave facet's rows owned elsewhere): the owner
    splits them into its diagonal and off-diagonal blocks by its own column range, not the giver's (the giver's
    range undercounted the owner's diagonal block: a reallocation, an error in a two-body Jacobian on 2 ranks)."""
    comm = MPI.COMM_WORLD
    n_local, m_local = 6 + comm.rank, 4 + 3 * comm.rank
    N, M = comm.allreduce(n_local), comm.allreduce(m_local)
    first = comm.exscan(n_local) or 0
    target = (comm.rank + 1) % comm.size  # the rank whose rows this rank fills
    starts = np.concatenate([[0], np.cumsum(comm.allgather(n_local))])
    rng = np.random.default_rng(11 + comm.rank)
    rows = np.repeat(np.arange(starts[target], starts[target + 1]), M)
    cols = np.tile(np.arange(M), starts[target + 1] - starts[target])  # every column: both blocks full
    vals = 1.0 + rng.random(len(rows))
    A = aij_matrix(comm, ((n_local, N), (m_local, M)), rows, cols, vals)
    mine = A.getValues(range(first, first + n_local), range(M))
    given = comm.allgather((rows, cols, vals))
    dense = np.zeros((N, M))
    for r, c, v in given:
        np.add.at(dense, (r, c), v)
    assert np.allclose(mine, dense[first:first + n_local])
    assert A.getInfo()["mallocs"] == 0
    A.destroy()


@pytest.mark.skipif(MPI.COMM_WORLD.size < 2, reason="needs a rank without rows beside ranks with rows")
def test_a_rank_without_rows():
    """The last rank owns no row and no column (a partition that puts every body on other ranks, as the two-body
    tests' ``by_body`` on 3 ranks): the same matrix, assembled on every rank. PETSc forbids new nonzeros only on
    the ranks whose count array is not empty; MatAssemblyEnd then took another collective on the empty rank (an
    all-reduce against the others' all-gather: a deadlock)."""
    comm = MPI.COMM_WORLD
    empty = comm.rank == comm.size - 1
    n_local, m_local = (0, 0) if empty else (5, 4)
    N, M = comm.allreduce(n_local), comm.allreduce(m_local)
    rows = np.repeat(np.arange(N), M)  # every rank gives the whole matrix, the empty one included
    cols = np.tile(np.arange(M), N)
    vals = 1.0 + rows + 0.5 * cols
    A = aij_matrix(comm, ((n_local, N), (m_local, M)), rows, cols, vals)
    assert np.array_equal(_dense(A), comm.size * (1.0 + np.arange(N)[:, None] + 0.5 * np.arange(M)[None, :]))
    assert A.getInfo()["mallocs"] == 0
    A.destroy()
