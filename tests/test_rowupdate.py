"""The semismooth Newton's dense solver (:class:`~fenics_contact.condensed.rowupdate.RowUpdatedSolve`): a matrix
changed in a few rows is solved by updating the base inverse (Sherman-Morrison-Woodbury), to round-off."""
import numpy as np
import pytest

from fenics_contact.condensed.rowupdate import REFACTOR, RowUpdatedSolve, SingularMatrix


def test_row_updates_equal_a_fresh_solve():
    """A sequence of matrices each differing from the base in a few rows (then in most): every solution equals
    LU's to 1e-12 (relative), the few-row changes by an update, the many-row change by a new inverse."""
    rng = np.random.default_rng(0)
    n = 120
    J = rng.standard_normal((n, n)) + n * np.eye(n)
    solver = RowUpdatedSolve()
    for k in (0, 1, 5, 20, int(REFACTOR * n)):
        Jk = J.copy()
        rows = rng.choice(n, size=k, replace=False)
        Jk[rows] = rng.standard_normal((k, n)) + n * np.eye(n)[rows]
        b = rng.standard_normal(n)
        x = solver.solve(Jk, b)
        assert np.max(np.abs(x - np.linalg.solve(Jk, b))) <= 1e-12 * np.max(np.abs(x))
    assert (solver.factorizations, solver.updates) == (1, 4)
    Jk = rng.standard_normal((n, n)) + n * np.eye(n)  # every row changed
    b = rng.standard_normal(n)
    assert np.allclose(solver.solve(Jk, b), np.linalg.solve(Jk, b), rtol=1e-12, atol=0)
    assert solver.factorizations == 2


def test_singular_update_falls_back_and_singular_matrix_is_refused():
    """A row change that makes the matrix singular is refused (SingularMatrix), whether reached by update or not;
    the solver then solves a regular matrix again."""
    n = 10
    solver = RowUpdatedSolve()
    J = 4.0 * np.eye(n)
    b = np.arange(1.0, n + 1)
    assert np.allclose(solver.solve(J, b), b / 4)
    S = J.copy()
    S[3] = 0.0
    with pytest.raises(SingularMatrix):
        solver.solve(S, b)
    assert np.allclose(solver.solve(J, b), b / 4)


def test_rows_told_touched_give_the_same_solutions():
    """A matrix changed in place, the changed rows told (touched), over several solves: every solution is the
    one of a solver told nothing (bit for bit: the same rows are found) and LU's to 1e-12."""
    rng = np.random.default_rng(1)
    n = 80
    J = rng.standard_normal((n, n)) + n * np.eye(n)
    told, blind = RowUpdatedSolve(), RowUpdatedSolve()
    b = rng.standard_normal(n)
    told.solve(J, b), blind.solve(J.copy(), b)
    for k in (3, 7, 2, 5):
        rows = rng.choice(n, size=k, replace=False)
        J[rows] = rng.standard_normal((k, n)) + n * np.eye(n)[rows]
        told.touched(rows)
        b = rng.standard_normal(n)
        x = told.solve(J, b)
        assert np.array_equal(x, blind.solve(J.copy(), b))
        assert np.max(np.abs(x - np.linalg.solve(J, b))) <= 1e-12 * np.max(np.abs(x))
    assert (told.factorizations, told.updates) == (blind.factorizations, blind.updates) == (1, 4)


def test_fixed_rows_eliminated_give_the_whole_systems_solutions():
    """A matrix whose last rows are fixed and solvable for the last unknowns (the two-body method's master rows):
    solved through the reduced matrix, with rows changed in place and told (or not), every solution equals LU's of
    the whole matrix to 1e-12; a change in the fixed block is not a case (the rows stay fixed)."""
    from fenics_contact.condensed.fixedrows import FixedRowsSolve

    rng = np.random.default_rng(3)
    na, nb = 70, 50
    n = na + nb
    J = rng.standard_normal((n, n)) + n * np.eye(n)
    La, Lb = J[na:, :na], J[na:, na:]
    inverse = np.linalg.inv(Lb)
    solver = FixedRowsSolve(-inverse @ La, inverse)
    for k, tell in ((0, True), (3, True), (8, False), (30, True)):
        rows = rng.choice(na, size=k, replace=False)
        J[rows] = rng.standard_normal((k, n)) + n * np.eye(n)[rows]
        solver.touched(rows if tell else None)
        b = rng.standard_normal(n)
        x = solver.solve(J, b)
        assert np.max(np.abs(x - np.linalg.solve(J, b))) <= 1e-12 * np.max(np.abs(x)), (k, tell)
    assert solver.factorizations + solver.updates == 4 and solver.updates >= 2
    J[:na] = 0.0  # the reduced matrix singular exactly when the whole one is
    solver.touched(None)
    with pytest.raises(SingularMatrix):
        solver.solve(J, rng.standard_normal(n))
