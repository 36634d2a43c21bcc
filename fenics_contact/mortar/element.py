"""The segment-to-segment element: residual and exact tangent of slave/master facet pairs, all at once.

2D (:func:`segment_element`): the slave points ``x_s(xi) = (1 - xi) x_s0 + xi x_s1`` whose closest point on
the master segment ``m`` is inside ``m`` satisfy ``0 <= eta_m(x_s(xi)) <= 1`` with

    eta_m(x) = (x - x_m0) . t / |t|^2,   t = x_m1 - x_m0,

which is linear in ``xi``: the sub-segment ``[xi_a, xi_b]`` is bounded by the slave facet's ends and the
points where the master vertices project on the slave facet (along the master normal). A 2-point Gauss rule
on each sub-segment integrates ``F(g) dg`` exactly for linear laws (``g`` and ``dg`` are linear in ``xi`` on
a sub-segment: degree 2), so the constant-pressure state is reproduced to round-off. The gap is the flat
master facet's normal distance (positive = penetration, :mod:`laws`), and the residual, with the slave
reference length ``J`` and the surface's weight ``w`` (1/2 in two-pass)::

    g(xi) = -(x_s(xi) - x_m0) . n_m,     n_m = (t_y, -t_x) / |t|
    R = w J sum_q (xi_b - xi_a) w_q F(g(xi_q), c(xi_q)) dg/dx(xi_q)     (8 entries: x_s0, x_s1, x_m0, x_m1)

``dg/dx`` is the variation at a fixed slave point (slave vertices and both master vertices, rotation of
``n_m`` included). The tangent is the exact derivative of this routine with respect to the vertex
coordinates, including the motion of the sub-segment ends and of the Gauss points with them: forward-mode
automatic differentiation (:mod:`~.dual`, vectorised over all pairs) through the law's own ``force`` formula.

3D (:func:`triangle_element`): the overlap polygon of :mod:`~.clipping`, each of its vertices evaluated again
in dual numbers from its two lines, fanned into triangles with a 3-point rule each (exact to degree 2); the
gap is the distance to the master plane, ``dg/dx`` includes the rotation of ``n_m = (e_1 x e_2)/|e_1 x e_2|``.
Nothing loops over pairs in Python.
"""
from __future__ import annotations

import numpy as np

from .clipping import MAX_VERTICES, SLAVE_LINES, clip_arrays, master_lines
from .dual import DUAL_OPS, Dual, cross, dot, dual_max, dual_min, dual_sqrt

__all__ = ["SEGMENT_RULE", "TRIANGLE_RULE", "reference_measure", "segment_element", "triangle_element", "segment_frame",
           "segment_gap", "point_table"]

# 2-point Gauss rule on [0, 1] (exact to degree 3).
SEGMENT_RULE = (np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)]), np.array([0.5, 0.5]))
# 3-point rule on a triangle, barycentric points and weights (exact to degree 2).
TRIANGLE_RULE = (np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]), np.full(3, 1 / 3))


def reference_measure(X: np.ndarray) -> np.ndarray:
    """The elements' ``J`` of slave facets with reference vertices ``X`` (nf, nv, gdim): the length of a
    segment, twice the area of a triangle."""
    if len(X) == 0:
        return np.zeros(0)
    if X.shape[-1] == 2:
        return np.linalg.norm(X[:, 1] - X[:, 0], axis=1)
    return np.linalg.norm(np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]), axis=1)


def segment_element(x: np.ndarray, J: np.ndarray, law, scalars: dict, fields: dict, weight: float = 1.0,
                    rule=SEGMENT_RULE, points: bool = False):
    """Residual (n, 8) and tangent (n, 8, 8) of ``n`` slave/master facet pairs with current vertices
    ``x`` (n, 4, 2) = ``(x_s0, x_s1, x_m0, x_m1)``; ``J`` (n,): slave reference lengths; ``scalars``: law
    scalars (floats); ``fields``: law fields at the two slave vertices, each (n, 2). Entries ordered
    ``x_s0, y_s0, x_s1, y_s1, x_m0, y_m0, x_m1, y_m1``. ``points=True`` also returns the Gauss points: pair
    index, slave shape values ``N``, weight (reference measure, without the two-pass factor), gap (> 0
    penetration), pressure (> 0 compression) and master normal, one row per point.

    The pair must overlap (``xi_a < xi_b``) with a slave tangent not orthogonal to the master's."""
    n, nd = len(x), 8
    X = [[Dual.seed(x[:, a, i], 2 * a + i, nd) for i in range(2)] for a in range(4)]
    s0, s1, m0, m1 = X
    L, nm, th, lo, length = segment_frame(s0, s1, m0, m1)
    R = Dual(np.zeros(n), np.zeros((n, nd)))
    res = [R] * nd
    out = {"pair": [], "N": [], "weight": [], "gap": [], "pressure": [], "normal": []}
    for r, wq in zip(*rule):
        xi = lo + length * r
        wt = length * (wq * weight) * J
        g, dg_slave, dg_master = segment_gap(s0, s1, m0, L, nm, th, xi)
        c = {**scalars, **{k: f[:, 0] + xi * (f[:, 1] - f[:, 0]) for k, f in fields.items()}}
        F = law.force(g, c, DUAL_OPS)
        if not isinstance(F, Dual):  # a law that is constant in g and c
            F = Dual(np.broadcast_to(F, (n,)), np.zeros((n, nd)))
        grad = dg_slave + dg_master
        Fw = F * wt
        res = [res[k] + Fw * grad[k] for k in range(nd)]
        if points:
            point_table(out, np.arange(n), np.stack([1.0 - xi.v, xi.v], 1), wt.v / weight, g.v, F.v,
                         np.stack([nm[0].v, nm[1].v], axis=1))
    r = np.stack([e.v for e in res], axis=1)
    K = np.stack([e.d for e in res], axis=1)
    if points:
        return r, K, {k: np.concatenate(v) for k, v in out.items()}
    return r, K


