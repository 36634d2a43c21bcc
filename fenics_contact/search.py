"""Closest-point search of points on a facet surface: k-d tree candidates, vectorised distances.

The candidates of a point are the facets whose bounding box lies within its
search radius: the smaller of the given radius and its distance to the
nearest master node (which bounds the distance to the closest facet); points
farther than the radius from the whole master surface's box are not
queried. The facets are grouped in size classes (half box diagonals within
a factor 2, :data:`SIZE_CLASSES` at most); a ``scipy.spatial.cKDTree`` of
each class's box centres is queried with each point (radius + the class's
largest half diagonal: on a graded surface the fine facets are not
candidates of every point within a coarse facet's size) and the answer is
filtered by the exact point-to-box distance. The distance to each candidate
facet (flat segment or triangle, or quadratic segment) is evaluated for all
pairs at once; each point keeps its nearest facet, with the rules of
:func:`project` for ties and hysteresis. A surface ends at its free boundary
(:func:`free_sides`: the ends of a curve, the edges of one facet): a point
whose closest point lies past it (:func:`beyond_free_sides`, beyond an
extension of :data:`EXTENSION` of the facet) has no pair.

Memory is bounded whatever an iterate does: the number of pairs is counted
before any is listed (``return_length``) and facets are processed in
chunks of at most ``PAIR_BUDGET`` pairs, so a Newton iterate that stretches
a facet across the whole surface costs time (every point becomes its
candidate), never an allocation proportional to the geometry's extent (a
uniform bucket grid would list a stretched facet in every cell of its
bounding box: gigabytes). The two-body surfaces also reject such an iterate
outright (:data:`STRETCH_LIMIT`).
"""
from __future__ import annotations

import itertools

import numpy as np
from scipy.spatial import cKDTree

__all__ = ["EXTENSION", "PAIR_BUDGET", "SIZE_CLASSES", "SMALL_SLIDING", "STRETCH_LIMIT", "beyond_free_sides",
           "candidates", "closest_point_on_facets", "closest_point_on_quadratic", "facet_normals", "facet_pairs",
           "facet_sizes", "free_sides", "project", "quadratic_normals", "quadratic_shape", "small_sliding_warning",
           "stretch"]

PAIR_BUDGET = 1 << 20  # (point, facet) pairs held at once: ~100 MB of work arrays at most
# A facet whose extent grew beyond this factor of its reference extent within one iterate is an exploded
# iterate, not a deformation: the two-body surfaces reject it (non-finite residual: a failed solve, cut step).
STRETCH_LIMIT = 10.0
# Small sliding (the pairs of the reference configuration, kept) holds while each pair stays on its master facet: a
# point within a facet size of closing that slid more than this fraction of its facet's size (longest edge) relative
# to its paired master point is over another facet, and its gap is measured against the wrong one.
SMALL_SLIDING = 0.5
# Facets are queried in at most this many classes of size (half bounding-box diagonal, factors of 2 below the largest).
SIZE_CLASSES = 8
# Relative tolerance of the closest-facet comparisons: values this close are ties (decided by the facet order).
TIE = 1e-9
# A surface's free boundary is extended by this fraction of its facet (barycentric units: of the facet's length in
# 2D, of its height over that edge in 3D), as commercial codes' default extension zone: a point sliding just past
# the last node (a block's corner under a drag) keeps its pair; the error is of the facet's size, gone under
# refinement, and a point farther beyond has no pair.
EXTENSION = 0.1


