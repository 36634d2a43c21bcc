"""The solver: load stepping with cutback and rollback, and the augmentation loop of each step."""
from __future__ import annotations

import logging
import time
from typing import Callable, Sequence

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from .. import failure as _failure
from ..capabilities import check, of
from ..compat import petsc_vec, release_free_memory
from ..nullspace import rigid_body_modes
from ..problem import ContactProblem
from .options import MULTIGRID, ScopedOptions, read_at_setup, solver_options
from .record import ConvergenceError, RunRecord, StepRecord, describe, progress_line, reason_text

__all__ = ["MUMPS_WORKSPACE_DEFAULT", "MUMPS_WORKSPACE_MAX", "PREDICTORS", "PREDICTOR_ETA", "PREDICTOR_FD", "Solver"]

logger = logging.getLogger(__package__)

# MUMPS's work arrays: ICNTL(14), percent over the analysis' estimate. MUMPS's default; the most the solver grows
# it to after a failed factorization (Solver._grow_mumps_workspace: 20 -> 40 -> ... -> 640, then a cutback).
MUMPS_WORKSPACE_DEFAULT = 20
MUMPS_WORKSPACE_MAX = 640

PREDICTORS = (False, True, "secant", "tangent")  # Solver(predictor=...)
PREDICTOR_FD = 1e-6  # forward-difference step of dR/dt in the tangent predictor, relative to the load step
# Line-search tolerance of the tangent predictor: |slope| <= PREDICTOR_ETA |slope at 0|. Near-exact (0.01 to 0.1
# give the same seal history); 0.5 accepts the full tangent where the seal's corner lands (16 iterations).
PREDICTOR_ETA = 0.05


class _Delegated:
    """An attribute of :class:`Solver` held by one of its parts (``part``, the name of the Solver's attribute)."""

    def __init__(self, part: str, name: str | None = None):
        self.part, self.name = part, name

    def __set_name__(self, owner, name: str) -> None:
        self.name = self.name or name

    def __get__(self, solver, owner=None):
        return self if solver is None else getattr(getattr(solver, self.part), self.name)

    def __set__(self, solver, value) -> None:
        setattr(getattr(solver, self.part), self.name, value)


