"""Closest-point pairing of the slave points with the current master facets.

Each update routes the master facets near this rank's slave facets (:class:`~.exchange.MasterExchange`),
projects the slave points on their current positions (:func:`search.project`: a k-d tree, memory bounded by
the surfaces' size whatever the iterate; a point past the master surface's free boundary, an end in 2D or an edge
of one facet in 3D, has no pair there: :func:`search.free_sides`) and evaluates the normal gap (positive =
penetration, see :mod:`laws`) and the master normal at each point, in NumPy with the formulas of the UFL gap
(:class:`~.mirror.MirrorObstacle`). A point keeps its facet while that facet stays nearly as close as the
closest one (the hysteresis of :func:`search.project`); the pairing is kept in global facet numbers, so it
survives a re-routing and does not depend on the partition. An iterate that stretched a master facet past
:data:`search.STRETCH_LIMIT` is rejected (``exploded``), not searched. Small sliding (``sliding="small"``): the
slave points are projected in the reference configuration (the same pair at every iterate; the projection is kept
and searched again only when the routed master facets or the pairs change) and the gap is
``-(x_s - sum_k N_k x_k) . n`` with the reference weights ``N_k`` and the reference normal ``n`` (linear in the
displacements, :class:`~.mirror.MirrorObstacle`).

Self-contact (``self_contact=True``, the slave surface its own master): a point never pairs with its own
neighbourhood: a master facet whose current normal faces the same way as the point's facet's (the normals less
than 60 degrees apart, :data:`FACING`; quadratic facets: the normals of their chords), or a facet near the point
in the reference configuration (within :data:`NEIGHBOURHOOD` search radii) that the point lies behind there
(by more than :data:`BEHIND` of its size: the other face of a convex corner of the body, rounded over a few facets
or sharp). What remains is the surface across a gap or a fold, as another body's would be, including the facet
next to the point across the tip of a fold (a concave crease: the point is in front of it, or on it, gap 0, if it
is the facets' common node).
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI

from ..search import facet_normals, facet_sizes, free_sides, project, quadratic_normals, quadratic_shape, stretch
from .exchange import MasterExchange
from .facets import FacetData, SlavePoints

__all__ = ["BEHIND", "FACING", "NEIGHBOURHOOD", "Pairing"]

# Self-contact: a master facet faces a point's facet when their normals are more than 60 degrees apart (n_s . n_m <
# 1/2): a fold is seen while it closes, before its two sides overlap (from 90 degrees on, Newton's iterates had crossed
# it at the tube's crease before it was seen)
FACING = 0.5
# Self-contact: the facets within this many search radii of a point in the reference configuration are its
# neighbourhood, where a facet it lies behind is the other face of a convex corner of the body (around a corner of
# a few facets, not only the facets sharing its node). Farther on, a point behind a facet's line may meet it in a
# fold of a convex body.
NEIGHBOURHOOD = 2.0
# ... "behind" by more than this fraction of the facet's size: a sharp corner's faces (turning by 60 degrees or more,
# FACING) put the contact points of the first facets past the corner at least 0.18 of a facet behind each other,
# while two sides of the surface that overlap slightly in the reference configuration (a mesh made with an
# interference) still meet.
BEHIND = 0.05


class Pairing:
    """The master facet, gap and normal of every local slave point. Collective construction and updates.

    Args:
        comm: the mesh's communicator.
        slave, master: the two surfaces' facets (:func:`~.facets.facet_pair`).
        points: the contact points on the slave facets.
        radius: search radius (default: 2 x the longest master facet, 1 without master facets); slave points
            farther from the master surface have no pair.
        seconds: the surface's timings; ``exchange_s`` and ``search_s`` are added to it.
        sliding: ``finite`` (pair the current positions) or ``small`` (pair the reference positions).
        self_contact: the slave surface is its own master: exclude each point's own neighbourhood.

    After :meth:`update` (unless ``exploded``): ``master`` the received master facets ``{"X", "G", "U", "ids",
    "x"}`` (reference and current coordinates, global displacement dofs, displacements, global facet numbers;
    partition-independent order), ``facet`` (nf, nq) index of each point's master facet in ``master`` (-1:
    none), ``ids`` the same as global facet numbers, ``local_coordinate`` (nf, nq) the closest point's ``xi``
    on a quadratic facet (None for flat facets) and ``projection``: ``facet``, ``bary`` (barycentric
    coordinates of the closest point), ``distance``, ``gap`` (> 0 penetration; ``-inf`` unpaired) and
    ``normal`` (master unit normal). ``changes``: updates that changed the pairing.

    Raises:
        ValueError: ``radius`` is not a finite number > 0.
    """

    def __init__(self, comm, slave: FacetData, master: FacetData, points: SlavePoints, radius: float | None,
                 seconds, sliding: str = "finite", self_contact: bool = False):
        self.comm, self.slave, self.master_facets, self.points = comm, slave, master, points
        self.self_contact = self_contact
        self.small = sliding == "small"
        self.quadratic, self.nv = slave.quadratic, slave.nv
        own = master.owned
        self.exchange = MasterExchange(comm, master.X[own], master.global_comp[own], master.global_facets[own],
                                       self.quadratic)
        # The master surface's free boundary (ends, or edges of one facet), per global facet number: a point past
        # it has no closest point on the surface (the surface does not go on along its last facet).
        ids, nodes = (np.concatenate(a) for a in zip(*comm.allgather(
            (master.global_facets[own], master.global_comp[own][..., 0]))))
        order = np.argsort(ids)
        self._free_ids = ids[order]
        self._free = free_sides(nodes, nodes, segments=master.X.shape[-1] == 2)[order]
        if radius is None:
            Xo = master.X[own]
            sides = (Xo[:, -1:] - Xo[:, :1]) if self.quadratic else np.diff(Xo, axis=1)
            longest = comm.allreduce(float(np.max(np.linalg.norm(sides, axis=2))) if len(Xo) else 0.0, op=MPI.MAX)
            radius = 2.0 * longest if longest > 0 else 1.0
        if not (np.isfinite(radius) and radius > 0):
            raise ValueError(f"search radius must be a finite number > 0, got {radius!r}")
        self.radius = float(radius)
        self._seconds = seconds
        self.master = None
        self.facet = None
        self.ids = None
        self.local_coordinate = None
        self.projection = None
        self.exploded = False  # the last update met a master facet stretched past search.STRETCH_LIMIT
        self._exploded_seen = False  # ... or one since take_failure()
        self.changes = 0
        self._reference_projection = None  # small sliding: ((master ids, pairs) searched, their projection)

    def update(self, u: np.ndarray, everywhere: bool = False) -> bool:
        """Pair the slave points at the unknown's local array ``u``. ``everywhere``: every master facet to every
        rank (the all-gather exchange). Returns True if the pairing changed on any rank (always on the first
        update); False, with ``exploded`` set and the last pairing kept, for an exploded iterate."""
        with self._seconds.measure("exchange_s"):
            master = self._route(u, everywhere)
        # An exploded iterate is rejected, not searched (every rank sees the largest stretch).
        self.exploded = master is None
        self._exploded_seen |= self.exploded
        if self.exploded:
            return False
        self.master = master
        with self._seconds.measure("search_s"):
            facet = self._project(u)
        ok = facet >= 0
        ids = np.full(facet.shape, -1, np.int64)
        ids[ok] = master["ids"][facet[ok]]
        same = self.ids is not None and np.array_equal(self.ids, ids)
        changed = self.comm.allreduce(0 if same else 1) > 0
        self.facet, self.ids = facet.copy(), ids
        self.changes += changed
        return changed

    def _route(self, u: np.ndarray, everywhere: bool) -> dict | None:
        """The master facets near this rank's slave facets with their current coordinates ``x``, or None (on
        every rank) if a master facet exploded."""
        md = self.master_facets
        X = md.X[md.owned]
        U = u[md.comp[md.owned]]
        xs = self.slave.current(u)
        smax, master = self.exchange.exchange(U, xs, self.radius, stretch(X + U, X), everywhere)
        if master is not None:
            master["x"] = master["X"] + master["U"]
        return master

    def _project(self, u: np.ndarray) -> np.ndarray:
        """Project the slave points on ``master`` (small sliding: in the reference configuration); set
        ``projection`` and ``local_coordinate``. Returns ``facet`` (nf, nq)."""
        xm = self.master["x"]
        pts = self.points.current(u)
        nf, nq, d = pts.shape if pts.size else (0, self.points.per_facet, pts.shape[-1])
        previous = None if self.ids is None else self._local_facets(self.ids.ravel())
        allowed = self._allowed(u, xm, nq) if self.self_contact else None
        # Small sliding projects the reference positions: the same master facets and previous pairs give the same
        # projection, kept from the last update (a search costs about a tenth of a Newton iteration at 5e5 dofs).
        key = (self.master["ids"], self.ids) if self.small and allowed is None else None
        cached = self._reference_projection
        if key is not None and cached is not None and all(_same(a, b) for a, b in zip(key, cached[0])):
            found = cached[1]
        else:
            free = self._free[np.searchsorted(self._free_ids, self.master["ids"])]
            found = project((self.points.reference() if self.small else pts).reshape(-1, d),
                            self.master["X"] if self.small else xm, self.radius, previous, quadratic=self.quadratic,
                            allowed=allowed, free=free)
            self._reference_projection = None if key is None else (key, found)
        facet, bary, dist = found[:3]
        facet = facet.reshape(nf, nq).copy()  # the kept projection stays as found
        facet[self.points.excluded] = -1
        xi = found[3].reshape(nf, nq) if self.quadratic else None
        # Gap and master normal at the points, in NumPy (the same formulas as the UFL).
        ok = facet >= 0
        gap = np.full((nf, nq), -np.inf)
        normal = np.zeros((nf, nq, d))
        if np.any(ok):
            xv = xm[facet[ok]]
            if self.quadratic:
                n = quadratic_normals(xv, xi[ok])
                q = np.einsum("ik,ikj->ij", quadratic_shape(xi[ok])[0], xv)
            elif self.small:  # the reference facet's normal at the reference closest point, moving with the facet
                n = facet_normals(self.master["X"][facet[ok]])
                q = np.einsum("ik,ikj->ij", bary.reshape(nf, nq, self.nv)[ok], xv)
            else:
                n = facet_normals(xv)
                q = xv[:, 0]
            normal[ok] = n
            gap[ok] = -np.einsum("ij,ij->i", pts[ok] - q, n)
        self.projection = {"facet": facet, "bary": bary.reshape(nf, nq, self.nv), "distance": dist.reshape(nf, nq),
                           "gap": gap, "normal": normal}
        self.local_coordinate = xi
        return facet

    def slide(self, u: np.ndarray) -> float:
        """The largest slide of a local slave point relative to its paired master point since the reference
        configuration (the tangential part of their relative displacement, along the pair's normal) over the size
        of its master facet (:func:`~fenics_contact.search.facet_sizes`), among the points within a facet size of
        closing (gap > -size) at the last update; 0 if there is none. Flat facets (small sliding)."""
        p = self.projection
        if p is None or self.master is None:
            return 0.0
        ok = p["facet"] >= 0
        if not ok.any():
            return 0.0
        facet, bary = p["facet"][ok], p["bary"][ok]
        X, x = self.master["X"][facet], self.master["x"][facet]
        h = facet_sizes(X)
        d = (self.points.current(u)[ok] - np.einsum("ik,ikj->ij", bary, x)) \
            - (self.points.reference()[ok] - np.einsum("ik,ikj->ij", bary, X))
        n = p["normal"][ok]
        tangential = d - np.einsum("ij,ij->i", d, n)[:, None] * n
        near = p["gap"][ok] > -h
        return float(np.max(np.linalg.norm(tangential[near], axis=1) / h[near])) if near.any() else 0.0

    def _allowed(self, u: np.ndarray, xm: np.ndarray, nq: int):
        """Self-contact: the test of :func:`search.project` that leaves out each point's own neighbourhood (module
        docstring)."""
        ends = [0, -1] if self.quadratic else slice(None)
        d = xm.shape[-1]
        ns = facet_normals(self.slave.current(u)[:, ends]) if len(self.slave.X) else np.zeros((0, d))
        nm = facet_normals(xm[:, ends]) if len(xm) else np.zeros((0, d))
        Xm = self.master["X"]
        nm_ref = facet_normals(Xm[:, ends]) if len(Xm) else np.zeros((0, d))
        X_points = self.points.reference().reshape(-1, d)
        size = np.linalg.norm(Xm[:, -1] - Xm[:, 0], axis=1) if len(Xm) else np.zeros(0)
        reach = NEIGHBOURHOOD * self.radius

        def allowed(points: np.ndarray, facets: np.ndarray) -> np.ndarray:
            own = points // nq  # the point's slave facet
            Xp = X_points[points]
            near = np.min(np.linalg.norm(Xm[facets] - Xp[:, None, :], axis=2), axis=1) <= reach
            # behind the facet's reference line by more than BEHIND of the facet (a point on it, its own node, is not)
            behind = np.einsum("ij,ij->i", Xp - Xm[facets][:, 0], nm_ref[facets]) < -BEHIND * size[facets]
            opposed = np.einsum("ij,ij->i", ns[own], nm[facets]) < FACING
            return opposed & ~(near & behind)

        return allowed

    def _local_facets(self, ids: np.ndarray) -> np.ndarray:
        """Indices into ``master`` of global facet numbers ``ids`` (-1: none, or not received, i.e. beyond the
        search radius of every local slave facet)."""
        mid = self.master["ids"]
        order = np.argsort(mid)
        pos = np.minimum(np.searchsorted(mid[order], ids), max(len(mid) - 1, 0))
        found = (ids >= 0) & (len(mid) > 0)
        if len(mid):
            found &= mid[order][pos] == ids
        return np.where(found, order[pos] if len(mid) else -1, -1)

    def reject(self, exploded_here: bool) -> bool:
        """Mark the iterate exploded on every rank if it already is or ``exploded_here`` (e.g. a slave facet
        stretched past :data:`search.STRETCH_LIMIT` on this rank). Collective. Returns ``exploded``."""
        self.exploded = self.comm.allreduce(self.exploded or exploded_here, op=MPI.LOR)
        self._exploded_seen |= self.exploded
        return self.exploded

    def take_failure(self) -> str | None:
        """``"exploded_geometry"`` if an update was rejected since the last call, else None."""
        seen, self._exploded_seen = self._exploded_seen, False
        return "exploded_geometry" if seen else None


def _same(a: np.ndarray | None, b: np.ndarray | None) -> bool:
    """Both None, or equal arrays."""
    return a is b or (a is not None and b is not None and np.array_equal(a, b))
