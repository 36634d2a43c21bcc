"""Run a scene set-up: solve, write XDMF per step and ``summary.json``, print the table."""
from __future__ import annotations

import resource
import time
from contextlib import nullcontext
from pathlib import Path
from typing import Callable

from mpi4py import MPI
from petsc4py import PETSc

from .output import XDMFWriter, write_summary
from .scenes import Setup
from .solver import ConvergenceError, Solver

__all__ = ["run"]


def run(setup: Setup, out: str | Path, method: str, method_params: dict, augment_max: int = 0,
        augment_tol: float = 1e-12, quiet: bool = False, options: dict | None = None, max_cutbacks: int = 4,
        on_iterate: Callable[[int], None] | None = None, predictor: bool | str = False,
        on_step: Callable[[float], None] | None = None, xdmf: bool = True) -> dict:
    """Solve ``setup`` over its loads; every converged step goes to ``out/<scene>.xdmf`` at once
    (``xdmf=False``: no field output, e.g. for benchmarks that time the solver alone).

    Returns the summary (also in ``out/summary.json``). A step that fails
    after ``max_cutbacks`` cutbacks writes the summary with ``converged: false``
    and ``failure`` (kind, step, iterations: :mod:`fenics_contact.failure`)
    and re-raises. ``on_iterate(it)`` is called after every Newton iterate, ``on_step(t)`` after every
    converged step (after its output); ``predictor``: see :class:`Solver`.
    """
    out = Path(out)
    comm = setup.problem.comm
    start = time.perf_counter()
    with XDMFWriter(out / f"{setup.name}.xdmf", setup.problem.u.function_space.mesh,
                    setup.fields) if xdmf else nullcontext() as writer:

        def write(t: float) -> None:
            if writer is not None:
                for c in setup.contacts:
                    c.update_output()
                writer.write(t)
            if on_step is not None:
                on_step(t)

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
               "newton_iterations": record["newton_iterations"], "augmentations": record["augmentations"],
               "linear_iterations": record["linear_iterations"],
               **{k: record[k] for k in ("stalled_solves", "residual_final", "condition_estimate")},
               "load_steps": record["load_steps"], "converged": record["converged"] and error is None,
               "error": error, "failure": record["failure"], "failures": record["failures"],
               **(setup.figures() if solver.records and solver.t > 0 else {}),
               "steps": record["steps"]}
    write_summary(out / "summary.json", summary, comm)
    if error is not None:
        raise ConvergenceError(error, failure)
    if not quiet:
        figures = {k: v for k, v in summary.items() if isinstance(v, float) and k != "wall_time_s"}
        PETSc.Sys.Print(f"{setup.name} / {method}: dofs {setup.dofs}, ranks {comm.size}, newton "
                        f"{summary['newton_iterations']}, augmentations {summary['augmentations']}, "
                        f"{wall:.2f} s", comm=comm)
        for k, v in figures.items():
            PETSc.Sys.Print(f"  {k:18s} {v: .10g}", comm=comm)
    return summary


