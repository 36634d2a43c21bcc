"""Ring between two rigid plates (Zavarise et al. 1998): after one augmentation the penalty method cycles,
cross-constraints converges."""
import numpy as np
import pytest

from fenics_contact.app.scenes import build, ring
from fenics_contact.laws import CrossConstraints, Penalty
from fenics_contact.solver import ConvergenceError, Solver

BASIC = {"snes_linesearch_type": "basic"}  # the paper's plain Newton


def solve(law, options=BASIC, augment=1):
    setup = build("ring", law=law)
    solver = Solver(setup.problem, augment_max=augment, max_cutbacks=0, quiet=True, options=options)
    error = None
    try:
        solver.run(setup.loads)
    except ConvergenceError as exc:
        error = exc
    return setup, solver.records[-1], error


def test_first_step_identical_for_both_methods_and_three_points_per_plate():
    setup, rec, _ = solve(Penalty(ring.K, augmented=True), augment=0)
    f = setup.figures()
    _, rec_cross, _ = solve(CrossConstraints(ring.K, 0.0), augment=0)
    assert rec.converged and rec.residuals[0][-1] < 1e-9 and rec_cross.residuals[0][-1] < 1e-9
    # F^ = 0: the cross-constraints law is the penalty law, iterate by iterate
    assert np.allclose(rec.residuals[0], rec_cross.residuals[0], rtol=1e-8)
    assert f["closed_points_per_plate"] == 3
    # the paper's 0.19e-3 (centre) and 0.13e-3 (neighbours), on an unknown mesh: same size within 10 %
    assert abs(f["penetration_centre"] - 0.19e-3) < 0.1 * 0.19e-3
    assert abs(f["penetration_neighbour"] - 0.13e-3) < 0.1 * 0.13e-3
    assert np.isclose(f["plate_force"], f["reaction_mid"], rtol=1e-8)


@pytest.mark.parametrize("linesearch", ["basic", "l2"])
def test_penalty_with_augmentation_is_detected_as_cycling(linesearch):
    _, rec, error = solve(Penalty(ring.K, augmented=True), {"snes_linesearch_type": linesearch})
    assert rec.residuals[0][-1] < 1e-9  # the first solve converged
    assert isinstance(error, ConvergenceError) and "cycling" in str(error)
    fail = error.failure
    assert fail["kind"] == "cycling" and fail["step"] == 1 and fail["augmentation"] == 1
    assert fail["period"] >= 2 and fail["repeats"] >= 2
    closed = rec.closed_points[1]
    if linesearch == "basic":
        assert closed[1] < closed[0]  # the first iterate opens a point (its force jumps to zero) ...
    assert len(set(closed[fail["start"]:])) >= 2  # ... and the number of closed points keeps changing


def test_cross_constraints_converges_after_the_same_augmentation():
    _, rec, error = solve(CrossConstraints(ring.K, 0.0))
    assert error is None and rec.converged and rec.augmentations == 1
    assert rec.residuals[0][-1] < 1e-9
    assert len(rec.residuals[1]) - 1 <= 6 and rec.residuals[1][-1] < 1e-9
    closed = rec.closed_points[1]
    assert closed[1] < closed[0]  # the same point opens ...
    assert len(set(closed[1:])) == 1  # ... but stays open, carried by the exponential branch