def segment_frame(s0: list, s1: list, m0: list, m1: list):
    """Of a slave segment ``s0 s1`` and a master facet ``m0 m1`` (current positions, Duals): the master facet's
    length ``L``, unit normal ``nm`` and unit tangent ``th``, and the part ``[lo, lo + length]`` of the slave
    segment (parameter 0 at ``s0``, 1 at ``s1``) whose projection falls on the master facet."""
    t = [m1[i] - m0[i] for i in range(2)]
    L = dual_sqrt(t[0] * t[0] + t[1] * t[1])
    nm = [t[1] / L, -t[0] / L]
    th = [t[0] / L, t[1] / L]
    L2 = L * L
    eta0 = ((s0[0] - m0[0]) * t[0] + (s0[1] - m0[1]) * t[1]) / L2
    eta1 = ((s1[0] - m0[0]) * t[0] + (s1[1] - m0[1]) * t[1]) / L2
    de = eta1 - eta0
    xa, xb = -1.0 * eta0 / de, (1.0 - eta0) / de
    lo = dual_max(0.0, dual_min(xa, xb))
    hi = dual_min(1.0, dual_max(xa, xb))
    return L, nm, th, lo, hi - lo


def segment_gap(s0: list, s1: list, m0: list, L, nm: list, th: list, xi) -> tuple:
    """The gap ``g`` (> 0 penetration) at the slave segment's point ``xi`` (:func:`segment_frame`'s ``L``,
    ``nm``, ``th``) and its variation: derivatives along the slave vertices (``x_s0, y_s0, x_s1, y_s1``) and
    along the master vertices (``x_m0, y_m0, x_m1, y_m1``), two lists of four."""
    xq = [s0[i] + xi * (s1[i] - s0[i]) for i in range(2)]
    d = [xq[i] - m0[i] for i in range(2)]
    dn = d[0] * nm[0] + d[1] * nm[1]
    # dg/dt = -(R^T d - t_hat (n . d)) / L with R^T d = (-d_y, d_x)
    gt = [-1.0 * ((-1.0 * d[1]) - th[0] * dn) / L, -1.0 * (d[0] - th[1] * dn) / L]
    return (-1.0 * dn, [-1.0 * (1.0 - xi) * nm[0], -1.0 * (1.0 - xi) * nm[1], -1.0 * xi * nm[0], -1.0 * xi * nm[1]],
            [nm[0] - gt[0], nm[1] - gt[1], gt[0], gt[1]])


def point_table(out: dict, pair, N, weight, gap, pressure, normal) -> None:
    """Append Gauss-point data: pair index, slave shape values ``N`` (np, nv), weight (reference measure,
    without the two-pass factor), gap, pressure, master normal."""
    for k, v in (("pair", pair), ("N", N), ("weight", weight), ("gap", gap), ("pressure", pressure),
                 ("normal", normal)):
        out[k].append(np.asarray(v))


