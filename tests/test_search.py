"""Closest-point search: the k-d tree answers as an all-pairs search does; memory stays bounded whatever the
geometry; an exploded two-body iterate is rejected with a non-finite residual."""
import resource

import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact import search
from fenics_contact.app.scenes import build
from fenics_contact.methods import make_law
from fenics_contact.search import closest_point_on_facets, closest_point_on_quadratic, project


def _ring(rng, n=60, wobble=0.05):
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    return np.stack([np.cos(t), np.sin(t)], 1) * (1 + wobble * rng.standard_normal((n, 1)))


def _brute(pts, facets, radius, quadratic=False):
    """Nearest facet of every point by an all-pairs loop (-1 beyond radius), and its distance."""
    out = []
    for p in pts:
        d = closest_point_on_quadratic(p, facets)[0] if quadratic else closest_point_on_facets(p, facets)[0]
        out.append((int(np.argmin(d)), d.min()) if d.min() <= radius else (-1, np.inf))
    return np.array([f for f, _ in out]), np.array([d for _, d in out])


@pytest.mark.parametrize("budget", [search.PAIR_BUDGET, 17])  # 17: many chunks, each a few facets
def test_projection_matches_brute_force_2d(budget, monkeypatch):
    """Segments and quadratic segments of a wobbly ring, points scattered around it: the same distances as an
    all-pairs search, the nearest facet (up to exact ties), no pair beyond the radius."""
    monkeypatch.setattr(search, "PAIR_BUDGET", budget)
    rng = np.random.default_rng(1)
    ring = _ring(rng)
    segments = np.stack([ring, np.roll(ring, -1, axis=0)], 1)
    mid = 0.5 * (segments[:, 0] + segments[:, 1]) * (1 + 0.02 * rng.standard_normal((60, 1)))
    curves = np.stack([segments[:, 0], mid, segments[:, 1]], 1)
    pts = rng.uniform(-1.3, 1.3, (300, 2))
    radius = 0.3
    for facets, quadratic in ((segments, False), (curves, True)):
        facet, bary, dist = project(pts, facets, radius, quadratic=quadratic)[:3]
        f_ref, d_ref = _brute(pts, facets, radius, quadratic)
        assert np.array_equal(facet >= 0, f_ref >= 0)
        ok = f_ref >= 0
        assert np.allclose(dist[ok], d_ref[ok], rtol=1e-12, atol=1e-14)
        assert np.all(np.isinf(dist[~ok]))


def test_quadratic_facet_outside_its_nodes_box_is_found():
    """A quadratic segment bulges beyond the box of its nodes (the middle node off centre: x(xi) < 0 near
    xi = 0.19): a point 0.044 from the curve but 0.1 from that box is paired within a radius of 0.05."""
    curve = np.array([[[0.0, 0.0], [0.1, 0.1], [1.0, 0.0]]])
    pts = np.array([[-0.1, 0.06]])
    facet, _, dist = project(pts, curve, 0.05, quadratic=True)[:3]
    d_ref = closest_point_on_quadratic(pts[0], curve)[0][0]
    assert d_ref < 0.05 and facet[0] == 0 and np.isclose(dist[0], d_ref, rtol=1e-12)


def test_point_radius_keeps_the_nearest_facet_on_a_graded_surface():
    """Fine facets next to coarse ones, a radius many fine facets wide: the search (each point's radius cut to
    its nearest node's distance) still answers as the all-pairs search."""
    rng = np.random.default_rng(5)
    x = np.concatenate([np.linspace(-1, -0.1, 4), np.linspace(-0.1, 0.1, 201)[1:], np.linspace(0.1, 1, 4)[1:]])
    nodes = np.stack([x, 0.02 * np.sin(7 * x)], 1)
    segments = np.stack([nodes[:-1], nodes[1:]], 1)
    pts = np.concatenate([rng.uniform([-1, -0.05], [1, 0.05], (300, 2)), nodes[::7] + [0.0, 0.01]])
    facet, _, dist = project(pts, segments, 0.8)[:3]
    f_ref, d_ref = _brute(pts, segments, 0.8)
    assert np.array_equal(facet >= 0, f_ref >= 0) and np.allclose(dist, d_ref, rtol=1e-12, atol=1e-14)


