"""The solver's load-step predictors: on a linear problem the tangent (Euler) predictor is the solution of the next
step; a bad predictor name is refused."""
import pytest

from fenics_contact.app.scenes import build
from fenics_contact.laws import Penalty
from fenics_contact.solver import Solver


def first_residuals(predictor):
    setup = build("block", law=Penalty(1e5), steps=4)  # linear elasticity, flat obstacle, penalty
    solver = Solver(setup.problem, quiet=True, predictor=predictor)
    solver.run(setup.loads)
    return solver.records


def test_tangent_predictor_is_exact_on_a_linear_problem():
    # once the whole base is closed (steps 2-4) the block is a linear problem in (u, t): the tangent of the load
    # path at the last converged state reaches the next one; without a predictor the step starts far from it
    plain, tangent = first_residuals(False), first_residuals("tangent")
    for p, r in zip(plain[1:], tangent[1:]):
        assert r.residuals[0][0] < 1e-7 * p.residuals[0][0]  # forward difference of dR/dt: ~1e-10 relative
        assert r.predictor_scale == 1.0 and r.newton_iterations <= 1
    assert all(r.converged for r in tangent)


def test_bad_predictor_names_the_parameter():
    setup = build("block", law=Penalty(1e5))
    with pytest.raises(ValueError, match="predictor"):
        Solver(setup.problem, predictor="quadratic")


def test_a_far_predicted_state_does_not_pass_the_relative_tolerance():
    """Two-body Hertz from rest (penalty, force control): the tangent predictor of the first step drives the disk
    through the block (residual ~3e11). Newton's relative tolerance then refers to the out-of-balance of the last
    converged state at the new load, not to the predicted one: every step ends converged in absolute terms (it
    stopped at a residual of 2.0, "converged" at 1e-11 x 3e11, before)."""
    from fenics_contact.methods import make_law

    setup = build("hertz", law=make_law("penalty", K=2.5e4), refinement=1, plate="meshed", E=200.0, nu=0.3, R=8.0,
                  load=10.0, plate_E=200.0, plate_width=32.0, plate_depth=16.0)
    solver = Solver(setup.problem, quiet=True, predictor="tangent")
    solver.run(setup.loads)
    for r in solver.records:
        assert r.converged and r.residuals[-1][-1] < 1e-9, (r.load, r.residuals[-1])
    f = setup.figures()
    assert f["load_error"] < 1e-9 and f["p0_error"] < 5e-3, (f["load_error"], f["p0_error"])
