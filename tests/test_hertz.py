"""Cylinder on a rigid plane against Hertz (plane strain)."""
import numpy as np
import pytest

from fenics_contact.laws import AugmentedLagrangian, CrossConstraints
from fenics_contact.scenes import hertz
from fenics_contact.solver import Solver


def solve(law, refinement=0, **kw):
    setup = hertz.build(law, refinement=refinement, **kw)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged and r.augmentation_converged for r in solver.records)
    return setup.figures()


def test_hertz_formulas():
    a, p0 = hertz.hertz(P=1.0, R=1.0, E=1.0, nu=0.0)
    assert np.isclose(a, np.sqrt(4 / np.pi)) and np.isclose(p0 * np.pi * a / 2, 1.0)
    x = np.linspace(0, 2, 21)
    p = np.sqrt(np.clip(1 - x**2 / 1.23**2, 0, None))
    assert np.isclose(hertz.contact_half_width(x, p), 1.23, rtol=1e-12)


@pytest.mark.parametrize("law", [CrossConstraints(hertz.DEFAULT_K), AugmentedLagrangian(hertz.DEFAULT_K)],
                         ids=["cross", "auglag"])
def test_p0_and_a_within_2_percent_and_equilibrium(law):
    f = solve(law)
    assert f["p0_error"] < 0.02 and f["a_error"] < 0.02
    assert f["contact_nodes"] >= 5
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


def test_plane_stress_against_hertz_with_E_star_E():
    """Plane stress: Hertz with E* = E (not E/(1-nu^2)); the same approach presses less hard (the plane-strain
    formula would be off by (1-nu^2)^(-1/2) - 1 = 4.8 % in p0)."""
    a, p0 = hertz.hertz(P=1.0, R=1.0, E=1.0, nu=0.3, plane="stress")
    assert np.isclose(a, np.sqrt(4 / np.pi))
    f = solve(AugmentedLagrangian(hertz.DEFAULT_K), plane="stress")
    strain = solve(AugmentedLagrangian(hertz.DEFAULT_K))
    assert f["p0_error"] < 0.01 and f["a_error"] < 0.02
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)
    assert f["total_force"] < strain["total_force"]


def test_refinement_reduces_p0_error():
    errors = [solve(AugmentedLagrangian(hertz.DEFAULT_K), r)["p0_error"] for r in (0, 1)]
    assert errors[1] < errors[0]


def test_snes_vi_reference_is_the_augmented_limit():
    """Exact nodal enforcement (SNES VI) and converged augmentation solve the same discrete problem."""
    from fenics_contact.laws import Exact

    vi = solve(Exact())
    aug = solve(AugmentedLagrangian(hertz.DEFAULT_K))
    assert np.isclose(vi["p0"], aug["p0"], rtol=1e-6) and np.isclose(vi["a"], aug["a"], rtol=1e-6)
    assert np.isclose(vi["total_force"], vi["reaction_top"], rtol=1e-8)


def test_neohookean_inverted_state_is_rejected_and_cut_back():
    """Neo-Hookean, approach 0.01 in 2 steps with SNES VI: the first Newton solve converges to a state with
    inverted elements (min det F = -1.18 measured) whose contact force is 40 % off; the solver rejects it as
    ``inverted_elements``, cuts the step back and reaches the state of the multipliers (min det F ~ 0.96)."""
    from fenics_contact.laws import make_law

    setup = hertz.build(make_law("vi"), model="neohookean", approach=0.01, steps=2)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    assert any(f["kind"] == "inverted_elements" and f["min_jacobian"] <= 0 for f in solver.failures)
    assert setup.problem.min_jacobian() > 0.9
    f = setup.figures()
    ref = hertz.build(make_law("lagrange"), model="neohookean", approach=0.01, steps=2)
    ref_solver = Solver(ref.problem, quiet=True)
    ref_solver.run(ref.loads)
    assert not ref_solver.failures
    assert np.isclose(f["total_force"], ref.figures()["total_force"], rtol=1e-8)
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


def test_meshed_plate_with_multipliers():
    """Two-body contact of the disk on the meshed stiff plate with the slave pressure as an unknown (method
    lagrange): Hertz within 2 % and equilibrium."""
    from fenics_contact.laws import LagrangeMultiplier

    setup = hertz.build(LagrangeMultiplier(hertz.DEFAULT_K), plate="meshed")
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    f = setup.figures()
    assert f["p0_error"] < 0.02 and f["a_error"] < 0.02, (f["p0_error"], f["a_error"])
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)
