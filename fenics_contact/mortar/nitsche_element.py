"""The segment-to-segment element of Nitsche's method between two bodies (2D, P1): residual and exact tangent of
slave-cell/master-facet pairs, all at once.

On the sub-segment ``[xi_a, xi_b]`` of the slave facet whose points project inside the master segment (bounded as
in :func:`~.element.segment_element`), with the master unit normal ``n`` (into the slave body), the gap
``g = -(x_s(xi) - x_m0) . n`` (> 0 penetration), the slave cell's traction ``t = P N`` (first Piola stress of the
slave cell, reference outward normal ``N``: constant on a P1 triangle), ``p_s = n . t`` and
``p = <gamma g + p_s>``, the residual is

    w J sum_q (xi_b - xi_a) w_q [p (gamma dg[v] + theta dp_s[v]) - theta p_s dp_s[v]] / gamma,

where ``v`` moves the slave cell's three vertices (``dg`` through the slave point, ``dp_s`` through ``P``) and the
two master vertices (``dg`` and ``dp_s`` through ``n``). On a sub-segment ``g`` and ``dg[v]`` are linear in ``xi``
and ``p_s``, ``dp_s[v]`` constant, so the 2-point Gauss rule integrates it exactly where ``p > 0`` throughout:
a uniform pressure is reproduced to round-off on non-matching meshes. The part of the slave facet no master
segment covers carries the traction-free term ``-theta p_0 dp_0[v] / gamma`` with ``p_0 = -N . t``; its
length is ``1 - sum (xi_b - xi_a)``, so each pair subtracts its length's share (:func:`segment_element`'s
``uncovered``) and :func:`uncovered_element` adds the whole facet's.

The tangent is the exact derivative of the residual with respect to the 10 vertex coordinates (dual numbers,
:mod:`~.dual`): ``dt/du`` and ``d^2 t/du^2`` of the cell come from the material (:class:`CellStress`), the
motion of the sub-segment ends and of the Gauss points is included.
"""
from __future__ import annotations

import numpy as np

from .dual import Dual, dual_max
from .element import SEGMENT_RULE, point_table, segment_frame, segment_gap

__all__ = ["NDOF", "traction_duals", "segment_element", "uncovered_element"]

NDOF = 10  # slave cell vertices s0, s1 (the facet's), s2, then master vertices m0, m1; (x, y) each


def traction_duals(t: np.ndarray, T: np.ndarray, T2: np.ndarray):
    """``t`` (components, Duals on the slave cell's 6 coordinates) and ``dt/du_k`` (2 x 6 Duals) from the cell
    traction ``t`` (n, 2), its derivative ``T`` (n, 2, 6) and second derivative ``T2`` (n, 2, 6, 6)."""
    n = len(t)
    pad = np.zeros((n, NDOF - 6))
    tc = [Dual(t[:, i], np.concatenate([T[:, i], pad], 1)) for i in range(2)]
    Tc = [[Dual(T[:, i, k], np.concatenate([T2[:, i, k], pad], 1)) for k in range(6)] for i in range(2)]
    return tc, Tc


