"""The solver: load stepping with cutback and rollback, and the augmentation loop of each step."""
from __future__ import annotations

import logging
import os
import sys
import time
from typing import Callable, Sequence

import numpy as np
from mpi4py import MPI

from .. import checkpoint as checkpoints
from ..compat import free_petsc_garbage, petsc_vec, release_free_memory
from ..failure import cutback_helps
from ..problem import ContactProblem
from .newton import Newton
from .options import ScopedOptions, check_option_values, solver_options
from .predictor import PREDICTORS, Predictor
from .record import (
    ConvergenceError,
    RunRecord,
    StepRecord,
    augmentation_warning,
    cutback_warning,
    describe,
    progress_line,
    reason_text,
)
from .validity import inverted_failure, range_warnings, strain_warning

__all__ = ["Solver"]

logger = logging.getLogger(__package__)


def show_progress(wanted: bool = True) -> None:
    """If ``wanted`` (a solver not ``quiet``), make the progress lines (INFO) of the package's logger
    ``fenics_contact`` visible where no one chose its level: FFCx configures the root logger on import (a handler
    on stderr, level WARNING), which hides them. The package's logger then gets level INFO (and a handler on stderr
    if none reaches it): a plain script shows them on stderr. A level set by the user
    (``logging.getLogger("fenics_contact").setLevel(...)``) or by the command line is left alone."""
    package = logging.getLogger(__package__.rpartition(".")[0])
    if not wanted or package.level != logging.NOTSET or package.getEffectiveLevel() <= logging.INFO:
        return
    package.setLevel(logging.INFO)
    if not package.hasHandlers():
        package.addHandler(logging.StreamHandler(sys.stderr))


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


def _check_arguments(options, augment_max, augment_tol, max_cutbacks, predictor) -> None:
    """Refuse, before any work, a :class:`Solver` argument out of its range (one line naming it)."""
    if predictor not in PREDICTORS:
        raise ValueError(f"predictor must be one of {PREDICTORS}, got {predictor!r}")
    if augment_max < 0:
        raise ValueError(f"augment_max must be >= 0, got {augment_max}")
    if not augment_tol > 0:
        raise ValueError(f"augment_tol must be > 0, got {augment_tol}")
    if max_cutbacks < 0:
        raise ValueError(f"max_cutbacks must be >= 0, got {max_cutbacks}")
    check_option_values(options)


