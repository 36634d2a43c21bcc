"""The figures do not depend on the number of ranks: each rank also solves the scene alone (COMM_SELF).

Under ``mpirun -n 2`` this compares the 2-rank solution with the serial one;
serially it checks that the solve is deterministic.
"""
import pytest
from mpi4py import MPI

from fenics_contact.app.scenes import build
from fenics_contact.laws import AugmentedLagrangian, CrossConstraints, SnesVI
from fenics_contact.solver import Solver


def figures(scene, law, comm, **kw):
    setup = build(scene, law=law, comm=comm, **kw)
    Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True).run(setup.loads)
    return setup.figures()


@pytest.mark.parametrize("scene,law,kw", [
    ("block", lambda: CrossConstraints(1e5, 100.0), {"quadrature": "gauss"}),
    ("block", lambda: AugmentedLagrangian(1e5), {}),
    ("hertz", lambda: CrossConstraints(1e6), {}),
    ("hertz", lambda: SnesVI(), {}),
], ids=["block-cross-gauss", "block-auglag", "hertz-cross", "hertz-vi"])
def test_parallel_equals_serial(scene, law, kw):
    parallel = figures(scene, law(), MPI.COMM_WORLD, **kw)
    serial = figures(scene, law(), MPI.COMM_SELF, **kw)
    for k, v in serial.items():
        scale = max(abs(v), abs(serial.get("contact_pressure", serial.get("p0", 1.0))) * 1e-6)
        assert abs(parallel[k] - v) <= 1e-8 * scale, (k, parallel[k], v)
