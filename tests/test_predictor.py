"""The solver's load-step predictors: on a linear problem the tangent (Euler) predictor is the solution of the next
step; a bad predictor name is refused."""
import pytest

from fenics_contact.laws import Penalty
from fenics_contact.scenes import build
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
