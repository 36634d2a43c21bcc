"""The closed part of a contact surface from its gap: the measure of the set where the gap, linear between the
vertices of each facet, is closed (``g >= 0``). Unlike the set of loaded vertices (``p > 0``), it ends between
the last closed vertex and the first open one, where the gap crosses zero: a pressure recovered at the vertices
from a Gauss rule spills onto the first open vertex, which then counts as loaded."""
from __future__ import annotations

import numpy as np

__all__ = ["closed_fraction", "closed_measure"]


def closed_fraction(g: np.ndarray) -> np.ndarray:
    """Fraction of each simplex (rows of ``g``: the values of a linear function at its 2 or 3 vertices) where the
    function is ``>= 0``. Segment: the crossing's position; triangle: one vertex alone on its side cuts off the
    corner ``g_a^2 / ((g_a - g_b)(g_a - g_c))`` of the area."""
    g = np.asarray(g, float)
    closed = g >= 0
    n = closed.sum(axis=1)
    out = (n == g.shape[1]).astype(float)
    if g.shape[1] == 2:
        mixed = n == 1
        a = g[mixed]
        out[mixed] = a.max(axis=1) / (a.max(axis=1) - a.min(axis=1))
        return out
    for alone, count in ((True, 1), (False, 2)):  # the lone closed vertex, or the lone open one
        rows = np.flatnonzero(n == count)
        if not len(rows):
            continue
        k = np.argmax(closed[rows] == alone, axis=1)
        a = g[rows, k]
        others = np.stack([g[rows, (k + 1) % 3], g[rows, (k + 2) % 3]], axis=1)
        corner = a**2 / ((a - others[:, 0]) * (a - others[:, 1]))
        out[rows] = corner if alone else 1.0 - corner
    return out


def _simplices(a: np.ndarray) -> np.ndarray:
    """Per-vertex data of facets (nf, v, ...) as simplices: segments and triangles as they are, a quadrilateral
    (vertices in dolfinx's tensor order 0 1 / 2 3) as the triangles (0, 1, 3) and (0, 3, 2)."""
    return a if a.shape[1] != 4 else np.concatenate([a[:, [0, 1, 3]], a[:, [0, 3, 2]]])


def _measure(simplices: np.ndarray) -> np.ndarray:
    edge = simplices[:, 1] - simplices[:, 0]
    if simplices.shape[1] == 2:
        return np.linalg.norm(edge, axis=1)
    return 0.5 * np.linalg.norm(np.cross(edge, simplices[:, 2] - simplices[:, 0]), axis=1)


def closed_measure(nodes: np.ndarray, gap: np.ndarray) -> float:
    """Measure (length of segments, area of triangles and quadrilaterals) of the part of the facets ``nodes``
    (nf, vertices, 3: their vertices' coordinates) where the gap, given at the vertices (``gap``: (nf, vertices))
    and linear on each simplex, is ``>= 0``."""
    if not len(nodes):
        return 0.0
    return float(np.sum(_measure(_simplices(np.asarray(nodes, float))) * closed_fraction(_simplices(gap))))
