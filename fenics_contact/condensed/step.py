"""What both condensed step solvers share: a load step solved on the stiffness condensed onto the contact dofs.

At the first step ``K`` is condensed (:class:`~.operator.CondensedStiffness`, again at a step where the
stiffness changed); each step the load's contact force ``r(t)`` (one solve), the semismooth Newton on ``u_c``
(:func:`~.newton.semismooth_newton`, the same small computation on every rank), the output on the surface and
the recovery of the displacement (one solve). A subclass (rigid obstacle, two bodies) chooses the contact dofs,
writes the Alart-Curnier residual, the output and the slip reference.
"""
from __future__ import annotations

import time

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from ..compat import petsc_vec
from ..surface import StepSolver
from .newton import semismooth_newton
from .operator import CondensedStiffness
from .rowupdate import RowUpdatedSolve
from .states import StepFailure

__all__ = ["CondensedStepSolver"]


class CondensedStepSolver(StepSolver):
    """A load step solved exactly on the condensed system (see the module). ``max_it`` semismooth Newton
    iterations at most per try, converged at the relative residual ``tol``; ``c_scale`` (``c`` in units of the
    mean diagonal of ``S``) and ``retries`` (tries with ``c / 10``, ``c / 100``, ...) steer the Newton.
    ``timings``: seconds spent condensing, in the loads, in the Newton and in the recovery.

    A subclass implements :meth:`_contact_dofs`, :meth:`_residual`, :meth:`_set_output` and
    :meth:`_slip_reference` (and :meth:`_step_data` if the step needs more than ``r(t)``)."""

    def __init__(self, comm, max_it: int, tol: float):
        if int(max_it) < 1 or not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"max_it must be >= 1 and tol a finite number > 0, got {max_it!r}, {tol!r}")
        self.comm = comm
        self.max_it, self.tol = int(max_it), float(tol)
        # Alart-Curnier's c = c_scale * (mean diagonal of S); a failed iteration is retried with c / 10 and
        # c / 100 (a safeguard). Measured on the slab from the zero start (mu 0.4 - 5): c_scale from 1e-3 to
        # 1e2 gives the same iterations (6-8) and the same solution to 1e-14: active contacts get d = 0 and
        # sticking vertices s = 0 exactly after one step, so c hardly enters the active-set decisions.
        self.c_scale, self.retries = 1.0, 2
        self.K: CondensedStiffness | None = None  # the condensed stiffness, from the first step on
        self._restored: dict | None = None  # a state restored before the first step (a checkpoint's)
        self.timings = {"condense_s": 0.0, "load_s": 0.0, "contact_newton_s": 0.0, "recover_s": 0.0}
        self.linear = RowUpdatedSolve()  # the Newton systems' solver, its factorization kept across steps

    @property
    def S(self) -> np.ndarray:
        """The Schur complement (the same on every rank)."""
        return self.K.S

    # --- what a subclass writes ----------------------------------------------------
    def _contact_dofs(self, problem, K: CondensedStiffness) -> np.ndarray:
        """The global numbers of the condensed dofs (the same order on every rank), from ``K``'s Dirichlet dofs
        and ownership range."""
        raise NotImplementedError

    def _step_data(self) -> None:
        """What else the step needs from the load mode ``self.K.x`` (after ``r(t)``)."""
        return None  # r(t) is all a rigid obstacle needs

    def _residual(self, uc: np.ndarray, t: float, c: float) -> tuple:
        """Alart-Curnier residual ``F``, its generalized Jacobian ``J``, the contact state (for the cycle
        detection) and the contact force ``R = S u_c + r(t)``."""
        raise NotImplementedError

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        """Hand the solved step to the surface (contact forces, gaps, states)."""
        raise NotImplementedError

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        """The tangential quantity whose change over a step is the slip increment, at ``uc``."""
        raise NotImplementedError

    # --- the step --------------------------------------------------------------------
    def _condense(self, problem) -> None:
        start = time.perf_counter()
        K = CondensedStiffness(problem, self.comm)
        K.condense(self._contact_dofs(problem, K))
        self.K = K
        self._uc = np.zeros(len(self.K.cidx))  # last solution
        if self._restored is not None:  # the condensation set the slip reference to zero
            self.restore(self._restored)
            self._restored = None
        self.timings["condense_s"] += self.comm.allreduce(time.perf_counter() - start, op=MPI.MAX)

    def solve_step(self, problem) -> tuple[int, list[float], str]:
        """Solve the step at the problem's current load and set ``problem.u``.

        Returns:
            ``(reason, residual history, message)``: ``reason`` > 0 converged (SNES's CONVERGED_FNORM_ABS),
            < 0 failed (DIVERGED_MAX_IT, the message says why).
        """
        if self.K is None:
            self._condense(problem)
        elif self.K.changed(problem):
            start = time.perf_counter()
            self.K.factor()
            self.timings["condense_s"] += self.comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
        t = float(problem.load.value)
        start = time.perf_counter()
        self._r = self.K.load(problem)
        self.timings["load_s"] += time.perf_counter() - start
        self._step_data()
        start = time.perf_counter()
        try:
            uc, history = semismooth_newton(lambda uc, c: self._residual(uc, t, c), self._uc, self._r,
                                            self.c_scale * self.K.diag, self.retries, self.max_it, self.tol,
                                            self.linear)
        except StepFailure as exc:
            self.timings["contact_newton_s"] += time.perf_counter() - start
            return int(PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT), list(exc.args[1]), \
                f"method 'coulomb', mu = {self.mu:g}: {exc.args[0]}"
        self.timings["contact_newton_s"] += time.perf_counter() - start
        start = time.perf_counter()
        self._uc = uc
        self._set_output(uc, t)
        self.K.displacement(uc, self.K.x)
        self.K.x.copy(petsc_vec(problem.u))
        problem.u.x.scatter_forward()
        self.timings["recover_s"] += time.perf_counter() - start
        return int(PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS), history, ""

    # --- step-solver hooks ---------------------------------------------------------------
    def commit(self) -> None:
        """The converged step becomes the reference of the next step's slip increments."""
        if self.K is not None:
            self._ref = self._slip_reference(self._uc)

    def state(self) -> dict:
        if self.K is None:
            return {}
        return {"uc": self._uc.copy(), "ref": self._ref.copy()}

    def restore(self, state: dict) -> None:
        if state:
            self._uc, self._ref = state["uc"].copy(), state["ref"].copy()
            if self.K is None:  # kept through the condensation at the first step
                self._restored = state
