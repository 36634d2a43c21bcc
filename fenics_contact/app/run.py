"""Run a scene set-up: solve; after every converged step write its fields, a checkpoint and ``summary.json`` with the
run's status; print the table. A stopped run goes on from its last completed step (``restart``).

``summary.json`` says ``status``: ``running`` (with the last completed step, and the writer's ``pid`` and
``host``), then ``converged`` or ``failed``, or ``interrupted`` after SIGTERM or SIGINT. A run killed otherwise
(SIGKILL) leaves ``running`` with a writer that no longer runs (:func:`~fenics_contact.output.process_alive`).
"""
from __future__ import annotations

import argparse
import json
import logging
import os
import resource
import shutil
import signal
import socket
import sys
import threading
import time
from contextlib import contextmanager, nullcontext
from pathlib import Path
from typing import Callable, Iterator, Sequence

from mpi4py import MPI

from .. import checkpoint
from ..output import OutputError, RunLock, XDMFWriter, on_rank0, process_alive, write_atomically, write_summary
from ..solver import ConvergenceError, Solver
from .checks import log_check
from .cli import check_petsc_options, recorded_options, refuse_condensed_solver
from .scenes import Setup, scale_alart_curnier

__all__ = ["run", "claim", "claimed", "CHECKPOINT"]

logger = logging.getLogger(__name__)

# PETSc options of ours read only after the run (Solver.summary): not checked after the first step
LATER_OPTIONS = ("condition_estimate",)
CHECKPOINT = "checkpoint"  # the checkpoints' folder in a run's output folder
RECORDS = ("summary.json", ".lock")  # a folder holding one of these holds a run's files
# what the names of a run's files (fields, summary, pictures, tables, logs) end in, and no folder of a run's
FILE_SUFFIXES = (".json", ".xdmf", ".h5", ".png", ".csv", ".md", ".txt")
IDENTITY = ("scene", "method", "parameters", "dofs", "ranks")  # what a restart must share with the run it continues
# On SIGTERM the ranks but rank 0 exit this much later (mpirun kills them about a second after it): rank 0 may be
# waiting in a collective for them before it can mark the summary ``interrupted``
RANK_GRACE_S = 0.5
_OURS: set[Path] = set()  # folders this process has run into (a demo's runs into subfolders of its own folder)


