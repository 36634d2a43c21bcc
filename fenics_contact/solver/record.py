"""What a run did: one record per load step, every failed solve, seconds per activity, and the summary of it all
(``summary.json``)."""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["ConvergenceError", "RunRecord", "StepRecord", "augmentation_warning", "cutback_warning", "describe",
           "progress_line", "reason_text"]

logger = logging.getLogger(__package__)


class ConvergenceError(RuntimeError):
    """A load step failed even after the allowed cutbacks; ``failure`` says why (see :mod:`failure`).

    Args:
        message: the one-line message.
        failure: the diagnosis (:mod:`failure`), or None.
        newton_iterations: Newton iterations spent, or None.
    """

    def __init__(self, message: str, failure: dict | None = None, newton_iterations: int | None = None):
        super().__init__(message)
        self.failure = failure
        self.newton_iterations = newton_iterations  # every iteration the run spent, if known (run.run)


@dataclass
class StepRecord:
    """One converged (or failed) load step: Newton residual histories per solve (one per augmentation).

    Args:
        step: the step's number (from 1).
        load: the load parameter ``t`` of the step.
        residuals: the Newton residual norms, one list per solve (augmentation).
        constraint_change: the augmentations' ``||g_new - g_old||`` (length).
        augmentations: the augmentations made.
        augmentation_converged: the augmentation met its tolerance.
        converged: the step converged.
        reason: the last SNES converged reason.
        wall_time_s: the step's wall time (s).
        closed_points: the number of closed contact points (all surfaces) at each Newton iterate, per solve.
        failure: the diagnosis of a failed step (:mod:`failure`), else None.
        message: the one-line message of a failed step.
        predictor_scale: the tangent predictor's scale, None without one.
        stalled: the solves that stopped at the round-off floor.
    """

    step: int
    load: float
    residuals: list[list[float]] = field(default_factory=list)
    constraint_change: list[float] = field(default_factory=list)
    augmentations: int = 0
    augmentation_converged: bool = True
    converged: bool = False
    reason: int = 0
    wall_time_s: float = 0.0
    closed_points: list[list[int]] = field(default_factory=list)  # closed contact points per iterate, per solve
    failure: dict | None = None  # why the last solve failed (failure.classify), with step, load, augmentation
    message: str = ""  # why a step failed, from a surface that solves the step itself
    predictor_scale: float | None = None  # the tangent predictor's scale s (predictor.Predictor.tangent)
    # solves that SNES accepted on the step length alone, their residual above rtol and atol: Newton stalled at
    # the round-off floor of an ill-conditioned Jacobian (failure.stalled)
    stalled: list[int] = field(default_factory=list)

    @property
    def newton_iterations(self) -> int:
        return sum(max(len(r) - 1, 0) for r in self.residuals)

    def as_dict(self) -> dict:
        return {"step": self.step, "load": self.load, "newton_iterations": self.newton_iterations,
                "residuals": self.residuals, "constraint_change": self.constraint_change,
                "augmentations": self.augmentations, "augmentation_converged": self.augmentation_converged,
                "converged": self.converged, "snes_reason": self.reason, "wall_time_s": self.wall_time_s,
                "closed_points": self.closed_points, "failure": self.failure, "message": self.message,
                "predictor_scale": self.predictor_scale, "stalled": self.stalled}


def _timings() -> dict[str, float]:
    # Seconds on this rank: forms assembled in the SNES callbacks, the whole SNES solves
    # (their difference is the linear solves and SNES's vector work), augmentation updates, the check of every
    # converged solve for inverted cells (det F).
    return {"assembly_s": 0.0, "snes_s": 0.0, "augmentation_s": 0.0, "active_set_s": 0.0, "predictor_s": 0.0,
            "validity_s": 0.0}


