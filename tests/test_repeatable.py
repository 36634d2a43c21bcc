"""The same input gives the same run on a fixed number of ranks: the Newton solver's linear solve returns the same
bits for the same system, and a friction scene whose Newton path decides stick or slip on the last bits (the
wedges: a whole interface changing from stick to slip) gives the same residual history and figures twice.

Serially this checks the serial solver; under ``mpirun -n 2`` the parallel one (an asynchronous parallel LU sums
the ranks' contributions in the order they arrive, and its solutions differ in the last bits from run to run)."""
from __future__ import annotations

import numpy as np

from fenics_contact.app.scenes import build
from fenics_contact.app.scenes.wedges import PREDICTOR
from fenics_contact.friction import Friction
from fenics_contact.laws import Penalty
from fenics_contact.solver import Solver

# A coarse wedges (the block pushed up the incline in 4 steps): its push turns the whole interface from stick to slip.
MESH, SLIDE_STEPS = ((20, 4), (6, 3)), 4


def _wedges():
    return build("wedges", law=Friction(Penalty(1e6), mu=0.3, omega_t=1e4), mesh=MESH, slide_steps=SLIDE_STEPS)


def _run() -> tuple[dict, list]:
    setup = _wedges()
    with Solver(setup.problem, predictor=PREDICTOR, quiet=True) as solver:
        solver.run(setup.loads)
        return setup.figures(), [r.residuals for r in solver.records]


def test_linear_solve_gives_the_same_bits():
    """The Newton solver's linear solver, 200 solves of the wedges' Jacobian under the vertical load with the same
    right-hand side: one solution, to the last bit, on every rank."""
    setup = _wedges()
    with Solver(setup.problem, predictor=PREDICTOR, quiet=True) as solver:
        solver.run(setup.loads[:1])
        newton = solver.newton
        x = newton.b.duplicate()
        seen = set()
        for _ in range(200):
            newton.linear.solve(newton.A, newton.b, x)
            seen.add(x.array_r.tobytes())
        x.destroy()
    assert len(seen) == 1


def test_wedges_twice_the_same():
    """The coarse wedges solved twice: the same Newton residual histories, bit for bit, and the same figures."""
    first, second = _run(), _run()
    assert second[1] == first[1]
    for k, v in first[0].items():
        assert np.array_equal(second[0][k], v), (k, v, second[0][k])


def test_distributed_lu_is_the_callers_choice():
    """On several ranks the Newton solver's LU is every rank's sequential MUMPS (``redundant``) unless the caller
    asks for ``distributed_lu``; one rank factors alone either way."""
    from mpi4py import MPI

    setup = _wedges()
    kinds = {}
    for distributed in (False, True):
        with Solver(setup.problem, quiet=True, options={"distributed_lu": distributed}) as solver:
            kinds[distributed] = solver.newton.linear.ksp.getPC().getType()
    assert kinds == {False: "redundant" if MPI.COMM_WORLD.size > 1 else "lu", True: "lu"}