def test_projection_matches_brute_force_3d():
    """Triangles of a bumpy sheet, points above and below it."""
    rng = np.random.default_rng(3)
    n = 9
    X, Y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    P = np.stack([X, Y, 0.05 * np.sin(3 * X) * np.cos(2 * Y)], -1)
    tris = np.array([t for i in range(n - 1) for j in range(n - 1)
                     for t in ([P[i, j], P[i + 1, j], P[i, j + 1]], [P[i + 1, j], P[i + 1, j + 1], P[i, j + 1]])])
    pts = np.column_stack([rng.uniform(-0.1, 1.1, (400, 2)), 0.1 * rng.standard_normal(400)])
    facet, bary, dist = project(pts, tris, 0.15)
    f_ref, d_ref = _brute(pts, tris, 0.15)
    assert np.array_equal(facet >= 0, f_ref >= 0)
    ok = f_ref >= 0
    assert np.allclose(dist[ok], d_ref[ok], rtol=1e-12, atol=1e-14)
    q = np.einsum("ik,ikj->ij", bary[ok], tris[facet[ok]])
    assert np.allclose(np.linalg.norm(q - pts[ok], axis=1), dist[ok], rtol=1e-12, atol=1e-14)


def test_graded_sheet_matches_brute_force_3d():
    """A sheet graded 1:400 (the facets fall in every size class of the search), points near it and far beyond
    its box: the candidate pairs are exactly the pairs whose facet box is within each point's radius, and the
    projection answers as the all-pairs search."""
    rng = np.random.default_rng(7)
    s = np.linspace(-1, 1, 25)
    g = np.sign(s) * np.abs(s) ** 4  # spacing from 4e-5 at the centre to 0.15 at the edges
    X, Y = np.meshgrid(g, g)
    P = np.stack([X, Y, 0.03 * np.sin(5 * X) * np.cos(4 * Y)], -1)
    n = len(g)
    tris = np.array([t for i in range(n - 1) for j in range(n - 1)
                     for t in ([P[i, j], P[i + 1, j], P[i, j + 1]], [P[i + 1, j], P[i + 1, j + 1], P[i, j + 1]])])
    half = 0.5 * np.linalg.norm(tris.max(axis=1) - tris.min(axis=1), axis=1)
    assert half.max() / half.min() > 2 ** search.SIZE_CLASSES
    pts = np.concatenate([np.column_stack([0.01 * rng.standard_normal((300, 2)), 0.01 * rng.standard_normal(300)]),
                          np.column_stack([rng.uniform(-1.2, 1.2, (300, 2)), 0.1 * rng.standard_normal(300)]),
                          rng.uniform(3, 4, (50, 3))])
    r = rng.uniform(0, 0.1, len(pts))
    found = {(int(p), int(f)) for pi, fi in search.candidates(pts, tris, r) for p, f in zip(pi, fi)}
    lo, hi = tris.min(axis=1), tris.max(axis=1)
    box = np.linalg.norm(np.maximum(np.maximum(lo[None] - pts[:, None], pts[:, None] - hi[None]), 0), axis=2)
    assert found == set(zip(*map(lambda a: a.tolist(), np.nonzero(box <= r[:, None]))))
    facet, bary, dist = project(pts, tris, 0.1)
    f_ref, d_ref = _brute(pts, tris, 0.1)
    assert np.array_equal(facet >= 0, f_ref >= 0) and np.all(facet[-50:] == -1)
    ok = f_ref >= 0
    assert np.allclose(dist[ok], d_ref[ok], rtol=1e-12, atol=1e-14)


