"""The ``axisphere`` scene: a sphere on a rigid plane and two elastic spheres, axisymmetric, against 3D Hertz."""
import numpy as np
import pytest
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app.scenes import axisphere, build


def solve(partner="plane", method="auglag", quadrature="nodal", comm=MPI.COMM_WORLD, **kw):
    law = fc.make_law(method, K=axisphere.DEFAULT_K)
    setup = build("axisphere", law=law, quadrature=quadrature, partner=partner, comm=comm, **kw)
    solver = fc.Solver(setup.problem, quiet=True, augment_max=30 if method == "auglag" else 0, augment_tol=1e-10)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    return setup.figures()


def test_sphere_on_a_rigid_plane_is_hertz():
    """a and p0 within 1 % of Hertz for the computed force (h = a / 14: measured p0 0.38 %, a 0.75 %); the contact
    force over the ring balances the equator's reaction."""
    f = solve(h_contact=0.005)
    assert f["p0_error"] < 1e-2 and f["a_error"] < 1e-2, f
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)
    assert 0.05 < f["a"] / axisphere.R < 0.1  # the approach's contact, small against R


def test_two_elastic_spheres_are_hertz():
    """Two spheres (R, and R2 = 2 R of half the modulus): a and p0 within 1 % of Hertz with the pair's E* and R*;
    the two-body force balances the equator's reaction."""
    f = solve("sphere", h_contact=0.005, E2=0.5 * axisphere.E)
    assert f["p0_error"] < 1e-2 and f["a_error"] < 1e-2, f
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-6)


@pytest.mark.parametrize("method,quadrature", [("penalty", "nodal"), ("nitsche", "nodal"), ("lagrange", "nodal")])
def test_methods_on_the_ring(method, quadrature):
    """Other enforcements of the rigid plane on the ring (pure penalty: its penetration p0 / K adds to the error,
    within 2 %): p0 and a of Hertz; the contact force balances the equator's reaction (Nitsche: its pressure
    integrated, not the residual's work-conjugate force: to the discretisation, 1e-4)."""
    law = {"penalty": lambda: fc.make_law("penalty", K=10 * axisphere.DEFAULT_K),
           "nitsche": lambda: fc.make_law("nitsche", gamma0=10.0),
           "lagrange": lambda: fc.make_law("lagrange", c=axisphere.DEFAULT_K)}[method]()
    setup = build("axisphere", law=law, quadrature=quadrature, h_contact=0.005)
    solver = fc.Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    f = setup.figures()
    assert f["p0_error"] < 2e-2 and f["a_error"] < 2e-2, f
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-4 if method == "nitsche" else 1e-8)


def test_same_answer_in_other_units():
    """Lengths x 10 and stresses x 1000: a scales by 10, p0 by 1000, the relative errors are the same."""
    f1 = solve(h_contact=0.01)
    law = fc.make_law("auglag", K=axisphere.DEFAULT_K * 100)
    setup = build("axisphere", law=law, R=10.0, E=1e6, approach=0.05, h_contact=0.1, contact_width=1.5, h_far=0.5)
    solver = fc.Solver(setup.problem, quiet=True, augment_max=30, augment_tol=1e-10)
    solver.run(setup.loads)
    f2 = setup.figures()
    assert np.isclose(f2["a"], 10 * f1["a"], rtol=1e-6) and np.isclose(f2["p0"], 1000 * f1["p0"], rtol=1e-6)


def test_parallel_equals_serial():
    """Under mpirun -n 2 the 2-rank figures equal those of each rank solving alone (COMM_SELF)."""
    for partner in ("plane", "sphere"):
        parallel = solve(partner, h_contact=0.01, comm=MPI.COMM_WORLD)
        serial = solve(partner, h_contact=0.01, comm=MPI.COMM_SELF)
        for k, v in serial.items():
            assert abs(parallel[k] - v) <= 1e-8 * max(abs(v), 1e-6 * serial["p0"]), (partner, k, parallel[k], v)


def test_bad_input():
    law = fc.make_law("auglag", K=1e6)
    with pytest.raises(ValueError, match="partner must be one of"):
        axisphere.build(law, partner="block")
    with pytest.raises(ValueError, match="nu must be in"):
        axisphere.build(law, nu=0.5)
    with pytest.raises(ValueError, match="h_contact must be a finite number > 0"):
        axisphere.build(law, h_contact=-1.0)
    with pytest.raises(ValueError, match="approach must be below"):
        axisphere.build(law, approach=0.6)
