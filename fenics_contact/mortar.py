"""Segment-to-segment (mortar-type) integration of two-body contact: segments (2D) and triangles (3D).

Pointwise two-body contact (:mod:`twobody`, nodal or Gauss points) sends the
forces of the slave points to the master vertices through master shape
functions that have kinks inside a slave facet: the rule is not exact, the
uniform-pressure state is not a discrete equilibrium and the patch test
fails on non-matching meshes. Here every slave facet ``s`` is cut into
*sub-segments*, one per master facet ``m`` whose projection overlaps it:
the slave points ``x_s(xi) = (1 - xi) x_s0 + xi x_s1`` whose closest point on
``m`` is inside ``m`` satisfy ``0 <= eta_m(x_s(xi)) <= 1`` with

    eta_m(x) = (x - x_m0) . t / |t|^2,   t = x_m1 - x_m0,

which is linear in ``xi``: the sub-segment ``[xi_a, xi_b]`` is bounded by the
slave facet's ends and the points where the master vertices project on the
slave facet (along the master normal). A 2-point Gauss rule on each
sub-segment integrates ``F(g) dg`` exactly for linear laws (``g`` is linear
in ``xi`` on a sub-segment, ``dg`` too: degree 2), so the constant-pressure
state is reproduced to round-off. The gap at a point is the flat master
facet's normal distance (positive = penetration, :mod:`laws`)::

    g(xi) = -(x_s(xi) - x_m0) . n_m,     n_m = (t_y, -t_x) / |t|

and the residual, with the slave reference length ``J`` and the surface's
weight ``w`` (1/2 in two-pass)::

    R = w J sum_q (xi_b - xi_a) w_q F(g(xi_q), c(xi_q)) dg/dx(xi_q)     (8 entries: x_s0, x_s1, x_m0, x_m1)

``dg/dx`` is the variation at a fixed slave point (slave vertices and both
master vertices, rotation of ``n_m`` included). The tangent is the exact
derivative of this element routine with respect to the 8 vertex
coordinates, including the motion of the sub-segment ends and of the Gauss
points with them: forward-mode automatic differentiation with dual numbers
(:class:`Dual`, vectorised over all sub-segments), through the law's own
``force`` formula (``ops`` = :data:`DUAL_OPS`): one law path, no finite
differences.

3D (:func:`triangle_element`): the master barycentric coordinates
``lambda_k`` of the projection of a slave point ``x_s(xi_1, xi_2)`` on the
master plane are affine in ``xi``; the overlap is the slave reference
triangle clipped by the three lines ``lambda_k(xi) = 0`` (Sutherland-Hodgman
on values, all pairs at once: :func:`clip_arrays`; each polygon vertex is the
intersection of two of the six lines, which is then evaluated in dual
numbers), fanned into triangles with a 3-point rule each (exact to degree 2).
Nothing loops over pairs in Python; the residual and the tangent of one state
come from one evaluation, and the tangent goes to PETSc summed per (row,
column) with an exact preallocation. The gap is the distance to the master
plane, ``dg/dx`` includes the rotation of ``n_m = (e_1 x e_2)/|e_1 x e_2|``.

Pairing: candidate master facets whose bounding box is within the search radius
of the slave facet's (:func:`search.facet_pairs`, a k-d tree), normals facing each other, a non-empty overlap;
a sub-segment is kept when :func:`search.project` (the pointwise
closest-point search) pairs its midpoint with the same master facet, so the
two options share one projection. At a convex master kink the slave points
whose closest point is the vertex itself belong to no sub-segment (no
force); on a flat or smooth master this set is empty or vanishes with h.

Law fields (augmentation multipliers) live at the slave vertices (P1, the
nodal state of :class:`twobody.TwoBodySurface`) and are interpolated
linearly at the sub-segment points; augmentation uses the nodal gaps
(closest point of each slave vertex). For a uniform state this changes
nothing: the patch test holds after every augmentation.

Parallel: each rank integrates its *owned* slave facets (each facet once)
against the master facets near its slave facets, which
:class:`twobody.MasterExchange` brings (global dof numbers; every master
facet within the search radius of a local slave facet's box is among them),
so a master facet on another rank is just a column;
residual and tangent entries go to PETSc with global indices
(``VecSetValues``/``MatSetValues`` with ``ADD``; off-process entries are
moved by the assembly).
"""
from __future__ import annotations

import types

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from .search import STRETCH_LIMIT, closest_point_on_facets, facet_normals, facet_pairs, project, stretch
from .sparse import aij_matrix
from .twobody import TwoBodySurface

__all__ = [
    "SEGMENT_RULE", "Dual", "dual_max", "dual_min", "dual_exp", "dual_sqrt", "DUAL_OPS", "segment_element",
    "clip_arrays", "clip_polygons", "polygon_area", "polygon_areas", "triangle_element", "overlap", "pair_segments",
    "pair_triangles", "SegmentSurface"
]