def test_round_off_does_not_pick_the_facet_at_a_ridge():
    """Two triangles meeting at a ridge along x = 0 (slopes +-0.01), points below the ridge (penetrating, the
    contact edge of a symmetric body) moved across it by round-off (|x| <= 1e-16): every point takes the same
    facet, the first in the given order, whichever side of the bisector round-off puts it (the serial and the
    parallel run of a symmetric scene differ by such round-off: the facet decides the normal)."""
    a, b, c, d = [0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.5, -0.01], [-1.0, 0.5, -0.01]
    tris = np.array([[a, b, c], [b, a, d]])
    for order in ((0, 1), (1, 0)):
        pts = np.array([[s * 1e-16, 0.5, -1e-5] for s in (-1.0, -0.3, 0.0, 0.4, 1.0)])
        facet = project(pts, tris[list(order)], 0.1)[0]
        assert np.all(facet == 0), (order, facet)
    off = np.array([[1e-7, 0.5, -1e-5], [-1e-7, 0.5, -1e-5]])  # beyond round-off: the geometry decides
    assert list(project(off, tris, 0.1)[0]) == [0, 1]


def test_closest_point_on_triangle_brute_force():
    rng = np.random.default_rng(2)
    tri = rng.standard_normal((1, 3, 3))
    for p in rng.standard_normal((50, 3)) * 2:
        d, b = closest_point_on_facets(p, tri)
        s = rng.uniform(0, 1, (20000, 2))
        s = np.where(s.sum(1, keepdims=True) > 1, 1 - s, s)
        q = tri[0, 0] + s[:, :1] * (tri[0, 1] - tri[0, 0]) + s[:, 1:] * (tri[0, 2] - tri[0, 0])
        assert d[0] <= np.linalg.norm(q - p, axis=1).min() + 1e-12
        assert np.all(b >= -1e-14) and np.isclose(b.sum(), 1.0)


def test_memory_bounded_for_a_stretched_facet():
    """One facet stretched to 1e12 (an exploded Newton iterate): the search still answers the nearest facet of
    every point, and the peak memory does not grow by more than 50 MB (a grid over the facet's bounding box, as
    the search had before, asks for 1e12 / radius cells)."""
    rng = np.random.default_rng(4)
    ring = _ring(rng, 400, 0.0)
    facets = np.stack([ring, np.roll(ring, -1, axis=0)], 1)
    facets[7, 1] = [1e12, -3e11]
    pts = ring * 1.01
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    facet, _, dist = project(pts, facets, 0.05)
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    f_ref, d_ref = _brute(pts, facets, 0.05)
    assert np.allclose(dist, d_ref, rtol=1e-12, atol=1e-14)
    assert grown_mb < 50


def test_exploded_two_body_iterate_is_rejected():
    """Master displacements that stretch a facet past search.STRETCH_LIMIT: the surface reports the iterate
    exploded and the contact residual is non-finite (the solve fails, the step is cut), on every rank."""
    setup = build("patch", law_factory=lambda: make_law("penalty", K=1e3), quadrature="nodal", passes="one")
    c = setup.contacts[0]
    p = setup.problem
    b = p.u.vector.copy() if hasattr(p.u, "vector") else p.u.x.petsc_vec.copy()
    c.prepare(p)
    assert not c.exploded
    md = c.master_data
    p.u.x.array[md.comp[:, 0]] += 1e6 * (1 + np.arange(md.comp[:, 0].size).reshape(md.comp[:, 0].shape))
    p.u.x.scatter_forward()
    c.prepare(p)
    assert MPI.COMM_WORLD.allreduce(c.exploded, op=MPI.LAND)
    b.set(0.0)
    c.add_residual(b)
    assert not np.isfinite(b.norm())


def test_exploded_iterate_is_a_failure_kind():
    """A Newton solve that meets an exploded two-body facet fails with the failure kind ``exploded_geometry``
    (named in the error, on every rank) instead of searching the exploded geometry; the solver's time split
    has the surface's search, exchange and coupling seconds."""
    from fenics_contact.solver import ConvergenceError, Solver

    setup = build("patch", law_factory=lambda: make_law("penalty", K=1e3), quadrature="nodal", passes="one")
    c = setup.contacts[0]
    p = setup.problem
    solver = Solver(p, quiet=True, max_cutbacks=1)
    md = c.master_data
    comp = md.comp[..., 0]
    p.u.x.array[comp] = 1e6 * (1 + np.arange(comp.size).reshape(comp.shape))  # every attempt starts here
    p.u.x.scatter_forward()
    with pytest.raises(ConvergenceError, match="exploded_geometry") as err:
        solver.run([1.0])
    assert err.value.failure["kind"] == "exploded_geometry"
    assert [f["kind"] for f in solver.failures] == ["exploded_geometry"] * 2  # the step and its cut
    split = solver.summary()["time_split"]
    assert {"search_s", "exchange_s", "coupling_s"} <= set(split)