def run(setup: Setup, out: str | Path, method: str, method_params: dict, augment_max: int = 0,
        augment_tol: float = 1e-12, quiet: bool = False, options: dict | None = None, max_cutbacks: int = 4,
        on_iterate: Callable[[int], None] | None = None, predictor: bool | str = False,
        on_step: Callable[[float], None] | None = None, xdmf: bool = True,
        check: Callable[[dict], dict] | None = None, restart: bool = False, overwrite: bool = False,
        keep: Sequence[list | dict] = (), args: argparse.Namespace | None = None) -> dict:
    """Solve ``setup`` over its loads into the folder ``out`` (:func:`claim`: refused while another run writes
    there, or if it holds another run's files unless ``overwrite`` or ``restart``). After every converged step:
    its fields into ``out/<scene>.xdmf`` (``xdmf=False``: none, e.g. for benchmarks that time the solver alone),
    ``on_step(t)``, a checkpoint (``out/checkpoint``) and ``out/summary.json`` (``running``). ``restart``: go on
    from the checkpoint of the same run (scene, method, parameters, dofs, ranks, load path and the command line's
    options ``args`` that shape them, :func:`~fenics_contact.app.cli.recorded_options`) stopped in ``out``, or
    start if there is none; a difference is refused naming it, and so are a run whose checkpoint is missing and
    files it cannot go on with. ``keep``: the lists and dicts that ``on_step`` and ``on_iterate`` fill,
    checkpointed with the solver and refilled on a restart.

    Returns the summary (also in ``out/summary.json``). A step that fails after ``max_cutbacks`` cutbacks writes the
    summary with ``converged: false`` and ``failure`` (kind, step, iterations: :mod:`fenics_contact.failure`)
    and re-raises. ``on_iterate(it)`` is called after every Newton iterate; ``predictor``: see :class:`Solver`.
    ``check(summary)``: the demo's self-check (:func:`fenics_contact.app.checks.reference_check`), stored as
    ``check`` and logged (also for a failed run).
    ``newton_iterations``: those of the converged steps, or for a failed run every iteration it spent
    (``newton_iterations_spent``, failed attempts included). Times are this process's (``restarted_from``: the
    step it went on from). Progress and figures go to the log (INFO on rank 0; ``quiet``: DEBUG).
    """
    out = Path(out)
    comm = setup.problem.comm
    start = time.perf_counter()
    if args is not None:
        refuse_condensed_solver(args, setup)
    if getattr(args, "scaled_c", False):  # method lagrange with friction, no --K: c from the problem
        c = scale_alart_curnier(setup)
        if c is not None:
            method_params = {**method_params, "K": c}
    head = {"scene": setup.name, "method": method, "parameters": {**setup.parameters, **method_params},
            "dofs": setup.dofs, "ranks": comm.size, "loads": [float(t) for t in setup.loads],
            **({"options": recorded_options(args)} if args is not None else {})}
    lock, previous = claim(out, comm, head, overwrite=overwrite, restart=restart)
    record = _Record(out / "summary.json", head, comm, lock)
    level = logging.DEBUG if quiet else logging.INFO
    try:
        solver = Solver(setup.problem, augment_max=augment_max, augment_tol=augment_tol, quiet=quiet,
                        options=options, max_cutbacks=max_cutbacks, on_iterate=on_iterate, predictor=predictor)
        found = checkpoint.restore(solver, out / CHECKPOINT) if previous is not None else None
        completed = previous.get("load_steps") if previous is not None else None
        if found is None and isinstance(completed, int) and completed > 0 and \
                not checkpoint.steps(out / CHECKPOINT, comm)[0]:
            raise OutputError(f"--restart: {out} holds a run of {completed} completed load step"
                              f"{'s' * (completed > 1)} without their checkpoint ({out / CHECKPOINT} is missing or "
                              f"empty): it cannot go on; --overwrite starts afresh")
        done = len(solver.records)
        if found is not None:
            _refill(keep, found["extra"])
            record.head["restarted_from"] = {"step": done, "load": solver.t}
            if comm.rank == 0:
                logger.log(level, f"{setup.name} / {method}: going on from step {done} (t = {solver.t:.6g})")
        with XDMFWriter(out / f"{setup.name}.xdmf", setup.problem.u.function_space.mesh, setup.fields,
                        resume=done) if xdmf else nullcontext() as writer:
            record.head["fields"] = f"{setup.name}.xdmf" if xdmf else None

            def write(t: float) -> None:
                begin = time.perf_counter()
                if not written:  # the set-up and a whole solve are done: a command-line PETSc option unused by
                    written.append(t)  # now is misspelt (checked again at the end by cli.main, for those read later)
                    check_petsc_options(later=LATER_OPTIONS)
                with record.writing():
                    if writer is not None:
                        for c in setup.contacts:
                            c.update_output()
                        writer.write(t)
                    if on_step is not None:
                        on_step(t)
                    checkpoint.save(solver, out / CHECKPOINT, extra=list(keep))
                    record.progress(solver)
                output[0] += time.perf_counter() - begin

            written: list[float] = []
            output = [0.0]  # seconds in write: fields, checkpoint and progress, not the solve
            solver.on_step = write
            record.progress(solver)
            error = failure = None
            with _interruptible(record):
                try:
                    solver.run(setup.loads if found is None else found["pending"])
                except ConvergenceError as exc:
                    error, failure = str(exc), exc.failure
                    steps = writer.steps if writer is not None else 0
                    if writer is not None:
                        error += (f"; steps 1 to {steps} written to {writer.path}" if steps > 1 else
                                  f"; step 1 written to {writer.path}" if steps else "; no step converged, no fields")
        wall = comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
        summary = _summary(setup, solver, record.head, wall, comm.allreduce(output[0], op=MPI.MAX), error)
        solver.destroy()  # its matrices and factorization: not left to the end of the process (Solver.destroy)
        if check is not None:
            summary["check"] = check(summary)
            if summary["check"].get("flag"):  # the reference out of its range
                summary["warnings"].append(f"check: {summary['check']['flag']}")
            summary["check"]["warnings"] = len(summary["warnings"])  # the check's line notes them
        record.write(summary)
        on_rank0(comm, str(lock.path), lock.release)  # every rank returns with the folder free
    except BaseException as exc:
        record.abandon(exc)
        raise
    finally:
        if comm.rank == 0:  # not collective: the run may be ending on one rank's error
            lock.release()
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


