"""Clipping of a slave triangle by the projection of a master triangle (3D segment integration).

The master barycentric coordinates ``lambda_k`` of the projection of a slave point ``x_s(xi_1, xi_2)`` on the
master plane are affine in ``xi``, so the overlap of the two facets is the slave reference triangle clipped
by the three lines ``lambda_k(xi) = 0``: Sutherland-Hodgman on values, all pairs at once
(:func:`clip_arrays`). Lines 0-2 are the slave edges ``xi_2 = 0`` (s0 -> s1), ``1 - xi_1 - xi_2 = 0``
(s1 -> s2), ``xi_1 = 0`` (s2 -> s0); lines 3-5 are ``lambda_0, lambda_1, lambda_2 = 0``. Each line is
``alpha + beta . xi >= 0`` inside; each polygon vertex is stored as the two lines it is the intersection of,
so the element can evaluate it again in dual numbers.
"""
from __future__ import annotations

import numpy as np

from .dual import dot

__all__ = ["SLAVE_LINES", "MAX_VERTICES", "master_lines", "clip_arrays", "clip_polygons", "intersect_values",
           "polygon_area", "polygon_areas"]

SLAVE_LINES = (np.array([0.0, 1.0, 0.0]), np.array([[0.0, 1.0], [-1.0, -1.0], [1.0, 0.0]]))  # (alpha, beta)
MAX_VERTICES = 6  # a triangle clipped by three half-planes


def master_lines(x):
    """``(alpha, beta)`` of the master barycentric lines in slave coordinates: lambda_k(xi) = alpha_k + beta_k .
    xi for pairs ``x`` (n, 6, 3) (slave vertices, master vertices), values or Duals (lists of components)."""
    s, m = x[:3], x[3:]
    e1 = [m[1][i] - m[0][i] for i in range(3)]
    e2 = [m[2][i] - m[0][i] for i in range(3)]
    g11, g12, g22 = dot(e1, e1), dot(e1, e2), dot(e2, e2)
    det = g11 * g22 - g12 * g12

    def bary(y):
        d = [y[i] - m[0][i] for i in range(3)]
        r1, r2 = dot(e1, d), dot(e2, d)
        l1 = (g22 * r1 - g12 * r2) / det
        l2 = (g11 * r2 - g12 * r1) / det
        return [1.0 - l1 - l2, l1, l2]

    b = [bary(v) for v in s]
    alpha = b[0]
    beta = [[b[1][k] - b[0][k], b[2][k] - b[0][k]] for k in range(3)]
    return alpha, beta


def _lines(alpha: np.ndarray, beta: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """All six lines of each pair: ``A`` (n, 6), ``B`` (n, 6, 2) (slave edges, then the master lines)."""
    n = len(alpha)
    A = np.concatenate([np.broadcast_to(SLAVE_LINES[0], (n, 3)), alpha], axis=1)
    B = np.concatenate([np.broadcast_to(SLAVE_LINES[1], (n, 3, 2)), beta], axis=1)
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



def clip_arrays(alpha: np.ndarray, beta: np.ndarray, tol: float = 1e-12) -> tuple[np.ndarray, np.ndarray]:
    """Sutherland-Hodgman clipping (values) of the slave reference triangle by the master lines of every pair
    at once: the polygons ``poly`` (n, 6, 2), vertex ``j < count[i]`` of pair ``i`` being ``(line in, line out)``
    (counter-clockwise in xi), and ``count`` (n,) (0: no overlap). ``alpha`` (n, 3), ``beta`` (n, 3, 2) of
    the master lines. A vertex within ``tol`` of a line counts as inside, so a slave edge on a master edge
    (matching meshes, block boundaries) is never intersected with its own line. Vectorised over pairs: one
    NumPy pass per master line and polygon vertex slot."""
    n = len(alpha)
    A, B = _lines(np.asarray(alpha, float), np.asarray(beta, float))
    poly = np.zeros((n, MAX_VERTICES + 1, 2), np.int64)
    poly[:, :3] = [(2, 0), (0, 1), (1, 2)]
    count = np.full(n, 3, np.int64)
    rows = np.arange(n)
    for k in (3, 4, 5):
        xi = _vertices(A, B, poly)
        with np.errstate(invalid="ignore"):
            inside = A[:, k, None] + (B[:, k, None, 0] * xi[..., 0] + B[:, k, None, 1] * xi[..., 1]) >= -tol
        new = np.zeros_like(poly)
        size = np.zeros(n, np.int64)
        for i in range(MAX_VERTICES):
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
    return poly[:, :MAX_VERTICES], count


def clip_polygons(alpha: np.ndarray, beta: np.ndarray, tol: float = 1e-12) -> list[list[tuple[int, int]]]:
    """:func:`clip_arrays` as one list of vertices ``(line in, line out)`` per pair (empty: no overlap)."""
    poly, count = clip_arrays(alpha, beta, tol)
    return [[(int(a), int(b)) for a, b in p[:c]] for p, c in zip(poly, count)]


def intersect_values(A, B, a, b):
    """``xi`` (2,) of the intersection of lines ``a`` and ``b`` of one pair (``A`` (6,), ``B`` (6, 2): values)."""
    det = B[a, 0] * B[b, 1] - B[a, 1] * B[b, 0]
    return np.array([(-A[a] * B[b, 1] + A[b] * B[a, 1]) / det, (-A[b] * B[a, 0] + A[a] * B[b, 0]) / det])


def polygon_area(alpha, beta, poly) -> float:
    """Area in xi of a clipped polygon (values)."""
    if not poly:
        return 0.0
    A = np.concatenate([SLAVE_LINES[0], alpha])
    B = np.concatenate([SLAVE_LINES[1], beta])
    P = np.array([intersect_values(A, B, *v) for v in poly])
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
