"""One MUMPS factorization for both the dense Schur complement onto a set of dofs and the solves with the rest.

:class:`SchurFactor` (MUMPS's ICNTL(19)): the Schur complement of the condensed method (:mod:`.operator`) and
every solve with the block it eliminates. The PETSc calls petsc4py 3.18 does not wrap go through
:func:`~fenics_contact.compat.petsc_library`.
"""
from __future__ import annotations

import ctypes

import numpy as np
from petsc4py import PETSc

from ..compat import check_petsc, petsc_library

__all__ = ["SchurFactor"]


class SchurFactor:
    """One MUMPS ``LDL^T`` factorization of the symmetric matrix ``A`` that eliminates every dof but the global
    ``rows`` (ICNTL(19)): :attr:`S`, the dense Schur complement ``A_cc - A_ci A_ii^-1 A_ic`` (rows and columns in
    the order of ``rows``, the same on every process), and :meth:`solve` with the eliminated block ``A_ii`` (the
    same factorization, ICNTL(26) = 0): about the cost of one factorization for both. ``A_ii`` must be regular;
    ``S`` may be singular (it is never factored). PETSc does not hand out MUMPS's distributed Schur complement:
    on more than one process the matrix is gathered on rank 0 (its ``nnz`` entries once; a 2D stiffness of 1e5
    dofs is ~25 MB), factored there, ``S`` broadcast, and the right-hand sides of :meth:`solve` gathered there.
    ``MatFactorSetSchurIS`` and ``MatFactorCreateSchurComplement`` are called in the PETSc library that petsc4py
    has loaded (petsc4py 3.18 does not wrap them). Collective; :meth:`destroy` it."""

    def __init__(self, A: PETSc.Mat, rows: np.ndarray):
        comm = A.getComm()
        self._local = None  # the gathered matrix (more than one process), alive as long as its factorization
        if comm.getSize() == 1:
            local = A
        else:
            n = A.getSize()[0] if comm.getRank() == 0 else 0
            whole = PETSc.IS().createStride(n, 0, 1, comm=PETSc.COMM_SELF)
            (local,) = A.createSubMatrices(whole, whole)  # collective: the whole matrix on rank 0, nothing elsewhere
            whole.destroy()
            self._local = local
        self._pc, S = (_serial_factor(local, np.asarray(rows)) if comm.getRank() == 0 else (None, None))
        self.S = comm.tompi4py().bcast(S, root=0) if comm.getSize() > 1 else S
        self._x = A.createVecLeft()
        self._scatter, self._b0 = PETSc.Scatter.toZero(self._x)  # the whole vector on rank 0
        self._x0 = self._b0.duplicate()

    def solve(self, b: PETSc.Vec, x: PETSc.Vec) -> None:
        """``x_i = A_ii^-1 b_i`` on the eliminated dofs, ``x_c = 0`` on ``rows`` (``b_c`` is not read);
        ``b`` and ``x`` are distributed as ``A``. Collective."""
        forward, reverse = PETSc.ScatterMode.FORWARD, PETSc.ScatterMode.REVERSE
        self._scatter.scatter(b, self._b0, PETSc.InsertMode.INSERT_VALUES, forward)
        if self._pc is not None:
            self._pc.apply(self._b0, self._x0)
        self._scatter.scatter(self._x0, x, PETSc.InsertMode.INSERT_VALUES, reverse)

    def destroy(self) -> None:
        """Free the factorization and the work vectors. Collective."""
        for obj in (self._pc, self._local, self._scatter, self._b0, self._x0, self._x):
            if obj is not None:
                obj.destroy()
        self._pc = self._local = None


def _serial_factor(A: PETSc.Mat, rows: np.ndarray):
    """:class:`SchurFactor`'s factorization of a matrix on one process: the PC and ``S``."""
    lib = petsc_library()
    n = len(rows)
    pc = PETSc.PC().create(PETSc.COMM_SELF)
    pc.setType("cholesky")  # LDL^T of the symmetric matrix (MUMPS SYM = 2): half LU's work
    pc.setFactorSolverType("mumps")
    pc.setOperators(A)
    pc.setFactorSetUpSolverType()  # the factor matrix exists from here on, before its factorization
    if not n:  # nothing to condense onto (no contact dof): a plain factorization
        pc.setUp()
        return pc, np.zeros((0, 0))
    index = PETSc.IS().createGeneral(np.asarray(rows, dtype=PETSc.IntType), comm=PETSc.COMM_SELF)
    S, status = ctypes.c_void_p(), ctypes.c_int()
    data = ctypes.POINTER(ctypes.c_double)()
    try:
        F = pc.getFactorMatrix()
        check_petsc(lib.MatFactorSetSchurIS(ctypes.c_void_p(F.handle), ctypes.c_void_p(index.handle)),
               "MatFactorSetSchurIS")
        pc.setUp()
        check_petsc(lib.MatFactorCreateSchurComplement(ctypes.c_void_p(F.handle), ctypes.byref(S),
                                                  ctypes.byref(status)), "MatFactorCreateSchurComplement")
        check_petsc(lib.MatDenseGetArrayRead(S, ctypes.byref(data)), "MatDenseGetArrayRead")
        out = np.ctypeslib.as_array(data, shape=(n * n,)).reshape(n, n, order="F").copy()
        check_petsc(lib.MatDenseRestoreArrayRead(S, ctypes.byref(data)), "MatDenseRestoreArrayRead")
        F.setMumpsIcntl(26, 0)  # solves: the eliminated block alone, zero on the Schur rows
    except BaseException:
        pc.destroy()
        raise
    finally:
        if S.value:
            lib.MatDestroy(ctypes.byref(S))
        index.destroy()
    return pc, out
