"""Papadopoulos & Solberg's collocated two-body element (P2 facets) on the concentric rings against Lamé."""
import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact.app.scenes import build
from fenics_contact.laws import LagrangeMultiplier, Penalty, PenaltyMultiplier
from fenics_contact.solver import Solver


def solve(law, comm=MPI.COMM_WORLD, **kw):
    setup = build("rings", law=law, degree=2, quadrature="collocated", comm=comm, **kw)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    return setup, setup.figures()


@pytest.fixture(scope="module")
def runs():
    return {n: solve(LagrangeMultiplier(1e3), n=n) for n in (8, 16)}


def test_collocated_multipliers_exact_on_the_curved_interface(runs):
    """Both surfaces' pressures (per reference length) within 0.5 % of Lamé everywhere at the default mesh
    (measured 0.06 %), converging faster than h^2 (0.32 % at n = 8); the interface force and u_r too."""
    (_, f8), (setup, f16) = runs[8], runs[16]
    assert f16["p_max_deviation"] < 1.5e-3 and f8["p_max_deviation"] > 4 * f16["p_max_deviation"]
    assert f16["p_reaction_deviation"] < 5e-4 and f16["ur_a_deviation"] < 3e-3 and f16["ur_c_deviation"] < 5e-4
    a, b = setup.contacts
    assert f16["points"] == 2 * 16 + 1 + 2 * 12 + 1  # every node of both surfaces carries a pressure
    # node on node (the meshes' common vertices at 0, 22.5, 45, 67.5, 90 degrees): one pressure
    Xa, _, ga, pa = a.point_table("cauchy")
    Xb, _, gb, pb = b.point_table("cauchy")
    va, vb = np.isfinite(ga), np.isfinite(gb)  # the vertices (a gap each)
    d = np.linalg.norm(Xa[va][:, None] - Xb[vb][None], axis=2)
    i, j = np.nonzero(d < 1e-6)
    assert len(i) == 5 and np.allclose(pa[va][i], pb[vb][j], rtol=1e-12)


def test_penalty_approaches_the_multipliers(runs):
    """p = eps <g> at the vertices of both surfaces, the middle value collocated: no locking, the pressure
    approaches the multipliers' as eps grows."""
    _, ref = runs[16]
    _, f6 = solve(PenaltyMultiplier(1e6), n=16)
    _, f5 = solve(PenaltyMultiplier(1e5), n=16)
    assert f5["p_reaction_deviation"] > 5 * f6["p_reaction_deviation"]
    assert f6["p_max_deviation"] < 2.5e-3 and abs(f6["p_min"] - ref["p_min"]) < 2e-3 * ref["p_lame"]


def test_serial_equals_ranks(runs):
    _, here = runs[8]
    _, alone = solve(LagrangeMultiplier(1e3), n=8, comm=MPI.COMM_SELF)
    for k in ("p_max_deviation", "p_mean_deviation", "p_reaction", "ur_a", "ur_c", "p_min", "p_max"):
        assert np.isclose(here[k], alone[k], rtol=1e-8, atol=0), (k, here[k], alone[k])


def test_bad_input():
    with pytest.raises(ValueError, match="collocated"):
        build("rings", law=LagrangeMultiplier(1e3), degree=1, quadrature="collocated")
    with pytest.raises(ValueError, match="collocated"):
        build("rings", law=Penalty(1e6), degree=2, quadrature="collocated")
