"""One Newton solve of a load step: the PETSc SNES and its callbacks, the solver's convergence test, the log of
every iterate (residual norm, active set of the contact points) and the diagnosis of a failed solve."""
from __future__ import annotations

import time
from typing import Callable

import numpy as np
from petsc4py import PETSc

from .. import failure as _failure
from ..compat import petsc_vec, release_free_memory
from ..problem import DIRICHLET_WEIGHT, ContactProblem
from .linear import LinearSolver
from .options import ATOL_RELATIVE, ROUNDOFF_FACTOR, ScopedOptions, read_at_setup, rtol_max_problem

__all__ = ["FORCING_MARGIN", "Newton"]

# The Krylov tolerance of a Newton iteration is no tighter than what takes the residual to this fraction of the
# solve's tolerance (Newton.forcing): the iterate after it converges, with room for the quadratic term.
FORCING_MARGIN = 0.1


class Newton:
    """The SNES solving ``problem`` (prefix and options from ``options``), with its residual vector ``b``,
    Jacobian matrix ``A``, solution vector ``x`` and linear solver ``linear``; owns them (:meth:`destroy`).
    Seconds go to ``timings`` (``assembly_s``, ``snes_s``, ``active_set_s``); ``on_iterate(it)`` is called after
    every Newton iterate, with ``problem.u`` at that iterate.

    Per solve (:meth:`solve`): ``history`` (residual norm per iterate), ``sets`` and ``closed`` (active-set
    fingerprint and number of closed contact points per iterate), ``message`` (a step solver's). Set
    ``reference`` before a solve to make ``rtol`` relative to the smaller of the first residual and it.

    The absolute tolerance (:attr:`atol`) is :data:`~.options.ATOL_RELATIVE` times ``force_scale``, the largest
    first residual of the solves so far (after a predictor: the out-of-balance of the last converged state at the
    new load, as for ``rtol``). The residual's rows are forces, so the decisions do not depend on the units; a
    ``snes_atol`` given in the options or on the command line is used as it is."""

    def __init__(self, problem: ContactProblem, options: ScopedOptions, timings: dict[str, float],
                 on_iterate: Callable[[int], None] | None = None):
        self.problem, self.options, self.timings, self.on_iterate = problem, options, timings, on_iterate
        self.bounded = any(c.bounded for c in problem.contacts)  # SNES VI
        self.b = problem.create_vector()  # the residual vector of the SNES (dolfinx_mpc style: public)
        self.A = problem.create_matrix()  # the Jacobian matrix of the SNES
        self.x = petsc_vec(problem.u).copy()
        self.snes = PETSc.SNES().create(problem.comm)
        self.snes.setOptionsPrefix(options.prefix)
        self.snes.setFunction(self.residual, self.b)
        self.snes.setJacobian(self.jacobian, self.A)
        self.snes.setMonitor(self.monitor)
        self.linear = LinearSolver(self.snes, problem, options)
        with options.active():
            self.snes.setFromOptions()
            self.snes.getKSP().setFromOptions()
            self.divergence_tolerance = options.get_real("snes_divergence_tolerance", 1e4)
            self.absolute_atol = options.has("snes_atol")  # the caller's (or the command line's) own
            if not options.has("snes_convergence_test"):
                self.snes.setConvergenceTest(self.convergence_test)
            self.linear.configure(self.A)
            rtol, rtol_max = self.snes.getKSP().getTolerances()[0], options.get_real("ksp_rtol_max", 0.0)
        complaint = rtol_max_problem(rtol_max)  # a command line's value (Solver's options are checked before)
        if complaint is not None:
            self.destroy()
            raise ValueError(f"-{options.prefix}ksp_rtol_max {rtol_max:g}: {complaint}")
        self.forcing_range = (rtol, rtol_max) if rtol_max > rtol else None  # see forcing
        self.history: list[float] = []
        self.sets: list = []
        self.closed: list[int] = []
        self.message = ""
        self.reference: float | None = None
        self._roundoff_floor: float | None = None  # roundoff_floor, once the problem is known
        self.force_scale: float | None = None  # the largest first residual of the run's solves (a force): atol's scale
        self.linear_iterations = 0  # Krylov iterations of all Newton steps (1 per step for LU)
        self._norms: list[float] = []  # residual norms of the current solve, for the convergence test

    def destroy(self) -> None:
        """Destroy the SNES, ``A``, ``b`` and ``x``. Collective."""
        for obj in (self.snes, self.A, self.b, self.x):
            obj.destroy()

    # --- SNES callbacks ---------------------------------------------------
    def set_u(self, x: PETSc.Vec) -> None:
        """Copy ``x`` into ``problem.u`` (ghosts updated)."""
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        x.copy(petsc_vec(self.problem.u))
        self.problem.u.x.scatter_forward()

    def residual(self, snes: PETSc.SNES, x: PETSc.Vec, b: PETSc.Vec) -> None:
        """Assemble the residual at ``x`` into ``b``."""
        start = time.perf_counter()
        self.problem.F(x, b)
        release_free_memory()  # the assembly's and the search's temporaries (see compat.release_free_memory)
        self.timings["assembly_s"] += time.perf_counter() - start

    def jacobian(self, snes: PETSc.SNES, x: PETSc.Vec, A: PETSc.Mat, P: PETSc.Mat) -> None:
        """Assemble the Jacobian at ``x`` into ``A``; renew the preconditioner on a new sparsity pattern."""
        start = time.perf_counter()
        # A contact's pairing changes A's pattern: factor from scratch. The old hierarchy or factorization is
        # freed first, not kept alongside the rebuilt matrix (the peak memory of a large two-body run).
        renewed = self.problem.pattern_changes()
        if renewed:
            self.linear.renew_pc()
        if self.problem.J(x, A) and not renewed:  # a pattern known only on assembly (collocated element)
            self.linear.renew_pc()
        release_free_memory()  # before the preconditioner's set-up and the Krylov vectors
        if self.forcing_range is not None:
            snes.getKSP().setTolerances(rtol=self.forcing())
        self.timings["assembly_s"] += time.perf_counter() - start

    def forcing(self) -> float:
        """The Krylov tolerance of this Newton iteration (option ``ksp_rtol_max`` above ``ksp_rtol``): the square
        of the last residual ratio ``||F_k|| / ||F_k-1||`` (Eisenstat and Walker's second choice, gamma 1, alpha
        2), within ``[ksp_rtol, ksp_rtol_max]``; ``ksp_rtol_max`` at a solve's first iteration. Loose while the
        residual falls slowly (the active set still moving), tight where Newton converges fast, so its last
        iterates keep their rate and the answer is that of tight solves. Never tighter than :data:`FORCING_MARGIN`
        times the solve's tolerance (:meth:`tolerance`) over the last residual, also above ``ksp_rtol_max`` (Kelley,
        Iterative Methods for Linear and Nonlinear Equations, 1995, eq. 6.20): a linear error of a tenth of it."""
        low, high = self.forcing_range
        h = self.history
        if len(h) < 2 or not h[-2] > 0:
            return high
        # Kelley's safeguard (a quadratic end's last iteration asked 1e-8 where 0.3 does: 51 Krylov iterations at 7e4)
        floor = min(FORCING_MARGIN * self.tolerance() / h[-1], FORCING_MARGIN) if h[-1] > 0 else 0.0
        return float(max(np.clip((h[-1] / h[-2]) ** 2, low, high), floor))

    def tolerance(self) -> float:
        """The residual norm the current solve converges below: :attr:`atol`, or ``rtol`` times :meth:`_first`."""
        return max(self.atol, self.snes.getTolerances()[0] * self._first()) if self._norms else self.atol

    def _first(self) -> float:
        """The residual ``rtol`` refers to: the solve's first, or ``reference`` where smaller."""
        return self._norms[0] if self.reference is None else min(self._norms[0], self.reference)

    @property
    def atol(self) -> float:
        """The absolute residual tolerance of the solves: the given ``snes_atol``, else
        :data:`~.options.ATOL_RELATIVE` times ``force_scale`` (0 before the first nonzero residual)."""
        if self.absolute_atol:
            return self.snes.getTolerances()[1]
        return max(ATOL_RELATIVE * (self.force_scale or 0.0), self.roundoff_floor)

    @property
    def roundoff_floor(self) -> float:
        """The residual norm below which a solve has converged whatever its loads: a finite-strain stress formed
        from ``F`` near ``I``, or a gap from the current positions, carries a round-off of ~ machine epsilon times
        the stiffness diagonal times the cell size in each row, whatever the strain (a strain of 1e-6 would
        otherwise never reach ``ATOL_RELATIVE`` of its first residual). :data:`~.options.ROUNDOFF_FACTOR` times
        that, in the norm over all rows; the cell size is the mesh's bounding-box diagonal over the d-th root of
        the rows. At strains above ~1e-4 it is below ``ATOL_RELATIVE`` of the first residual."""
        if self._roundoff_floor is None:
            problem = self.problem
            n = self.b.getSize()
            d = problem.u.function_space.mesh.geometry.dim
            h = problem.mesh_size() / max(n, 1) ** (1.0 / d)
            diagonal = problem.stiffness / DIRICHLET_WEIGHT
            self._roundoff_floor = ROUNDOFF_FACTOR * np.finfo(float).eps * diagonal * h * np.sqrt(n)
        return self._roundoff_floor

    def convergence_test(self, snes: PETSc.SNES, it: int, norms: tuple[float, float, float]) -> int:
        """PETSc's default test (``SNESConvergedDefault``: NaN, atol, rtol, stol) with two changes: divergence is
        the residual above ``snes_divergence_tolerance`` times the first one *and* grown in each of the last two
        iterations (see ``DEFAULT_OPTIONS``); after a predictor, ``rtol`` is relative to the smaller of the first
        residual and ``reference``, the out-of-balance of the last converged state at the new load (a predicted
        state far off, residual 3e11, would otherwise pass at 3); ``atol`` is :attr:`atol`."""
        xnorm, ynorm, fnorm = norms
        R = PETSc.SNES.ConvergedReason
        rtol, _, stol, _ = snes.getTolerances()
        if it == 0:
            self._norms = [fnorm]
            first = self._first()
            if np.isfinite(first) and first > (self.force_scale or 0.0):
                self.force_scale = float(first)
        else:
            self._norms.append(fnorm)
        if not np.isfinite(fnorm):
            return R.DIVERGED_FNORM_NAN
        if fnorm == 0 or fnorm < self.atol:
            return R.CONVERGED_FNORM_ABS
        if it == 0:
            return R.CONVERGED_ITERATING
        r = self._norms
        if fnorm <= rtol * self._first():
            return R.CONVERGED_FNORM_RELATIVE
        if ynorm < stol * xnorm:
            return R.CONVERGED_SNORM_RELATIVE
        divtol = self.divergence_tolerance
        if divtol > 0 and len(r) >= 3 and fnorm > divtol * r[0] and r[-1] > r[-2] > r[-3]:
            return R.DIVERGED_DTOL
        return R.CONVERGED_ITERATING

    def monitor(self, snes: PETSc.SNES, it: int, norm: float) -> None:
        """Log the iterate: its residual norm and active set."""
        self.history.append(float(norm))
        self._log_active_set(snes, it)

    def _log_active_set(self, snes: PETSc.SNES, it: int) -> None:
        """Active set (closed contact points) at the current iterate, for the failure diagnosis."""
        laws = [c for c in self.problem.contacts if not c.bounded]
        if not laws and self.on_iterate is None:
            return
        start = time.perf_counter()
        self.set_u(snes.getSolution())
        if laws:
            flags = np.concatenate([c.closed_points() for c in laws])
            digest, closed = _failure.fingerprint(flags, self.problem.comm)
            self.sets.append(digest)
            self.closed.append(closed)
        self.timings["active_set_s"] += time.perf_counter() - start
        if self.on_iterate is not None:
            self.on_iterate(it)

    # --- one solve --------------------------------------------------------
    def set_bounds(self, t: float) -> None:
        """SNES VI's variable bounds: the tightest of all bounded contact surfaces at load ``t``."""
        pairs = [c.bounds(t, self.x) for c in self.problem.contacts if c.bounded]
        lower, upper = pairs[0]
        for lo, up in pairs[1:]:
            lower.pointwiseMax(lower, lo)
            upper.pointwiseMin(upper, up)
        self.snes.setVariableBounds(lower, upper)

    def solve(self) -> int:
        """Solve from ``problem.u`` at its current load, into ``problem.u``: by SNES, or by the problem's step
        solver if it has one (a strategy that solves the whole step, e.g. condensed exact contact). Returns the
        SNES converged reason (negative: failed)."""
        self.history, self.message, self.sets, self.closed = [], "", [], []
        for c in self.problem.contacts:  # what a surface sees from here on belongs to this solve
            c.take_failure()
        if self.problem.step_solver is not None:
            start = time.perf_counter()
            reason, self.history, self.message = self.problem.step_solver.solve_step(self.problem)
            self.timings["snes_s"] += time.perf_counter() - start
            return reason
        petsc_vec(self.problem.u).copy(self.x)
        start = time.perf_counter()
        with self.options.active(read_at_setup):
            self.snes.solve(None, self.x)
        self.timings["snes_s"] += time.perf_counter() - start
        self.linear_iterations += self.snes.getLinearSolveIterations()
        self.set_u(self.x)
        return self.snes.getConvergedReason()

    # --- verdict on a solve -------------------------------------------------
    def stalled(self, reason: int) -> bool:
        """True if the last solve was accepted on the step length alone with its residual above ``rtol`` and
        ``atol`` (:func:`failure.stalled`)."""
        return _failure.stalled(_failure.reason_name(PETSc.SNES.ConvergedReason, reason), self.history,
                                self.snes.getTolerances()[0], self.atol)

    def condition_estimate(self) -> float | None:
        """Condition estimate of the last Jacobian (:func:`failure.condition_estimate`; direct solvers only,
        else None). Collective."""
        return _failure.condition_estimate(self.A, self.snes.getKSP())

    def ill_conditioned(self) -> bool:
        """True if the condition estimate of the last Jacobian is above :data:`failure.ILL_CONDITIONED` (direct
        solvers only). Collective."""
        condition = self.condition_estimate()
        return condition is not None and condition > _failure.ILL_CONDITIONED

    def diagnose(self, reason: int) -> dict:
        """Classify the failed solve just done (see :mod:`fenics_contact.failure`)."""
        ksp = self.snes.getKSP()
        ksp_reason = _failure.reason_name(PETSc.KSP.ConvergedReason, ksp.getConvergedReason())
        condition = None
        if ksp_reason not in ("DIVERGED_PCSETUP_FAILED", "DIVERGED_PC_FAILED"):  # a failed factorization: no estimate
            condition = _failure.condition_estimate(self.A, ksp)
        out = _failure.classify(_failure.reason_name(PETSc.SNES.ConvergedReason, reason), ksp_reason,
                                self.history, self.sets, self.closed, condition, _failure.mumps_error(ksp))
        seen = [k for k in (c.take_failure() for c in self.problem.contacts) if k]
        if seen:  # what a surface saw (the same on every rank: the surfaces decide collectively)
            out["kind"] = seen[0]
        return out