def triangle_element(x: np.ndarray, J: np.ndarray, law, scalars: dict, fields: dict, weight: float = 1.0,
                     points: bool = False):
    """3D analogue of :func:`segment_element` for triangle facets: residual (n, 18) and tangent (n, 18, 18)
    of pairs ``x`` (n, 6, 3) = ``(x_s0, x_s1, x_s2, x_m0, x_m1, x_m2)``; ``J``: twice the slave reference
    area; ``fields`` (n, 3) at the slave vertices. The overlap polygon (slave triangle clipped by the
    projected master triangle) is fanned into triangles with a 3-point rule each (exact to degree 2);
    its vertices are Duals, so the tangent includes their motion."""
    n, nd = len(x), 18
    X = [[Dual.seed(x[:, a, i], 3 * a + i, nd) for i in range(3)] for a in range(6)]
    alpha, beta = master_lines(X)
    poly, count = clip_arrays(np.stack([a.v for a in alpha], 1),
                              np.array([[beta[k][j].v for j in range(2)] for k in range(3)]).transpose(2, 0, 1))
    # Sub-triangles of the fans (pair, polygon vertices 0, i, i + 1), pair by pair.
    pi = [np.flatnonzero(i < count - 1) for i in range(1, MAX_VERTICES - 1)]
    fan = np.concatenate([np.full(len(p), i + 1) for i, p in enumerate(pi)]).astype(np.int64)
    tp = np.concatenate(pi).astype(np.int64)
    order = np.lexsort((fan, tp))
    tp, fan = tp[order], fan[order]
    r = np.zeros((n, nd))
    K = np.zeros((n, nd, nd))
    out = {"pair": [], "N": [], "weight": [], "gap": [], "pressure": [], "normal": []}
    if not len(tp):
        return (r, K, {k: np.zeros((0,) + ((3,) if k in ("N", "normal") else ())) for k in out}) if points else (r, K)
    corners = np.stack([poly[tp, 0], poly[tp, fan], poly[tp, fan + 1]], axis=1)  # (nt, 3 corners, 2 lines)
    lines_a, lines_b = corners[..., 0], corners[..., 1]

    def take(d, idx):
        return Dual(d.v[idx], d.d[idx]) if isinstance(d, Dual) else np.asarray(d)[idx]

    # Line coefficients of every pair as (n, 6) Duals, then gathered per corner.
    A = [Dual(np.full(n, SLAVE_LINES[0][k]), np.zeros((n, nd))) for k in range(3)] + list(alpha)
    B = [[Dual(np.full(n, SLAVE_LINES[1][k][j]), np.zeros((n, nd))) for j in range(2)] for k in range(3)] + \
        [list(b) for b in beta]
    Av = Dual(np.stack([a.v for a in A], 1), np.stack([a.d for a in A], 1))  # v (n, 6), d (n, 6, nd)
    Bv = [Dual(np.stack([B[k][j].v for k in range(6)], 1), np.stack([B[k][j].d for k in range(6)], 1))
          for j in range(2)]

    def coef(D, la):  # D.v (n, 6) -> per corner (nt,)
        return Dual(D.v[tp, la], D.d[tp, la])

    xi_c = []
    for c in range(3):
        la, lb = lines_a[:, c], lines_b[:, c]
        aa, ab = coef(Av, la), coef(Av, lb)
        ba0, ba1, bb0, bb1 = coef(Bv[0], la), coef(Bv[1], la), coef(Bv[0], lb), coef(Bv[1], lb)
        det = ba0 * bb1 - ba1 * bb0
        xi_c.append(((-1.0 * aa * bb1 + ab * ba1) / det, (-1.0 * ab * ba0 + aa * bb0) / det))
    (u0, w0), (u1, w1), (u2, w2) = xi_c
    area2 = (u1 - u0) * (w2 - w0) - (u2 - u0) * (w1 - w0)  # twice the sub-triangle's area in xi (> 0)
    s = [[take(X[a][i], tp) for i in range(3)] for a in range(3)]
    m = [[take(X[3 + a][i], tp) for i in range(3)] for a in range(3)]
    e1 = [m[1][i] - m[0][i] for i in range(3)]
    e2 = [m[2][i] - m[0][i] for i in range(3)]
    cvec = cross(e1, e2)
    clen = dual_sqrt(dot(cvec, cvec))
    nm = [ci / clen for ci in cvec]
    Jt = J[tp]
    res = [Dual(np.zeros(len(tp)), np.zeros((len(tp), nd)))] * nd
    for bq, wq in zip(*TRIANGLE_RULE):
        xi1 = bq[0] * xi_c[0][0] + bq[1] * xi_c[1][0] + bq[2] * xi_c[2][0]
        xi2 = bq[0] * xi_c[0][1] + bq[1] * xi_c[1][1] + bq[2] * xi_c[2][1]
        N = [1.0 - xi1 - xi2, xi1, xi2]
        wt = area2 * (0.5 * wq * weight) * Jt
        xq = [N[0] * s[0][i] + N[1] * s[1][i] + N[2] * s[2][i] for i in range(3)]
        d = [xq[i] - m[0][i] for i in range(3)]
        dn = dot(d, nm)
        g = -1.0 * dn
        c = {**scalars, **{k: sum(N[a] * f[tp, a] for a in range(3)) for k, f in fields.items()}}
        F = law.force(g, c, DUAL_OPS)
        if not isinstance(F, Dual):
            F = Dual(np.broadcast_to(F, (len(tp),)), np.zeros((len(tp), nd)))
        v = [-1.0 * (d[i] - nm[i] * dn) / clen for i in range(3)]  # dg/dc, c = e1 x e2
        g1, g2 = cross(e2, v), cross(v, e1)  # dg/dx_m1, dg/dx_m2
        grad = [-1.0 * N[a] * nm[i] for a in range(3) for i in range(3)] + \
               [nm[i] - g1[i] - g2[i] for i in range(3)] + g1 + g2
        Fw = F * wt
        res = [res[k] + Fw * grad[k] for k in range(nd)]
        if points:
            point_table(out, tp, np.stack([e.v for e in N], 1), wt.v / weight, g.v, F.v,
                         np.stack([e.v for e in nm], 1))
    np.add.at(r, tp, np.stack([e.v for e in res], axis=1))
    np.add.at(K, tp, np.stack([e.d for e in res], axis=1))
    if points:
        return r, K, {k: np.concatenate(v) for k, v in out.items()}
    return r, K
