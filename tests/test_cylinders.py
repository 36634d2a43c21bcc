"""Two neo-Hookean cylinders between rigid plates: Hertz at small load, both surfaces, equilibrium."""
import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact.app.scenes import build, cylinders
from fenics_contact.methods import make_law
from fenics_contact.solver import Solver


def solve(comm=MPI.COMM_WORLD, quadrature="gauss"):
    setup = build("cylinders", law_factory=lambda: make_law("penalty", K=cylinders.DEFAULT_K),
                  loads=[cylinders.T_HERTZ], comm=comm, quadrature=quadrature)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    return setup, solver


@pytest.fixture(scope="module", params=["gauss", "segment"])
def solved(request):
    """Two-pass, Gauss points (the demo's default) or segment-to-segment integration (:mod:`mortar`)."""
    return solve(quadrature=request.param)


def test_hertz_formulas():
    a, p0 = cylinders.hertz_two_cylinders(10.0, 8.0, 8.0)
    # Equal radii: R = 4; E* = E / (2 (1 - nu^2)) with E = 499.2, nu = 0.3.
    Es = 499.2 / (2 * (1 - 0.09))
    assert np.isclose(a, np.sqrt(4 * 10 * 4 / (np.pi * Es))) and np.isclose(p0 * np.pi * a / 2, 10.0)


def test_hertz_both_surfaces_and_equilibrium(solved):
    setup, solver = solved
    f = setup.figures()
    assert f["p0_error"] < 0.03 and f["a_error"] < 0.03, f
    assert f["pressure_mismatch"] < 0.02, f
    # The upper cylinder: plate force = contact force between the cylinders = lower plate force.
    assert np.isclose(f["plate_force"], f["total_force"], rtol=1e-6)
    assert np.isclose(f["lower_plate_force"], f["total_force"], rtol=1e-6)
    # Newton converges quadratically once the contact set settles.
    res = solver.records[0].residuals[0]
    # (measured: ... 1.3e-2, 4.5e-6, 6.5e-12: e_{k+1} ~ e_k^2)
    assert res[-1] < 1e-10 * res[0] and res[-1] <= 10 * res[-2] ** 2 and res[-2] <= 10 * res[-3] ** 2, res


def test_ranks_agree(solved):
    """The same figures on all ranks of COMM_WORLD as on one rank (each rank re-solves alone)."""
    if MPI.COMM_WORLD.size == 1:
        pytest.skip("needs mpirun")
    setup, _ = solved
    fp = setup.figures()
    fs = solve(MPI.COMM_SELF, setup.parameters["quadrature"])[0].figures()
    for k in ("total_force", "p0", "a", "plate_force", "pressure_mismatch"):
        assert abs(fp[k] - fs[k]) <= 1e-8 * max(abs(fs[k]), 1e-3), (k, fp[k], fs[k])
