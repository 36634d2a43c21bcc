"""Checkpoints: a solver's converged state after each load step, one file per rank, to go on with a stopped run.

``Solver.run(loads, checkpoint=folder)`` writes them; ``Solver.restart(folder)`` goes back to the last one.

A checkpoint holds this rank's ``u`` (owned and ghost values), every surface's and the step solver's ``state()``
(and a surface's ``log`` of committed steps), the load, the load targets still to reach, the predictor's last
converged states and the step records. Each rank's file is written under a temporary name and renamed; a step's
checkpoint counts once every rank's file is there, and the one before it is then deleted (but for a run's last
step). A restart needs the same mesh, partition and number of ranks. The files are pickles: load only checkpoints
you wrote.
"""
from __future__ import annotations

import hashlib
import pickle
import re
from pathlib import Path

from mpi4py import MPI

from .output import OutputError, write_atomically

__all__ = ["save", "restore", "steps"]

FORMAT = 1
_FILE = re.compile(r"step_(\d+)\.rank(\d+)of(\d+)\.pkl")


def _file(folder: Path, step: int, comm) -> Path:
    return folder / f"step_{step:06d}.rank{comm.rank}of{comm.size}.pkl"


def _fingerprint(problem) -> str:
    """This rank's mesh nodes and number of values of ``u``: the same mesh and partition, or not."""
    h = hashlib.sha1(problem.u.function_space.mesh.geometry.x.tobytes())
    h.update(str(problem.u.x.array.size).encode())
    return h.hexdigest()


# what restore reads from a checkpoint (every checkpoint of this FORMAT has them)
_KEYS = ("format", "step", "fingerprint", "t", "pending", "u", "stateful", "predictor", "records", "failures",
         "newton_spent", "linear_iterations", "extra")


def _read(folder: Path, step: int, comm) -> dict:
    """This rank's checkpoint of ``step``; ``ValueError`` on every rank if a rank's cannot be read (truncated,
    emptied, not a checkpoint). Collective."""
    path = _file(folder, step, comm)
    data, error = None, None
    try:
        data = pickle.loads(path.read_bytes())
    except Exception as exc:  # noqa: BLE001 - whatever unpickling a damaged file raises
        error = f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else 'no data'}"
    if error is None and not (isinstance(data, dict) and all(k in data for k in _KEYS)):
        error = "not a checkpoint"
    errors = [e for e in comm.allgather(None if error is None else f"{path} ({error})") if e]
    if errors:
        raise ValueError(f"cannot go on from the checkpoint of step {step}: {errors[0]}; it is damaged (truncated, "
                         f"emptied or overwritten)")
    return data


def steps(folder: str | Path, comm) -> tuple[list[int], set[int]]:
    """The steps whose checkpoint is complete in ``folder`` for ``comm.size`` ranks, and the other numbers of ranks
    that wrote checkpoints there. Collective."""
    mine, sizes = set(), set()
    for f in Path(folder).glob("step_*.pkl"):
        m = _FILE.fullmatch(f.name)
        if m and int(m[3]) == comm.size and int(m[2]) == comm.rank:
            mine.add(int(m[1]))
        elif m and int(m[3]) != comm.size:
            sizes.add(int(m[3]))
    return sorted(set.intersection(*map(set, comm.allgather(mine)))), sizes


def save(solver, folder: str | Path, extra: object = None) -> int:
    """Write ``solver``'s converged state (and ``extra``, anything picklable the caller keeps across steps) into
    ``folder``; returns its step (converged steps so far). Then delete this rank's older checkpoints, but the one
    before a run's last step (:func:`restore` solves that step again). :class:`~fenics_contact.output.OutputError`
    on every rank if a rank cannot write. Collective."""
    folder, comm = Path(folder), solver.problem.comm
    step = sum(r.converged for r in solver.records)
    data = {"format": FORMAT, "step": step, "ranks": comm.size, "fingerprint": _fingerprint(solver.problem),
            "t": solver.t, "pending": list(solver.pending), "u": solver.problem.u.x.array.copy(),
            "stateful": [{"state": c.state(), **({"log": list(c.log)} if isinstance(getattr(c, "log", None), list)
                                                 else {})} for c in solver.stateful()],
            "predictor": solver.prediction.converged, "records": solver.records, "failures": solver.failures,
            "warnings": solver.record.warnings, "newton_spent": solver.newton_spent,
            "linear_iterations": solver.linear_iterations, "force_scale": solver.newton.force_scale, "extra": extra}
    error = None
    try:
        folder.mkdir(parents=True, exist_ok=True)
        write_atomically(_file(folder, step, comm), pickle.dumps(data, protocol=pickle.HIGHEST_PROTOCOL))
    except OSError as exc:
        error = f"could not write the checkpoint of step {step} in {folder}: {exc.strerror or exc}"
    errors = [e for e in comm.allgather(error) if e]
    if errors:
        raise OutputError(errors[0])
    keep = step if solver.pending else step - 1
    for f in folder.glob(f"step_*.rank{comm.rank}of{comm.size}.pkl"):
        if int(f.name[5:11]) < keep:
            f.unlink(missing_ok=True)
    return step


def restore(solver, folder: str | Path) -> dict | None:
    """Bring ``solver`` (made as for the run that wrote ``folder``, not yet run) to the last complete checkpoint in
    ``folder`` with a load step still to solve: for a run that had ended, the one before its last step (what a
    surface derives from a solve, e.g. its pairing, comes back with it). Returns its ``step``, ``t``, ``pending``
    (the load targets still to reach) and ``extra`` (as given to :func:`save`), or None if there is none.
    ``ValueError`` if the checkpoint is of another number of ranks, mesh or partition. Collective."""
    folder, comm, problem = Path(folder), solver.problem.comm, solver.problem
    done, sizes = steps(folder, comm)
    if not done:
        if sizes:
            n = " or ".join(str(s) for s in sorted(sizes))
            raise ValueError(f"{folder}: the checkpoint was written by {n} ranks, this run has {comm.size}: "
                             f"restart with the same number of ranks (mpirun -n {n})")
        return None
    data = _read(folder, done[-1], comm)
    if not data["pending"]:  # the run had ended
        if len(done) < 2:
            return None
        data = _read(folder, done[-2], comm)
    same = data.get("format") == FORMAT and data["fingerprint"] == _fingerprint(problem)
    if not comm.allreduce(same, op=MPI.LAND):
        raise ValueError(f"{folder}: the checkpoint is of another mesh or partition than this run's")
    problem.u.x.array[:] = data["u"]
    problem.u.x.scatter_forward()
    for c, saved in zip(solver.stateful(), data["stateful"]):
        c.restore(saved["state"])
        if "log" in saved:
            c.log = saved["log"]
    problem.set_load(data["t"])  # after the logs: a problem may take its load from them (force control)
    if problem.step_solver is None:
        # the kept Jacobian of the load reached, as the run that wrote the checkpoint had it: its residuals are then
        # products with it where that run's were (kept.AffineResidual), to the last bit
        problem.bulk_jacobian.current(problem.bcs, problem.stiffness)
    solver.t, solver.pending = data["t"], data["pending"]
    solver.prediction.converged = data["predictor"]
    solver.records[:], solver.failures[:] = data["records"], data["failures"]
    solver.record.warnings[:] = data.get("warnings", [])
    solver.newton_spent, solver.linear_iterations = data["newton_spent"], data["linear_iterations"]
    solver.newton.force_scale = data.get("force_scale")  # the absolute tolerance of the run it goes on
    return {"step": data["step"], "t": data["t"], "pending": list(data["pending"]), "extra": data["extra"]}