class Solver:
    """Drives a :class:`ContactProblem` through a sequence of load values.

    ``augment_max`` augmentations at most per load step (0: none), stopping when ``R = ||g_new - g_old|| <=
    augment_tol D`` (``R``: the gaps' change; ``D``: the size of the mesh, :meth:`ContactProblem.mesh_size`); a step
    that reaches ``augment_max`` first is accepted with a line in the run's warnings (``summary()["warnings"]``,
    logged at WARNING). A step whose SNES diverges is halved up to ``max_cutbacks`` times, each cutback a line of
    the warnings too (the failed solves: :attr:`failures`). ``on_step(t)`` is called after every converged step
    (output); ``on_iterate(it)`` after every Newton iterate, with ``problem.u`` at that iterate. Progress: one line
    per load step on rank 0 through ``logging`` (logger ``fenics_contact.solver``, INFO, shown in a plain script:
    :func:`show_progress`; ``quiet``: DEBUG, silent unless the log asks for it). ``predictor`` chooses the state
    each load step starts from: ``False`` the last converged state; ``"secant"`` (or ``True``) the linear
    extrapolation in ``t`` of the last two converged states; ``"tangent"`` the Euler predictor of
    :meth:`Predictor.tangent` (the tangent of the load path at the last converged state, scaled back to the
    energy's stationary point along it when the energy rises before its end: a contact that the step closes is
    not driven far into the obstacle). The tangent needs a force-based contact law (not ``bounded``).

    PETSc options (``prefix``, ``options``): see :mod:`.options`. The solver owns its PETSc objects (the SNES,
    ``A``, ``b``): :meth:`destroy` them, or use the solver as a context manager.

    Args:
        problem: the :class:`ContactProblem`.
        prefix: the PETSc options prefix.
        options: PETSc options (name without dash or prefix -> value) on top of the defaults; a value PETSc
            cannot use is a ``ValueError`` naming the option (:func:`~.options.check_option_values`).
        augment_max: augmentations at most per load step (0: none).
        augment_tol: the augmentation's tolerance on ``||g_new - g_old||`` (length).
        max_cutbacks: step halvings at most per load step.
        quiet: log the steps at DEBUG, not INFO.
        on_step: called with ``t`` after every converged step.
        on_iterate: called with the iteration number after every Newton iterate.
        predictor: ``False``, ``"secant"`` (or ``True``) or ``"tangent"``.
    """

    snes = _Delegated("newton")  # the SNES
    A = _Delegated("newton")  # the Jacobian matrix of the SNES
    b = _Delegated("newton")  # the residual vector of the SNES
    linear_iterations = _Delegated("newton")  # Krylov iterations of all Newton steps (1 per step for LU)
    on_iterate = _Delegated("newton")
    predictor = _Delegated("prediction", "kind")  # False, "secant" or "tangent"
    records = _Delegated("record")
    failures = _Delegated("record")  # every failed solve, also those rescued by a cutback
    timings = _Delegated("record")  # seconds on this rank per activity
    newton_spent = _Delegated("record")  # Newton iterations of every solve, also of failed attempts (cut back or final)
    _residual = _Delegated("newton", "residual")
    _jacobian = _Delegated("newton", "jacobian")

    def __init__(self, problem: ContactProblem, prefix: str = "fc_", options: dict | None = None,
                 augment_max: int = 0, augment_tol: float = 1e-12, max_cutbacks: int = 4,
                 quiet: bool = False, on_step: Callable[[float], None] | None = None,
                 on_iterate: Callable[[int], None] | None = None, predictor: bool | str = False):
        _check_arguments(options, augment_max, augment_tol, max_cutbacks, predictor)
        self.problem, self.quiet, self.on_step = problem, quiet, on_step
        show_progress(not quiet)
        self.augment_max, self.augment_tol, self.max_cutbacks = augment_max, augment_tol, max_cutbacks
        self.options = ScopedOptions(prefix, solver_options(problem, options), options)
        self.record = RunRecord(warnings=list(getattr(problem, "warnings", ())))
        self.newton = Newton(problem, self.options, self.record.timings, on_iterate)
        try:  # a misspelt option of the caller's: refused now, not silently ignored
            self.options.refuse_unused()
        except ValueError:
            self.newton.destroy()
            raise
        self.prediction = Predictor(predictor, self.newton, self.record.timings)
        self.t = 0.0  # the load of the last converged step
        self.pending: list[float] = []  # the load targets of run() still to reach after that step

    def destroy(self) -> None:
        """Destroy the solver's PETSc objects (SNES, ``A``, ``b``, work vectors) and the communicator's garbage
        (:func:`~fenics_contact.compat.free_petsc_garbage`; dropped, they outlive the mesh). Collective."""
        self.prediction.destroy()
        self.newton.destroy()
        free_petsc_garbage(self.problem.comm)

    def __enter__(self) -> Solver:
        return self

    def __exit__(self, *exc) -> None:
        self.destroy()

    def _grow_mumps_workspace(self, failure: dict | None) -> bool:
        """:meth:`LinearSolver.grow_mumps_workspace`: True if the failed step should be retried."""
        return self.newton.linear.grow_mumps_workspace(failure)

    def condition_estimate(self) -> float | None:
        """The last Jacobian's condition estimate (:func:`failure.condition_estimate`; direct solvers, else None).
        Collective."""
        return self.newton.condition_estimate()

    def linear_solve_time(self) -> float:
        """Seconds for one Jacobian assembly and one solve with a fresh linear solver of the same kind (factorization
        included): the cost floor of one linear elastic solve here, max over ranks (:meth:`LinearSolver.solve_time`).
        Collective."""
        newton = self.newton
        petsc_vec(self.problem.u).copy(newton.x)  # the current state (a step solver's too)
        self.problem.bulk_jacobian.reuse = False  # a fresh solve assembles the whole Jacobian
        try:
            return newton.linear.solve_time(newton.A, newton.x,
                                            lambda: newton.jacobian(newton.snes, newton.x, newton.A, newton.A))
        finally:
            self.problem.bulk_jacobian.reuse = True

    def summary(self) -> dict:
        """Totals over the converged steps; the time split is the maximum over ranks (:meth:`RunRecord.summary`);
        ``-fc_condition_estimate``: also the last Jacobian's condition estimate (stability map). Collective."""
        condition = self.condition_estimate() if self.options.get_bool("condition_estimate", False) else None
        return self.record.summary(self.problem.comm, self.problem.contacts, self.linear_iterations, condition)

    # --- load stepping ----------------------------------------------------
    def run(self, loads: Sequence[float], checkpoint: str | os.PathLike | None = None) -> list[StepRecord]:
        """Solve at every load value of ``loads`` in turn (cutting steps in half when needed). ``checkpoint``: a
        folder that gets the converged state after every step, after ``on_step`` (:func:`checkpoint.save
        <fenics_contact.checkpoint.save>`; :meth:`restart` goes on from it). Collective."""
        loads, comm = list(loads), self.problem.comm
        self.prediction.start(self.t)
        for i, target in enumerate(loads):
            cuts = 0
            while self.t != target:
                t = target if cuts == 0 else self.t + (target - self.t) / 2**cuts
                snap = self._snapshot()
                rec = self._step(t, len(self.records) + 1)
                free_petsc_garbage(self.problem.comm)  # the step's dropped objects, where every rank is
                release_free_memory()
                self.record.newton_spent += rec.newton_iterations
                if rec.converged:
                    snap[0].destroy()
                    for c in self.stateful():
                        c.commit()  # history (friction, condensed slip reference) advances only on accepted steps
                    self.records.append(rec)
                    strain_warning(self.problem, rec.step, rec.load, self.record.warnings, self.timings)
                    range_warnings(self.problem, rec.step, rec.load, self.record.warnings, self.timings)
                    if not rec.augmentation_converged:
                        self.record.warn(augmentation_warning(rec, self.augment_tol * self.problem.mesh_size()), comm)
                    self.options.refuse_unused_later(self.linear_iterations > 0)
                    self.t, self.pending = t, loads[i + 1:] if t == target else loads[i:]
                    self.prediction.accept(t)
                    self._progress(rec)
                    if self.on_step is not None:
                        self.on_step(t)
                    if checkpoint is not None:
                        checkpoints.save(self, checkpoint)
                    cuts = 0
                    continue
                self._rollback(snap)
                snap[0].destroy()
                self.failures.append(rec.failure)
                self._progress(rec, failed=True)
                if self._grow_mumps_workspace(rec.failure):
                    continue  # the same step again, with more room for MUMPS: not a cutback
                cuts += 1
                hopeless = not cutback_helps(rec.failure)  # out of memory: a smaller step factors the same pattern
                if cuts <= self.max_cutbacks and not hopeless:
                    self.record.warn(cutback_warning(rec, self.t, self.t + (target - self.t) / 2**cuts), comm)
                if cuts > self.max_cutbacks or hopeless:
                    self.records.append(rec)
                    raise ConvergenceError(
                        f"load step {rec.step} (t = {t:.6g}, from t = {self.t:.6g}) did not converge "
                        f"{'(a cutback cannot help)' if hopeless else f'after {self.max_cutbacks} cutbacks'}: "
                        f"{describe(rec.failure)}, "
                        f"{rec.message or rec.failure.get('message') or 'SNES reason ' + reason_text(rec.reason)}; "
                        f"the last converged state is t = {self.t:.6g}", rec.failure)
        return self.records

    def restart(self, folder: str | os.PathLike) -> list[float]:
        """Go back to the last checkpoint in ``folder`` with a step to solve (:func:`checkpoint.restore
        <fenics_contact.checkpoint.restore>`; this solver made as for the run that wrote it); returns the loads that
        run had still to reach (``solver.run(solver.restart(folder), checkpoint=folder)`` finishes it). Collective."""
        found = checkpoints.restore(self, folder)
        if found is None:
            raise ValueError(f"no checkpoint to go on from in {folder}")
        return found["pending"]

    def _progress(self, rec: StepRecord, failed: bool = False) -> None:
        """One progress line per load step (and failed attempt) on rank 0, logged (INFO; ``quiet``: DEBUG)."""
        level = logging.DEBUG if self.quiet else logging.INFO
        if self.problem.comm.rank == 0 and logger.isEnabledFor(level):
            logger.log(level, progress_line(rec, failed))

    def stateful(self) -> list:
        """The contacts and the step solver: everything with ``state``/``restore``/``commit``."""
        return [*self.problem.contacts, *([self.problem.step_solver] if self.problem.step_solver else [])]

    def _snapshot(self):
        """``problem.u`` (a copy, the caller's to destroy) and the states of :meth:`stateful`."""
        return petsc_vec(self.problem.u).copy(), [c.state() for c in self.stateful()]

    def _rollback(self, snap) -> None:
        """Back to the state of :meth:`_snapshot` ``snap``."""
        snap[0].copy(petsc_vec(self.problem.u))
        self.problem.u.x.scatter_forward()
        for c, s in zip(self.stateful(), snap[1]):
            c.restore(s)

    # --- one load step ----------------------------------------------------
    def _step(self, t: float, number: int) -> StepRecord:
        """Solve at load ``t`` with the augmentation loop; the record says whether it converged."""
        rec = StepRecord(step=number, load=t)
        start = time.perf_counter()
        newton = self.newton
        self.problem.set_load(t)
        if newton.bounded:
            newton.set_bounds(t)
        augmentable = [c for c in self.problem.contacts if c.augmentable]
        for c in augmentable:
            c.forget_gap()
        newton.reference, rec.predictor_scale = self.prediction.predict(t, self.t)
        while True:
            rec.reason = newton.solve()
            rec.residuals.append(newton.history)
            rec.closed_points.append(newton.closed)
            rec.message = newton.message
            # Accepted on the step length with the residual above tolerance: the round-off floor of the linear
            # solves. On a Jacobian whose condition estimate exceeds failure.ILL_CONDITIONED (direct solvers) the
            # step is then garbage (singular: a free rigid mode) and the solve fails as ill_conditioning;
            # otherwise it is accepted and recorded in ``stalled``.
            ill = False
            if rec.reason > 0 and newton.stalled(rec.reason):
                rec.stalled.append(rec.augmentations)
                ill = newton.ill_conditioned()
            if rec.reason <= 0 or ill:
                rec.failure = {"step": rec.step, "load": t, "augmentation": rec.augmentations,
                               **newton.diagnose(rec.reason), **({"message": rec.message} if rec.message else {})}
                break
            inverted = inverted_failure(self.problem, self.timings)  # a state that overlaps itself is no answer
            if inverted is not None:
                rec.message = inverted["message"]
                rec.failure = {"step": rec.step, "load": t, "augmentation": rec.augmentations,
                               "iterations": max(len(newton.history) - 1, 0), **inverted}
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
            if R <= self.augment_tol * self.problem.mesh_size():
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
