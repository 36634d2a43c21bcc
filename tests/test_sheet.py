"""Sheet over a (rigid) cylinder, quadratic elements: two-point multipliers / penalty against three-point penalty."""
import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact.laws import LagrangeMultiplier, Penalty, PenaltyMultiplier
from fenics_contact.scenes import build, sheet
from fenics_contact.solver import Solver

MESH = {"n_arc": 12, "n_leg": 4, "steps": 2}  # loads t = 0.5, 1


def solve(law, comm=MPI.COMM_WORLD):
    setup = build("sheet", law=law, comm=comm, **MESH)
    kept = {}
    solver = Solver(setup.problem, quiet=True, on_step=lambda t: kept.__setitem__(round(t, 6), setup.profile()))
    solver.run(setup.loads)
    return setup.figures(), kept


@pytest.fixture(scope="module")
def runs():
    laws = {"mult": LagrangeMultiplier(1e3), "two4": PenaltyMultiplier(1e4), "two6": PenaltyMultiplier(1e6),
            "three4": Penalty(1e4), "three6": Penalty(1e6)}
    return {k: solve(law) for k, law in laws.items()}


def test_equilibrium_and_exact_contact(runs):
    for name, (f, _) in runs.items():
        # the end's pull is carried by the cylinder (frictionless, no other support in y)
        assert np.isclose(f["contact_force_y"], f["end_force"], rtol=1e-8), name
        assert 0.8 < f["p_mean_arc"] / f["belt_T_over_R"] < 1.2, name  # belt formula p ~ T/R, thick sheet
    f, prof = runs["mult"]
    assert f["max_penetration"] <= 1e-12 and prof[1.0]["p"].min() >= -1e-10 * f["p_max"]


def test_two_point_penalty_approaches_the_multipliers(runs):
    for t in (0.5, 1.0):
        ref = runs["mult"][1][t]["p"]
        diff = {k: np.abs(runs[k][1][t]["p"] - ref).max() / ref.max() for k in ("two4", "two6", "three4", "three6")}
        assert diff["two6"] < diff["two4"] and diff["two6"] < 0.02, (t, diff)
        assert diff["three6"] > 0.02, (t, diff)  # the three-point pressure does not reach it


def test_three_point_penalty_oscillates_more_as_eps_grows(runs):
    for t in (0.5, 1.0):
        osc = {k: sheet.oscillation(runs[k][1][t]["p"]) for k in ("two4", "two6", "three4", "three6")}
        peak = runs["mult"][1][t]["p"].max()
        assert abs(osc["two4"]) < 1e-9 * peak and abs(osc["two6"]) < 1e-9 * peak  # linear on each facet
        assert osc["three6"] > osc["three4"] > 1e-3 * peak, (t, osc)


def test_multipliers_independent_of_c_and_of_ranks():
    f3, p3 = solve(LagrangeMultiplier(1e3))
    f5, p5 = solve(LagrangeMultiplier(1e5))
    assert np.allclose(p3[1.0]["p"], p5[1.0]["p"], rtol=0, atol=1e-8 * f3["p_max"])
    fs, ps = solve(LagrangeMultiplier(1e3), MPI.COMM_SELF)
    assert np.allclose(p3[1.0]["p"], ps[1.0]["p"], rtol=0, atol=1e-8 * f3["p_max"])
    for k in ("end_force", "p_max", "total_variation"):
        assert np.isclose(f3[k], fs[k], rtol=1e-8), k


def test_bad_input():
    with pytest.raises(ValueError, match="n_arc"):
        build("sheet", law=LagrangeMultiplier(), n_arc=0)
    with pytest.raises(ValueError, match="quadrature"):
        build("sheet", law=LagrangeMultiplier(), quadrature="gauss", **MESH)