@dataclass
class RunRecord:
    """The load steps' records (converged, and the last failed one), every failed solve (also those rescued by a
    cutback), the warnings of the run (a model past its range: not failures), seconds per activity on this rank
    (``timings``: the parts of a solver add to it) and the Newton iterations of every solve (``newton_spent``,
    failed attempts included)."""

    records: list[StepRecord] = field(default_factory=list)
    failures: list[dict] = field(default_factory=list)
    warnings: list[str] = field(default_factory=list)  # a model or a reference out of its range (not a failure)
    timings: dict[str, float] = field(default_factory=_timings)
    newton_spent: int = 0

    def warn(self, text: str, comm: MPI.Comm) -> None:
        """A line of the run's warnings (a limit the run met, not a failure), logged on rank 0 (WARNING)."""
        self.warnings.append(text)
        if comm.rank == 0:
            logger.warning(text)

    def summary(self, comm: MPI.Comm, contacts, linear_iterations: int, condition: float | None) -> dict:
        """Totals over the converged steps; the time split is the maximum over ranks. ``contacts``: the surfaces
        (their own timings); ``linear_iterations``: Krylov iterations of all Newton steps; ``condition``: the
        condition estimate of the last Jacobian, or None. Collective."""
        done = [r for r in self.records if r.converged]
        t = {k: comm.allreduce(v, op=MPI.MAX) for k, v in self.timings.items()}
        # active_set_s: the per-iterate active-set log (failure diagnosis), inside the SNES solves too
        split = {"assembly_s": t["assembly_s"],
                 "linear_solve_s": max(t["snes_s"] - t["assembly_s"] - t["active_set_s"], 0.0),
                 "augmentation_s": t["augmentation_s"], "active_set_s": t["active_set_s"],
                 "predictor_s": t["predictor_s"], "validity_s": t["validity_s"]}
        # the surfaces' own work (two-body search, exchange, coupling: inside assembly_s), summed over surfaces
        own: dict[str, float] = {}
        for c in contacts:
            for k, v in c.timings().items():
                own[k] = own.get(k, 0.0) + v
        split.update({k: comm.allreduce(v, op=MPI.MAX) for k, v in sorted(own.items())})
        return {"time_split": split, "newton_iterations": sum(r.newton_iterations for r in done),
                "newton_iterations_spent": self.newton_spent,
                "augmentations": sum(r.augmentations for r in done), "linear_iterations": linear_iterations,
                "load_steps": len(done), "stalled_solves": sum(len(r.stalled) for r in done),
                "residual_final": done[-1].residuals[-1][-1] if done and done[-1].residuals[-1] else None,
                "condition_estimate": condition,
                "converged": bool(self.records) and all(r.converged for r in self.records),
                "failure": None if not self.records or self.records[-1].converged else self.records[-1].failure,
                "failures": self.failures, "warnings": list(self.warnings),
                "steps": [r.as_dict() for r in self.records]}


def augmentation_warning(rec: StepRecord, tolerance: float) -> str:
    """The warning of a step accepted at ``augment_max`` (``rec.augmentations``) with the gaps' change above
    ``tolerance`` (a length: ``augment_tol`` times the mesh size)."""
    return (f"augmentation stopped at augment_max = {rec.augmentations} at step {rec.step} (t = {rec.load:.6g}): the "
            f"gaps' change R = {rec.constraint_change[-1]:.3g} > augment_tol D = {tolerance:.3g}; the constraint is "
            "met only to R (raise augment_max, or K)")


def cutback_warning(rec: StepRecord, start: float, to: float) -> str:
    """The warning of a failed attempt ``rec`` from the load ``start``, cut back to the load ``to``."""
    return (f"step {rec.step} (t = {rec.load:.6g}, from t = {start:.6g}) failed: {describe(rec.failure)}; cut back "
            f"to t = {to:.6g}")


def reason_text(code: int) -> str:
    """``"NAME (code)"`` of a SNES converged reason."""
    names = {v: k for k, v in vars(PETSc.SNES.ConvergedReason).items() if isinstance(v, int)}
    return f"{names.get(code, '?')} ({code})"


def describe(failure: dict | None) -> str:
    """One line for a failure record."""
    if not failure:
        return "no diagnosis"
    text = f"{failure['kind']} after {failure['iterations']} iterations (augmentation {failure['augmentation']})"
    if failure["kind"] == "cycling" and failure.get("period"):
        text += f", active set repeating with period {failure['period']} from iterate {failure['start']}"
    return text


def progress_line(rec: StepRecord, failed: bool = False) -> str:
    """One line on a load step (``failed``: an attempt that is cut back)."""
    last = rec.residuals[-1][-1] if rec.residuals and rec.residuals[-1] else float("nan")
    why = f"{describe(rec.failure)} ({rec.message or reason_text(rec.reason)})"
    tag = f"FAILED: {why}, cutting the step" if failed else (
        f"aug {rec.augmentations:2d} R {rec.constraint_change[-1]:.2e}" if rec.constraint_change else "")
    return (f"step {rec.step:3d}  t {rec.load:9.4g}  newton {rec.newton_iterations:3d}  "
            f"|r| {last:9.2e}  {rec.wall_time_s:7.2f} s  {tag}")