def _summary(setup: Setup, solver: Solver, head: dict, wall: float, output: float, error: str | None) -> dict:
    """The run's summary at its end (figures reduced over the ranks). Collective. ``wall``: the run's seconds;
    ``output``: of them, those spent writing after each step (fields, checkpoint, progress): the solve is the
    rest (``solve_time_s``), the time ``ratio_to_linear_solve`` compares with one linear solve."""
    comm = setup.problem.comm
    record = solver.summary()
    floor = solver.linear_solve_time()
    memory = comm.allreduce(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0, op=MPI.MAX)
    converged = record["converged"] and error is None
    return {**{k: head[k] for k in IDENTITY}, "status": "converged" if converged else "failed",
            **{k: v for k, v in head.items() if k not in IDENTITY and k != "status"}, "wall_time_s": wall,
            "output_time_s": output, "solve_time_s": wall - output,
            "setup_time_s": setup.build_time_s, "time_split": record["time_split"],
            "linear_solve_floor_s": floor, "ratio_to_linear_solve": (wall - output) / floor, "memory_peak_mb": memory,
            "newton_iterations": record["newton_iterations"] if converged else record["newton_iterations_spent"],
            "newton_iterations_spent": record["newton_iterations_spent"],
            "augmentations": record["augmentations"], "linear_iterations": record["linear_iterations"],
            **{k: record[k] for k in ("stalled_solves", "residual_final", "condition_estimate")},
            "load_steps": record["load_steps"], "converged": converged,
            "error": error, "failure": record["failure"], "failures": record["failures"],
            "warnings": record["warnings"],
            **(setup.figures() if solver.records and solver.t > 0 else {}),
            "steps": record["steps"]}


def _refill(keep: Sequence[list | dict], saved: list) -> None:
    """Each of ``keep`` refilled in place with its checkpointed content."""
    for kept, content in zip(keep, saved or []):
        if isinstance(kept, dict):
            kept.clear()
            kept.update(content)
        else:
            kept[:] = content


class _Record:
    """``summary.json`` of a run under way: ``head`` (what the run is, who writes it) and its status. ``last`` is
    what the file holds, or is being replaced with: a signal handler writing ``last`` never writes an older state.
    The writes after a step (:meth:`writing`) are one: a signal arriving meanwhile is acted on once they are done,
    so that the fields, the checkpoint and the summary a stopped run leaves are of the same step."""

    def __init__(self, path: Path, head: dict, comm: MPI.Comm, lock: RunLock):
        self.path, self.comm, self.lock = path, comm, lock
        writer = comm.bcast({"pid": os.getpid(), "host": socket.gethostname(),
                             "started": time.strftime("%Y-%m-%d %H:%M:%S")}, root=0)
        self.head = {**head, "status": "running", **writer}
        self.last: dict | None = None  # the last summary written (or being written)
        self.busy = False  # inside writing()
        self.deferred: int | None = None  # a signal that came while busy
        self.interrupt: Callable[[int, object], None] | None = None  # the signal handler (_interruptible)

    def write(self, summary: dict) -> None:
        """Write ``summary`` (:func:`write_summary`). Collective."""
        self.last = summary  # first: the file is never newer than ``last``
        write_summary(self.path, summary, self.comm)

    def progress(self, solver: Solver) -> None:
        """``running``, with the steps completed so far. Collective."""
        done = [r for r in solver.records if r.converged]
        self.write({**self.head, "load_steps": len(done), "last_load": solver.t,
                    "newton_iterations": sum(r.newton_iterations for r in done), "converged": False,
                    "checkpoint": f"{CHECKPOINT}/step_{len(done):06d}" if done else None,
                    "steps": [r.as_dict() for r in done]})

    @contextmanager
    def writing(self) -> Iterator[None]:
        """The writes after a step (fields, checkpoint, summary) as one: SIGTERM or SIGINT meanwhile is acted on
        when they are done (or have failed)."""
        self.busy = True
        try:
            yield
        finally:
            self.busy = False
            if self.deferred is not None and self.interrupt is not None:
                signum, self.deferred = self.deferred, None
                self.interrupt(signum, None)

    def stop(self, status: str, **more) -> None:
        """The last summary with ``status`` if it was ``running`` (else as it is), by rank 0 alone and without
        raising (a run that is ending)."""
        if self.comm.rank != 0 or self.last is None:
            return
        final = {**self.last, "status": status, **more} if self.last["status"] == "running" else self.last
        try:
            write_atomically(self.path, json.dumps(final, indent=1, default=float))
        except OSError:
            pass  # the previous summary stays: ``running``, by a writer that will have ended

    def abandon(self, exc: BaseException) -> None:
        """The run ends with an error that is not a failed step (a file it could not write, a bug)."""
        self.stop("failed", error=f"{type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}")