# 2-point Gauss rule on [0, 1] (exact to degree 3).
SEGMENT_RULE = (np.array([0.5 - 0.5 / np.sqrt(3.0), 0.5 + 0.5 / np.sqrt(3.0)]), np.array([0.5, 0.5]))


# --------------------------------------------------------------------------------------------
# Forward-mode dual numbers, vectorised: value v (n,), derivatives d (n, nd)
# --------------------------------------------------------------------------------------------
class Dual:
    """``v + d . eps``: values ``v`` (n,) and derivatives ``d`` (n, nd) with respect to ``nd`` inputs."""

    __array_ufunc__ = None  # numpy arrays on the left defer to Dual's reflected operators

    def __init__(self, v, d):
        self.v, self.d = np.asarray(v, float), np.asarray(d, float)

    @staticmethod
    def seed(v: np.ndarray, k: int, nd: int) -> Dual:
        d = np.zeros((len(v), nd))
        d[:, k] = 1.0
        return Dual(v, d)

    def _parts(self, o):
        if isinstance(o, Dual):
            return o.v, o.d
        o = np.asarray(o, float)
        return o, np.zeros((1, self.d.shape[1]))

    def __add__(self, o):
        v, d = self._parts(o)
        return Dual(self.v + v, self.d + d)

    __radd__ = __add__

    def __sub__(self, o):
        v, d = self._parts(o)
        return Dual(self.v - v, self.d - d)

    def __rsub__(self, o):
        v, d = self._parts(o)
        return Dual(v - self.v, d - self.d)

    def __neg__(self):
        return Dual(-self.v, -self.d)

    def __mul__(self, o):
        v, d = self._parts(o)
        return Dual(self.v * v, self.d * _col(v) + _col(self.v) * d)

    __rmul__ = __mul__

    def __truediv__(self, o):
        v, d = self._parts(o)
        return Dual(self.v / v, (self.d * _col(v) - _col(self.v) * d) / _col(v * v))

    def __rtruediv__(self, o):
        v, d = self._parts(o)
        return Dual(v / self.v, (d * _col(self.v) - _col(v) * self.d) / _col(self.v * self.v))

    def __pow__(self, p: float):
        return Dual(self.v ** p, _col(p * self.v ** (p - 1.0)) * self.d)


def _col(a):
    a = np.asarray(a, float)
    return a[:, None] if a.ndim == 1 else a


def _value(a):
    return a.v if isinstance(a, Dual) else np.asarray(a, float)


def _select(mask, a, b, n: int, nd: int) -> Dual:
    """``a`` where ``mask`` else ``b`` (Dual or numbers)."""
    av, ad = (a.v, a.d) if isinstance(a, Dual) else (np.broadcast_to(np.asarray(a, float), (n,)), np.zeros((n, nd)))
    bv, bd = (b.v, b.d) if isinstance(b, Dual) else (np.broadcast_to(np.asarray(b, float), (n,)), np.zeros((n, nd)))
    mask = np.broadcast_to(mask, (n,))
    return Dual(np.where(mask, av, bv), np.where(mask[:, None], ad, bd))


def _shape(*xs) -> tuple[int, int]:
    for x in xs:
        if isinstance(x, Dual):
            return x.d.shape
    raise TypeError("dual ops need at least one Dual argument")


def dual_max(a, b):
    if not isinstance(a, Dual) and not isinstance(b, Dual):
        return np.maximum(a, b)
    return _select(_value(a) > _value(b), a, b, *_shape(a, b))


def dual_min(a, b):
    if not isinstance(a, Dual) and not isinstance(b, Dual):
        return np.minimum(a, b)
    return _select(_value(a) < _value(b), a, b, *_shape(a, b))


def dual_exp(a):
    if not isinstance(a, Dual):
        return np.exp(a)
    e = np.exp(a.v)
    return Dual(e, e[:, None] * a.d)


def dual_sqrt(a: Dual) -> Dual:
    s = np.sqrt(a.v)
    return Dual(s, a.d / (2.0 * s[:, None]))


#: The law operator namespace (:mod:`laws`) for dual numbers: a law's ``force`` gives force and tangent.
DUAL_OPS = types.SimpleNamespace(exp=dual_exp, max=dual_max, min=dual_min)


