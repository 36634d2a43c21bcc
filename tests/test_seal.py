"""Seal flattened between two rigid plates (Zavarise et al. 1998): the whole load history at the default mesh
(cross-constraints, neo-Hookean): convergence of every step, Newton rate, contact zones over the history."""
import numpy as np
import pytest

from fenics_contact.laws import CrossConstraints
from fenics_contact.scenes import build, seal
from fenics_contact.solver import Solver


@pytest.fixture(scope="module")
def history():
    setup = build("seal", law=CrossConstraints(seal.K_HAT, seal.F_HAT))
    figures = []
    solver = Solver(setup.problem, quiet=True, predictor=True, options={"snes_linesearch_type": "basic"},
                    on_step=lambda t: figures.append((t, setup.figures())))
    solver.run(setup.loads)
    return solver, figures


def test_every_step_converges_without_cutback(history):
    solver, figures = history
    assert solver.failures == [] and [r.load for r in solver.records] == pytest.approx(seal.LOADS)
    assert all(r.converged and r.residuals[-1][-1] < 1e-8 for r in solver.records)
    for _, f in figures:  # equilibrium: the plates push equally (the body is held by nothing else)
        assert np.isclose(f["plate_force_lower"], f["plate_force_upper"], rtol=1e-6)


def test_quadratic_convergence_at_the_end_of_at_least_half_of_the_steps(history):
    solver, _ = history

    def quadratic(r):
        # log|r_k+1| / log|r_k| (|r_k| < 0.1) over the last three pairs of iterates: near 2 or above
        pairs = [(a, b) for a, b in zip(r[:-1], r[1:]) if 0 < a < 0.1][-3:]
        return any(np.log(b) / np.log(a) >= 1.8 for a, b in pairs)

    hits = [quadratic(r.residuals[-1]) for r in solver.records]
    assert sum(hits) >= len(hits) / 2, hits


@pytest.mark.xfail(strict=True, reason="does not hold on our design of the seal: the first step (11 "
                   "iterations), the step where the bottom zone spreads (t = 5.5, 13) and the last (t = 6, 12) "
                   "need more than 10 Newton iterations")
def test_no_step_needs_more_than_10_iterations(history):
    solver, _ = history
    assert max(r.newton_iterations for r in solver.records) <= 10


def test_bottom_contact_zone_splits_and_the_parts_move_apart(history):
    _, figures = history
    lower = [f["zones_lower"] for _, f in figures]
    upper = [f["zones_upper"] for _, f in figures]
    assert upper == [2] * len(figures)  # the two upper (inner) corners, throughout
    split = lower.index(2)
    assert set(lower[:split]) == {1} and set(lower[split:]) == {2} and 0 < split < len(lower) - 1
    # after the split, the zones of the half model no longer touch the symmetry line and move outward
    inner_edges = [f["zones_lower_x"][0][0] for _, f in figures[split:]]
    assert inner_edges[0] > 0 and all(np.diff(inner_edges) > 0)
