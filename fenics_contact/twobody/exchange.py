"""The master facets each rank needs, sent by their owners (:class:`MasterExchange`).

Every rank takes part in every collective call, with or without slave or master facets. Each rank projects
its own slave points (owned and ghost) on the master facets that can be within the search radius of them:

- *Routes* (the first update, and when something moved too far): every rank bounds its current slave facets
  by :data:`LEAVES` boxes (:func:`leaf_boxes`) grown by the search radius plus a margin (:data:`MARGIN` x
  radius); the boxes and the owned master facets' largest stretch (:data:`search.STRETCH_LIMIT`) are
  all-gathered, ``2 gdim LEAVES + 1`` numbers per rank; each owned master facet whose current box
  (quadratic: with the Bezier control point) overlaps one of a rank's boxes goes to that rank: global facet
  number and current displacements, ``1 + nv gdim`` numbers, and the first time it goes there its reference
  coordinates, global dof numbers and ordering key, ``2 nv gdim + gdim`` more (the receiver caches them; the
  cache only grows, up to the master facets that ever came near). Counts by one ``MPI_Alltoall`` (2 integers
  per rank pair), data by one integer and one floating-point ``MPI_Alltoallv``.
- *Every other update*: the owners send the current displacements along the routes (``nv gdim`` numbers per
  routed facet) in one ``MPI_Alltoallv`` that also carries every rank's largest stretch and largest motion
  since the routes (2 numbers to every rank: one message per update). If a slave or owned master vertex
  moved by half the margin (quadratic: a sixth), the routes are made again in that update: until then the
  routed boxes still hold every facet within the radius.

Every master facet within the radius of a slave point (or of a slave facet's box: segment pairing) overlaps a
routed box, so the search sees the same candidates as on the whole surface. The received facets are sorted
by their reference centroid (rounded to 1e-12, then the global facet number), a partition-independent order,
so ties go the same way on any partition. Cost per update: ``O(P)`` numbers (P ranks) and ``O(N_near)`` per
rank, ``N_near`` the master facets near its slave facets, where an all-gather of the master surface is
``O(N_master)`` to every rank. Where the whole master surface is within the radius of a rank's slave facets
nothing is saved. ``everywhere=True`` routes every master facet to every rank (the all-gather's traffic, for
comparison; the same answers).
"""
from __future__ import annotations

import time

import numpy as np
from mpi4py import MPI

from ..search import STRETCH_LIMIT

__all__ = ["LEAVES", "MARGIN", "MasterExchange", "leaf_boxes"]

LEAVES = 16  # boxes per rank bounding its slave facets in the master exchange (a power of 2)
MARGIN = 0.5  # the exchange's routes hold while nothing moved by MARGIN / 2 x the search radius