@contextmanager
def _interruptible(record: _Record):
    """SIGTERM and SIGINT end the run: rank 0 marks the summary ``interrupted``, frees the folder and exits at once;
    the other ranks exit :data:`RANK_GRACE_S` later. Every completed step is on disk already; a signal that comes
    while a step's files are written is acted on once they are (:meth:`_Record.writing`). Not collective: a rank
    acts on its own signal (mpirun sends it to every rank)."""
    if threading.current_thread() is not threading.main_thread():
        yield
        return

    def stop(signum: int, frame) -> None:
        if record.busy:  # the step's files are being written: stop when they all are
            record.deferred = signum
            return
        if record.comm.rank != 0:  # rank 0 writes the summary: go on a moment, to end a collective it may wait in
            end = threading.Timer(RANK_GRACE_S, os._exit, (128 + signum,))
            end.daemon = True
            end.start()
            return
        name = signal.Signals(signum).name
        record.stop("interrupted", signal=name)
        try:
            record.lock.release()
            last = record.last or {}
            print(f"{record.head['scene']}: interrupted by {name} after step {last.get('load_steps', 0)}; "
                  f"--restart goes on from there", file=sys.stderr, flush=True)
        except (OSError, RuntimeError):  # RuntimeError: the signal came while stderr was being written
            pass
        os._exit(128 + signum)

    record.interrupt = stop
    before = {s: signal.signal(s, stop) for s in (signal.SIGTERM, signal.SIGINT)}
    try:
        yield
    finally:
        record.interrupt = None
        for s, handler in before.items():
            signal.signal(s, handler)


# --- the output folder ------------------------------------------------------------------------------------------

def claim(out: str | Path, comm: MPI.Comm, head: dict | None = None, overwrite: bool = False,
          restart: bool = False) -> tuple[RunLock, dict | None]:
    """Make the folder ``out`` this run's and lock it (:class:`~fenics_contact.output.RunLock`). Refused
    (:class:`~fenics_contact.output.OutputError`) while another run writes into it, and if it holds another run's
    files (``summary.json``, a lock) unless ``overwrite`` (then its content is deleted first, but for the
    subfolders this process has run into) or ``restart`` (kept: the run is the same as ``head``'s, in scene, method,
    parameters, dofs and ranks, and goes on). Returns the lock and, for a restart, the summary found there
    (None: there is none, start afresh). Collective."""
    if overwrite and restart:
        raise OutputError("--restart goes on with a run, --overwrite replaces it: give one of them")
    out = Path(out)
    lock = RunLock(out)

    def take() -> dict | None:
        if out.exists() and not out.is_dir():
            raise OutputError(f"{out} is a file, not a folder: give a folder as --out")
        try:
            out.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise OutputError(f"cannot make the output folder {out}: {exc.strerror or exc}") from None
        holder = lock.holder()
        alive = None if holder is None else lock.alive(holder)
        if alive:
            raise OutputError(f"{out} is in use by another run (pid {holder.get('pid', '?')} on "
                              f"{holder.get('host', '?')} since {holder.get('since', '?')}): wait for it to end, "
                              f"or give another --out")
        if holder is not None and alive is None:
            raise OutputError(f"{out} is locked by a run on {holder['host']} (pid {holder['pid']}): if it has "
                              f"ended, remove {lock.path}")
        previous = _read_summary(out / "summary.json")
        another = any((out / name).exists() for name in RECORDS)
        if holder is not None and "stale" in holder and previous is None and not (overwrite or restart):
            raise OutputError(f"{lock.path} is a stale lock ({holder['stale']}; no run writes into {out}): remove "
                              f"it, or give --overwrite")
        if another and not (overwrite or restart):
            raise OutputError(f"{out} holds the files of another run ({_describe(previous, holder)}): --overwrite "
                              f"replaces them, --restart goes on with that run; or give another --out")
        if another and overwrite:  # only a run's folder is emptied
            _empty(out)
        in_the_way = sorted(p.name for p in out.iterdir() if p.is_dir() and p.suffix in FILE_SUFFIXES)
        if in_the_way:
            raise OutputError(f"{out / in_the_way[0]} is a folder where the run writes a file: remove it, or give "
                              f"another --out")
        if restart and previous is not None and head is not None:
            _same_run(previous, head, out)
        if not restart or previous is None:  # a fresh start: an old run's checkpoints are not this run's
            for f in (out / CHECKPOINT).glob("step_*.pkl"):
                f.unlink()
        if not lock.acquire(replace=holder is not None):
            raise OutputError(f"{out} is in use by another run that has just started: give another --out")
        _OURS.add(out.resolve())
        return previous if restart else None

    return lock, on_rank0(comm, str(out), take)