def _boxes(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return x.min(axis=1), x.max(axis=1)


def _control_points(facets: np.ndarray, quadratic: bool) -> np.ndarray:
    """The facets' nodes, and for ``quadratic`` facets (end, middle, end) also the middle Bezier control point
    ``2 x_1 - (x_0 + x_2) / 2``: their box holds the whole curve (the nodes' box need not)."""
    if not quadratic:
        return facets
    return np.concatenate([facets, (2 * facets[:, 1] - 0.5 * (facets[:, 0] + facets[:, 2]))[:, None]], axis=1)


def _box_distance(p: np.ndarray, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.maximum(np.maximum(lo - p, p - hi), 0.0), axis=1)


def _chunks(counts: np.ndarray):
    """Consecutive index ranges whose ``counts`` add up to at most ``PAIR_BUDGET`` (one item at least)."""
    start, n = 0, len(counts)
    total = np.cumsum(counts)
    while start < n:
        base = total[start - 1] if start else 0
        stop = max(int(np.searchsorted(total, base + PAIR_BUDGET, side="right")), start + 1)
        yield start, min(stop, n)
        start = stop


def _ball_pairs(tree: cKDTree, centres: np.ndarray, r: np.ndarray):
    """Chunks of (query index, tree point index) pairs: the tree's points within ``r[i]`` of ``centres[i]``,
    counted before they are listed (at most ``PAIR_BUDGET`` pairs per chunk, one query at least)."""
    counts = tree.query_ball_point(centres, r, return_length=True)
    for a, b in _chunks(np.asarray(counts)):
        lists = tree.query_ball_point(centres[a:b], r[a:b])
        sizes = np.fromiter((len(v) for v in lists), np.int64, b - a)
        query = np.repeat(np.arange(a, b, dtype=np.int64), sizes)
        found = np.fromiter(itertools.chain.from_iterable(lists), np.int64, int(sizes.sum()))
        yield query, found


def _query(tree: cKDTree, lo: np.ndarray, hi: np.ndarray, radius: float):
    """For boxes ``[lo, hi]``: chunks of (box index, tree point index) pairs with the points within the box's
    ball of radius ``radius + half diagonal`` (a superset of the points within ``radius`` of the box)."""
    yield from _ball_pairs(tree, 0.5 * (lo + hi), radius + 0.5 * np.linalg.norm(hi - lo, axis=1))


def candidates(points: np.ndarray, facets: np.ndarray, radius: float | np.ndarray, quadratic: bool = False):
    """Chunks of ``(point index, facet index)`` pairs, every pair whose facet bounding box is within ``radius``
    of the point (a number, or one per point), each pair once, in some chunk. Per size class of the facets, a k-d
    tree of their box centres is queried with each point's radius plus the class's largest half diagonal, then
    filtered exactly.
    ``quadratic`` facets (end, middle, end nodes): the box of the curve's Bezier control points, which holds the
    whole curve (the nodes' box need not)."""
    if len(points) == 0 or len(facets) == 0:
        return
    lo, hi = _boxes(_control_points(facets, quadratic))
    r = np.broadcast_to(np.asarray(radius, dtype=float), (len(points),))
    half = 0.5 * np.linalg.norm(hi - lo, axis=1)
    # One tree per size class (half diagonals within a factor 2; the smallest classes merged): each query grows by
    # its class's largest half diagonal, not the surface's: on a graded surface the fine facets, where the contact
    # is, are not all candidates of every point within the coarse facets' size (8x fewer pairs on the block).
    size_class = np.minimum(np.floor(np.log2(half.max() / np.maximum(half, 1e-300 + 1e-12 * half.max()))),
                            SIZE_CLASSES - 1)
    for c in np.unique(size_class):
        ids = np.flatnonzero(size_class == c)
        for p, f in _ball_pairs(cKDTree(0.5 * (lo[ids] + hi[ids])), points, r + float(half[ids].max())):
            f = ids[f]
            keep = _box_distance(points[p], lo[f], hi[f]) <= r[p]
            yield p[keep], f[keep]


def facet_pairs(xs: np.ndarray, xm: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """``(slave facet, master facet)`` index pairs whose bounding boxes are within ``radius`` of each other,
    sorted by slave then master index (segment-to-segment pairing)."""
    if len(xs) == 0 or len(xm) == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    slo, shi = _boxes(xs)
    tree = cKDTree(0.5 * (slo + shi))
    mlo, mhi = _boxes(xm)
    # Box-to-box within radius: the slave box centre within radius + both half diagonals of the master centre.
    grow = radius + 0.5 * float(np.max(np.linalg.norm(shi - slo, axis=1)))
    fs, ms = [], []
    for m, s in _query(tree, mlo, mhi, grow):
        gap = np.maximum(np.maximum(mlo[m] - shi[s], slo[s] - mhi[m]), 0.0)
        keep = np.linalg.norm(gap, axis=1) <= radius
        fs.append(s[keep])
        ms.append(m[keep])
    fs = np.concatenate(fs) if fs else np.zeros(0, np.int64)
    ms = np.concatenate(ms) if ms else np.zeros(0, np.int64)
    order = np.lexsort((ms, fs))
    return fs[order], ms[order]


def stretch(x: np.ndarray, X: np.ndarray) -> float:
    """Largest ratio of a facet's current extent (bounding-box diagonal of ``x`` (n, nv, d)) to its reference
    extent (``X``); 0 without facets."""
    if len(x) == 0:
        return 0.0
    lo, hi = _boxes(x)
    Lo, Hi = _boxes(X)
    return float(np.max(np.linalg.norm(hi - lo, axis=1) / np.linalg.norm(Hi - Lo, axis=1)))


# --------------------------------------------------------------------------------------------
# Facet geometry (vectorised over pairs: one point per facet row)
# --------------------------------------------------------------------------------------------
def facet_normals(x: np.ndarray) -> np.ndarray:
    """Unit normals of flat facets ``x`` (nf, nv, gdim): ``(t_y, -t_x)`` of ``t = x_1 - x_0`` in 2D,
    ``(x_1 - x_0) x (x_2 - x_0)`` in 3D (the same formulas as the UFL gap)."""
    if x.shape[2] == 2:
        t = x[:, 1] - x[:, 0]
        n = np.stack([t[:, 1], -t[:, 0]], axis=1)
    else:
        n = np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0])
    return n / np.linalg.norm(n, axis=1)[:, None]