def segment_element(x: np.ndarray, N: np.ndarray, t: np.ndarray, T: np.ndarray, T2: np.ndarray, gamma: np.ndarray,
                    theta: float, J: np.ndarray, weight: float = 1.0, rule=SEGMENT_RULE, points: bool = False):
    """Residual (n, 10) and tangent (n, 10, 10) of ``n`` pairs with current vertices ``x`` (n, 5, 2) =
    ``(s0, s1, s2, m0, m1)`` (slave facet ``s0 s1``, the cell's third vertex ``s2``); ``N`` (n, 2) the slave
    facet's reference outward unit normal; ``t, T, T2`` the cell traction and its derivatives
    (:func:`traction_duals`; columns ordered as ``x``'s first three vertices); ``gamma`` (n,) Nitsche's
    ``gamma0 E / h`` (force per length cubed); ``J`` (n,) the slave reference lengths. ``points=True`` also
    returns the Gauss points (pair, slave shape values ``N``, weight without the two-pass factor, gap, pressure,
    master normal)."""
    n, nd = len(x), NDOF
    X = [[Dual.seed(x[:, a, i], 2 * a + i, nd) for i in range(2)] for a in range(5)]
    s0, s1, _, m0, m1 = X
    tc, Tc = traction_duals(t, T, T2)
    L, nm, th, lo, length = segment_frame(s0, s1, m0, m1)
    ps = nm[0] * tc[0] + nm[1] * tc[1]
    # dp_s along each test direction: slave vertices through t, master vertices through n.
    dps_t = [((-1.0) * tc[1] - ps * th[0]) / L, (tc[0] - ps * th[1]) / L]  # d p_s / d(m1 - m0)
    dps = [nm[0] * Tc[0][k] + nm[1] * Tc[1][k] for k in range(6)] + \
          [-1.0 * dps_t[0], -1.0 * dps_t[1], dps_t[0], dps_t[1]]
    zero = Dual(np.zeros(n), np.zeros((n, nd)))
    res = [zero] * nd
    out = {"pair": [], "N": [], "weight": [], "gap": [], "pressure": [], "normal": []}
    for r, wq in zip(*rule):
        xi = lo + length * r
        wt = length * (wq * weight) * J
        g, dg_slave, dg_master = segment_gap(s0, s1, m0, L, nm, th, xi)
        p = dual_max(gamma * g + ps, 0.0)
        dg = dg_slave + [0.0, 0.0] + dg_master  # the cell's third vertex moves no gap
        for k in range(nd):
            res[k] = res[k] + wt * (p * (gamma * dg[k] + theta * dps[k]) - theta * ps * dps[k]) / gamma
        if points:
            point_table(out, np.arange(n), np.stack([1.0 - xi.v, xi.v], 1), wt.v / weight, g.v, p.v,
                        np.stack([nm[0].v, nm[1].v], axis=1))
    if theta != 0.0:  # this pair's length is not in the facet's traction-free part
        p0, dp0 = _free_traction(N, tc, Tc)
        for k in range(6):
            res[k] = res[k] + (length * (weight * theta) * J) * p0 * dp0[k] / gamma
    r = np.stack([e.v for e in res], axis=1)
    K = np.stack([e.d for e in res], axis=1)
    if points:
        return r, K, {k: np.concatenate(v) for k, v in out.items()}
    return r, K


def _free_traction(N: np.ndarray, tc, Tc):
    """``p_0 = -N . t`` and ``dp_0[v_k]`` (Duals) of the slave's own normal (no master)."""
    p0 = -1.0 * (N[:, 0] * tc[0] + N[:, 1] * tc[1])
    return p0, [-1.0 * (N[:, 0] * Tc[0][k] + N[:, 1] * Tc[1][k]) for k in range(6)]


def uncovered_element(N: np.ndarray, t: np.ndarray, T: np.ndarray, T2: np.ndarray, gamma: np.ndarray, theta: float,
                      J: np.ndarray, weight: float = 1.0):
    """Residual (n, 10) and tangent (n, 10, 10) of the whole slave facet's traction-free term
    ``-w J theta p_0 dp_0[v] / gamma`` (entries of the slave cell's vertices ordered as in :func:`segment_element`;
    the master entries zero): each pair's :func:`segment_element` takes its own length back out."""
    n = len(t)
    if theta == 0.0 or n == 0:
        return np.zeros((n, NDOF)), np.zeros((n, NDOF, NDOF))
    tc, Tc = traction_duals(t, T, T2)
    p0, dp0 = _free_traction(N, tc, Tc)
    res = [(-weight * theta) * J * p0 * dp0[k] / gamma for k in range(6)]
    r = np.zeros((n, NDOF))
    K = np.zeros((n, NDOF, NDOF))
    r[:, :6] = np.stack([e.v for e in res], axis=1)
    K[:, :6] = np.stack([e.d for e in res], axis=1)
    return r, K