class MasterExchange:
    """The master facets near this rank's slave facets, sent by their owners (see the module docstring).

    Args:
        X: (n, nv, gdim) reference coordinates of the owned master facets.
        G: (n, nv, gdim) global numbers of their displacement components.
        ids: (n,) their global facet numbers.
        quadratic: quadratic facets (end, middle, end; boxed with the middle Bezier control point).

    ``stats``: this rank's updates, re-routings, bytes and master facets received from other ranks, seconds,
    and ``allgather_bytes``, what an all-gather of the whole master surface would have received. Collective
    construction and calls."""

    def __init__(self, comm, X: np.ndarray, G: np.ndarray, ids: np.ndarray, quadratic: bool):
        self.comm, self.quadratic = comm, quadratic
        n, nv, d = X.shape
        self.nv, self.gdim = nv, d
        self.X, self.G, self.ids = X, np.asarray(G, np.int64).reshape(n, nv, d), np.asarray(ids, np.int64)
        self.key = np.round(X.mean(axis=1), 12) if n else np.zeros((0, d))
        self._sent: dict[int, np.ndarray] = {}  # destination -> facets whose reference data it holds
        # Received reference data (cache): coordinates, dof numbers, keys, global facet numbers (and their argsort).
        self._cX, self._cG = np.zeros((0, nv, d)), np.zeros((0, nv, d), np.int64)
        self._ckey, self._cid, self._csort = np.zeros((0, d)), np.zeros(0, np.int64), np.zeros(0, np.int64)
        self._route = None  # (facets sent, facet counts sent, facet counts received, receive permutation)
        n_total = comm.allreduce(n)
        k = nv * d
        # Bytes an all-gather would move into this rank: reference data and dof numbers once, then U per update.
        self._allgather_once = 16 * k * (n_total - n)
        self._allgather_update = 8 * k * (n_total - n)
        self._sub = self._U_in = self._xs0 = self._U0 = self._everywhere = None  # the last routes' data
        self.stats = {"updates": 0, "reroutes": 0, "bytes_received": 0, "facets_received": 0, "seconds": 0.0,
                      "allgather_bytes": self._allgather_once}

    def boxes(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Bounding boxes ``(lo, hi)`` of facets ``x`` (n, nv, gdim) (quadratic: the Bezier control points')."""
        if self.quadratic and len(x):
            x = np.concatenate([x, (2 * x[:, 1] - 0.5 * (x[:, 0] + x[:, 2]))[:, None]], axis=1)
        return x.min(axis=1), x.max(axis=1)

    def exchange(self, U: np.ndarray, xs: np.ndarray, radius: float, stretch_local: float,
                 everywhere: bool = False) -> tuple[float, dict | None]:
        """The master facets within ``radius`` of this rank's current slave facets ``xs`` (nf, nv, gdim), with
        their current displacements, from the owned ones' displacements ``U`` (n, nv, gdim). Returns the largest
        ``stretch_local`` of all ranks and, unless it exceeds :data:`search.STRETCH_LIMIT` (nothing is sent
        then), the received facets in the partition-independent order: ``{"X", "G", "U", "ids"}``.

        The facets go to the ranks whose slave boxes (:func:`leaf_boxes`) grown by ``radius + margin``
        (``margin = MARGIN radius``) their box overlaps; while no slave or owned master vertex has moved by
        ``margin / 2`` (a quadratic facet's box: ``margin / 6``, its Bezier point moves three times as far) since,
        those routes still hold every facet within ``radius`` and only the displacements are sent again, in one
        ``MPI_Alltoallv`` that also takes every rank's stretch and motion (2 numbers) to every rank: one message
        per update, as an all-gather. ``everywhere``: every facet to every rank."""
        t0 = time.perf_counter()
        margin = MARGIN * radius
        if self._route is None or self._everywhere != everywhere:  # the first call (on every rank): routes
            smax = self._reroute(U, xs, radius + margin, everywhere, stretch_local)
            U_in = self._U_in
        else:
            moved = max(float(np.max(np.abs(xs - self._xs0), initial=0.0)),
                        float(np.max(np.abs(U - self._U0), initial=0.0))) * (3.0 if self.quadratic else 1.0)
            U_in, flags = self._along_routes(U, np.array([stretch_local, moved]))
            smax = float(flags[:, 0].max())
            if smax <= STRETCH_LIMIT and flags[:, 1].max() >= 0.5 * margin:
                smax = self._reroute(U, xs, radius + margin, everywhere, stretch_local)
                U_in = self._U_in
        if smax > STRETCH_LIMIT:
            self.stats["seconds"] += time.perf_counter() - t0
            return smax, None
        self.stats["updates"] += 1
        self.stats["allgather_bytes"] += self._allgather_update
        self.stats["seconds"] += time.perf_counter() - t0
        return smax, {"X": self._sub["X"], "G": self._sub["G"], "U": U_in, "ids": self._sub["ids"]}

    def _along_routes(self, a: np.ndarray, header: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Values ``a`` (n, nv, gdim) of the owned facets along the last routes, and ``header`` (h numbers) from
        every rank to every rank: one ``MPI_Alltoallv``. Returns the received values in the received facets'
        order and the headers (P, h)."""
        idx, sc, rc, perm = self._route
        k, h = self.nv * self.gdim, len(header)
        parts = np.split(np.ascontiguousarray(a[idx], dtype=float).reshape(-1, k), np.cumsum(sc)[:-1])
        sb = np.concatenate([np.concatenate([header, p.ravel()]) for p in parts])
        scount, rcount = h + sc * k, h + rc * k
        rb = np.empty(int(rcount.sum()))
        self.comm.Alltoallv([sb, (scount, _displs(scount)), MPI.DOUBLE], [rb, (rcount, _displs(rcount)), MPI.DOUBLE])
        start = _displs(rcount)
        heads = np.stack([rb[b:b + h] for b in start])
        data = np.concatenate([rb[b + h:b + c] for b, c in zip(start, rcount)])
        me = self.comm.rank
        self.stats["bytes_received"] += 8 * int(rcount.sum() - rcount[me])
        self.stats["facets_received"] += int(rc.sum() - rc[me])
        return data.reshape(-1, self.nv, self.gdim)[perm], heads

    def _reroute(self, U: np.ndarray, xs: np.ndarray, grow: float, everywhere: bool, stretch_local: float) -> float:
        """New routes: box (and stretch) all-gather, counts (``MPI_Alltoall``), facet numbers and displacements
        with, for facets new to a rank, their reference data (two ``MPI_Alltoallv``). Returns the largest stretch
        (above :data:`search.STRETCH_LIMIT`: nothing else is done). Collective."""
        comm, size, d, k = self.comm, self.comm.size, self.gdim, self.nv * self.gdim
        nb = LEAVES * d
        lo, hi = leaf_boxes(*self.boxes(xs), grow) if len(xs) else (np.full((LEAVES, d), np.inf),
                                                                      np.full((LEAVES, d), -np.inf))
        gathered = np.empty((size, 2 * nb + 1))
        comm.Allgather(np.concatenate([lo.ravel(), hi.ravel(), [stretch_local]]), gathered)
        smax = float(gathered[:, -1].max())
        if smax > STRETCH_LIMIT:
            return smax
        blo = gathered[:, :nb].reshape(size * LEAVES, d)  # every rank's boxes, rank by rank
        bhi = gathered[:, nb:2 * nb].reshape(size * LEAVES, d)
        n = len(self.X)
        flo, fhi = self.boxes(self.X + U) if n else (np.zeros((0, d)), np.zeros((0, d)))
        if everywhere:
            hit = np.ones((n, size), bool)
        else:
            hit = np.zeros((n, size), bool)
            live = np.flatnonzero(np.all(blo <= bhi, axis=1))  # non-empty boxes
            step = max(1, (1 << 22) // max(len(live), 1))  # bounded work arrays
            for a in range(0, n, step):
                over = np.all(flo[a:a + step, None, :] <= bhi[None, live], axis=2) & \
                    np.all(fhi[a:a + step, None, :] >= blo[None, live], axis=2)
                for r in np.unique(live // LEAVES):
                    hit[a:a + step, r] = over[:, live // LEAVES == r].any(axis=1)
        counts = np.zeros((size, 2), np.int64)  # per destination: facets, of which new (first ones)
        order, ibuf, fbuf = [], [], []
        for r in np.flatnonzero(hit.any(axis=0)):
            idx = np.flatnonzero(hit[:, r])
            sent = self._sent.setdefault(int(r), np.zeros(n, bool))
            new, old = idx[~sent[idx]], idx[sent[idx]]
            sent[new] = True
            idx = np.concatenate([new, old])
            counts[r] = len(idx), len(new)
            order.append(idx)
            ibuf += [self.ids[idx], self.G[new].ravel()]
            fbuf += [U[idx].ravel(), self.X[new].ravel(), self.key[new].ravel()]
        rcounts = np.empty_like(counts)
        comm.Alltoall(counts, rcounts)
        si = counts[:, 0] + counts[:, 1] * k
        sf = counts[:, 0] * k + counts[:, 1] * (k + d)
        ri = rcounts[:, 0] + rcounts[:, 1] * k
        rf = rcounts[:, 0] * k + rcounts[:, 1] * (k + d)
        ib = np.concatenate(ibuf).astype(np.int64) if ibuf else np.zeros(0, np.int64)
        fb = np.concatenate(fbuf).astype(float) if fbuf else np.zeros(0)
        rib, rfb = np.empty(int(ri.sum()), np.int64), np.empty(int(rf.sum()))
        comm.Alltoallv([ib, (si, _displs(si)), MPI.INT64_T], [rib, (ri, _displs(ri)), MPI.INT64_T])
        comm.Alltoallv([fb, (sf, _displs(sf)), MPI.DOUBLE], [rfb, (rf, _displs(rf)), MPI.DOUBLE])
        # Unpack per source: facet numbers (new ones first), new dof numbers; U, new coordinates, new keys.
        ids, Us, nid, nG, nX, nK = [], [], [], [], [], []
        io = fo = 0
        for r in np.flatnonzero(rcounts[:, 0]):
            m, q = rcounts[r]
            ids.append(rib[io:io + m])
            nid.append(rib[io:io + q])
            nG.append(rib[io + m:io + m + q * k])
            Us.append(rfb[fo:fo + m * k])
            nX.append(rfb[fo + m * k:fo + (m + q) * k])
            nK.append(rfb[fo + (m + q) * k:fo + (m + q) * k + q * d])
            io, fo = io + m + q * k, fo + (m + q) * k + q * d
        ids = np.concatenate(ids) if ids else np.zeros(0, np.int64)
        U_in = np.concatenate(Us).reshape(-1, self.nv, d) if Us else np.zeros((0, self.nv, d))
        if rcounts[:, 1].any():
            self._cid = np.concatenate([self._cid, *nid])
            self._cG = np.concatenate([self._cG, np.concatenate(nG).reshape(-1, self.nv, d)])
            self._cX = np.concatenate([self._cX, np.concatenate(nX).reshape(-1, self.nv, d)])
            self._ckey = np.concatenate([self._ckey, np.concatenate(nK).reshape(-1, d)])
            self._csort = np.argsort(self._cid, kind="stable")
        rows = self._csort[np.searchsorted(self._cid[self._csort], ids)] if len(ids) else np.zeros(0, np.int64)
        perm = np.lexsort((ids, *self._ckey[rows].T[::-1])) if len(ids) else np.zeros(0, np.int64)
        rows = rows[perm]
        self._route = (np.concatenate(order) if order else np.zeros(0, np.int64), counts[:, 0], rcounts[:, 0], perm)
        self._sub = {"X": self._cX[rows], "G": self._cG[rows], "ids": ids[perm]}
        self._U_in = U_in[perm]
        self._xs0, self._U0, self._everywhere = xs.copy(), U.copy(), everywhere
        me = comm.rank
        st = self.stats
        st["reroutes"] += 1
        st["bytes_received"] += 8 * (int(ri.sum() - ri[me] + rf.sum() - rf[me]) + (size - 1) * (2 * nb + 3))
        st["facets_received"] += int(rcounts[:, 0].sum() - rcounts[me, 0])
        return smax

    def values(self, a: np.ndarray) -> np.ndarray:
        """Values ``a`` (n, nv, gdim) of the owned master facets on the facets this rank received at the last
        :meth:`exchange`, in its order (e.g. the last accepted displacement): one ``MPI_Alltoallv``. Collective."""
        t0 = time.perf_counter()
        out = self._along_routes(a, np.zeros(0))[0]
        self.stats["seconds"] += time.perf_counter() - t0
        return out


def leaf_boxes(lo: np.ndarray, hi: np.ndarray, grow: float, leaves: int | None = None) -> tuple[np.ndarray,
                                                                                                 np.ndarray]:
    """At most ``leaves`` (default :data:`LEAVES`, a power of 2) boxes covering the boxes ``[lo, hi]`` (n, gdim),
    grown by ``grow``: the boxes' centres are halved at the median of their widest spread, recursively, and each
    part's boxes are merged. Returns ``(lo, hi)`` (leaves, gdim); unused leaves are empty (``lo = inf > hi``)."""
    leaves = leaves or LEAVES
    d = lo.shape[1]
    out_lo, out_hi = np.full((leaves, d), np.inf), np.full((leaves, d), -np.inf)
    parts = [np.arange(len(lo))] if len(lo) else []
    for _ in range(int(np.log2(leaves))):  # each round halves every part of two boxes or more
        split = []
        for p in parts:
            if len(p) < 2:
                split.append(p)
                continue
            c = 0.5 * (lo[p] + hi[p])
            order = p[np.argsort(c[:, int(np.argmax(np.ptp(c, axis=0)))], kind="stable")]
            split += [order[: len(p) // 2], order[len(p) // 2:]]
        parts = split
    for i, p in enumerate(parts):
        out_lo[i], out_hi[i] = lo[p].min(axis=0) - grow, hi[p].max(axis=0) + grow
    return out_lo, out_hi


def _displs(counts: np.ndarray) -> np.ndarray:
    return np.concatenate([[0], np.cumsum(counts)[:-1]]).astype(np.int64)