class Solver:
    """Drives a :class:`ContactProblem` through a sequence of load values.

    ``augment_max`` augmentations at most per load step (0: none), stopping
    when ``R = ||g_new - g_old|| <= augment_tol``. A step whose SNES
    diverges is halved up to ``max_cutbacks`` times. ``on_step(t)`` is
    called after every converged step (output); ``on_iterate(it)`` after
    every Newton iterate, with ``problem.u`` at that iterate. Progress: one
    line per load step on rank 0 through ``logging`` (logger
    ``fenics_contact.solver``, INFO; ``quiet``: DEBUG, i.e. silent unless
    the log asks for it). ``predictor`` chooses the state each load
    step starts from: ``False`` the last converged state; ``"secant"`` (or
    ``True``) the linear extrapolation in ``t`` of the last two converged
    states; ``"tangent"`` the Euler predictor of :meth:`_tangent_predictor`
    (the tangent of the load path at the last converged state, scaled back
    to the energy's stationary point along it when the energy rises before
    its end: a contact that the step closes is not driven far into the
    obstacle). The tangent needs a force-based contact law (not ``bounded``).
    """

    records = _Delegated("record")
    failures = _Delegated("record")  # every failed solve, also those rescued by a cutback
    timings = _Delegated("record")  # seconds on this rank per activity
    newton_spent = _Delegated("record")  # Newton iterations of every solve, also of failed attempts (cut back or final)

    def __init__(self, problem: ContactProblem, prefix: str = "fc_", options: dict | None = None,
                 augment_max: int = 0, augment_tol: float = 1e-12, max_cutbacks: int = 4,
                 quiet: bool = False, on_step: Callable[[float], None] | None = None,
                 on_iterate: Callable[[int], None] | None = None, predictor: bool | str = False):
        if predictor not in PREDICTORS:
            raise ValueError(f"predictor must be one of {PREDICTORS}, got {predictor!r}")
        if augment_max < 0:
            raise ValueError(f"augment_max must be >= 0, got {augment_max}")
        if not augment_tol > 0:
            raise ValueError(f"augment_tol must be > 0, got {augment_tol}")
        if max_cutbacks < 0:
            raise ValueError(f"max_cutbacks must be >= 0, got {max_cutbacks}")
        self.problem, self.quiet, self.on_step, self.on_iterate = problem, quiet, on_step, on_iterate
        self.predictor = "secant" if predictor is True else predictor  # False, "secant" or "tangent"
        self._converged: list[tuple[float, np.ndarray]] = []  # last two converged (t, u), for the predictor
        self.augment_max, self.augment_tol, self.max_cutbacks = augment_max, augment_tol, max_cutbacks
        self._bounded = any(c.bounded for c in problem.contacts)
        self.options = ScopedOptions(prefix, solver_options(problem, options))
        u = problem.u
        self.b = problem.create_vector()  # the residual vector of the SNES (dolfinx_mpc style: public)
        self.A = problem.create_matrix()  # the Jacobian matrix of the SNES
        self._x = petsc_vec(u).copy()
        self.snes = PETSc.SNES().create(problem.comm)
        self.snes.setOptionsPrefix(self.options.prefix)
        self.snes.setFunction(self._residual, self.b)
        self.snes.setJacobian(self._jacobian, self.A)
        self.snes.setMonitor(self._monitor)
        with self.options.active():
            self.snes.setFromOptions()
            self.snes.getKSP().setFromOptions()
            self._divtol = self.options.get_real("snes_divergence_tolerance", 1e4)
            if not self.options.has("snes_convergence_test"):
                self.snes.setConvergenceTest(self._convergence_test)
            self._split_fields()
            if self.snes.getKSP().getPC().getType() in MULTIGRID:
                for c in problem.contacts:  # the capability matrix, before any assembly
                    check(**of(c.law, u), solver="iterative")
                self.A.setNearNullSpace(rigid_body_modes(u.function_space))
        self.record = RunRecord()
        self._history: list[float] = []
        self._reference: float | None = None  # the rtol reference after a predictor (_convergence_test)
        self._sets: list = []  # active-set fingerprint per iterate of the current solve
        self._closed: list[int] = []
        self.t = 0.0
        self.linear_iterations = 0  # Krylov iterations of all Newton steps (1 per step for LU)

    # --- SNES callbacks ---------------------------------------------------
    def _set_u(self, x: PETSc.Vec) -> None:
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        x.copy(petsc_vec(self.problem.u))
        self.problem.u.x.scatter_forward()

    def _residual(self, snes, x, b):
        start = time.perf_counter()
        self.problem.F(x, b)
        release_free_memory()  # the assembly's and the search's temporaries (see compat.release_free_memory)
        self.timings["assembly_s"] += time.perf_counter() - start

    def _jacobian(self, snes, x, A, P):
        start = time.perf_counter()
        # A contact's pairing changes A's pattern: factor from scratch. The old hierarchy or factorization is
        # freed first, not kept alongside the rebuilt matrix (the peak memory of a large two-body run).
        renewed = self.problem.pattern_changes()
        if renewed:
            self._renew_pc()
        if self.problem.J(x, A) and not renewed:  # a pattern known only on assembly (collocated element)
            self._renew_pc()
        release_free_memory()  # before the preconditioner's set-up and the Krylov vectors
        self.timings["assembly_s"] += time.perf_counter() - start

    def _renew_pc(self) -> None:
        """Set the preconditioner up from scratch for a new matrix pattern. A factorization is reset; a
        multigrid hierarchy is replaced by a new preconditioner: PCReset keeps GAMG's level solvers, whose
        coarse sizes then change under it ("Cannot change local size of Amat after use", seen on 2 ranks)."""
        ksp = self.snes.getKSP()
        old = ksp.getPC()
        if old.getType() in MULTIGRID:
            pc = PETSc.PC().create(self.problem.comm)
            pc.setOptionsPrefix(old.getOptionsPrefix())
            with self.options.active():
                pc.setFromOptions()
            ksp.setPC(pc)
            pc.destroy()  # the KSP holds its own reference
            # Ours is the last reference to the old one: dropping it would only put it on petsc4py's garbage
            # list (see :meth:`run`) with its whole GAMG hierarchy, ~45 MB per pairing change at 1.2e5 dofs.
            old.destroy()
        else:
            old.reset()
        self._split_fields()  # a reset field split has forgotten its index sets

    def _split_fields(self, pc: PETSc.PC | None = None) -> None:
        """Give a ``fieldsplit`` preconditioner (default: the SNES's) the index sets of the contact that
        defines them (multipliers: free dofs and pinned pressure dofs); without any, MUMPS LU on the whole."""
        pc = pc or self.snes.getKSP().getPC()
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

    def _convergence_test(self, snes: PETSc.SNES, it: int, norms: tuple[float, float, float]) -> int:
        """PETSc's default test (``SNESConvergedDefault``: NaN, atol, rtol, stol) with two changes: divergence is
        the residual above ``snes_divergence_tolerance`` times the first one *and* grown in each of the last two
        iterations (see ``DEFAULT_OPTIONS``); after a predictor, ``rtol`` is relative to the smaller of the first
        residual and the out-of-balance of the last converged state at the new load (a predicted state far off,
        residual 3e11, would otherwise pass at 3)."""
        xnorm, ynorm, fnorm = norms
        R = PETSc.SNES.ConvergedReason
        rtol, atol, stol, _ = snes.getTolerances()
        if it == 0:
            self._norms = [fnorm]
        else:
            self._norms.append(fnorm)
        if not np.isfinite(fnorm):
            return R.DIVERGED_FNORM_NAN
        if fnorm < atol:
            return R.CONVERGED_FNORM_ABS
        if it == 0:
            return R.CONVERGED_ITERATING
        r = self._norms
        if fnorm <= rtol * (r[0] if self._reference is None else min(r[0], self._reference)):
            return R.CONVERGED_FNORM_RELATIVE
        if ynorm < stol * xnorm:
            return R.CONVERGED_SNORM_RELATIVE
        if self._divtol > 0 and len(r) >= 3 and fnorm > self._divtol * r[0] and r[-1] > r[-2] > r[-3]:
            return R.DIVERGED_DTOL
        return R.CONVERGED_ITERATING

    def _monitor(self, snes, it, norm):
        self._history.append(float(norm))
        self._log_iterate(snes, it)

    def _log_iterate(self, snes, it: int) -> None:
        """Active set (closed contact points) at the current iterate, for the failure diagnosis."""
        laws = [c for c in self.problem.contacts if not c.bounded]
        if not laws and self.on_iterate is None:
            return
        start = time.perf_counter()
        self._set_u(snes.getSolution())
        if laws:
            flags = np.concatenate([c.closed_points() for c in laws])
            digest, closed = _failure.fingerprint(flags, self.problem.comm)
            self._sets.append(digest)
            self._closed.append(closed)
        self.timings["active_set_s"] += time.perf_counter() - start
        if self.on_iterate is not None:
            self.on_iterate(it)

    # --- driver -----------------------------------------------------------
    def _newton(self) -> int:
        self._history, self._message, self._sets, self._closed = [], "", [], []
        for c in self.problem.contacts:  # what a surface sees from here on belongs to this solve
            c.take_failure()
        if self.problem.step_solver is not None:  # a strategy that solves the whole step (condensed exact contact)
            start = time.perf_counter()
            reason, self._history, self._message = self.problem.step_solver.solve_step(self.problem)
            self.timings["snes_s"] += time.perf_counter() - start
            return reason
        petsc_vec(self.problem.u).copy(self._x)
        start = time.perf_counter()
        with self.options.active(read_at_setup):
            self.snes.solve(None, self._x)
        self.timings["snes_s"] += time.perf_counter() - start
        self.linear_iterations += self.snes.getLinearSolveIterations()
        self._set_u(self._x)
        return self.snes.getConvergedReason()

    def _bounds(self, t: float) -> tuple[PETSc.Vec, PETSc.Vec]:
        """The tightest bounds of all contact surfaces at load ``t``."""
        pairs = [c.bounds(t, self._x) for c in self.problem.contacts if c.bounded]
        lower, upper = pairs[0]
        for lo, up in pairs[1:]:
            lower.pointwiseMax(lower, lo)
            upper.pointwiseMin(upper, up)
        return lower, upper

    def _stateful(self) -> list:
        """The contacts and the step solver: everything with ``state``/``restore``/``commit``."""
        return [*self.problem.contacts, *([self.problem.step_solver] if self.problem.step_solver else [])]

    def _snapshot(self):
        return petsc_vec(self.problem.u).copy(), [c.state() for c in self._stateful()]

    def _rollback(self, snap) -> None:
        snap[0].copy(petsc_vec(self.problem.u))
        self.problem.u.x.scatter_forward()
        for c, s in zip(self._stateful(), snap[1]):
            c.restore(s)

    def _step(self, t: float, number: int) -> StepRecord:
        """Solve at load ``t`` with the augmentation loop; the record says whether it converged."""
        rec = StepRecord(step=number, load=t)
        start = time.perf_counter()
        self.problem.set_load(t)
        if self._bounded:
            lower, upper = self._bounds(t)
            self.snes.setVariableBounds(lower, upper)
        augmentable = [c for c in self.problem.contacts if c.augmentable]
        for c in augmentable:
            c.forget_gap()
        tangent = self.predictor == "tangent" and not self._bounded and t != self.t
        secant = self.predictor == "secant" and len(self._converged) == 2
        self._reference = None
        if tangent or secant:  # the relative tolerance refers to the out-of-balance of u_n at t (_convergence_test)
            x = petsc_vec(self.problem.u).copy()
            self._residual(self.snes, x, self.b)
            self._reference = self.b.norm()
            x.destroy()
        if tangent:
            rec.predictor_scale = self._tangent_predictor(t)
        elif secant:
            (t0, u0), (t1, u1) = self._converged
            self.problem.u.x.array[:] = u1 + (t - t1) / (t1 - t0) * (u1 - u0)
        while True:
            rec.reason = self._newton()
            rec.residuals.append(self._history)
            rec.closed_points.append(self._closed)
            rec.message = self._message
            # Accepted on the step length with the residual above tolerance: the round-off floor of the linear
            # solves. On a Jacobian whose condition estimate exceeds failure.ILL_CONDITIONED (direct solvers) the
            # step is then garbage (singular: a free rigid mode) and the solve fails as ill_conditioning;
            # otherwise it is accepted and recorded in ``stalled``.
            ill = False
            if rec.reason > 0 and _failure.stalled(_failure.reason_name(PETSc.SNES.ConvergedReason, rec.reason),
                                                   self._history, *self.snes.getTolerances()[:2]):
                rec.stalled.append(rec.augmentations)
                condition = self.condition_estimate()
                ill = condition is not None and condition > _failure.ILL_CONDITIONED
            if rec.reason <= 0 or ill:
                rec.failure = {"step": rec.step, "load": t, "augmentation": rec.augmentations,
                               **self._diagnose(rec.reason), **({"message": rec.message} if rec.message else {})}
                break
            J = self.problem.min_jacobian()  # finite strain: a converged state with an inverted element is no answer
            if J is not None and not J > 0.0:
                rec.message = f"converged to a state with an inverted element (min det F = {J:.3g})"
                rec.failure = {"step": rec.step, "load": t, "augmentation": rec.augmentations,
                               "kind": "inverted_elements", "iterations": max(len(self._history) - 1, 0),
                               "min_jacobian": J, "message": rec.message}
                break
            for c in self.problem.contacts:
                c.after_solve(self.problem)
            if not self.augment_max or not augmentable:
                rec.converged = True
                break
            start_aug = time.perf_counter()
            R = max(c.constraint_change() for c in augmentable)
            if np.isfinite(R):
                rec.constraint_change.append(R)
            if R <= self.augment_tol:
                rec.converged = True
                break
            if rec.augmentations == self.augment_max:
                rec.converged, rec.augmentation_converged = True, False
                break
            for c in augmentable:
                c.augment()
            rec.augmentations += 1
            self.timings["augmentation_s"] += time.perf_counter() - start_aug
        rec.wall_time_s = self.problem.comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
        return rec

    def _tangent_predictor(self, t: float) -> float:
        """Start the step to load ``t`` from ``u_n + s du``: ``u_n`` converged at ``t_n = self.t``, ``du = -J^-1
        dR/dt (t - t_n)`` the tangent of the load path there (``J`` at ``(u_n, t_n)``, so with the contact set of
        ``u_n``; ``dR/dt`` by a forward difference of the residual in ``t``, which also moves Dirichlet values along
        their paths). ``s = 1`` unless the energy rises before the end of ``du``, i.e. the slope ``R(u_n + s du, t) .
        du`` (the derivative of the energy along ``du``) at ``s = 1`` is positive and above ``PREDICTOR_ETA`` times
        its value at 0: then ``s`` in (0, 1) is its root (regula falsi, Illinois), to ``PREDICTOR_ETA`` too.

        Why: the tangent holds until the next contact event. A contact that closes within the step (the seal's
        outer corner) is driven far into the obstacle by the tangent of the open state (0.44 at h = 0.5, a force
        of ~1e4 against plate forces ~1), and Newton rocks from there. Returns ``s``."""
        start, assembly = time.perf_counter(), self.timings["assembly_s"]
        p, t0 = self.problem, self.t
        if not hasattr(self, "_work"):
            self._work = [self.b.duplicate() for _ in range(4)]
        x, r0, r1, du = self._work
        petsc_vec(p.u).copy(x)
        p.set_load(t0)
        self._residual(self.snes, x, r0)
        self._jacobian(self.snes, x, self.A, self.A)
        eps = PREDICTOR_FD * abs(t - t0)
        p.set_load(t0 + eps)
        self._residual(self.snes, x, r1)
        r1.axpy(-1.0, r0)
        r1.scale(-(t - t0) / eps)
        ksp = self.snes.getKSP()
        ksp.setOperators(self.A)
        with self.options.active(read_at_setup):
            ksp.solve(r1, du)
        p.set_load(t)
        if ksp.getConvergedReason() < 0 or not np.isfinite(du.norm()):  # no tangent (e.g. a singular J): u_n
            self._set_u(x)
            self.timings["assembly_s"] = assembly
            self.timings["predictor_s"] += time.perf_counter() - start
            return 0.0

        def slope(s: float) -> float:
            """The energy's derivative along ``du`` at ``u_n + s du``; +inf where it has none (a non-finite
            residual: an exploded two-body geometry), i.e. beyond the stationary point."""
            x.copy(r0)
            r0.axpy(s, du)
            self._residual(self.snes, r0, r1)
            f = r1.dot(du)
            return f if np.isfinite(f) else np.inf

        s, f0, f1 = 1.0, slope(0.0), slope(1.0)
        tol = PREDICTOR_ETA * abs(f0)
        if f0 < 0 < f1 and f1 > tol:  # the energy has a minimum inside: find it (bracket [a, b])
            a, fa, b, fb, side = 0.0, f0, 1.0, f1, 0
            for _ in range(30):
                # an end beyond the geometry (an exploded two-body state: no slope) is halved towards
                s = (a * fb - b * fa) / (fb - fa) if np.isfinite(fb) else (a + b) / 2
                f = slope(s)
                if abs(f) <= tol:
                    break
                if f < 0:
                    a, fa = s, f
                    fb, side = (fb / 2, -1) if side == -1 else (fb, -1)  # Illinois: halve the stale end
                else:
                    b, fb = s, f
                    fa, side = (fa / 2, 1) if side == 1 else (fa, 1)
        x.axpy(s, du)
        self._set_u(x)
        self.timings["assembly_s"] = assembly  # counted here, not as the Newton iterations' assembly
        self.timings["predictor_s"] += time.perf_counter() - start
        return s

    def _diagnose(self, reason: int) -> dict:
        """Classify the failed solve just done (see :mod:`fenics_contact.failure`)."""
        ksp = self.snes.getKSP()
        ksp_reason = _failure.reason_name(PETSc.KSP.ConvergedReason, ksp.getConvergedReason())
        condition = None
        if ksp_reason not in ("DIVERGED_PCSETUP_FAILED", "DIVERGED_PC_FAILED"):  # a failed factorization: no estimate
            condition = _failure.condition_estimate(self.A, ksp)
        out = _failure.classify(_failure.reason_name(PETSc.SNES.ConvergedReason, reason), ksp_reason,
                                self._history, self._sets, self._closed, condition, _failure.mumps_error(ksp))
        seen = [k for k in (c.take_failure() for c in self.problem.contacts) if k]
        if seen:  # what a surface saw (the same on every rank: the surfaces decide collectively)
            out["kind"] = seen[0]
        return out

    def condition_estimate(self) -> float | None:
        """Condition estimate of the last Jacobian (:func:`failure.condition_estimate`; direct solvers only,
        else None). Collective."""
        return _failure.condition_estimate(self.A, self.snes.getKSP())

    def run(self, loads: Sequence[float]) -> list[StepRecord]:
        """Solve at every load value of ``loads`` in turn (cutting steps in half when needed)."""
        if self.predictor and not self._converged:
            self._converged = [(self.t, self.problem.u.x.array.copy())]
        for target in loads:
            cuts = 0
            while self.t != target:
                t = target if cuts == 0 else self.t + (target - self.t) / 2**cuts
                snap = self._snapshot()
                rec = self._step(t, len(self.records) + 1)
                # petsc4py (>= 3.18) defers destroying objects whose last Python reference is dropped to a
                # per-communicator garbage list (destruction is collective): free it here, where every rank is.
                PETSc.garbage_cleanup(self.problem.comm)
                release_free_memory()
                self.record.newton_spent += rec.newton_iterations
                if rec.converged:
                    for c in self._stateful():
                        c.commit()  # history (friction, condensed slip reference) advances only on accepted steps
                    self.records.append(rec)
                    self.t = t
                    if self.predictor:
                        self._converged = [*self._converged[-1:], (t, self.problem.u.x.array.copy())]
                    self._progress(rec)
                    if self.on_step is not None:
                        self.on_step(t)
                    cuts = 0
                    continue
                self._rollback(snap)
                self.failures.append(rec.failure)
                self._progress(rec, failed=True)
                if self._grow_mumps_workspace(rec.failure):
                    continue  # the same step again, with more room for MUMPS: not a cutback
                cuts += 1
                if cuts > self.max_cutbacks:
                    self.records.append(rec)
                    raise ConvergenceError(
                        f"load step {rec.step} (t = {t:.6g}, from t = {self.t:.6g}) did not converge after "
                        f"{self.max_cutbacks} cutbacks: {describe(rec.failure)}, "
                        f"{rec.message or 'SNES reason ' + reason_text(rec.reason)}; "
                        f"the last converged state (t = {self.t:.6g}) has been written", rec.failure)
        return self.records

    def _grow_mumps_workspace(self, failure: dict | None) -> bool:
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
        for F in _failure.mumps_factors(self.snes.getKSP()):  # a refactorization of the same pattern keeps F
            F.setMumpsIcntl(14, grown)
        failure["message"] = f"MUMPS INFOG(1) = {info[0]}: work array too small; ICNTL(14) {now} -> {grown}"
        if self.problem.comm.rank == 0:
            logger.warning("%s, retrying the step", failure["message"])
        return True

    def _progress(self, rec: StepRecord, failed: bool = False) -> None:
        """One progress line per load step (and per failed attempt) on rank 0, through ``logging`` (INFO;
        ``quiet``: DEBUG)."""
        level = logging.DEBUG if self.quiet else logging.INFO
        if self.problem.comm.rank == 0 and logger.isEnabledFor(level):
            logger.log(level, progress_line(rec, failed))

    def linear_solve_time(self) -> float:
        """Seconds for one Jacobian assembly and one solve with a fresh linear solver of the same kind
        (factorization included): the cost floor of one linear elastic solve on this mesh (max over ranks).
        Frees the SNES's own factorization or multigrid hierarchy first (rebuilt if it solves again): two at
        once would double the peak memory of a large run."""
        self.snes.getKSP().reset()
        ksp = PETSc.KSP().create(self.problem.comm)
        # the SNES's linear-solver options (ours and the command line's), under the same prefix
        ksp.setOptionsPrefix(self.snes.getOptionsPrefix())
        with self.options.active(lambda k: k.startswith(("ksp_", "pc_", "mg_"))):
            ksp.setFromOptions()
            self._split_fields(ksp.getPC())
        x = self.b.duplicate()
        start = time.perf_counter()
        self._jacobian(self.snes, self._x, self.A, self.A)
        ksp.setOperators(self.A)
        with self.options.active(lambda k: k.startswith("fieldsplit_")):  # a nested split's blocks: see _newton
            ksp.solve(self.b, x)
        elapsed = time.perf_counter() - start
        ksp.destroy()
        x.destroy()
        return self.problem.comm.allreduce(elapsed, op=MPI.MAX)

    def summary(self) -> dict:
        """Totals over the converged steps; the time split is the maximum over ranks (:meth:`RunRecord.summary`).
        ``-fc_condition_estimate``: also the condition estimate of the last Jacobian (benchmarks' stability map).
        Collective."""
        condition = self.condition_estimate() if self.options.get_bool("condition_estimate", False) else None
        return self.record.summary(self.problem.comm, self.problem.contacts, self.linear_iterations, condition)
