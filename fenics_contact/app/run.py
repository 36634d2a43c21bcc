"""Run a scene set-up: solve, write XDMF per step and ``summary.json``, print the table."""
from __future__ import annotations

import logging
import resource
import time
from contextlib import nullcontext
from pathlib import Path
from typing import Callable

from mpi4py import MPI

from ..output import XDMFWriter, write_summary
from ..solver import ConvergenceError, Solver
from .checks import log_check
from .cli import check_petsc_options
from .scenes import Setup

__all__ = ["run"]

logger = logging.getLogger(__name__)

# PETSc options of ours read only after the run (Solver.summary): not checked after the first step
LATER_OPTIONS = ("condition_estimate",)


def run(setup: Setup, out: str | Path, method: str, method_params: dict, augment_max: int = 0,
        augment_tol: float = 1e-12, quiet: bool = False, options: dict | None = None, max_cutbacks: int = 4,
        on_iterate: Callable[[int], None] | None = None, predictor: bool | str = False,
        on_step: Callable[[float], None] | None = None, xdmf: bool = True,
        check: Callable[[dict], dict] | None = None) -> dict:
    """Solve ``setup`` over its loads; every converged step goes to ``out/<scene>.xdmf`` at once
    (``xdmf=False``: no field output, e.g. for benchmarks that time the solver alone).

    Returns the summary (also in ``out/summary.json``). A step that fails
    after ``max_cutbacks`` cutbacks writes the summary with ``converged: false``
    and ``failure`` (kind, step, iterations: :mod:`fenics_contact.failure`)
    and re-raises. ``on_iterate(it)`` is called after every Newton iterate, ``on_step(t)`` after every
    converged step (after its output); ``predictor``: see :class:`Solver`. ``check(summary)``: the demo's
    self-check (:func:`fenics_contact.app.checks.reference_check`), stored as ``check`` and logged (also for a
    failed run).
    ``newton_iterations``: those of the converged steps, or for a failed run every iteration it spent
    (``newton_iterations_spent``, failed attempts included). Progress and figures go to the log (INFO on rank 0;
    ``quiet``: DEBUG).
    """
    out = Path(out)
    comm = setup.problem.comm
    start = time.perf_counter()
    with XDMFWriter(out / f"{setup.name}.xdmf", setup.problem.u.function_space.mesh,
                    setup.fields) if xdmf else nullcontext() as writer:

        def write(t: float) -> None:
            if not written:  # the set-up and a whole solve are done: a command-line PETSc option unused by now is
                written.append(t)  # misspelt (checked again at the end by cli.main, for the options read later)
                check_petsc_options(later=LATER_OPTIONS)
            if writer is not None:
                for c in setup.contacts:
                    c.update_output()
                writer.write(t)
            if on_step is not None:
                on_step(t)

        written: list[float] = []
        solver = Solver(setup.problem, augment_max=augment_max, augment_tol=augment_tol, quiet=quiet,
                        options=options, on_step=write, max_cutbacks=max_cutbacks, on_iterate=on_iterate,
                        predictor=predictor)
        error = failure = None
        try:
            solver.run(setup.loads)
        except ConvergenceError as exc:
            error, failure = str(exc), exc.failure
    wall = comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
    record = solver.summary()
    floor = solver.linear_solve_time()
    memory = comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, op=MPI.MAX)
    summary = {"scene": setup.name, "method": method, "parameters": {**setup.parameters, **method_params},
               "dofs": setup.dofs, "ranks": comm.size, "wall_time_s": wall,
               "setup_time_s": setup.build_time_s, "time_split": record["time_split"],
               "linear_solve_floor_s": floor, "ratio_to_linear_solve": wall / floor, "memory_peak_mb": memory,
               "newton_iterations": record["newton_iterations"] if error is None and record["converged"]
               else record["newton_iterations_spent"], "newton_iterations_spent": record["newton_iterations_spent"],
               "augmentations": record["augmentations"],
               "linear_iterations": record["linear_iterations"],
               **{k: record[k] for k in ("stalled_solves", "residual_final", "condition_estimate")},
               "load_steps": record["load_steps"], "converged": record["converged"] and error is None,
               "error": error, "failure": record["failure"], "failures": record["failures"],
               **(setup.figures() if solver.records and solver.t > 0 else {}),
               "steps": record["steps"]}
    if check is not None:
        summary["check"] = check(summary)
    write_summary(out / "summary.json", summary, comm)
    level = logging.DEBUG if quiet else logging.INFO
    if comm.rank == 0 and error is None and logger.isEnabledFor(level):
        figures = {k: v for k, v in summary.items() if isinstance(v, float) and k != "wall_time_s"}
        logger.log(level, f"{setup.name} / {method}: dofs {setup.dofs}, ranks {comm.size}, newton "
                          f"{summary['newton_iterations']}, augmentations {summary['augmentations']}, {wall:.2f} s")
        for k, v in figures.items():
            logger.log(level, f"  {k:18s} {v: .10g}")
    if check is not None:
        log_check(summary["check"], comm)
    if error is not None:
        raise ConvergenceError(error, failure, summary["newton_iterations_spent"])
    return summary


