"""The linear solver inside the Newton iteration: field split and Schur complement, near-nullspace, a repeatable LU
on several ranks, renewal of the preconditioner on a new sparsity pattern, growth of MUMPS's work arrays, and the
time of one linear solve."""
from __future__ import annotations

import logging
import time
from typing import Callable

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from .. import failure as _failure
from ..capabilities import check, of
from ..compat import redundant_ksp
from ..nullspace import rigid_body_modes
from ..problem import ContactProblem
from .options import MULTIGRID, ScopedOptions, read_at_setup

__all__ = ["MUMPS_WORKSPACE_DEFAULT", "MUMPS_WORKSPACE_MAX", "LinearSolver"]

logger = logging.getLogger(__package__)

# MUMPS's work arrays: ICNTL(14), percent over the analysis' estimate. MUMPS's default; the most the solver grows
# it to after a failed factorization (LinearSolver.grow_mumps_workspace: 20 -> 40 -> ... -> 640, then a cutback).
MUMPS_WORKSPACE_DEFAULT = 20
MUMPS_WORKSPACE_MAX = 640
# The cost floor (LinearSolver.solve_time): a solve this short (s) is timed again, at most this many times
FLOOR_REPEAT_S, FLOOR_REPEATS = 1.0, 5


class LinearSolver:
    """Set-up of the KSP of ``snes`` (which owns it) for ``problem``, with the options of ``options``."""

    def __init__(self, snes: PETSc.SNES, problem: ContactProblem, options: ScopedOptions):
        self.snes, self.problem, self.options = snes, problem, options

    @property
    def ksp(self) -> PETSc.KSP:
        """The SNES's KSP."""
        return self.snes.getKSP()

    def configure(self, A: PETSc.Mat) -> None:
        """Set the KSP up after its ``setFromOptions``: the field split's index sets; for multigrid, the
        capability check and the rigid-body modes as ``A``'s near-nullspace. Call inside ``options.active()``."""
        self.split_fields()
        if self.ksp.getPC().getType() in MULTIGRID:
            u = self.problem.u
            for c in self.problem.contacts:  # the capability matrix, before any assembly
                check(**of(c.law, u, self.problem.material), solver="iterative")
            modes = rigid_body_modes(u.function_space)
            A.setNearNullSpace(modes)
            modes.destroy()  # A holds its own reference
        self.repeatable_lu()

    def repeatable_lu(self) -> None:
        """On several ranks, make the SNES's MUMPS LU a ``redundant`` preconditioner: every rank factors and solves
        the whole matrix with sequential MUMPS (the same options prefix, so ``mat_mumps_*`` options apply). MUMPS on
        several ranks is asynchronous: its solve phase sums the contributions of the ranks in the order they
        arrive, so the same factorization of the same matrix and right-hand side gives solutions that differ in
        the last bits from run to run (2-3 distinct ones in 300 solves of a 920-dof wedges Jacobian on 2 ranks).
        A Newton path that decides stick or slip, open or closed, on such bits then takes another branch (wedges
        on 2 ranks: 18 and 21 iterations in one step of two runs). Sequential MUMPS is repeatable; the price is
        the factorization's memory of one rank on every rank. The option ``distributed_lu`` (``options=
        {"distributed_lu": True}``, ``-fc_distributed_lu``) keeps MUMPS distributed: less memory per rank, not
        repeatable to the last bit. Call inside ``options.active()``."""
        distributed = self.options.get_bool("distributed_lu", False)  # read on any number of ranks: used
        pc = self.ksp.getPC()
        if distributed or self.problem.comm.size == 1 or pc.getType() != "lu" or pc.getFactorSolverType() != "mumps":
            return
        prefix = pc.getOptionsPrefix() or ""
        pc.setType("redundant")  # as many sub-communicators as ranks: one rank each
        inner = redundant_ksp(pc)
        inner.setOptionsPrefix(prefix)
        inner.setType("preonly")
        inner.getPC().setType("lu")
        inner.getPC().setFactorSolverType("mumps")

    def split_fields(self, pc: PETSc.PC | None = None) -> None:
        """Give a ``fieldsplit`` preconditioner (default: the SNES's) the index sets of the contact that
        defines them (multipliers: free dofs and pinned pressure dofs); without any, MUMPS LU on the whole."""
        pc = pc or self.ksp.getPC()
        if pc.getType() != "fieldsplit":
            return
        for c in self.problem.contacts:
            fields = c.field_split()
            if fields:
                pc.setFieldSplitIS(*fields)
                # The split's own KSPs exist now: they read their options (``fieldsplit_<name>_...``), which
                # are out of the database again after setFromOptions (also after a reset of the split).
                with self.options.active(lambda k: k.startswith("fieldsplit_")):
                    for ksp in pc.getFieldSplitSubKSP():
                        ksp.setFromOptions()
                    inner = pc.getFieldSplitSubKSP()[0].getPC()  # the first block split again (Schur)
                    split = c.schur_split() if inner.getType() == "fieldsplit" else None
                    if split is not None:
                        (name, first), second = split[0]
                        if split[1] is not None:  # the first field's sub-matrix takes it (PCFIELDSPLIT's query)
                            first.compose("nearnullspace", split[1])
                        inner.setFieldSplitIS((name, first), second)  # its KSPs: made and set up in the solve
                return
        pc.setType("lu")
        pc.setFactorSolverType("mumps")

    def renew_pc(self) -> None:
        """Set the preconditioner up from scratch for a new matrix pattern. A factorization is reset; a
        multigrid hierarchy is replaced by a new preconditioner: PCReset keeps GAMG's level solvers, whose
        coarse sizes then change under it ("Cannot change local size of Amat after use", seen on 2 ranks)."""
        ksp = self.ksp
        old = ksp.getPC()
        if old.getType() in MULTIGRID:
            pc = PETSc.PC().create(self.problem.comm)
            pc.setOptionsPrefix(old.getOptionsPrefix())
            with self.options.active():
                pc.setFromOptions()
            ksp.setPC(pc)
            pc.destroy()  # the KSP holds its own reference
            # Ours is the last reference to the old one: dropping it would only put it on petsc4py's garbage
            # list (see stepping.Solver.run) with its whole GAMG hierarchy, ~45 MB per pairing change at 1.2e5
            # dofs.
            old.destroy()
        else:
            old.reset()
        self.split_fields()  # a reset field split has forgotten its index sets

    def solve(self, A: PETSc.Mat, rhs: PETSc.Vec, x: PETSc.Vec) -> int:
        """Solve ``A x = rhs`` with the SNES's KSP, outside a Newton solve. Returns the KSP's converged reason
        (negative: failed)."""
        ksp = self.ksp
        ksp.setOperators(A)
        with self.options.active(read_at_setup):
            ksp.solve(rhs, x)
        return ksp.getConvergedReason()

    def grow_mumps_workspace(self, failure: dict | None) -> bool:
        """After a MUMPS factorization that ran out of a work array (:data:`failure.MUMPS_WORKSPACE`), double
        ``mat_mumps_icntl_14`` (the percent of room over the analysis' estimate; MUMPS's default 20) up to
        ``MUMPS_WORKSPACE_MAX`` and say so: True if the step should be retried. Not if the option was given on
        the command line (the user's value stands; the failure then names it)."""
        info = (failure or {}).get("mumps_infog")
        if not info or info[0] not in _failure.MUMPS_WORKSPACE or self.options.has("mat_mumps_icntl_14"):
            return False
        now = int(self.options.wanted.get("mat_mumps_icntl_14", MUMPS_WORKSPACE_DEFAULT))
        if now >= MUMPS_WORKSPACE_MAX:
            return False
        grown = min(max(2 * now, 2 * MUMPS_WORKSPACE_DEFAULT), MUMPS_WORKSPACE_MAX)
        self.options.wanted["mat_mumps_icntl_14"] = grown
        for F in _failure.mumps_factors(self.ksp):  # a refactorization of the same pattern keeps F
            F.setMumpsIcntl(14, grown)
        failure["message"] = f"MUMPS INFOG(1) = {info[0]}: work array too small; ICNTL(14) {now} -> {grown}"
        if self.problem.comm.rank == 0:
            logger.warning("%s, retrying the step", failure["message"])
        return True

    def solve_time(self, A: PETSc.Mat, x: PETSc.Vec, assemble_jacobian: Callable[[], None]) -> float:
        """Seconds for one Jacobian assembly (``assemble_jacobian``, into ``A``) and one solve of ``A y = A x``
        with a fresh linear solver of the same kind (factorization included): the cost floor of one linear elastic
        solve on this mesh (max over ranks). ``x``: the current state, so the right-hand side has the problem's
        own scales (a converged residual is round-off, and the Krylov iterations to reduce it vary from run to
        run). Frees the SNES's own factorization or multigrid hierarchy first (rebuilt if it
        solves again): two at once would double the peak memory of a large run. A solve of less than
        :data:`FLOOR_REPEAT_S` is timed up to :data:`FLOOR_REPEATS` times and the fastest kept: a single timing of
        a few milliseconds is mostly the machine's noise."""
        self.ksp.reset()
        best, spent = np.inf, 0.0
        for _ in range(FLOOR_REPEATS):
            ksp = PETSc.KSP().create(self.problem.comm)
            # the SNES's linear-solver options (ours and the command line's), under the same prefix
            ksp.setOptionsPrefix(self.snes.getOptionsPrefix())
            with self.options.active(lambda k: k.startswith(("ksp_", "pc_", "mg_"))):
                ksp.setFromOptions()
                self.split_fields(ksp.getPC())
            b, y = x.duplicate(), x.duplicate()
            start = time.perf_counter()
            assemble_jacobian()
            if x.norm() > 0:
                A.mult(x, b)
            else:  # no state yet (a run that failed at its first step): a right-hand side of ones
                b.set(1.0)
            ksp.setOperators(A)
            with self.options.active(lambda k: k.startswith("fieldsplit_")):  # a nested split: see read_at_setup
                ksp.solve(b, y)
            elapsed = self.problem.comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
            ksp.destroy()
            b.destroy()
            y.destroy()
            best, spent = min(best, elapsed), spent + elapsed
            if spent >= FLOOR_REPEAT_S:  # collective: every rank has the same spent
                break
        return best
