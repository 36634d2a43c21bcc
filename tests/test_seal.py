"""Seal flattened between two rigid plates (Zavarise et al. 1998): the whole load history at the default mesh
(wave-shaped section, cross-constraints, neo-Hookean): convergence of every step, Newton rate, contact zones over
the history; the S and U alternatives."""
import numpy as np
import pytest

from fenics_contact.app.meshes import seal_wave_geometry
from fenics_contact.app.scenes import build, seal
from fenics_contact.laws import CrossConstraints
from fenics_contact.solver import Solver


def solve(shape):
    setup = build("seal", law=CrossConstraints(seal.K_HAT, seal.F_HAT), shape=shape)
    figures = []
    solver = Solver(setup.problem, quiet=True, predictor=seal.PREDICTOR[shape], options=seal.SOLVER_OPTIONS,
                    on_step=lambda t: figures.append((t, setup.figures())))
    solver.run(setup.loads)
    return solver, figures


@pytest.fixture(scope="module")
def history():
    return solve("wave")


def test_every_step_converges_without_cutback(history):
    solver, figures = history
    assert solver.failures == [] and [r.load for r in solver.records] == pytest.approx(seal.LOADS)
    # the solver's test: |r| <= 1e-11 |r_0| or its absolute floor (the paper's steps end at ~1e-9 from ~1e4)
    atol = solver.newton.atol
    assert all(r.converged and r.residuals[-1][-1] <= max(atol, 1e-11 * r.residuals[-1][0]) for r in solver.records)
    for _, f in figures:  # equilibrium: the two plates push equally (nothing else holds the band vertically)
        assert abs(f["plate_force_lower"] - f["plate_force_upper"]) < 1e-6 * max(f["plate_force_lower"], 1.0)
    forces = [f["plate_force_lower"] for _, f in figures]
    assert forces[0] > 0 and all(np.diff(forces) > 0)  # a structure with stiffness: the force grows every step


def test_quadratic_convergence_at_the_end_of_at_least_half_of_the_steps(history):
    solver, _ = history

    def quadratic(r):
        # on residuals scaled by the step's first one (unit-free): e_k = |r_k| / |r_0|; over the last three
        # pairs with e_k < 0.1, log e_k+1 / log e_k near 2 or above on one of them
        e = np.array(r) / r[0]
        pairs = [(a, b) for a, b in zip(e[:-1], e[1:]) if 0 < a < 0.1][-3:]
        return any(np.log(b) / np.log(a) >= 1.8 for a, b in pairs)

    hits = [quadratic(r.residuals[-1]) for r in solver.records]
    assert sum(hits) >= len(hits) / 2, hits


def test_no_step_needs_more_than_10_iterations(history):
    # the paper's Table I: 5-8; here 3-8 (the tangent predictor, seal.PREDICTOR; the secant one needed 16 and 17
    # where the outer corner lands, t = 2.0 and 2.5)
    solver, _ = history
    its = [r.newton_iterations for r in solver.records]
    assert max(its) <= 10, its


def test_contacts_move_to_the_middle_a_corner_touches_and_zones_split(history):
    _, figures = history
    geo = seal_wave_geometry(seal.R_OUT, seal.R_IN, seal.GAP)
    lower = [f["zones_lower"] for _, f in figures]  # whole section: each half's zone counts twice
    upper = [f["zones_upper"] for _, f in figures]  # ... but a zone on the symmetry line x = 0 once
    # the zone counts over the history: upper 1 (crown) -> 3 (+ the two outer corners) -> 4 (the crown zone
    # leaves the middle: two zones); lower 2 (the humps) -> 4 (each hump's zone split in two)
    corner, crown_split, split = upper.index(3), upper.index(4), lower.index(4)
    assert set(upper[:corner]) == {1} and set(upper[corner:crown_split]) == {3} and set(upper[crown_split:]) == {4}
    assert set(lower[:split]) == {2} and set(lower[split:]) == {4}
    assert 0 < corner < crown_split <= split < len(figures) - 1
    # while only the crown and the humps touch, each hump's contact point travels toward the middle
    hump = [f["zones_lower_x"][0][1] for _, f in figures[:corner + 1]]
    assert all(np.diff(hump) <= 0) and hump[-1] < geo["C2"][0] - 1.5
    # the new contact is the upper right corner of the band's end (inner arc), a mesh vertex
    assert figures[corner][1]["zones_upper_x"][-1] == pytest.approx([geo["corner_in"][0]] * 2, abs=1e-8)
    # the crown zone has left x = 0; the hump's zone splits into two that move apart (edges vertex by vertex)
    assert all(f["zones_upper_x"][0][0] > 0 for _, f in figures[crown_split:])
    parts = [f["zones_lower_x"] for _, f in figures[split:]]
    inner, outer = [z[0][0] for z in parts], [z[1][1] for z in parts]
    assert all(np.diff(inner) <= 0) and inner[-1] < inner[0] - 2
    assert all(np.diff(outer) >= 0) and outer[-1] > outer[0] + 2


def test_u_shape_bottom_zone_splits_and_the_parts_move_apart():
    solver, figures = solve("U")
    assert solver.failures == [] and len(solver.records) == len(seal.LOADS)
    lower = [f["zones_lower"] for _, f in figures]
    assert [f["zones_upper"] for _, f in figures] == [2] * len(figures)  # the two inner corners, throughout
    split = lower.index(2)
    assert set(lower[:split]) == {1} and set(lower[split:]) == {2} and 0 < split < len(lower) - 1
    inner_edges = [f["zones_lower_x"][0][0] for _, f in figures[split:]]  # off the symmetry line, moving out
    assert inner_edges[0] > 0 and all(np.diff(inner_edges) > 0)


def test_bad_shape_names_the_parameter():
    with pytest.raises(ValueError, match="seal shape"):
        build("seal", law=CrossConstraints(seal.K_HAT, seal.F_HAT), shape="O")


def test_s_shape_rolls_then_a_corner_touches_and_a_zone_splits():
    solver, figures = solve("S")  # rolling is a mechanism: step 1 is cut once (README), the rest converges
    assert [r.load for r in solver.records][-len(seal.LOADS) + 1:] == pytest.approx(seal.LOADS[1:])
    for _, f in figures:  # the point-symmetric solution needs no support at P0
        scale = max(f["plate_force_lower"], 1.0)
        assert abs(f["reaction_P0_x"]) < 1e-6 * scale and abs(f["reaction_P0_y"]) < 1e-6 * scale
    t = np.array([s for s, _ in figures])
    lower = np.array([f["zones_lower"] for _, f in figures])
    rolling = [f["zones_upper_x"][0] for _, f in figures if f["zones_upper"] == 1]
    assert len(rolling) >= 2 and rolling[-1][1] > rolling[0][1] + 0.5  # the upper contact moves toward x = 0
    corner = next(i for i, (_, f) in enumerate(figures) if f["zones_upper"] == 2)
    assert figures[corner][1]["zones_upper_x"][-1][0] > 13.0  # the right end's corner (x ~ 13.49)
    split = int(np.argmax(lower == 3))
    assert lower[split] == 3 and t[split] > t[corner] and set(lower[split:]) == {3}
