"""The closed part of a contact surface from the gap (:mod:`fenics_contact.closed_area`): exact for a gap linear
on each facet, segments, triangles and quadrilaterals."""
import numpy as np

from fenics_contact.closed_area import closed_fraction, closed_measure


def test_segment_ends_where_the_gap_crosses_zero():
    assert np.allclose(closed_fraction(np.array([[1.0, -1.0], [-1.0, 3.0], [1.0, 2.0], [-1.0, -2.0]])),
                       [0.5, 0.75, 1.0, 0.0])


def test_triangle_corner_cut_by_a_line():
    # g = x - 1/2 on the unit right triangle: the closed corner x >= 1/2 is a quarter of it; g = 1/2 - x the rest
    assert np.allclose(closed_fraction(np.array([[-0.5, 0.5, -0.5], [0.5, -0.5, 0.5]])), [0.25, 0.75])
    rng = np.random.default_rng(1)
    g = rng.normal(size=(1, 3))  # against sampling: the barycentric points of a fine uniform grid
    n = 400
    i, j = np.meshgrid(np.arange(n), np.arange(n))
    keep = i + j < n
    lam = np.stack([i[keep], j[keep]], axis=1) / n + 1 / (3 * n)
    values = g[0, 0] * (1 - lam.sum(axis=1)) + g[0, 1] * lam[:, 0] + g[0, 2] * lam[:, 1]
    assert abs(closed_fraction(g)[0] - np.mean(values >= 0)) < 5 / n


def test_measure_of_segments_triangles_and_quadrilaterals():
    # a line of 4 unit segments along x, the gap 1 - x: closed over [0, 1] plus nothing else
    x = np.arange(5.0)
    nodes = np.stack([np.stack([x[:-1], 0 * x[:-1], 0 * x[:-1]], 1), np.stack([x[1:], 0 * x[1:], 0 * x[1:]], 1)], 1)
    assert np.isclose(closed_measure(nodes, 1.0 - nodes[:, :, 0]), 1.0)
    # the unit square as a quadrilateral (dolfinx's vertex order 0 1 / 2 3) and as two triangles, gap 0.7 - x
    quad = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0], [1, 1, 0]]], float)
    assert np.isclose(closed_measure(quad, 0.7 - quad[:, :, 0]), 0.7)
    tris = np.array([[[0, 0, 0], [1, 0, 0], [0, 1, 0]], [[1, 0, 0], [1, 1, 0], [0, 1, 0]]], float)
    assert np.isclose(closed_measure(tris, 0.7 - tris[:, :, 0]), 0.7)
    assert closed_measure(np.zeros((0, 2, 3)), np.zeros((0, 2))) == 0.0