def test_free_sides_of_open_and_closed_surfaces():
    """The ends of a polyline and the boundary edges of a triangulated square are free; a closed polyline has no
    free end; quadratic segments count their end nodes only."""
    line = np.array([[0, 1], [1, 2], [2, 3]])
    assert search.free_sides(line, line).tolist() == [[True, False], [False, False], [False, True]]
    loop = np.array([[0, 1], [1, 2], [2, 0]])
    assert not search.free_sides(loop, loop).any()
    quadratic = np.array([[0, 10, 1], [1, 11, 2]])  # (end, middle, end)
    assert search.free_sides(quadratic, quadratic, segments=True).tolist() == [[True, False], [False, True]]
    square = np.array([[0, 1, 2], [0, 2, 3]])  # the diagonal 0-2 shared; side k: the edge opposite vertex k
    assert search.free_sides(square, square).tolist() == [[True, False, True], [True, True, False]]


def test_a_point_past_a_free_end_has_no_pair():
    """A master surface ends at its free boundary: a point past it (beyond the extension of a tenth of the facet)
    has no pair, where its clipped closest point would pair it with the last facet as if the surface went on; a
    point within the extension, or in front of the surface, keeps its pair. 2D (flat and quadratic) and 3D (past
    a free edge, and past the square's corner, a vertex that facets without a free edge also reach)."""
    x = np.array([[[1.0, 0], [0, 0]], [[2.0, 0], [1, 0]]])  # y = 0 facing +y, x in [0, 2]
    free = search.free_sides(np.array([[1, 0], [2, 1]]), np.array([[1, 0], [2, 1]]))
    pts = np.array([[1.5, 0.01], [2.05, 0.01], [2.5, 0.01], [-0.3, -0.01]])
    assert project(pts, x, 1.0)[0].tolist() == [1, 1, 1, 0]  # without the free boundary: every point paired
    assert project(pts, x, 1.0, free=free)[0].tolist() == [1, 1, -1, -1]
    xq = np.array([[[2.0, 0], [1.5, 0.02], [1, 0]], [[1.0, 0], [0.5, 0.02], [0, 0]]])
    quadratic_nodes = np.array([[2, 5, 1], [1, 4, 0]])
    fq = search.free_sides(quadratic_nodes, quadratic_nodes, segments=True)
    assert project(pts, xq, 1.0, quadratic=True, free=fq)[0].tolist() == [0, 0, -1, -1]
    # The unit square at z = 0, a fan round the node (1, 0.5) of its right side: the first two triangles reach that
    # node with interior edges only, the tie at it goes to the first.
    nodes = np.array([[2, 5, 0], [2, 4, 5], [1, 2, 0], [2, 3, 4]])
    xs = np.array([[0.0, 0, 0], [1, 0, 0], [1, 0.5, 0], [1, 1, 0], [0, 1, 0], [0, 0.5, 0]])[nodes]
    pts3 = np.array([[0.3, 0.6, 0.01], [1.05, 0.2, -0.01], [1.5, 0.2, -0.01], [1.5, 0.5, 0.01], [1.3, 1.3, 0.01],
                     [0.5, -0.4, 0.0]])
    assert (project(pts3, xs, 1.0)[0] >= 0).all()
    assert project(pts3, xs, 1.0)[0][3] == 0
    assert (project(pts3, xs, 1.0, free=search.free_sides(nodes, nodes))[0] >= 0).tolist() == [
        True, True, False, False, False, False]
