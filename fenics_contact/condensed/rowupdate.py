"""Dense solves with a matrix that changes in a few rows from one solve to the next (the semismooth Newton's).

The semismooth Newton's Jacobian (:mod:`.newton`) has a row per contact condition; from one iteration to the
next, and from a converged step to the next step's first iteration, only the rows of the vertices whose contact
state changed differ. :class:`RowUpdatedSolve` keeps the inverse of a base matrix ``J0`` and solves with
``J = J0 + U V`` (``U``: the identity's columns of the ``k`` changed rows, ``V``: their change) by the Sherman-
Morrison-Woodbury formula, ``x = y - Z (I + V Z)^-1 V y`` with ``y = J0^-1 b`` and ``Z = J0^-1 U`` (columns of
the inverse): ``O(n^2 + k^2 n)`` instead of the ``O(n^3)`` of a new factorization. It inverts ``J`` instead (and
makes it the base) when more than ``REFACTOR`` of the rows changed or when the updated solution's residual is
above round-off; a solution from a new inverse with a residual above round-off is solved again by LU. A caller
that changes ``J`` in place may say which rows it touched (:meth:`RowUpdatedSolve.touched`): the rows that differ
from ``J0`` are then looked for among those and the ones that differed at the last solve only (``O(k n)``, not
``O(n^2)``).
numpy's LAPACK (OpenBLAS) does the dense algebra: SciPy's may be the reference one, several times slower.
"""
from __future__ import annotations

import numpy as np

__all__ = ["RowUpdatedSolve", "SingularMatrix", "REFACTOR", "add_touched"]

REFACTOR = 0.5  # the largest fraction of changed rows updated (the k x k system costs (k / n)^3 of an inverse)


class SingularMatrix(ValueError):
    """The matrix is singular (an exact zero pivot)."""


class RowUpdatedSolve:
    """``solve(J, b)``: ``J^-1 b`` from the inverse of a base matrix updated in the rows that differ (see the
    module). ``factorizations``, ``updates``: how many solves inverted and how many updated."""

    def __init__(self):
        self._J0, self._inv = None, None
        self._rowmax0 = None  # max |J0| row by row (the round-off scale of an updated solution's residual)
        self._differ = None  # the rows of the last solved J that differ from J0
        self._touched = None  # rows touched since the last solve (None: not known, every row is compared)
        self.factorizations, self.updates = 0, 0

    def touched(self, rows: np.ndarray | None) -> None:
        """The caller changed ``rows`` of the matrix of the last :meth:`solve` in place (None: any row, or a new
        matrix); the next :meth:`solve` compares only those and the rows that differed from the base."""
        self._touched = add_touched(self._touched, rows)

    def solve(self, J: np.ndarray, b: np.ndarray) -> np.ndarray:
        """``J^-1 b``. Raises :class:`SingularMatrix` if ``J`` is exactly singular."""
        n = len(b)
        touched, self._touched = self._touched, None
        if self._J0 is not None and self._J0.shape == J.shape:
            if touched is None or touched is False or self._differ is None:
                rows = np.flatnonzero(np.any(J != self._J0, axis=1))
            else:
                candidates = np.union1d(self._differ, touched)
                rows = candidates[np.any(J[candidates] != self._J0[candidates], axis=1)]
            if len(rows) <= REFACTOR * n:
                x = self._updated(J, b, rows)
                if x is not None and _accurate(J, x, b, self._max_abs(J, rows)):
                    self.updates += 1
                    self._differ = rows
                    return x
        try:
            inv = np.linalg.inv(J)
        except np.linalg.LinAlgError:
            self._J0 = self._differ = None
            raise SingularMatrix("exactly singular matrix") from None
        self._J0, self._inv = J.copy(), inv
        self._rowmax0 = np.max(np.abs(J), axis=1) if n else np.zeros(0)
        self._differ = np.zeros(0, np.int64)
        self.factorizations += 1
        x = inv @ b
        return x if _accurate(J, x, b) else np.linalg.solve(J, b)

    def _max_abs(self, J: np.ndarray, rows: np.ndarray) -> float:
        """``max |J|`` from the base's row maxima and the ``rows`` that differ from the base."""
        if not len(rows):
            return float(np.max(self._rowmax0, initial=0.0))
        other = np.max(np.delete(self._rowmax0, rows), initial=0.0)
        return max(float(other), float(np.max(np.abs(J[rows]))))

    def _updated(self, J: np.ndarray, b: np.ndarray, rows: np.ndarray) -> np.ndarray | None:
        """The Woodbury solution (see the module); None if the ``k x k`` system is singular."""
        y = self._inv @ b
        if not len(rows):
            return y
        V = J[rows] - self._J0[rows]
        Z = self._inv[:, rows]
        try:
            return y - Z @ np.linalg.solve(np.eye(len(rows)) + V @ Z, V @ y)
        except np.linalg.LinAlgError:
            return None


def add_touched(so_far: np.ndarray | None | bool, rows: np.ndarray | None) -> np.ndarray | bool:
    """The rows touched since the last solve, ``so_far`` (None: none yet; False: not known), with ``rows`` (None:
    any row) added."""
    if rows is None or so_far is False:
        return False
    return np.asarray(rows, dtype=np.int64) if so_far is None else np.union1d(so_far, rows)


def _accurate(J: np.ndarray, x: np.ndarray, b: np.ndarray, max_abs: float | None = None) -> bool:
    """The residual of ``J x = b`` at round-off against the sizes of ``J x`` and ``b`` (``max_abs``: ``max |J|``
    if known)."""
    if not np.all(np.isfinite(x)):
        return False
    if max_abs is None:
        max_abs = max(float(J.max()), -float(J.min()))  # max |J| without a copy of J
    size = max_abs * float(np.max(np.abs(x)))
    return float(np.max(np.abs(J @ x - b))) <= 1e-12 * (size + float(np.max(np.abs(b))))