# --------------------------------------------------------------------------------------------
# The element routine
# --------------------------------------------------------------------------------------------
def segment_element(x: np.ndarray, J: np.ndarray, law, scalars: dict, fields: dict, weight: float = 1.0,
                    rule=SEGMENT_RULE, points: bool = False):
    """Residual (n, 8) and tangent (n, 8, 8) of ``n`` slave/master facet pairs with current vertices
    ``x`` (n, 4, 2) = ``(x_s0, x_s1, x_m0, x_m1)``; ``J`` (n,): slave reference lengths; ``scalars``: law
    scalars (floats); ``fields``: law fields at the two slave vertices, each (n, 2). Entries ordered
    ``x_s0, y_s0, x_s1, y_s1, x_m0, y_m0, x_m1, y_m1``. ``points=True`` also returns the Gauss points
    (:func:`_point_table`)

    The pair must overlap (``xi_a < xi_b``) with a slave tangent not orthogonal to the master's."""
    n, nd = len(x), 8
    X = [[Dual.seed(x[:, a, i], 2 * a + i, nd) for i in range(2)] for a in range(4)]
    s0, s1, m0, m1 = X
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
    length = hi - lo
    R = Dual(np.zeros(n), np.zeros((n, nd)))
    res = [R] * nd
    out = {"pair": [], "N": [], "weight": [], "gap": [], "pressure": [], "normal": []}
    for r, wq in zip(*rule):
        xi = lo + length * r
        wt = length * (wq * weight) * J
        xq = [s0[i] + xi * (s1[i] - s0[i]) for i in range(2)]
        d = [xq[i] - m0[i] for i in range(2)]
        dn = d[0] * nm[0] + d[1] * nm[1]
        g = -1.0 * dn
        c = {**scalars, **{k: f[:, 0] + xi * (f[:, 1] - f[:, 0]) for k, f in fields.items()}}
        F = law.force(g, c, DUAL_OPS)
        if not isinstance(F, Dual):  # a law that is constant in g and c
            F = Dual(np.broadcast_to(F, (n,)), np.zeros((n, nd)))
        # dg/dt = -(R^T d - t_hat (n . d)) / L with R^T d = (-d_y, d_x)
        gt = [-1.0 * ((-1.0 * d[1]) - th[0] * dn) / L, -1.0 * (d[0] - th[1] * dn) / L]
        grad = [-1.0 * (1.0 - xi) * nm[0], -1.0 * (1.0 - xi) * nm[1], -1.0 * xi * nm[0], -1.0 * xi * nm[1],
                nm[0] - gt[0], nm[1] - gt[1], gt[0], gt[1]]
        Fw = F * wt
        res = [res[k] + Fw * grad[k] for k in range(nd)]
        if points:
            _point_table(out, np.arange(n), np.stack([1.0 - xi.v, xi.v], 1), wt.v / weight, g.v, F.v,
                         np.stack([nm[0].v, nm[1].v], axis=1))
    r = np.stack([e.v for e in res], axis=1)
    K = np.stack([e.d for e in res], axis=1)
    if points:
        return r, K, {k: np.concatenate(v) for k, v in out.items()}
    return r, K


def _point_table(out: dict, pair, N, weight, gap, pressure, normal) -> None:
    """Append Gauss-point data: pair index, slave shape values ``N`` (np, nv), weight (reference measure,
    without the two-pass factor), gap, pressure, master normal."""
    for k, v in (("pair", pair), ("N", N), ("weight", weight), ("gap", gap), ("pressure", pressure),
                 ("normal", normal)):
        out[k].append(np.asarray(v))


# Triangles (3D): the slave reference triangle (xi_1, xi_2) is clipped by the three lines lambda_k(xi) = 0
# of the master's barycentric coordinates (affine in xi). Lines 0-2: the slave edges xi_2 = 0 (s0 -> s1),
# 1 - xi_1 - xi_2 = 0 (s1 -> s2), xi_1 = 0 (s2 -> s0); lines 3-5: lambda_0, lambda_1, lambda_2 = 0. Each
# line is alpha + beta . xi >= 0 inside; each polygon vertex is the intersection of two lines.
_TRI_RULE = (np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]), np.full(3, 1 / 3))
_SLAVE_LINES = (np.array([0.0, 1.0, 0.0]), np.array([[0.0, 1.0], [-1.0, -1.0], [1.0, 0.0]]))


def _master_lines(x):
    """``(alpha, beta)`` of the master barycentric lines in slave coordinates: lambda_k(xi) = alpha_k + beta_k .
    xi for pairs ``x`` (n, 6, 3) (slave vertices, master vertices), values or Duals (lists of components)."""
    s, m = x[:3], x[3:]
    e1 = [m[1][i] - m[0][i] for i in range(3)]
    e2 = [m[2][i] - m[0][i] for i in range(3)]
    g11, g12, g22 = _dot(e1, e1), _dot(e1, e2), _dot(e2, e2)
    det = g11 * g22 - g12 * g12

    def bary(y):
        d = [y[i] - m[0][i] for i in range(3)]
        r1, r2 = _dot(e1, d), _dot(e2, d)
        l1 = (g22 * r1 - g12 * r2) / det
        l2 = (g11 * r2 - g12 * r1) / det
        return [1.0 - l1 - l2, l1, l2]

    b = [bary(v) for v in s]
    alpha = b[0]
    beta = [[b[1][k] - b[0][k], b[2][k] - b[0][k]] for k in range(3)]
    return alpha, beta


