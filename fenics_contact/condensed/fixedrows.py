"""Solves with a semismooth Newton matrix whose last rows are fixed and can be solved for the last unknowns.

With ``J = [[J_a, J_b], [L_a, L_b]]`` (the last rows ``L`` the same at every iteration, ``L_b`` square and
regular) ``J x = b`` is ``x_b = L_b^-1 b_b + D x_a`` (``D = -L_b^-1 L_a``) and ``J_r x_a = b_a - J_b L_b^-1 b_b``
with the reduced matrix ``J_r = J_a + J_b D`` (the Schur complement of ``L_b``: regular exactly when ``J`` is).
:class:`FixedRowsSolve` keeps ``J_r``, forms again only the rows of ``J`` changed in place (the caller says which,
as to :class:`~.rowupdate.RowUpdatedSolve`) and solves with it by a :class:`~.rowupdate.RowUpdatedSolve`: the
iterates are those of the whole system, at the cost of a system smaller by the fixed rows (for the two-body
method, the master rows: about half of them, an eighth of the cost of an inverse).
"""
from __future__ import annotations

import numpy as np

from .rowupdate import RowUpdatedSolve, add_touched

__all__ = ["FixedRowsSolve", "master_elimination", "ELIMINATE"]

# The smallest Cholesky pivot of S_mm, relative to the largest, that eliminates the master dofs (a master body held
# by the contact alone has a rigid mode: a pivot at round-off)
ELIMINATE = 1e-8


def master_elimination(S: np.ndarray, MS: np.ndarray, ns: int) -> tuple[np.ndarray, np.ndarray] | None:
    """``(D, S_mm^-1)`` that solve the two-body method's master rows ``MS = M S`` for the master dofs, or None
    (the whole system): ``u_c = (u_s, u_m)`` (``ns`` slave dofs first), ``M = [C | I]``. When the two surfaces'
    dofs are not coupled through the bodies (``S_sm = 0``: two separate bodies) the master rows are ``[C S_ss |
    S_mm]``, solvable for ``u_m`` when the master body is held: ``S_mm`` positive definite, its Cholesky pivots
    above :data:`ELIMINATE` of the largest (a master body held by the contact alone has a rigid mode, a pivot at
    round-off)."""
    if ns == len(S) or np.any(S[:ns, ns:]):
        return None
    Smm = S[ns:, ns:]
    try:
        pivots = np.diag(np.linalg.cholesky(Smm)) ** 2
    except np.linalg.LinAlgError:
        return None
    if pivots.min() <= ELIMINATE * pivots.max():
        return None
    inverse = np.linalg.inv(Smm)
    return -inverse @ MS[:, :ns], inverse


class FixedRowsSolve:
    """``solve(J, b)``: ``J^-1 b`` for ``J`` whose last ``len(inverse)`` rows are ``[L_a, L_b]`` with ``L_b^-1 =
    inverse`` and ``D = -L_b^-1 L_a`` (see the module). ``factorizations``, ``updates``: those of the reduced
    matrix's solver."""

    def __init__(self, D: np.ndarray, inverse: np.ndarray):
        self.D, self.inverse = D, inverse
        self.reduced = RowUpdatedSolve()
        self._Jr = None
        self._touched: np.ndarray | None | bool = None  # rows changed since the last solve (False: unknown)

    @property
    def factorizations(self) -> int:
        return self.reduced.factorizations

    @property
    def updates(self) -> int:
        return self.reduced.updates

    def touched(self, rows: np.ndarray | None) -> None:
        """The caller changed ``rows`` of the matrix of the last :meth:`solve` in place (None: any row, or a new
        matrix)."""
        self._touched = add_touched(self._touched, rows)

    def solve(self, J: np.ndarray, b: np.ndarray) -> np.ndarray:
        """``J^-1 b``. Raises :class:`~.rowupdate.SingularMatrix` if the reduced matrix is exactly singular."""
        na = self.D.shape[1]
        nr = J.shape[0] - len(self.inverse)
        touched, self._touched = self._touched, None
        Ja, Jb = J[:nr, :na], J[:nr, na:]
        if self._Jr is None or touched is None or touched is False or self._Jr.shape != (nr, na):
            self._Jr = Ja + Jb @ self.D
            self.reduced.touched(None)
        else:
            rows = touched[touched < nr]
            if len(rows):
                self._Jr[rows] = Ja[rows] + Jb[rows] @ self.D
            self.reduced.touched(rows)
        y = self.inverse @ b[nr:]
        xa = self.reduced.solve(self._Jr, b[:nr] - Jb @ y)
        return np.concatenate([xa, y + self.D @ xa])