@contextmanager
def claimed(out: str | Path, comm: MPI.Comm, overwrite: bool = False, restart: bool = False) -> Iterator[Path]:
    """:func:`claim` ``out`` for a demo that writes into it beside runs into its subfolders; the lock is released
    at the end. Collective."""
    lock, _ = claim(out, comm, overwrite=overwrite, restart=restart)
    try:
        yield Path(out)
        on_rank0(comm, str(lock.path), lock.release)
    finally:
        if comm.rank == 0:  # not collective: the demo may be ending on one rank's error
            lock.release()


def _read_summary(path: Path) -> dict | None:
    """The summary in ``path``; None if there is none; ``{"status": "unreadable summary.json"}`` if it is not a
    summary (not JSON, not an object, or a folder)."""
    try:
        found = json.loads(path.read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError):
        return {"status": "unreadable summary.json"}
    return found if isinstance(found, dict) else {"status": "unreadable summary.json"}


def _describe(summary: dict | None, holder: dict | None) -> str:
    """What a folder's run is, in a few words."""
    if summary is None and holder and "stale" in holder:
        return f"a stale lock, {holder['stale']}"
    if summary is None:
        return f"a lock of pid {holder.get('pid', '?')} on {holder.get('host', '?')}, which has ended" if holder \
            else "no summary"
    text = f"{summary.get('scene', '?')} / {summary.get('method', '?')}, {summary.get('status', 'no status')}"
    if summary.get("status") == "running" and process_alive(summary.get("pid", -1), summary.get("host", "")) is False:
        text += f", its writer (pid {summary['pid']}) has died"
    return text


def _same_run(previous: dict, head: dict, out: Path) -> None:
    """Refuse to go on with another run than ``head``'s."""
    mine = json.loads(json.dumps(head, default=float))
    before, now = previous.get("options"), mine.get("options")
    if isinstance(before, dict) and now is not None and previous.get("scene") == mine["scene"]:  # by option
        differ = [f for f in dict.fromkeys([*now, *before]) if before.get(f) != now.get(f) or
                  (f in before) != (f in now)]
        if differ:
            raise OutputError(f"--restart: {out} holds a run with {', '.join(_shown(f, before) for f in differ)}; "
                              f"this one has {', '.join(_shown(f, now) for f in differ)}: give that run's options, "
                              f"or --overwrite to start afresh")
    if previous.get("ranks") != mine["ranks"] and previous.get("ranks") is not None:
        raise OutputError(f"--restart: {out} holds a run on {previous['ranks']} ranks, this one has "
                          f"{mine['ranks']}: restart with the same number of ranks (mpirun -n {previous['ranks']})")
    if (previous.get("scene"), previous.get("method")) != (mine["scene"], mine["method"]):
        raise OutputError(f"--restart: {out} holds a run of {_describe(previous, None)}, not of {mine['scene']} / "
                          f"{mine['method']}: give another --out, or --overwrite")
    differ = [k for k in IDENTITY if previous.get(k) != mine[k]]
    if differ:
        what = [k for k in mine["parameters"] if previous.get("parameters", {}).get(k) != mine["parameters"][k]]
        raise OutputError(f"--restart: {out} holds another run ({_describe(previous, None)}; it differs in "
                          f"{', '.join(what or differ)}): give that run's options, or --overwrite")
    loads = previous.get("loads")
    if loads is not None and loads != mine["loads"]:
        def path(t: list) -> str:
            return f"{len(t)} load steps to t = {t[-1]:g}" if t and isinstance(t[-1], (int, float)) else str(t)
        raise OutputError(f"--restart: {out} holds a run of another load path ({path(loads)}; this one: "
                          f"{path(mine['loads'])}): give that run's options, or --overwrite to start afresh")


def _shown(flag: str, options: dict) -> str:
    """``flag`` with its value in ``options``, as on a command line (``no --flag``: not given, or off)."""
    value = options.get(flag)
    if value is None or value is False:
        return f"no {flag}"
    if value is True:
        return flag
    def text(v: object) -> str:
        return f"{v:.12g}" if isinstance(v, float) else str(v)
    return f"{flag} {' '.join(map(text, value)) if isinstance(value, list) else text(value)}"


def _empty(out: Path) -> None:
    """Delete what ``out`` holds but for the folders this process has run into (and those holding one)."""
    for entry in out.iterdir():
        path = entry.resolve()
        if any(path == ours or path in ours.parents for ours in _OURS):
            continue
        if entry.is_dir() and not entry.is_symlink():
            shutil.rmtree(entry)
        else:
            entry.unlink()
