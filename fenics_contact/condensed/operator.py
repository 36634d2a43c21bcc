"""The stiffness condensed onto the contact dofs (Schur complement), the load of a step and the recovery.

``K`` is the stiffness (the problem's Jacobian, constant for linear elasticity). With the Dirichlet rows and
columns of ``K`` replaced by the identity, one MUMPS ``LDL^T`` factorization that eliminates every dof but the
contact dofs ``c`` (:class:`~.schur.SchurFactor`, MUMPS's ICNTL(19)) gives both the dense Schur
complement ``S = K_cc - K_ci K_ii^-1 K_ic`` (``i``: the dofs off the contact, the Dirichlet ones the identity)
and every solve with ``K_ii``, which is regular even when the body floats without its contact (the slab): the
base is clamped. ``S`` is singular for a floating body; nothing here inverts it.

Each load step, the load as the problem has set it at ``t`` (tractions, body forces and Dirichlet values: any
path, not only ``t`` times a load): one solve gives the load mode ``u_0(t)`` (``u_c = 0``, the load ``f(t)``,
the Dirichlet data at ``t``; no solve when the load is a combination of earlier steps', :mod:`.loadmodes`), and
the force the contact dofs need (the contact force on the body) is
``R(u_c) = S u_c + r(t)``, ``r(t) = (K u_0(t) - f(t))_c``. Recovery: one solve with ``K_ii``, ``u_c``
prescribed. ``K`` is re-assembled at a step where a value its form depends on (a Constant, a Function) has
changed, and compared with the condensed one: a stiffness that changes with the load (the vanishing spring of a
force-controlled scene) is condensed again for that step.

Parallel: ``K`` is distributed; PETSc does not hand out MUMPS's distributed Schur complement, so ``K`` is
gathered on rank 0 and factored there (its ``nnz`` entries once), ``S`` (``n_c x n_c``, a few hundred to a few
thousand) is broadcast: every rank holds the same dense ``S`` (``O(n_c^2)`` memory, 8 n_c^2 bytes), and the
right-hand sides of the solves are gathered on rank 0. Cost: one factorization; per step at most one solve for
the load mode, and one for the recovery.
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
from petsc4py import PETSc

from ..compat import bc_dofs, create_vector
from ..form_inputs import input_values, same_everywhere
from .loadmodes import LoadModes
from .schur import SchurFactor

__all__ = ["CondensedStiffness", "CondensedTooLarge", "MAX_CONDENSED", "check_size"]

# The largest condensed system held dense: S, the semismooth Newton's matrix, its inverse and the blocks of the
# Jacobian are n_c x n_c arrays of 8 bytes on every rank (about 7 of them: 2 GB at 6000), and the Newton's
# inverse costs O(n_c^3) (about 20 s at 6000 on one core). Beyond, the method is refused before any work.
MAX_CONDENSED = 6000
DENSE_ARRAYS = 7


class CondensedTooLarge(ValueError):
    """A condensed system larger than :data:`MAX_CONDENSED`; ``n_c`` its contact dofs."""

    def __init__(self, message: str, n_c: int):
        super().__init__(message)
        self.n_c = n_c


def check_size(n_c: int, where: str) -> None:
    """Refuse (:class:`CondensedTooLarge`, one line) a condensed system of more than :data:`MAX_CONDENSED` dofs:
    ``n_c`` the contact dofs (an upper bound is enough), ``where`` what sets them (the contact surface and how to
    have fewer)."""
    if n_c > MAX_CONDENSED:
        gb = DENSE_ARRAYS * 8.0 * n_c**2 / 1e9
        raise CondensedTooLarge(f"method 'coulomb': {where} gives {n_c} contact dofs, more than the {MAX_CONDENSED} "
                                f"its dense condensed system allows (about {gb:.3g} GB per rank); the sparse exact "
                                f"method has no such limit: fc.Friction(fc.make_law('lagrange', c=...), mu=...)", n_c)


class CondensedStiffness:
    """``K`` of a linear-elastic ``problem`` (on ``comm``) and its Dirichlet dofs; after :meth:`condense`, the
    factorization of ``K`` that eliminates all but the contact dofs ``cidx`` (global numbers, the same order on
    every rank) and the dense Schur complement ``S`` onto them.

    Attributes: ``A`` (``K``, no boundary conditions), ``dir_idx`` (this rank's owned Dirichlet dofs, global),
    ``dir_all`` (every rank's, sorted), ``cidx``, ``S`` (symmetrized, the same on every rank), ``diag`` (the mean
    absolute diagonal of ``S``: the scale of the semismooth Newton's ``c``), ``x`` (after :meth:`load`: the load
    mode ``u_0(t)``; the work vector of :meth:`displacement`), ``assemblies`` and ``factorizations`` (of ``K``,
    each with its ``S``, so far)."""

    def __init__(self, problem, comm):
        if not problem.material.linear:
            raise ValueError("method 'coulomb' needs linear elasticity (a constant stiffness to condense), "
                             f"got material {type(problem.material).__name__}")
        self.comm = comm
        V = problem.u.function_space
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        # K (no boundary conditions; linear elasticity: constant unless a load-scaled term such as a vanishing
        # spring changes it, re-checked at every step by changed) and a vector for the load.
        self.A = fem_petsc.assemble_matrix(problem.a)
        self.A.assemble()
        # What K depends on (the values of the Constants and Functions of its form): changed re-assembles K only
        # when one of them has changed (a re-assembly per step costs about a third of a factorization).
        self._u, self._inputs = problem.u, problem.jacobian_inputs()
        self._seen = input_values(self._inputs, self._u)  # None: K depends on u (re-assembled each step)
        self.assemblies, self.factorizations = 1, 0  # of K (each factorization with its S)
        self.modes = LoadModes(comm)  # earlier steps' load modes (their combinations need no solve)
        self._f = create_vector(problem.L)
        lo, hi = self.A.getOwnershipRange()
        # Dirichlet dofs (owned, global) and the Dirichlet condition each belongs to (its value at t, per step).
        self._dirichlet = []
        for d in problem.dirichlet:
            local = bc_dofs(d.bc)
            self._dirichlet.append((d, (local[local < n_owned] + lo).astype(PETSc.IntType)))
        self.dir_idx = np.concatenate([i for _, i in self._dirichlet] + [np.empty(0, PETSc.IntType)])
        self.dir_all = np.unique(np.concatenate(comm.allgather(self.dir_idx))).astype(np.int64)  # every rank's
        self._factor = None

    def condense(self, cidx: np.ndarray) -> None:
        """Factor ``K`` and form ``S`` for the contact dofs ``cidx``."""
        lo, hi = self.A.getOwnershipRange()
        self.cidx = np.asarray(cidx, dtype=PETSc.IntType)
        self._cmine = np.flatnonzero((self.cidx >= lo) & (self.cidx < hi))
        self.x, self._b, self._y = self._f.duplicate(), self._f.duplicate(), self._f.duplicate()
        self.factor()

    def factor(self) -> None:
        """Factor ``K`` with the Dirichlet rows and columns replaced by the identity, eliminating all but the
        contact dofs, and form the dense Schur complement ``S`` (every rank): one factorization serves ``S`` and
        the solves (:class:`~.schur.SchurFactor`)."""
        nc = len(self.cidx)
        self.factorizations += 1
        self.modes.clear()  # the load modes of another stiffness
        if self._factor is not None:
            self._factor.destroy()
        M = self.A.duplicate(copy=True)
        M.zeroRowsColumns(self.dir_idx, diag=1.0)
        self._factor = SchurFactor(M, self.cidx)
        M.destroy()  # the factorization keeps what it needs (on rank 0 its own copy in parallel)
        self.S = 0.5 * (self._factor.S + self._factor.S.T)
        self.diag = float(np.mean(np.abs(np.diag(self.S)))) if nc else 1.0

    def changed(self, problem) -> bool:
        """True (and ``K`` replaced) if ``K`` at the step differs from the condensed one beyond round-off (a
        load-dependent stiffness, e.g. the vanishing spring of a force-controlled scene): the caller then calls
        :meth:`factor` for the step. ``K`` is re-assembled only when a value its form depends on has changed."""
        now = input_values(self._inputs, self._u)
        if same_everywhere(self.comm, now, self._seen):
            return False
        self._seen = now
        self.assemblies += 1
        A = fem_petsc.assemble_matrix(problem.a)
        A.assemble()
        ref = self.A.norm(PETSc.NormType.FROBENIUS)
        A.axpy(-1.0, self.A, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
        changed = A.norm(PETSc.NormType.FROBENIUS) > 1e-13 * ref
        if changed:
            A.axpy(1.0, self.A, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
            self.A.destroy()
            self.A = A
        else:
            A.destroy()
        return changed

    def load(self, problem) -> np.ndarray:
        """The load of the step as the problem has set it (any path: tractions, body forces and Dirichlet values
        at ``problem.load``): ``f(t)`` (``-F`` at ``u = 0``), the Dirichlet values, the load mode ``u_0(t)``
        (``u_c = 0``) into :attr:`x`; returns ``r(t) = (K u_0(t) - f(t))_c`` (the same on every rank)."""
        u = problem.u
        saved = u.x.array.copy()
        u.x.array[:] = 0.0
        with self._f.localForm() as fl:
            fl.set(0.0)
        fem_petsc.assemble_vector(self._f, problem.L)
        self._f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self._f.scale(-1.0)
        u.x.array[:] = saved
        self._dir_val = np.concatenate([np.full(len(i), float(d.value.value)) for d, i in self._dirichlet]
                                       + [np.empty(0)])
        r = self.modes.combine(self._f, self._dir_val, self.x)  # a combination of earlier steps' loads
        if r is not None:
            return r
        self.displacement(np.zeros(len(self.cidx)), self.x)
        self.A.mult(self.x, self._y)
        self._y.axpy(-1.0, self._f)
        lo = self.A.getOwnershipRange()[0]
        r = np.zeros(len(self.cidx))
        for idx, v in self.comm.allgather((self._cmine, self._y.array[self.cidx[self._cmine] - lo])):
            r[idx] = v
        self.modes.add(self._f, self._dir_val, self.x, r)
        return r

    def displacement(self, uc: np.ndarray, x: PETSc.Vec) -> None:
        """``x``: the displacement with contact dofs ``uc``, the step's Dirichlet data and load (:meth:`load`),
        in equilibrium elsewhere (one solve with ``K_ii``)."""
        lo, hi = self.A.getOwnershipRange()
        g = self._y
        g.set(0.0)
        idx = np.concatenate([self.dir_idx, self.cidx]).astype(PETSc.IntType)
        val = np.concatenate([self._dir_val, uc])
        keep = (idx >= lo) & (idx < hi)
        g.array[idx[keep] - lo] = val[keep]
        self.A.mult(g, self._b)
        self._b.scale(-1.0)
        self._b.axpy(1.0, self._f)
        self._b.array[idx[keep] - lo] = val[keep]  # the Dirichlet rows are the identity
        self._factor.solve(self._b, x)
        x.array[self.cidx[self._cmine] - lo] = uc[self._cmine]

    def values(self, dofs: np.ndarray, x: PETSc.Vec) -> np.ndarray:
        """The entries ``dofs`` (global numbers, the same on every rank) of the distributed vector ``x``, on every
        rank."""
        lo, hi = self.A.getOwnershipRange()
        out = np.zeros(len(dofs))
        here = np.flatnonzero((dofs >= lo) & (dofs < hi))
        for idx, v in self.comm.allgather((here, x.array[dofs[here] - lo])):
            out[idx] = v
        return out
