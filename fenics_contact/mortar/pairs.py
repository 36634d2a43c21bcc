"""Slave/master facet pairs of segment integration: the pairs whose overlap is not empty.

Candidates are the master facets whose bounding box is within the search radius of the slave facet's
(:func:`search.facet_pairs`, a k-d tree), with normals facing each other and a non-empty overlap; a pair is
kept when :func:`search.project` (the pointwise closest-point search) pairs the middle of its overlap with the
same master facet, so the pointwise and the segment options share one projection. At a convex master kink
the slave points whose closest point is the vertex itself belong to no pair (no force); on a flat or smooth
master this set is empty or vanishes with h.
"""
from __future__ import annotations

import numpy as np

from ..search import closest_point_on_facets, facet_normals, facet_pairs, project
from .clipping import clip_arrays, master_lines, polygon_areas

__all__ = ["overlap", "pair_segments", "pair_triangles", "SegmentPairs"]


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
    alpha, beta = master_lines([[x[:, a, i] for i in range(3)] for a in range(6)])
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



class SegmentPairs:
    """The slave/master facet pairs of the owned slave facets at the last update, kept between updates.

    ``pairs`` (n, 2): (local slave facet, index into ``master_x`` and ``master_dofs``, the current coordinates
    and global displacement dofs (k, nv, gdim) of the master facets received then); ``ids``: the same pairs
    with global master facet numbers (the pairing state)."""

    def __init__(self, comm):
        self.comm = comm
        self.pairs = self.ids = self.master_x = self.master_dofs = None

    def update(self, xs: np.ndarray, owned: np.ndarray, master: dict, radius: float) -> bool:
        """Pair the owned ones (``owned`` (nf,) flags) of the current slave facets ``xs`` (nf, nv, gdim) with the
        master facets ``master`` (:class:`twobody.Pairing`'s). Collective. Returns True if the pairs changed on
        any rank (always on the first update)."""
        own = np.flatnonzero(owned)
        pair = pair_segments if xs.shape[-1] == 2 else pair_triangles
        fs, ms = pair(xs[own], master["x"], radius)
        pairs = np.stack([own[fs], ms], axis=1)
        ids = np.stack([own[fs], master["ids"][ms]], axis=1)
        same = self.ids is not None and np.array_equal(self.ids, ids)
        changed = self.comm.allreduce(0 if same else 1) > 0
        self.pairs, self.ids = pairs, ids
        self.master_x, self.master_dofs = master["x"], master["G"]
        return changed