def _dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def _cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _lines(alpha: np.ndarray, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All six lines of each pair: ``A`` (n, 6), ``B`` (n, 6, 2) (slave edges, then the master lines)."""
    n = len(alpha)
    A = np.concatenate([np.broadcast_to(_SLAVE_LINES[0], (n, 3)), alpha], axis=1)
    B = np.concatenate([np.broadcast_to(_SLAVE_LINES[1], (n, 3, 2)), beta], axis=1)
    return A, B


def _vertices(A: np.ndarray, B: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """``xi`` (n, m, 2) of polygon vertices ``poly`` (n, m, 2): the intersections of their two lines (values;
    non-finite where the lines are parallel, e.g. unused slots)."""
    rows = np.arange(len(A))[:, None]
    a, b = poly[..., 0], poly[..., 1]
    Aa, Ab, Ba, Bb = A[rows, a], A[rows, b], B[rows, a], B[rows, b]
    with np.errstate(divide="ignore", invalid="ignore"):
        det = Ba[..., 0] * Bb[..., 1] - Ba[..., 1] * Bb[..., 0]
        return np.stack([(-Aa * Bb[..., 1] + Ab * Ba[..., 1]) / det, (-Ab * Ba[..., 0] + Aa * Bb[..., 0]) / det],
                        axis=-1)


_MAX_VERTICES = 6  # a triangle clipped by three half-planes


def clip_arrays(alpha: np.ndarray, beta: np.ndarray, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """Sutherland-Hodgman clipping (values) of the slave reference triangle by the master lines of every pair
    at once: the polygons ``poly`` (n, 6, 2), vertex ``j < count[i]`` of pair ``i`` being ``(line in, line out)``
    (counter-clockwise in xi), and ``count`` (n,) (0: no overlap). ``alpha`` (n, 3), ``beta`` (n, 3, 2) of
    the master lines. A vertex within ``tol`` of a line counts as inside, so a slave edge on a master edge
    (matching meshes, block boundaries) is never intersected with its own line. Vectorised over pairs: one
    NumPy pass per master line and polygon vertex slot."""
    n = len(alpha)
    A, B = _lines(np.asarray(alpha, float), np.asarray(beta, float))
    poly = np.zeros((n, _MAX_VERTICES + 1, 2), np.int64)
    poly[:, :3] = [(2, 0), (0, 1), (1, 2)]
    count = np.full(n, 3, np.int64)
    rows = np.arange(n)
    for k in (3, 4, 5):
        xi = _vertices(A, B, poly)
        with np.errstate(invalid="ignore"):
            inside = A[:, k, None] + (B[:, k, None, 0] * xi[..., 0] + B[:, k, None, 1] * xi[..., 1]) >= -tol
        new = np.zeros_like(poly)
        size = np.zeros(n, np.int64)
        for i in range(_MAX_VERTICES):
            on = i < count
            if not on.any():
                break
            ip = np.where(i == 0, count - 1, i - 1)  # the previous vertex (cyclic)
            p_out = poly[rows, np.maximum(ip, 0), 1]
            q_in, p_in = inside[:, i], inside[rows, np.maximum(ip, 0)]
            m = on & q_in & ~p_in  # entering: the edge p -> q lies on p's out line
            new[m, size[m]] = np.stack([np.full(m.sum(), k), p_out[m]], axis=1)
            size += m
            m = on & q_in
            new[m, size[m]] = poly[m, i]
            size += m
            m = on & ~q_in & p_in  # leaving
            new[m, size[m]] = np.stack([p_out[m], np.full(m.sum(), k)], axis=1)
            size += m
        poly, count = new, size
    count = np.where(count >= 3, count, 0)
    return poly[:, :_MAX_VERTICES], count


def clip_polygons(alpha: np.ndarray, beta: np.ndarray, tol: float = 1e-12) -> list[list[tuple[int, int]]]:
    """:func:`clip_arrays` as one list of vertices ``(line in, line out)`` per pair (empty: no overlap)."""
    poly, count = clip_arrays(alpha, beta, tol)
    return [[(int(a), int(b)) for a, b in p[:c]] for p, c in zip(poly, count)]


def _intersect_values(A, B, a, b):
    det = B[a, 0] * B[b, 1] - B[a, 1] * B[b, 0]
    return np.array([(-A[a] * B[b, 1] + A[b] * B[a, 1]) / det, (-A[b] * B[a, 0] + A[a] * B[b, 0]) / det])


def polygon_area(alpha, beta, poly) -> float:
    """Area in xi of a clipped polygon (values)."""
    if not poly:
        return 0.0
    A = np.concatenate([_SLAVE_LINES[0], alpha])
    B = np.concatenate([_SLAVE_LINES[1], beta])
    P = np.array([_intersect_values(A, B, *v) for v in poly])
    return 0.5 * float(np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]))


def polygon_areas(alpha: np.ndarray, beta: np.ndarray, poly: np.ndarray, count: np.ndarray) -> tuple[np.ndarray,
                                                                                                     np.ndarray]:
    """Areas (n,) and vertex means (n, 2) in xi of the polygons of :func:`clip_arrays` (0 without a polygon)."""
    A, B = _lines(np.asarray(alpha, float), np.asarray(beta, float))
    P = _vertices(A, B, poly)
    used = np.arange(poly.shape[1])[None, :] < count[:, None]
    P = np.where(used[..., None], P, 0.0)
    nxt = np.where(np.arange(poly.shape[1])[None, :] + 1 < count[:, None], np.arange(1, poly.shape[1] + 1) %
                   poly.shape[1], 0)
    Pn = np.take_along_axis(P, nxt[..., None], axis=1)
    area = 0.5 * np.sum(np.where(used, P[..., 0] * Pn[..., 1] - Pn[..., 0] * P[..., 1], 0.0), axis=1)
    centre = P.sum(axis=1) / np.maximum(count, 1)[:, None]
    return area, centre


def triangle_element(x: np.ndarray, J: np.ndarray, law, scalars: dict, fields: dict, weight: float = 1.0,
                     points: bool = False):
    """3D analogue of :func:`segment_element` for triangle facets: residual (n, 18) and tangent (n, 18, 18)
    of pairs ``x`` (n, 6, 3) = ``(x_s0, x_s1, x_s2, x_m0, x_m1, x_m2)``; ``J``: twice the slave reference
    area; ``fields`` (n, 3) at the slave vertices. The overlap polygon (slave triangle clipped by the
    projected master triangle) is fanned into triangles with a 3-point rule each (exact to degree 2);
    its vertices are Duals, so the tangent includes their motion."""
    n, nd = len(x), 18
    X = [[Dual.seed(x[:, a, i], 3 * a + i, nd) for i in range(3)] for a in range(6)]
    alpha, beta = _master_lines(X)
    poly, count = clip_arrays(np.stack([a.v for a in alpha], 1),
                              np.array([[beta[k][j].v for j in range(2)] for k in range(3)]).transpose(2, 0, 1))
    # Sub-triangles of the fans (pair, polygon vertices 0, i, i + 1), pair by pair.
    pi = [np.flatnonzero(i < count - 1) for i in range(1, _MAX_VERTICES - 1)]
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
    A = [Dual(np.full(n, _SLAVE_LINES[0][k]), np.zeros((n, nd))) for k in range(3)] + list(alpha)
    B = [[Dual(np.full(n, _SLAVE_LINES[1][k][j]), np.zeros((n, nd))) for j in range(2)] for k in range(3)] + \
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
    cvec = _cross(e1, e2)
    clen = dual_sqrt(_dot(cvec, cvec))
    nm = [ci / clen for ci in cvec]
    Jt = J[tp]
    res = [Dual(np.zeros(len(tp)), np.zeros((len(tp), nd)))] * nd
    for bq, wq in zip(*_TRI_RULE):
        xi1 = bq[0] * xi_c[0][0] + bq[1] * xi_c[1][0] + bq[2] * xi_c[2][0]
        xi2 = bq[0] * xi_c[0][1] + bq[1] * xi_c[1][1] + bq[2] * xi_c[2][1]
        N = [1.0 - xi1 - xi2, xi1, xi2]
        wt = area2 * (0.5 * wq * weight) * Jt
        xq = [N[0] * s[0][i] + N[1] * s[1][i] + N[2] * s[2][i] for i in range(3)]
        d = [xq[i] - m[0][i] for i in range(3)]
        dn = _dot(d, nm)
        g = -1.0 * dn
        c = {**scalars, **{k: sum(N[a] * f[tp, a] for a in range(3)) for k, f in fields.items()}}
        F = law.force(g, c, DUAL_OPS)
        if not isinstance(F, Dual):
            F = Dual(np.broadcast_to(F, (len(tp),)), np.zeros((len(tp), nd)))
        v = [-1.0 * (d[i] - nm[i] * dn) / clen for i in range(3)]  # dg/dc, c = e1 x e2
        g1, g2 = _cross(e2, v), _cross(v, e1)  # dg/dx_m1, dg/dx_m2
        grad = [-1.0 * N[a] * nm[i] for a in range(3) for i in range(3)] + \
               [nm[i] - g1[i] - g2[i] for i in range(3)] + g1 + g2
        Fw = F * wt
        res = [res[k] + Fw * grad[k] for k in range(nd)]
        if points:
            _point_table(out, tp, np.stack([e.v for e in N], 1), wt.v / weight, g.v, F.v,
                         np.stack([e.v for e in nm], 1))
    np.add.at(r, tp, np.stack([e.v for e in res], axis=1))
    np.add.at(K, tp, np.stack([e.d for e in res], axis=1))
    if points:
        return r, K, {k: np.concatenate(v) for k, v in out.items()}
    return r, K


def overlap(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sub-segment ``[xi_a, xi_b]`` of each slave facet ``x[:, :2]`` whose points project inside master facet
    ``x[:, 2:]`` (``xi_b <= xi_a``: no overlap)."""
    t = x[:, 3] - x[:, 2]
    L2 = np.einsum("ij,ij->i", t, t)
    eta0 = np.einsum("ij,ij->i", x[:, 0] - x[:, 2], t) / L2
    eta1 = np.einsum("ij,ij->i", x[:, 1] - x[:, 2], t) / L2
    de = eta1 - eta0
    with np.errstate(divide="ignore", invalid="ignore"):
        xa, xb = -eta0 / de, (1.0 - eta0) / de
    lo = np.maximum(0.0, np.minimum(xa, xb))
    hi = np.minimum(1.0, np.maximum(xa, xb))
    bad = ~np.isfinite(lo) | ~np.isfinite(hi)
    return np.where(bad, 0.0, lo), np.where(bad, 0.0, hi)


def pair_segments(xs: np.ndarray, xm: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """Slave/master facet pairs ``(slave index, master index)`` with a sub-segment: the master facet's
    projection overlaps the slave facet (more than 1e-10 of it), their normals face each other, and the
    closest-point search (:func:`search.project`) pairs the sub-segment's midpoint with that facet."""
    fs, ms = facet_pairs(xs, xm, radius)
    if len(fs) == 0:
        return fs, ms
    facing = np.einsum("ij,ij->i", facet_normals(xs[fs]), facet_normals(xm[ms])) < 0.0
    fs, ms = fs[facing], ms[facing]
    lo, hi = overlap(np.concatenate([xs[fs], xm[ms]], axis=1))
    keep = hi - lo > 1e-10
    fs, ms, lo, hi = fs[keep], ms[keep], lo[keep], hi[keep]
    mid = 0.5 * (lo + hi)
    p = xs[fs, 0] + mid[:, None] * (xs[fs, 1] - xs[fs, 0])
    best, _, dist = project(p, xm, radius)
    t = xm[ms, 1] - xm[ms, 0]  # distance of each midpoint to its own facet (2D segments, vectorised)
    s = np.clip(np.einsum("ij,ij->i", p - xm[ms, 0], t) / np.einsum("ij,ij->i", t, t), 0.0, 1.0)
    own = np.linalg.norm(p - xm[ms, 0] - s[:, None] * t, axis=1)
    keep = (best == ms) | ((best >= 0) & (own <= dist * (1 + 1e-9) + 1e-14 * radius))
    return fs[keep], ms[keep]


def pair_triangles(xs: np.ndarray, xm: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """3D analogue of :func:`pair_segments`: pairs whose overlap polygon covers more than 1e-10 of the slave
    triangle, normals facing, and whose polygon centroid :func:`search.project` pairs with that facet."""
    fs, ms = facet_pairs(xs, xm, radius)
    if len(fs) == 0:
        return fs, ms
    facing = np.einsum("ij,ij->i", facet_normals(xs[fs]), facet_normals(xm[ms])) < 0.0
    fs, ms = fs[facing], ms[facing]
    if len(fs) == 0:
        return fs, ms
    x = np.concatenate([xs[fs], xm[ms]], axis=1)
    alpha, beta = _master_lines([[x[:, a, i] for i in range(3)] for a in range(6)])
    alpha = np.stack(alpha, 1)
    beta = np.array(beta).transpose(2, 0, 1)
    # A slave triangle whose three vertices are all outside one master line has no overlap (what the clipping,
    # with its tolerance, would find): most candidates, left out before clipping.
    lam = np.stack([alpha, alpha + beta[..., 0], alpha + beta[..., 1]], axis=2)
    inside = ~np.any(np.all(lam < -1e-12, axis=2), axis=1)
    fs, ms, x, alpha, beta = fs[inside], ms[inside], x[inside], alpha[inside], beta[inside]
    poly, count = clip_arrays(alpha, beta)
    area, cen = polygon_areas(alpha, beta, poly, count)
    keep = area > 0.5e-10
    fs, ms, cen, x = fs[keep], ms[keep], cen[keep], x[keep]
    p = x[:, 0] + cen[:, :1] * (x[:, 1] - x[:, 0]) + cen[:, 1:] * (x[:, 2] - x[:, 0])
    best, _, dist = project(p, xm, radius)
    own = closest_point_on_facets(p, xm[ms])[0] if len(p) else dist
    keep = (best == ms) | ((best >= 0) & (own <= dist * (1 + 1e-9) + 1e-14 * radius))
    return fs[keep], ms[keep]


# --------------------------------------------------------------------------------------------
# The surface
# --------------------------------------------------------------------------------------------
def _same(a: tuple, b: tuple) -> bool:
    """Whether two element inputs ``(x, scalars, fields, weight, dofs)`` are equal (arrays exactly)."""
    xa, sa, fa, wa, da = a
    xb, sb, fb, wb, db = b
    return (wa == wb and sa == sb and xa.shape == xb.shape and np.array_equal(xa, xb) and np.array_equal(da, db)
            and fa.keys() == fb.keys() and all(np.array_equal(fa[k], fb[k]) for k in fa))


class SegmentSurface(TwoBodySurface):
    """Two-body contact with segment-to-segment integration (``quadrature="segment"``, 2D and 3D): the same
    projection, master exchange, nodal state, augmentation and outputs as
    :class:`twobody.TwoBodySurface` with nodal points, but the contact residual and tangent on slave and
    master dofs come from :func:`segment_element`, assembled in NumPy and added by the solver hooks."""

    ufl_coupling = False

    def __init__(self, u, facet_tags, slave_tag, master_tag, law, load, weight=1.0, radius=None,
                 name="twobody"):
        if u.function_space.num_sub_spaces > 0 and u.function_space.sub(0).num_sub_spaces > 0:
            raise ValueError("contact quadrature 'segment' needs a displacement unknown (not a mixed space)")
        self._segments = None
        self._segment_pairs = None  # (owned slave facet, index into the received master facets)
        self._segment_ids = None  # the same with global master facet numbers (the pairing state)
        self._element_cache = None  # (inputs, (residuals, tangents)) of the last element evaluation
        super().__init__(u, facet_tags, slave_tag, master_tag, law, load, "nodal", weight, radius, name)
        self.quadrature = "segment"
        sd = self.slave_data
        if len(sd.X) == 0:
            self._J = np.zeros(0)
        elif self.gdim == 2:  # reference length
            self._J = np.linalg.norm(sd.X[:, 1] - sd.X[:, 0], axis=1)
        else:  # twice the reference area
            self._J = np.linalg.norm(np.cross(sd.X[:, 1] - sd.X[:, 0], sd.X[:, 2] - sd.X[:, 0]), axis=1)

    def residual(self, v):
        return None  # everything is in add_residual / add_jacobian

    # --- pairing -------------------------------------------------------------
    def _slave_current(self) -> np.ndarray:
        sd = self.slave_data
        return sd.X + self.u.x.array[sd.comp]

    def update(self) -> bool:
        """Nodal projection (state, outputs) and the sub-segments of the owned slave facets. Collective."""
        changed = super().update()
        # Slave facets are local: an exploded slave facet on any rank rejects the iterate on every rank.
        local = stretch(self._slave_current(), self.slave_data.X) > STRETCH_LIMIT
        self.exploded = self.comm.allreduce(self.exploded or local, op=MPI.LOR)
        self._exploded_seen |= self.exploded
        if self.exploded:
            return False
        xm = self._master["x"]
        own = np.flatnonzero(self.slave_data.owned)
        pair = pair_segments if self.gdim == 2 else pair_triangles
        fs, ms = pair(self._slave_current()[own], xm, self.radius)
        pairs = np.stack([own[fs], ms], axis=1)
        ids = np.stack([own[fs], self._master["ids"][ms]], axis=1)  # the state: global master facet numbers
        same = self._segment_ids is not None and np.array_equal(self._segment_ids, ids)
        seg_changed = self.comm.allreduce(0 if same else 1) > 0
        self._segment_pairs, self._segment_ids = pairs, ids
        if seg_changed:
            self._pattern_version += 1
        self._xm = xm
        return changed or seg_changed

    def pairing(self) -> np.ndarray:
        """The point pairs (:meth:`TwoBodySurface.pairing`) followed by the (slave facet, master facet) pairs of
        the sub-segments, flattened."""
        return np.concatenate([super().pairing(), self._segment_ids.ravel()])

    def _elements(self, points: bool = False):
        """Element residuals, tangents and global dof indices (n, 8) of the current sub-segments."""
        f, m = self._segment_pairs[:, 0], self._segment_pairs[:, 1]
        x = np.concatenate([self._slave_current()[f], self._xm[m]], axis=1)
        scalars = {k: float(c.value) for k, c in self.constants.items()}
        fields = {k: fn.x.array[self._sdofs[f]] for k, fn in self.fields.items()}
        weight = float(self.weight.value)
        k = self.nv * self.gdim
        dofs = np.concatenate([self.slave_data.global_comp[f].reshape(-1, k), self._master["G"][m].reshape(-1, k)],
                              axis=1)
        # The residual and the Jacobian of one state (a Newton iteration's F then J) share one evaluation: the
        # element routine gives both; it is reused while its inputs are unchanged (compared, not assumed).
        inputs = (x, scalars, fields, weight, dofs)
        if not points and self._element_cache is not None and _same(self._element_cache[0], inputs):
            return self._element_cache[1], dofs
        element = segment_element if self.gdim == 2 else triangle_element
        out = element(x, self._J[f], self.law, scalars, fields, weight, points=points)
        if not points:
            self._element_cache = (inputs, out)
        return out, dofs

    # --- solver hooks ----------------------------------------------------------
    def add_residual(self, b: PETSc.Vec) -> None:
        if self.exploded:  # a non-finite residual: the solve fails and the step is cut (search.STRETCH_LIMIT)
            b.set(np.nan)
            return
        (r, _), dofs = self._elements()
        if len(r):
            b.setValues(dofs.ravel().astype(PETSc.IntType), r.ravel(), addv=PETSc.InsertMode.ADD_VALUES)
        b.assemblyBegin()
        b.assemblyEnd()

    def coupling_matrix(self, bcs) -> PETSc.Mat:
        """The whole contact tangent (slave and master rows and columns; Dirichlet rows and columns zero)."""
        (_, K), dofs = self._elements()
        Vmap, bs = self.V.dofmap.index_map, self.V.dofmap.index_map_bs
        n_local, N = Vmap.size_local * bs, Vmap.size_global * bs
        # The element entries summed per (row, column) here, Dirichlet rows and columns left out.
        rows = cols = np.zeros(0, np.int64)
        vals = np.zeros(0)
        if len(K):
            idx = np.where(np.isin(dofs, self._bc_array), -1, dofs).astype(np.int64)
            m = idx.shape[1]
            rows, cols = np.repeat(idx, m, axis=1).ravel(), np.tile(idx, (1, m)).ravel()
            keep = (rows >= 0) & (cols >= 0)
            key, inverse = np.unique(rows[keep] * N + cols[keep], return_inverse=True)
            vals = np.bincount(inverse.ravel(), weights=K.ravel()[keep], minlength=len(key))
            rows, cols = key // N, key % N
        return aij_matrix(self.comm, ((n_local, N),) * 2, rows, cols, vals)

    # --- figures ---------------------------------------------------------------
    def segment_points(self) -> dict:
        """Sub-segment Gauss points of the owned slave facets (local): reference and current position,
        weight (reference length, without the two-pass factor), gap, pressure, master normal."""
        d = self.gdim
        if len(self._segment_pairs) == 0:
            z = np.zeros((0, d))
            return {"X": z, "x": z, "weight": np.zeros(0), "gap": np.zeros(0), "pressure": np.zeros(0), "normal": z}
        (_, _, pts), _ = self._elements(points=True)
        f = self._segment_pairs[pts["pair"], 0]
        N = pts["N"]
        X = np.einsum("qa,qaj->qj", N, self.slave_data.X[f])
        x = np.einsum("qa,qaj->qj", N, self._slave_current()[f])
        return {"X": X, "x": x, "weight": pts["weight"], "gap": pts["gap"], "pressure": pts["pressure"],
                "normal": pts["normal"]}

    def point_values(self, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Current position, gap and nominal pressure (per reference slave area) at every sub-segment Gauss
        point, gathered on every rank and sorted by reference position. ``kind="cauchy"`` is refused here
        (use the pointwise quadratures' :meth:`TwoBodySurface.point_values`)."""
        if kind != "nominal":
            raise ValueError(f"{self.name}: segment integration reports the nominal pressure only (kind "
                             f"'nominal'), got kind {kind!r}; the pointwise quadratures give 'cauchy' too")
        p = self.segment_points()
        data = [np.concatenate(a) for a in zip(*self.comm.allgather((p["X"], p["x"], p["gap"], p["pressure"])))]
        order = np.lexsort(np.round(data[0], 12).T[::-1])
        return data[1][order], data[2][order], data[3][order]

    def total_force(self) -> np.ndarray:
        """Force of the master on the slave body, ``sum_q w_q F_q n_m`` (per unit thickness)."""
        p = self.segment_points()
        local = np.einsum("q,q,qj->j", p["weight"], p["pressure"], p["normal"]) if len(p["weight"]) else \
            np.zeros(self.gdim)
        return np.array(self.comm.allreduce(local))
