"""Seal flattened between two rigid plates (Zavarise et al. 1998): the whole load history at the default mesh
(cross-constraints, neo-Hookean): convergence of every step, Newton rate, contact zones over the history."""
import numpy as np
import pytest

from fenics_contact.laws import CrossConstraints
from fenics_contact.scenes import build, seal
from fenics_contact.solver import Solver


def solve(shape):
    setup = build("seal", law=CrossConstraints(seal.K_HAT, seal.F_HAT), shape=shape)
    figures = []
    solver = Solver(setup.problem, quiet=True, predictor=True, on_step=lambda t: figures.append((t, setup.figures())))
    solver.run(setup.loads)
    return solver, figures


@pytest.fixture(scope="module")
def history():
    return solve("S")


def test_every_step_converges_without_cutback(history):
    solver, figures = history
    assert solver.failures == [] and [r.load for r in solver.records] == pytest.approx(seal.LOADS)
    # SNES's test: |r| <= 1e-11 |r_0| or 1e-10 (the paper's steps end at ~1e-9 from ~1e4)
    assert all(r.converged and r.residuals[-1][-1] <= max(1e-10, 1e-11 * r.residuals[-1][0]) for r in solver.records)
    for _, f in figures:  # equilibrium: the plates push equally; the point-symmetric solution needs no support
        scale = max(f["plate_force_lower"], 1.0)
        assert abs(f["plate_force_lower"] - f["plate_force_upper"]) < 1e-6 * scale
        assert abs(f["reaction_P0_x"]) < 1e-6 * scale and abs(f["reaction_P0_y"]) < 1e-6 * scale


def test_quadratic_convergence_at_the_end_of_at_least_half_of_the_steps(history):
    solver, _ = history

    def quadratic(r):
        # log|r_k+1| / log|r_k| (|r_k| < 0.1) over the last three pairs of iterates: near 2 or above
        pairs = [(a, b) for a, b in zip(r[:-1], r[1:]) if 0 < a < 0.1][-3:]
        return any(np.log(b) / np.log(a) >= 1.8 for a, b in pairs)

    hits = [quadratic(r.residuals[-1]) for r in solver.records]
    assert sum(hits) >= len(hits) / 2, hits


@pytest.mark.xfail(strict=True, reason="does not hold on our seal: while the S rolls between the plates "
                   "(t <= 2.5, contact forces ~0, only the contacts resist the rotation) Newton needs 16-27 "
                   "iterations, and the last step 14")
def test_no_step_needs_more_than_10_iterations(history):
    solver, _ = history
    assert max(r.newton_iterations for r in solver.records) <= 10


def test_contacts_move_to_the_middle_a_corner_touches_and_a_zone_splits(history):
    _, figures = history
    t = np.array([s for s, _ in figures])
    lower = np.array([f["zones_lower"] for _, f in figures])
    upper = np.array([f["zones_upper"] for _, f in figures])
    # the S rolls: one contact per plate (the humps), moving toward the middle
    rolling = [f["zones_upper_x"][0] for s, f in figures if f["zones_upper"] == 1]
    assert len(rolling) >= 2 and rolling[-1][1] > rolling[0][1] + 0.5  # x of the upper contact, toward 0
    # then a new contact at the right end's corner on the upper plate (x ~ 13.49)
    corner = next(i for i, (_, f) in enumerate(figures) if f["zones_upper"] == 2)
    assert figures[corner][1]["zones_upper_x"][-1][0] > 13.0 and upper[corner] == 2
    # then the lower zone under the right hump splits in two that move apart
    split = int(np.argmax(lower == 3))
    assert lower[split] == 3 and t[split] > t[corner] and set(lower[split:]) == {3}
    hump = [f["zones_lower_x"][1:] for _, f in figures[split:]]
    inner, outer = [z[0][0] for z in hump], [z[1][1] for z in hump]  # edges move vertex by vertex
    assert all(np.diff(inner) <= 0) and inner[-1] < inner[0] - 1
    assert all(np.diff(outer) >= 0) and outer[-1] > outer[0] + 1


def test_u_shape_bottom_zone_splits_and_the_parts_move_apart():
    solver, figures = solve("U")
    assert solver.failures == [] and len(solver.records) == len(seal.LOADS)
    lower = [f["zones_lower"] for _, f in figures]
    assert [f["zones_upper"] for _, f in figures] == [2] * len(figures)  # the two inner corners, throughout
    split = lower.index(2)
    assert set(lower[:split]) == {1} and set(lower[split:]) == {2} and 0 < split < len(lower) - 1
    inner_edges = [f["zones_lower_x"][0][0] for _, f in figures[split:]]  # off the symmetry line, moving out
    assert inner_edges[0] > 0 and all(np.diff(inner_edges) > 0)
