"""The local Signorini-Coulomb solve on the condensed system: Alart-Curnier's semismooth Newton on ``u_c``.

With ``R(u_c) = S u_c + r(t)`` the force the contact dofs need (:mod:`.operator`), the contact force is
eliminated and the unknowns are ``u_c`` alone. Per contact vertex, with the distance ``d`` (>= 0 open, the
negative gap), the normal force ``R_n`` (> 0 compression) and the slip increment ``s = u_t - u_t(previous
converged step)``::

    R_n - max(0, R_n - c d) = 0
    R_t - proj_[-mu l, mu l](R_t - c s) = 0,   l = max(0, R_n - c d)

``c`` only steers the iteration: the solution does not depend on it (no penalty). The residual and its
generalized Jacobian are the step solver's (rigid obstacle or two bodies); this module drives the iteration:
converged when the largest residual entry is below ``tol`` times the largest entry of ``r(t)``; a repeated
active set without progress (a cycle), a singular Jacobian or ``max_it`` iterations end a try, which is
retried with ``c / 10``, ``c / 100``, ... Per iteration one dense ``n_c x n_c`` solve, the same on every rank:
``O(k n_c^2)`` when ``k`` rows changed since the last factorization (:mod:`.rowupdate`), ``O(n_c^3)`` when
many did.
"""
from __future__ import annotations

from typing import Callable

import numpy as np

from .rowupdate import RowUpdatedSolve, SingularMatrix
from .states import StepFailure

__all__ = ["semismooth_newton"]

# residual(uc, c) -> (F, J, state, R): the Alart-Curnier residual, its generalized Jacobian, the contact state
# (an integer array: equal states mean the same active set) and the contact force R = S u_c + r(t).
Residual = Callable[[np.ndarray, float], tuple]


def semismooth_newton(residual: Residual, uc: np.ndarray, r: np.ndarray, c: float, retries: int, max_it: int,
                      tol: float, linear: RowUpdatedSolve | None = None) -> tuple[np.ndarray, list[float]]:
    """Semismooth Newton from ``uc`` with ``c``; if a try fails, again from ``uc`` with ``c`` divided by 10,
    ``retries`` times. ``r``: the load's contact force ``r(t)`` (the residual's scale); ``linear``: the solver of
    the Newton systems (kept across steps: its factorization serves while few contact states change).

    Returns:
        ``u_c`` and the relative residual history of all tries.

    Raises:
        StepFailure: every try failed (the message names each try's ``c`` and reason).
    """
    history, reasons = [], []
    linear = RowUpdatedSolve() if linear is None else linear
    for k in range(retries + 1):
        ck = c / 10**k
        try:
            out, h = _newton_c(residual, uc, r, ck, max_it, tol, linear)
            return out, history + h
        except StepFailure as exc:
            history += exc.args[1]
            reasons.append(f"c = {ck:.3g}: {exc.args[0]}")
    raise StepFailure("; ".join(reasons), history)


def _newton_c(residual: Residual, uc: np.ndarray, r: np.ndarray, c: float, max_it: int,
              tol: float, linear: RowUpdatedSolve) -> tuple[np.ndarray, list[float]]:
    """One try with a fixed ``c``."""
    scale = max(float(np.max(np.abs(r))) if len(r) else 0.0, 1e-300)
    uc = uc.copy()
    history, seen = [], {}
    for it in range(max_it + 1):
        F, J, state, _ = residual(uc, c)
        norm = float(np.max(np.abs(F))) if len(F) else 0.0
        history.append(norm / scale)
        if norm <= tol * scale:
            return uc, history
        if it == max_it:
            raise StepFailure(f"no convergence in {max_it} iterations (relative residual {norm / scale:.2e})",
                              history)
        key = state.tobytes()
        if key in seen and history[seen[key]] <= norm / scale:
            raise StepFailure(f"the semismooth Newton cycles (the contact state of iteration {it} repeats that "
                              f"of iteration {seen[key]} without progress, relative residual {norm / scale:.2e})",
                              history)
        seen[key] = it
        try:
            uc = uc - linear.solve(J, F)
        except SingularMatrix:
            raise StepFailure(f"singular semismooth Newton matrix at iteration {it} (no vertex in contact "
                              "holds the body)", history) from None
    raise AssertionError("unreachable")
