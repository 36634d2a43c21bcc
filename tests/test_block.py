"""Block on a rigid foundation (Zavarise et al. 1998): penalty, cross-constraints, augmented Lagrangian."""
import numpy as np
import pytest

from fenics_contact.app.scenes import block
from fenics_contact.laws import AugmentedLagrangian, CrossConstraints, Penalty
from fenics_contact.methods import make_law
from fenics_contact.solver import Solver

EXACT = block.EXACT_PRESSURE
F_HATS = [0.0, 100.0, 170.0, 180.0, 1000.0, 10000.0]


def solve(law, quadrature="nodal", augment_max=0, comm=None):
    setup = block.build(law, quadrature=quadrature, **({"comm": comm} if comm else {}))
    solver = Solver(setup.problem, augment_max=augment_max, augment_tol=1e-12, quiet=True)
    solver.run(setup.loads)
    return setup.figures(), solver.records[-1]


def test_exact_pressure_value():
    # the paper prints 175.8243; E/(1-nu^2) * 0.32/2 = 175.824176 (the paper's last digit is off by one)
    assert np.isclose(EXACT, 175.8243, rtol=1e-6)


@pytest.mark.parametrize("quadrature", ["nodal", "gauss"])
def test_penalty_penetration_is_p_over_K(quadrature):
    K = 1e5
    f, rec = solve(Penalty(K), quadrature)
    d = f["max_penetration"]
    assert d > 0
    assert np.isclose(d, f["contact_pressure"] / K, rtol=1e-6)
    assert np.isclose(f["contact_pressure"], EXACT * (1 - d / 0.32), rtol=1e-6)
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


@pytest.mark.parametrize("F_hat", F_HATS)
def test_cross_constraints_penetrates_below_and_opens_above_the_true_pressure(F_hat):
    f, _ = solve(CrossConstraints(1e5, F_hat))
    if F_hat < EXACT:
        assert f["max_penetration"] > 0
    else:
        assert f["max_penetration"] < 0
    # open or closed, the pressure follows the block's compliance exactly
    assert np.isclose(f["contact_pressure"], EXACT * (1 - f["max_penetration"] / 0.32), rtol=1e-6)


def test_cross_constraints_with_zero_target_equals_penalty():
    f_cc, _ = solve(CrossConstraints(1e5, 0.0))
    f_p, _ = solve(Penalty(1e5))
    assert np.isclose(f_cc["contact_pressure"], f_p["contact_pressure"], rtol=1e-12)
    assert np.isclose(f_cc["max_penetration"], f_p["max_penetration"], rtol=1e-10)


@pytest.mark.parametrize("quadrature", ["nodal", "gauss"])
@pytest.mark.parametrize("F_hat", F_HATS)
def test_augmented_cross_constraints_reach_the_exact_pressure(F_hat, quadrature):
    f, rec = solve(CrossConstraints(1e5, F_hat), quadrature, augment_max=10)
    assert rec.converged and rec.augmentation_converged
    assert rec.augmentations <= 10  # converged: the last gap change within augment_tol of the mesh size
    assert np.isclose(f["contact_pressure"], EXACT, rtol=1e-8)
    assert abs(f["max_penetration"]) < 1e-10
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


@pytest.mark.parametrize("quadrature", ["nodal", "gauss"])
def test_augmented_lagrangian_reaches_the_exact_pressure(quadrature):
    f, rec = solve(AugmentedLagrangian(1e5), quadrature, augment_max=10)
    assert rec.converged and rec.augmentation_converged
    assert np.isclose(f["contact_pressure"], EXACT, rtol=1e-8)


def test_snes_vi_is_exact_in_one_load_step():
    from fenics_contact.laws import SnesVI

    f, rec = solve(SnesVI())
    assert rec.converged and np.isclose(f["contact_pressure"], EXACT, rtol=1e-10)
    assert abs(f["max_penetration"]) <= 1e-12


def test_snes_vi_rejects_what_it_cannot_enforce():
    from fenics_contact.laws import SnesVI

    with pytest.raises(ValueError, match="quadrature 'nodal'"):
        solve(SnesVI(), quadrature="gauss")


@pytest.mark.parametrize("method,augment_max", [("lagrange", 0), ("vi", 0), ("auglag", 20)])
def test_plane_stress_exact_methods_give_the_plane_stress_pressure(method, augment_max):
    # plane stress (sigma_zz = 0, lambda* = 2 lambda mu / (lambda + 2 mu)): uniaxial stress, p = E * 0.32/2 = 160
    law = make_law(method, **({"K": 1e5} if method == "auglag" else {}))
    setup = block.build(law, plane="stress")
    solver = Solver(setup.problem, augment_max=augment_max, augment_tol=1e-12, quiet=True)
    solver.run(setup.loads)
    rec = solver.records[-1]
    assert rec.converged and (augment_max == 0 or rec.augmentation_converged)
    f = setup.figures()
    assert np.isclose(block.homogeneous_state("linear", "stress")["p_nominal"], 1000.0 * 0.16, rtol=1e-15)
    assert np.isclose(f["contact_pressure"], 160.0, rtol=1e-8)
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


def test_plane_stress_neohookean_exact_state():
    """Neo-Hookean plane stress (out-of-plane stretch l3 from P_33 = 0 per point): SNES VI reaches the closed
    form, and the lateral stretch equals l3 (equal lateral and thickness stretches of uniaxial stress)."""
    setup = block.build(make_law("vi"), plane="stress", model="neohookean")
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert solver.records[-1].converged
    exact = block.homogeneous_state("neohookean", "stress")
    f = setup.figures()
    assert np.isclose(f["contact_pressure"], exact["p_nominal"], rtol=1e-8)
    assert np.isclose(f["contact_pressure_cauchy"], exact["p_cauchy"], rtol=1e-8)
    assert np.isclose(exact["a"], exact["l3"]) and exact["a"] > 1.0
    u = setup.displacement
    X = u.function_space.tabulate_dof_coordinates()
    n_own = u.function_space.dofmap.index_map.size_local
    ux = u.x.array.reshape(-1, 2)[:n_own, 0]
    assert np.allclose(ux, (exact["a"] - 1.0) * X[:n_own, 0], rtol=0, atol=1e-10)


def test_plane_option_is_checked():
    with pytest.raises(ValueError, match="plane"):
        block.build(make_law("vi"), plane="strian")
