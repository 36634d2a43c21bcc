import logging
import os
import tempfile

import numpy as np
import pytest
from mpi4py import MPI

# FFCx/UFL chatter at INFO level on every JIT compile.
logging.getLogger().setLevel(logging.WARNING)
logging.getLogger("UFL").setLevel(logging.ERROR)


@pytest.fixture
def comm():
    return MPI.COMM_WORLD


@pytest.fixture
def tangent_check():
    """``check(solver, x, d, eps, pairing) -> (J d, central difference of the residual along d)`` at the state
    ``x`` (PETSc vectors), asserting that ``pairing(contact)`` of every contact is the same at ``x +- eps d``
    as at ``x`` (a pairing change is a discrete event, not part of the derivative)."""
    def check(solver, x, d, eps, pairing):
        problem = solver.problem
        contacts = problem.contacts
        b = x.duplicate()
        problem.F(x, b)
        before = [pairing(c) for c in contacts]
        problem.J(x, solver.A)
        Jd = x.duplicate()
        solver.A.mult(d, Jd)
        r = []
        for s in (1.0, -1.0):
            xs = x.copy()
            xs.axpy(s * eps, d)
            bs = x.duplicate()
            problem.F(xs, bs)
            r.append(bs)
            assert all(np.array_equal(p, pairing(c)) for p, c in zip(before, contacts))
        fd = r[0].copy()
        fd.axpy(-1.0, r[1])
        fd.scale(0.5 / eps)
        return Jd, fd
    return check


@pytest.fixture
def contact_tangent_error(tangent_check):
    """``error(solver, x, d, pairing, A_bulk, master_rows) -> (relative error, master share)`` of the contact part
    of the tangent along ``d``: ``J d`` and the central difference (``tangent_check``, eps 1e-6) less the bulk
    stiffness ``A_bulk d``; relative error ``|fd - J d| / |J d|``; master share: the norm of that ``J d`` on this
    rank's ``master_rows`` (a mask of the local rows), over all ranks, over ``|J d|``."""
    def error(solver, x, d, pairing, A_bulk, master_rows):
        Jd, fd = tangent_check(solver, x, d, 1e-6, pairing)
        Bd = x.duplicate()
        A_bulk.mult(d, Bd)
        Jd.axpy(-1.0, Bd)
        fd.axpy(-1.0, Bd)
        master = np.sqrt(MPI.COMM_WORLD.allreduce(float(np.sum(Jd.array[master_rows] ** 2))))
        fd.axpy(-1.0, Jd)
        return fd.norm() / Jd.norm(), master / Jd.norm()
    return error


def pytest_configure(config):
    # Under mpirun every rank runs pytest: give each its own base temporary folder, or the
    # ranks clean up each other's folders. Tests that write from all ranks broadcast rank 0's path.
    comm = MPI.COMM_WORLD
    if comm.size > 1 and config.option.basetemp is None:
        config.option.basetemp = os.path.join(tempfile.gettempdir(), f"pytest-fc-rank{comm.rank}-of-{comm.size}")


@pytest.fixture(autouse=True)
def _petsc_options_unchanged():
    """No test may leave options in PETSc's database: a later solver with the same prefix would read them (a
    divergence tolerance, a line search, a linear solver left by one test changed another's answer)."""
    from petsc4py import PETSc

    opts = PETSc.Options()
    before = opts.getAll()
    yield
    after = opts.getAll()
    leaked = {k: v for k, v in after.items() if before.get(k) != v}
    for k in leaked:
        opts.delValue(k)
    for k, v in before.items():
        if k not in after:
            opts.setValue(k, v)
    assert not leaked, f"options left in PETSc's database: {leaked}"
