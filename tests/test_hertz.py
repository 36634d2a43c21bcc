"""Cylinder on a rigid plane against Hertz (plane strain)."""
import numpy as np
import pytest

from fenics_contact.laws import AugmentedLagrangian, CrossConstraints
from fenics_contact.scenes import hertz
from fenics_contact.solver import Solver


def solve(law, refinement=0):
    setup = hertz.build(law, refinement=refinement)
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
