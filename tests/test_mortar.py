"""Vectorised 3D clipping of segment integration (fenics_contact.mortar) against the per-pair loop and geometry."""
import numpy as np

from fenics_contact.mortar import _SLAVE_LINES, _intersect_values, _master_lines, clip_arrays, polygon_areas


def _clip_loop(alpha, beta, tol=1e-12):
    """The per-pair Sutherland-Hodgman loop the vectorised clipping replaced (the reference)."""
    out = []
    for a, b in zip(alpha, beta):
        A = np.concatenate([_SLAVE_LINES[0], a])
        B = np.concatenate([_SLAVE_LINES[1], b])
        poly = [(2, 0), (0, 1), (1, 2)]
        for k in (3, 4, 5):
            if not poly:
                break
            val = [A[k] + B[k] @ _intersect_values(A, B, *v) for v in poly]
            new = []
            for i, q in enumerate(poly):
                p = poly[i - 1]
                if val[i] >= -tol:
                    if val[i - 1] < -tol:
                        new.append((k, p[1]))
                    new.append(q)
                elif val[i - 1] >= -tol:
                    new.append((p[1], k))
            poly = new
        out.append(poly if len(poly) >= 3 else [])
    return out


def _lines(x):
    alpha, beta = _master_lines([[x[:, a, i] for i in range(3)] for a in range(6)])
    return np.stack(alpha, 1), np.array(beta).transpose(2, 0, 1)


def test_clipping_equals_the_loop_on_random_pairs():
    """Random slave/master triangle pairs (tilted, overlapping partly, fully or not at all, with matching
    edges): the vectorised polygons are the loop's vertex for vertex, their areas the shoelace formula's."""
    rng = np.random.default_rng(7)
    n = 600
    s = rng.uniform(0, 1, (n, 3, 3)) * [1, 1, 0.05]
    m = s + rng.uniform(-0.5, 0.5, (n, 1, 3)) * [1, 1, 0] + rng.normal(0, 0.2, (n, 3, 3)) * [1, 1, 0.1]
    m[:50] = s[:50]  # coinciding triangles: edges on edges
    m[50:100, :2] = s[50:100, :2]  # one shared edge
    alpha, beta = _lines(np.concatenate([s, m], axis=1))
    poly, count = clip_arrays(alpha, beta)
    ref = _clip_loop(alpha, beta)
    assert [len(p) for p in ref] == list(count)
    assert all([tuple(v) for v in poly[i, :count[i]]] == ref[i] for i in range(n))
    assert 100 < np.count_nonzero(count) < n  # both kinds present
    area, _ = polygon_areas(alpha, beta, poly, count)
    for i in np.flatnonzero(count):
        A, B = np.concatenate([_SLAVE_LINES[0], alpha[i]]), np.concatenate([_SLAVE_LINES[1], beta[i]])
        P = np.array([_intersect_values(A, B, *v) for v in ref[i]])
        shoelace = 0.5 * np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1])
        assert abs(area[i] - shoelace) <= 1e-12
    assert np.allclose(area[:50], 0.5, rtol=0, atol=1e-12)  # coinciding: the whole reference triangle


def test_overlaps_of_a_tiling_cover_the_slave_triangle():
    """A slave triangle over a master plane tiled by triangles (a tilted, unrelated grid): the overlap areas
    add up to the whole reference triangle (1/2), whatever the tiling cuts."""
    rng = np.random.default_rng(3)
    h = 0.13
    ij = np.stack(np.meshgrid(np.arange(-12, 12), np.arange(-12, 12), indexing="ij"), -1).reshape(-1, 2)
    c = np.cos(0.4), np.sin(0.4)
    R = np.array([[c[0], -c[1]], [c[1], c[0]]])
    corner = lambda a, b: (np.stack([a, b], -1) * h) @ R.T  # noqa: E731
    lower = np.stack([corner(ij[:, 0], ij[:, 1]), corner(ij[:, 0] + 1, ij[:, 1]), corner(ij[:, 0], ij[:, 1] + 1)], 1)
    upper = np.stack([corner(ij[:, 0] + 1, ij[:, 1]), corner(ij[:, 0] + 1, ij[:, 1] + 1),
                      corner(ij[:, 0], ij[:, 1] + 1)], 1)
    master2 = np.concatenate([lower, upper])
    master = np.concatenate([master2, np.full(master2.shape[:2] + (1,), -0.01)], axis=2)  # below the slave
    for _ in range(5):
        s = np.concatenate([rng.uniform(-0.5, 0.5, (3, 2)), np.zeros((3, 1))], axis=1)
        s = s[::-1] if np.cross(s[1] - s[0], s[2] - s[0])[2] > 0 else s  # normal down, towards the master
        x = np.concatenate([np.broadcast_to(s, master.shape), master], axis=1)
        alpha, beta = _lines(x)
        poly, count = clip_arrays(alpha, beta)
        area, _ = polygon_areas(alpha, beta, poly, count)
        assert abs(area.sum() - 0.5) <= 1e-12, area.sum()
        assert np.count_nonzero(count) > 3
