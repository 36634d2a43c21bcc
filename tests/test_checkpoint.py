"""Checkpoints (fenics_contact.checkpoint): a run stopped after a step and restarted from its checkpoint in a fresh
solver ends with the figures of an uninterrupted run (1e-8), serially and on every rank of the lane."""
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact import checkpoint
from fenics_contact.app.scenes import build
from fenics_contact.output import OutputError


class Stop(Exception):
    """What kills the run in these tests: raised by on_step before the step's checkpoint."""


# scene -> (builder arguments, predictor); each has several load steps and a state that a step changes
SCENES = {
    "slab coulomb": (lambda: dict(name="slab", law=fc.make_law("coulomb", mu=0.4), steps=4), False),
    "hertz vi": (lambda: dict(name="hertz", law=fc.make_law("vi"), steps=3), False),
    "mindlin coulomb": (lambda: dict(name="mindlin", law=fc.make_law("coulomb", mu=0.3), ratios=(0.5, 0.8),
                                     press_steps=2), False),
    "compliance3d friction": (lambda: dict(name="compliance3d", nx=8, ny=4, nz=2, drag_steps=2), False),
    "ironing": (lambda: dict(name="ironing", law=fc.Friction(fc.Penalty(1e5), mu=0.3, omega_t=1e4), drag=0.35,
                             drag_steps=2, margin=0.5, steady_from=0.15), "secant"),
}


# Restarted bit for bit: the SNES solves (the condensed exact method's dense Newton keeps a factorization that it
# updates row by row across steps: a restart factors afresh, the same answer to round-off)
BIT_FOR_BIT = ("hertz vi", "compliance3d friction", "ironing")


def _folder(tmp_path_factory, comm, name):
    return comm.bcast(str(tmp_path_factory.mktemp(name)) if comm.rank == 0 else None)


def _solve(kind, stop_after=None, folder=None, restart=False):
    kw, predictor = SCENES[kind]
    kw = kw()
    setup = build(kw.pop("name"), **kw)
    done = []

    def on_step(t):
        done.append(t)
        if stop_after is not None and len(done) > stop_after:
            raise Stop

    solver = fc.Solver(setup.problem, quiet=True, predictor=predictor, on_step=on_step)
    loads = solver.restart(folder) if restart else setup.loads
    try:
        solver.run(loads, checkpoint=folder)
    except Stop:
        pass
    return setup, solver


def _same_figures(a: dict, b: dict) -> None:
    for k, v in a.items():
        if isinstance(v, float):
            assert np.isclose(b[k], v, rtol=1e-8, atol=1e-12 * max(1.0, abs(v))), (k, v, b[k])


@pytest.mark.parametrize("kind", list(SCENES))
def test_restart_gives_the_uninterrupted_figures(kind, tmp_path_factory, comm):
    folder = _folder(tmp_path_factory, comm, "checkpoint")
    full, full_solver = _solve(kind)
    _solve(kind, stop_after=2, folder=folder)  # stopped in step 3: its checkpoint is step 2's
    assert checkpoint.steps(folder, comm)[0] == [2]
    restarted, solver = _solve(kind, folder=folder, restart=True)
    _same_figures(full.figures(), restarted.figures())
    assert [r.newton_iterations for r in solver.records] == [r.newton_iterations for r in full_solver.records]
    assert [r.load for r in solver.records] == [r.load for r in full_solver.records]
    assert solver.newton_spent == full_solver.newton_spent
    if kind in BIT_FOR_BIT:  # the same Jacobians (pattern and sums) and the same iterates, on every rank
        same = np.array_equal(full.problem.u.x.array, restarted.problem.u.x.array) and \
            [r.residuals for r in solver.records] == [r.residuals for r in full_solver.records]
        assert comm.allreduce(int(same), op=MPI.MIN) == 1
    n = len(full_solver.records)
    assert checkpoint.steps(folder, comm)[0] == [n - 1, n]  # the older ones deleted; the last step's kept
    again, solver = _solve(kind, folder=folder, restart=True)  # the run had ended: its last step solved again
    _same_figures(full.figures(), again.figures())
    assert [r.newton_iterations for r in solver.records] == [r.newton_iterations for r in full_solver.records]


def test_restart_needs_a_checkpoint_of_as_many_ranks(tmp_path_factory, comm):
    folder = _folder(tmp_path_factory, comm, "ranks")
    if comm.rank == 0:  # files as 3 ranks more than this run's would have written
        for r in range(comm.size + 3):
            (Path(folder) / f"step_000002.rank{r}of{comm.size + 3}.pkl").write_bytes(b"")
    comm.barrier()
    setup = build("block", law=fc.Penalty(1e5), comm=comm)
    solver = fc.Solver(setup.problem, quiet=True)
    with pytest.raises(ValueError, match=rf"written by {comm.size + 3} ranks.*mpirun -n {comm.size + 3}"):
        solver.restart(folder)
    empty = _folder(tmp_path_factory, comm, "empty")
    with pytest.raises(ValueError, match="no checkpoint to go on from"):
        solver.restart(empty)


def test_restart_refuses_another_mesh(tmp_path_factory, comm):
    folder = _folder(tmp_path_factory, comm, "mesh")
    _solve("hertz vi", stop_after=1, folder=folder)
    setup = build("slab", law=fc.make_law("coulomb", mu=0.4), steps=4)
    with pytest.raises(ValueError, match="another mesh or partition"):
        fc.Solver(setup.problem, quiet=True).restart(folder)


def test_a_checkpoint_that_cannot_be_written_fails_on_every_rank(tmp_path_factory, comm):
    folder = _folder(tmp_path_factory, comm, "unwritable")
    blocked = f"{folder}/file"  # a file where the folder should be: the write fails on every rank
    if comm.rank == 0:
        open(blocked, "w").close()
    comm.barrier()
    setup = build("block", law=fc.Penalty(1e5), comm=comm)
    with pytest.raises(OutputError, match="could not write the checkpoint of step 1"):
        fc.Solver(setup.problem, quiet=True).run(setup.loads, checkpoint=blocked)
    assert MPI.COMM_WORLD.allreduce(1) == comm.size