def small_sliding_warning(ratio: float) -> str | None:
    """The line of a small-sliding surface whose largest slide is ``ratio`` facet sizes, if past
    :data:`SMALL_SLIDING`; else None."""
    if not ratio > SMALL_SLIDING:
        return None
    return (f"small sliding past its range: a point slid {ratio:.3g} of its master facet's size relative to its pair "
            f"(> {SMALL_SLIDING:g}: over another facet); sliding 'finite' holds there")


def facet_sizes(x: np.ndarray) -> np.ndarray:
    """The longest edge of each facet ``x`` (nf, nv, gdim) (a segment: its length)."""
    nv = x.shape[1]
    edges = [np.linalg.norm(x[:, i] - x[:, j], axis=1) for i in range(nv) for j in range(i + 1, nv)]
    return np.max(edges, axis=0) if edges else np.zeros(len(x))


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    return np.einsum("ij,ij->i", a, b)


def _closest_on_triangles(p: np.ndarray, x: np.ndarray) -> np.ndarray:
    """Barycentric coordinates (n, 3) of the closest point of triangle ``x[i]`` to ``p[i]`` (Ericson's Voronoi
    regions, vectorised: the first region that applies, in Ericson's order)."""
    a, b, c = x[:, 0], x[:, 1], x[:, 2]
    ab, ac = b - a, c - a
    ap, bp, cp = p - a, p - b, p - c
    d1, d2, d3, d4, d5, d6 = _dot(ab, ap), _dot(ac, ap), _dot(ab, bp), _dot(ac, bp), _dot(ab, cp), _dot(ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    n = len(p)
    out = np.zeros((n, 3))
    done = np.zeros(n, bool)

    def put(mask, value):
        m = mask & ~done
        out[m] = value(m) if callable(value) else value
        done[m] = True

    with np.errstate(divide="ignore", invalid="ignore"):
        put((d1 <= 0) & (d2 <= 0), (1.0, 0.0, 0.0))
        put((d3 >= 0) & (d4 <= d3), (0.0, 1.0, 0.0))
        put((vc <= 0) & (d1 >= 0) & (d3 <= 0),
            lambda m: np.stack([1 - d1[m] / (d1[m] - d3[m]), d1[m] / (d1[m] - d3[m]), 0 * d1[m]], axis=1))
        put((d6 >= 0) & (d5 <= d6), (0.0, 0.0, 1.0))
        put((vb <= 0) & (d2 >= 0) & (d6 <= 0),
            lambda m: np.stack([1 - d2[m] / (d2[m] - d6[m]), 0 * d2[m], d2[m] / (d2[m] - d6[m])], axis=1))

        def edge_bc(m):
            w = (d4[m] - d3[m]) / ((d4[m] - d3[m]) + (d5[m] - d6[m]))
            return np.stack([0 * w, 1 - w, w], axis=1)

        put((va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0), edge_bc)

        def inside(m):
            denom = 1.0 / (va[m] + vb[m] + vc[m])
            v, w = vb[m] * denom, vc[m] * denom
            return np.stack([1 - v - w, v, w], axis=1)

        put(np.ones(n, bool), inside)
    return out


def closest_point_on_facets(p: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from ``p`` ((n, gdim), or one point (gdim,) for every facet) to each flat facet ``x``
    (n, nv, gdim) and the barycentric coordinates of the closest point (clipped to the facet)."""
    p = np.broadcast_to(p, (len(x), x.shape[2]))
    if x.shape[1] == 2:
        t = x[:, 1] - x[:, 0]
        s = np.clip(_dot(p - x[:, 0], t) / _dot(t, t), 0.0, 1.0)
        bary = np.stack([1 - s, s], axis=1)
    else:
        bary = _closest_on_triangles(p, x)
    q = np.einsum("ik,ikj->ij", bary, x)
    return np.linalg.norm(q - p, axis=1), bary


def quadratic_shape(xi: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Quadratic Lagrange shape functions on ``xi`` in [0, 1] with nodes (end 0, middle, end 1) at 0, 1/2, 1,
    and their first and second derivatives: three arrays (..., 3)."""
    xi = np.asarray(xi, dtype=float)[..., None]
    N = np.concatenate([2 * (xi - 0.5) * (xi - 1), -4 * xi * (xi - 1), 2 * xi * (xi - 0.5)], axis=-1)
    dN = np.concatenate([4 * xi - 3, 4 - 8 * xi, 4 * xi - 1], axis=-1)
    return N, dN, np.broadcast_to(np.array([4.0, -8.0, 4.0]), N.shape)


def closest_point_on_quadratic(p: np.ndarray, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance from ``p`` ((n, 2), or one point for every segment) to each quadratic segment ``x`` (n, 3, 2)
    (nodes end, middle, end) and the local coordinate ``xi`` in [0, 1] of the closest point: Newton on
    ``(p - x(xi)) . x'(xi) = 0`` from the chord's projection, clipped to the segment (a step that would go
    uphill is replaced by a bisection)."""
    t = x[:, 2] - x[:, 0]
    xi = np.clip(np.einsum("ij,ij->i", p - x[:, 0], t) / np.einsum("ij,ij->i", t, t), 0.0, 1.0)
    for _ in range(50):
        N, dN, ddN = quadratic_shape(xi)
        r = p - np.einsum("ik,ikj->ij", N, x)
        dX, ddX = np.einsum("ik,ikj->ij", dN, x), np.einsum("ik,ikj->ij", ddN, x)
        f = np.einsum("ij,ij->i", r, dX)
        curv = np.einsum("ij,ij->i", dX, dX) - np.einsum("ij,ij->i", r, ddX)  # d2/dxi2 of |p - x|^2 / 2
        step = np.where(curv > 0, f / np.where(curv > 0, curv, 1.0), np.sign(f) * 0.25)
        new = np.clip(xi + step, 0.0, 1.0)
        if np.all(np.abs(new - xi) < 1e-15):
            xi = new
            break
        xi = new
    N = quadratic_shape(xi)[0]
    return np.linalg.norm(p - np.einsum("ik,ikj->ij", N, x), axis=1), xi


def quadratic_normals(x: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Unit normals ``(x'_y, -x'_x)/|x'|`` of quadratic segments ``x`` (n, 3, 2) at ``xi`` (n,)."""
    dX = np.einsum("ik,ikj->ij", quadratic_shape(xi)[1], x)
    n = np.stack([dX[:, 1], -dX[:, 0]], axis=1)
    return n / np.linalg.norm(n, axis=1)[:, None]


# --------------------------------------------------------------------------------------------
# The surface's free boundary
# --------------------------------------------------------------------------------------------
def free_sides(nodes: np.ndarray, surface: np.ndarray, segments: bool | None = None) -> np.ndarray:
    """Which sides of the facets ``nodes`` lie on the free boundary of ``surface``: (n, 2) in 2D, ``[:, k]`` end
    ``k`` (node column 0 or -1) is the end of no other facet; (n, 3) in 3D, ``[:, k]`` the edge opposite vertex
    ``k`` is an edge of no other facet.

    Args:
        nodes: (n, nv) node ids of the facets (any numbering that is the same for a node in every facet).
        surface: (N, nv) node ids of every facet of the whole surface, each facet once.
        segments: the facets are 2D segments (``nv`` 2, or 3 for quadratic segments: end, middle, end); default:
            ``nv == 2``.
    """
    nodes, surface = np.asarray(nodes, np.int64), np.asarray(surface, np.int64)
    if segments is None:
        segments = nodes.shape[1] == 2
    if segments:
        mine, every = nodes[:, [0, -1]], surface[:, [0, -1]].ravel()
        ids, count = np.unique(every, return_counts=True)
        once = ids[count == 1]
        return np.isin(mine, once)
    key = np.sort(nodes[:, [[1, 2], [2, 0], [0, 1]]], axis=2)
    every = np.sort(surface[:, [[1, 2], [2, 0], [0, 1]]], axis=2).reshape(-1, 2)
    ids, count = np.unique(every, axis=0, return_counts=True)
    once = ids[count == 1]
    if not len(once):
        return np.zeros(key.shape[:2], bool)
    # Edge (a, b) as one integer a * (largest + 1) + b for np.isin.
    base = int(max(surface.max(initial=0), nodes.max(initial=0))) + 1
    return np.isin(key[..., 0] * base + key[..., 1], once[:, 0] * base + once[:, 1])


def beyond_free_sides(p: np.ndarray, x: np.ndarray, free: np.ndarray, xi: np.ndarray | None = None,
                      tol: float | np.ndarray = EXTENSION) -> np.ndarray:
    """Whether point ``p[i]`` lies beyond a free side of facet ``x[i]``: its projection on the facet's line or
    plane, unclipped, is outside the facet across a side flagged in ``free[i]`` (:func:`free_sides`) by more
    than ``tol`` of the facet (barycentric coordinate below ``-tol``; default :data:`EXTENSION`). There the
    surface ends: the point has no closest point on it, though the clipped one is the side.

    Args:
        p: (n, gdim) points.
        x: (n, nv, gdim) facets (flat, or quadratic segments: end, middle, end).
        free: (n, 2) in 2D, (n, 3) in 3D, from :func:`free_sides`.
        xi: quadratic segments: the closest point's local coordinate in [0, 1] (:func:`closest_point_on_quadratic`);
            None for flat facets.
        tol: the extension (a number, or one per point).
    """
    n = len(p)
    if n == 0:
        return np.zeros(0, bool)
    tol = np.broadcast_to(np.asarray(tol, dtype=float), (n,))
    if xi is not None:  # quadratic: clipped to an end with the point still beyond it along the curve's tangent
        dN = quadratic_shape(xi)[1]
        tangent = np.einsum("ik,ikj->ij", dN, x)
        along = _dot(p - np.einsum("ik,ikj->ij", quadratic_shape(xi)[0], x), tangent) / _dot(tangent, tangent)
        return ((xi <= 0) & (along < -tol) & free[:, 0]) | ((xi >= 1) & (along > tol) & free[:, 1])
    if x.shape[1] == 2:
        t = x[:, 1] - x[:, 0]
        s = _dot(p - x[:, 0], t) / _dot(t, t)
        return ((s < -tol) & free[:, 0]) | ((s > 1 + tol) & free[:, 1])
    ab, ac, ap = x[:, 1] - x[:, 0], x[:, 2] - x[:, 0], p - x[:, 0]
    g11, g12, g22 = _dot(ab, ab), _dot(ab, ac), _dot(ac, ac)
    r1, r2 = _dot(ab, ap), _dot(ac, ap)
    det = g11 * g22 - g12 * g12
    l1, l2 = (g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det
    lam = np.stack([1 - l1 - l2, l1, l2], axis=1)
    return np.any((lam < -tol[:, None]) & free, axis=1)


# --------------------------------------------------------------------------------------------
# Projection
# --------------------------------------------------------------------------------------------
def _first_per_group(group: np.ndarray, keys: tuple[np.ndarray, ...]) -> np.ndarray:
    """Index of the first row of each group after sorting by ``group`` then ``keys`` (last key most minor)."""
    order = np.lexsort((*keys[::-1], group))
    g = group[order]
    first = np.ones(len(g), bool)
    first[1:] = g[1:] != g[:-1]
    return order[first]


def project(points: np.ndarray, master: np.ndarray, radius: float, previous: np.ndarray | None = None,
            hysteresis: float = 1e-2, quadratic: bool = False, allowed=None, free: np.ndarray | None = None):
    """Closest master facet to each point within ``radius``: ``(facet or -1, barycentric coordinates,
    distance)``, and for ``quadratic`` facets (n, 3, 2) also the local coordinate ``xi`` (the
    "barycentric coordinates" are then the shape function values). Ties go to the lowest facet index
    (callers order facets independently of the partition); a point outside a convex vertex, equally close to
    both facets there, takes the facet whose plane is farthest (the gap is then continuous as it moves across).
    ``previous`` (facet per point, -1 for none): a point keeps its previous facet while that facet is no
    more than ``hysteresis`` x its own size farther than the closest one, so that a point sitting where
    two facets are (almost) equally close does not switch back and forth between Newton iterations.
    ``allowed(points, facets)`` (index arrays of equal length -> bool array): the pairs that may pair at all
    (self-contact: not a point's own neighbourhood); None: every pair. With it, every facet within ``radius``
    is a candidate (the nearest master node may be the point itself). ``free`` (one row per master facet, from
    :func:`free_sides`): a point whose closest point lies past a free side of a facet that attains it
    (:func:`beyond_free_sides`: past the end of the surface, beyond :data:`EXTENSION` for a point with a
    ``previous`` facet, on the surface for one without; in 3D a free vertex is attained by facets with and
    without a free edge) has no pair; None: every closest point counts (the last facets extend the surface)."""
    n = len(points)
    nv = master.shape[1] if master.ndim == 3 else 2
    facet = np.full(n, -1, np.int64)
    bary = np.zeros((n, nv))
    dist = np.full(n, np.inf)
    xis = np.zeros(n)
    beyond = np.full(n, np.inf)  # the distance at which a point's closest point lay past a free side
    # The extension holds a paired point; an unpaired one pairs again on the surface (a point released at the end of
    # the extension is not taken back within it: Newton's iterates cannot cycle across its edge).
    extension = np.full(n, EXTENSION) if previous is None else np.where(previous >= 0, EXTENSION, TIE)
    # Each point's search radius: the distance to the nearest master node bounds the distance to the closest facet
    # (the node lies on a facet), with the tie tolerance below; most points then have a few candidates, not every
    # facet within ``radius`` (a graded master surface's radius is several of its largest facets).
    # Only points within ``radius`` of the master surface's box can have a facet (its curves' box: Bezier control
    # points); the others are not queried at all (most of a body's surface, away from the contact).
    near_box = np.zeros(0, np.int64)
    if n and len(master):
        flat = _control_points(master, quadratic).reshape(-1, master.shape[-1])
        near_box = np.flatnonzero(_box_distance(points, flat.min(axis=0), flat.max(axis=0)) <= radius)
    if len(near_box) and allowed is not None:
        bound = np.full(len(near_box), float(radius))
    elif len(near_box):
        near = cKDTree(master.reshape(-1, master.shape[-1])).query(points[near_box])[0] * (1 + TIE) + 1e-14 * radius
        bound = np.where(near < radius, near, radius)
    else:
        bound = np.zeros(0)
    for pi, fi in candidates(points[near_box], master, bound, quadratic):
        pi = near_box[pi]
        # Chunks may split a point's candidates: the running best of a point joins as one more candidate.
        old = np.unique(pi[facet[pi] >= 0])
        if len(old):
            pi, fi = np.concatenate([pi, old]), np.concatenate([fi, facet[old]])
        if allowed is not None:
            keep = allowed(pi, fi)
            pi, fi = pi[keep], fi[keep]
            if not len(pi):
                continue
        p, mf = points[pi], master[fi]
        if quadratic:
            d, xi = closest_point_on_quadratic(p, mf)
            b = quadratic_shape(xi)[0]
            q = np.einsum("ik,ikj->ij", b, mf)
            line = np.abs(_dot(p - q, quadratic_normals(mf, xi)))
        else:
            d, b = closest_point_on_facets(p, mf)
            xi = np.zeros(len(pi))
            line = np.abs(_dot(p - mf[:, 0], facet_normals(mf)))
        # Nearest distance per point; among the (near-)tied facets the (near-)farthest plane, then the lowest index.
        # Both comparisons carry the same tolerance: a point on the bisector of two facets' planes (over their
        # shared edge, e.g. on a symmetry plane) is equally far from both up to round-off, and round-off that
        # differs between runs (another partition, another solver) must not pick the facet (its normal).
        dmin = np.full(n, np.inf)
        np.minimum.at(dmin, pi, d)
        k = np.flatnonzero(d <= dmin[pi] * (1 + TIE) + 1e-14 * radius)
        if free is not None:  # the closest point lies past a free side of a facet that attains it
            out = k[beyond_free_sides(p[k], mf[k], free[fi[k]], xi[k] if quadratic else None, extension[pi[k]])]
            np.minimum.at(beyond, pi[out], d[out])
        lmax = np.full(n, -np.inf)
        np.maximum.at(lmax, pi[k], line[k])
        k = k[line[k] >= lmax[pi[k]] * (1 - TIE) - 1e-14 * radius]
        best = k[_first_per_group(pi[k], (fi[k],))]
        i = pi[best]
        facet[i], bary[i], dist[i], xis[i] = fi[best], b[best], d[best], xi[best]
    if previous is not None:  # hysteresis: keep the previous facet (a candidate) if it is nearly as close
        i = np.flatnonzero((previous >= 0) & (facet >= 0) & (facet != previous))
        if len(i) and allowed is not None:
            i = i[allowed(i, previous[i])]
        if len(i):
            mp = master[previous[i]]
            lo, hi = _boxes(mp)
            i, mp = i[_box_distance(points[i], lo, hi) <= radius], mp[_box_distance(points[i], lo, hi) <= radius]
        if len(i):
            if quadratic:
                d, xi = closest_point_on_quadratic(points[i], mp)
                b = quadratic_shape(xi)[0]
            else:
                d, b = closest_point_on_facets(points[i], mp)
                xi = np.zeros(len(i))
            size = np.linalg.norm(mp[:, -1 if quadratic else 1] - mp[:, 0], axis=1)
            keep = d <= dist[i] + hysteresis * size
            i = i[keep]
            facet[i], bary[i], dist[i], xis[i] = previous[i], b[keep], d[keep], xi[keep]
    far = dist > radius
    if free is not None:  # the closest point is on the surface's free boundary, and the point lies past it
        far |= beyond <= dist * (1 + TIE) + 1e-14 * radius
    facet[far], bary[far], dist[far], xis[far] = -1, 0.0, np.inf, 0.0
    return (facet, bary, dist, xis) if quadratic else (facet, bary, dist)
