"""Two deformable bodies in one mesh: closest-point projection, mirror fields, coupling.

Setting (formulation 1.4, frictionless): a *slave* and a *master* surface,
both facet tags of the same dolfinx mesh. For every slave contact quadrature
point ``x_s = X + u`` (vertices with ``nodal`` quadrature, Gauss points with
``gauss``) the projection finds the closest point on the master's **current**
surface: the master facet, the local coordinate ``xi`` on it, the normal gap
and the master normal. The gap is written in UFL against *mirror* fields on
the slave side (a ``Function`` whose values at the slave quadrature points
are the reference positions ``X_k`` and displacements ``w_k`` of the vertices
``k`` of the paired master facet)::

    x_k = X_k + w_k,   n = outward unit normal of the flat facet (x_1, .., x_nv),
    g   = -(x_s - x_1) . n          (positive = penetration, see :mod:`laws`)

For a flat (P1) master facet the distance to its plane does not depend on
``xi``, so this ``g`` is the exact closest-point gap as a function of the
slave and master vertex positions while the projection stays on the facet:
its derivatives with respect to ``u`` and to ``w`` (taken by UFL) are the
complete consistent linearisation, including the rotation of the master
normal; the change of the projection point drops out. A pairing change
(large sliding) is a discrete event between Newton iterations.

Coupling. ``I`` is the sparse operator (rows: mirror dofs, columns: global
displacement dofs) with ``w = I u``: a selection of master vertex values
(nodal quadrature) or its combination with the inverse of the facet's
Gauss-point interpolation (``gauss``: the mirror lives in DG1 whose trace has
one value per Gauss point). With the slave-side forms ``r_u = dP/du``,
``r_w = dP/dw`` and their derivatives compiled once by FFCx, the contact
residual and tangent on the global dofs are::

    R = r_u + I^T r_w,
    K = A_uu + A_uw I + I^T A_wu + I^T A_ww I        (MatMatMult, TransposeMatMult, PtAP)

``A_uu`` goes in the problem's own Jacobian form; the rest is added by the
solver's hooks (:meth:`TwoBodySurface.add_residual`, :meth:`add_jacobian`).
Dirichlet dofs are dropped from the columns of ``I`` and the coupling forms
are assembled with the boundary conditions, so the constrained rows and
columns stay the identity. The global matrix gets the coupling's extra
sparsity by ``MatAXPY(DIFFERENT_NONZERO_PATTERN)`` only when the pairing
changed since the last Jacobian (the pattern then only grows; the solver
resets its factorization); otherwise the pattern is reused.

Parallel. Every rank takes part in every collective call, with or without
slave or master facets. Each rank projects its own slave points (owned and
ghost) with a k-d tree (:mod:`search`: memory bounded by the surfaces' size
whatever the iterate; no all-pairs loop) on the master facets that can be
within the search radius of them, which their owners send it
(:class:`MasterExchange`):

- *Routes* (the first update, and when something moved too far): every
  rank bounds its current slave facets by :data:`LEAVES` boxes
  (:func:`leaf_boxes`: the facets halved at the median of their widest
  spread, recursively) grown by the search radius plus a margin
  (:data:`MARGIN` x radius); the boxes and the owned master facets' largest
  stretch (:data:`search.STRETCH_LIMIT`) are all-gathered, ``2 gdim LEAVES +
  1`` numbers per rank; each owned master facet whose current box
  (quadratic: with the Bezier control point) overlaps one of a rank's boxes
  goes to that rank: global facet number and current displacements, ``1 +
  nv gdim`` numbers, and the first time it goes there its reference
  coordinates, global dof numbers and ordering key, ``2 nv gdim + gdim``
  more (the receiver caches them; the cache only grows, up to the master
  facets that ever came near). Counts by one ``MPI_Alltoall`` (2 integers
  per rank pair), data by one integer and one floating-point
  ``MPI_Alltoallv``.
- *Every other update*: the owners send the current displacements along the
  routes (``nv gdim`` numbers per routed facet) in one ``MPI_Alltoallv``
  that also carries every rank's largest stretch and largest motion since
  the routes (2 numbers to every rank: one message per update, as the
  former all-gather). If a slave or owned master vertex moved by half the
  margin (quadratic: a sixth), the routes are made again in that update:
  until then the routed boxes still hold every facet within the radius.

Every master facet within the radius of a slave point (or of a slave facet's
box: segment pairing) overlaps a routed box, so the search sees the same
candidates as on the whole surface; the received facets are sorted by their
reference centroid (rounded to 1e-12, then the global facet number), a
partition-independent order, so ties go the same way on any partition, and
the pairing state (hysteresis, pairing changes) is kept in global facet
numbers (:meth:`TwoBodySurface.pairing`). Cost per update: ``O(P)`` numbers
(P ranks) and ``O(N_near)`` per rank, ``N_near`` the master facets near its
slave facets, where all-gathering the master surface was ``O(N_master)`` to
every rank; a master facet owned by another rank is then just a column of
``I`` with a global index, PETSc moves the values. Where the whole master
surface is within the radius of a rank's slave facets (the sphere on its
block) nothing is saved. ``TwoBodySurface.exchange = "allgather"`` routes
every master facet to every rank (the former scheme's traffic, for
comparison; same answers); bytes and seconds: ``exchange_stats()``, the
measured figures: ``docs/benchmarks.md``.

Quadratic facets (2D, a degree-2 displacement on triangles or 9-node
quadrilaterals with curved facets): the master facet is the curve
``x(xi) = sum_k N_k(xi) x_k`` through its three nodes (end, middle, end;
``xi`` in [0, 1]); the slave points are the three nodes of each slave facet
(the mirror fields live in P2, the constraint is integrated with the end
nodes only, ``nodal``, or with Simpson's rule over all three). We project
on the curve, not on the two chords through the middle node: the chords of
two non-matching discretizations of one circle sag by different amounts
(``h^2/8R``, 4e-4 for the sheet's facets), so chords would make the two
surfaces overlap by as much as an exact method enforces (the cylinders
scene's P1 problem); the quadratic curves agree to ``O(h^4)``. The
closest point is found by Newton on ``(x_s - x(xi)) . x'(xi) = 0`` per
candidate facet (NumPy), and written in UFL as one further Newton
correction ``xi = xi0 - f/f'`` of the stored ``xi0`` (:class:`MirrorObstacle`):
its value is ``xi0`` and its derivative the implicit-function one, so
UFL's second derivative of ``g = -(x_s - x(xi)) . n(xi)`` is the complete
consistent tangent (curvature and the moving projection point included;
``tests/test_sheet.py`` checks it against central differences to 1e-10).
Points that project on a facet's end (``xi`` clipped) keep ``xi`` fixed.

Two-pass: two surfaces, each side slave once, each with ``weight = 1/2``
(forces averaged); coinciding points of the two passes both stay on flat
facets (each at weight 1/2: together the one-pass force; leaving one out
doubled the other's pressure); quadratic facets still leave the second-pass
point out (node-on-node). Two passes of multipliers are refused
(:mod:`capabilities`). Flat facets: segments (2D), triangles (3D);
quadratic: curved segments (2D).
"""
from __future__ import annotations

import time
from typing import Sequence

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .capabilities import check, of
from .compat import bc_dofs, function_space, release_free_memory
from .contact import ContactSurface, check_facet_tag, contact_measure, is_mixed
from .laws import ContactLaw
from .obstacles import Obstacle
from .search import (
    STRETCH_LIMIT,
    facet_normals,
    project,
    quadratic_normals,
    quadratic_shape,
    stretch,
)
from .sparse import aij_matrix

__all__ = ["LEAVES", "PASSES", "QUADRATURES", "FacetData", "ufl_normal", "MasterExchange", "leaf_boxes",
           "MirrorObstacle", "TwoBodySurface"]

PASSES = ("one", "two")
LEAVES = 16  # boxes per rank bounding its slave facets in the master exchange (a power of 2)
MARGIN = 0.5  # the exchange's routes hold while nothing moved by MARGIN / 2 x the search radius
QUADRATURES = ("nodal", "gauss", "segment")  # segment: segment-to-segment integration (:mod:`mortar`)

# Barycentric coordinates of the slave points on a facet (rows: points, columns: facet vertices).
_S = 0.5 / np.sqrt(3.0)
_POINTS = {
    ("nodal", 2): np.eye(2),
    ("gauss", 2): np.array([[0.5 + _S, 0.5 - _S], [0.5 - _S, 0.5 + _S]]),
    ("nodal", 3): np.eye(3),
    ("gauss", 3): np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]),
}


# --------------------------------------------------------------------------------------------
# Surface data
# --------------------------------------------------------------------------------------------
class FacetData:
    """Vertices of the local facets with ``tag``: displacement block dofs ``dofs`` (nf, nv), ordered so
    that the facet normal of :func:`facet_normals` points out of the body; reference coordinates ``X``
    (nf, nv, gdim); the cell of each facet and the cell-local index of each facet vertex; ``owned``.
    ``comp`` (nf, nv, gdim): local indices of the displacement components in the unknown's array,
    ``global_comp``: their global numbers; for a mixed unknown (:mod:`multipliers`) ``V`` is the collapsed
    displacement space and ``parent = (collapsed-to-parent map, parent space)``."""

    def __init__(self, V: fem.FunctionSpace, facets: np.ndarray, parent=None):
        mesh = V.mesh
        tdim, gdim = mesh.topology.dim, mesh.geometry.dim
        mesh.topology.create_connectivity(tdim - 1, tdim)
        mesh.topology.create_connectivity(tdim - 1, 0)
        mesh.topology.create_connectivity(tdim, 0)
        mesh.topology.create_connectivity(tdim, tdim - 1)
        f2c, f2v, c2v, c2f = (mesh.topology.connectivity(tdim - 1, tdim), mesh.topology.connectivity(tdim - 1, 0),
                              mesh.topology.connectivity(tdim, 0), mesh.topology.connectivity(tdim, tdim - 1))
        # Quadratic facets: a 2D space with one dof per edge (P2); other spaces use the facets' vertices.
        self.quadratic = tdim == 2 and len(V.dofmap.dof_layout.entity_dofs(1, 0)) == 1
        nv = 3 if self.quadratic else tdim  # nodes of a facet: (end, middle, end) or the simplex vertices
        nf = len(facets)
        self.cells = np.zeros(nf, np.int32)
        self.local = np.zeros((nf, nv), np.int32)
        self.vertex_local = np.zeros((nf, tdim), np.int32)  # cell-local vertex numbers (= P1 dofs) of the ends
        coords = V.tabulate_dof_coordinates()
        layout = V.dofmap.dof_layout
        dofs = np.zeros((nf, nv), np.int32)
        for i, f in enumerate(facets):
            cells = f2c.links(f)
            if len(cells) != 1:
                raise ValueError(f"facet {f} of a contact surface is not on the boundary (it has {len(cells)} cells)")
            c = cells[0]
            cv = list(c2v.links(c))
            if not self.quadratic and len(cv) != tdim + 1:
                raise ValueError("two-body contact with degree-1 facets needs simplex cells (flat facets): "
                                 "triangles or tetrahedra")
            vloc = [cv.index(v) for v in f2v.links(f)]
            cdofs = V.dofmap.cell_dofs(c)
            if self.quadratic:
                mid = layout.entity_dofs(1, list(c2f.links(c)).index(f))[0]
                ends = [layout.entity_dofs(0, v)[0] for v in vloc]
                loc = [ends[0], mid, ends[1]]
                fd = cdofs[loc]
                # Outward: the normal of the ordered ends must point away from the cell's centre.
                n = facet_normals(coords[fd[[0, 2]]][None, :, :gdim])[0]
                inside = coords[cdofs, :gdim].mean(axis=0)
                if np.dot(n, coords[fd[1], :gdim] - inside) < 0:
                    loc, vloc, fd = loc[::-1], vloc[::-1], fd[::-1]
            else:
                loc = vloc
                fd = cdofs[loc]
                # Orientation: the normal of the ordered vertices must point away from the opposite vertex.
                other = cdofs[[j for j in range(tdim + 1) if j not in loc][0]]
                n = facet_normals(coords[fd][None, :, :gdim])[0]
                if np.dot(n, coords[fd[0], :gdim] - coords[other, :gdim]) < 0:
                    loc, vloc, fd = loc[::-1], vloc[::-1], fd[::-1]
            self.cells[i], self.local[i], self.vertex_local[i], dofs[i] = c, loc, vloc, fd
        self.dofs = dofs
        self.facets = np.asarray(facets, dtype=np.int32)
        self.X = coords[dofs][..., :gdim] if nf else np.zeros((0, nv, gdim))
        imap = mesh.topology.index_map(tdim - 1)
        self.owned = np.asarray(facets) < imap.size_local
        Vmap = V.dofmap.index_map
        self.global_dofs = Vmap.local_to_global(dofs.ravel()).reshape(dofs.shape) if nf else dofs.astype(np.int64)
        comp = dofs[..., None] * gdim + np.arange(gdim)
        if parent is None:
            self.comp, self.global_comp = comp, self.global_dofs[..., None] * gdim + np.arange(gdim)
        else:
            to_parent, W = np.asarray(parent[0]), parent[1]
            self.comp = to_parent[comp].astype(np.int32)
            Wmap = W.dofmap.index_map  # a mixed space has block size 1
            self.global_comp = (Wmap.local_to_global(self.comp.ravel()).reshape(self.comp.shape) if nf
                                else self.comp.astype(np.int64))


def ufl_normal(xs: Sequence[ufl.core.expr.Expr]) -> ufl.core.expr.Expr:
    """UFL unit normal of the flat facet with current vertices ``xs`` (same formula as :func:`facet_normals`)."""
    if len(xs) == 2:
        t = xs[1] - xs[0]
        n = ufl.as_vector((t[1], -t[0]))
    else:
        n = ufl.cross(xs[1] - xs[0], xs[2] - xs[0])
    return n / ufl.sqrt(ufl.dot(n, n))


# --------------------------------------------------------------------------------------------
# Parallel exchange of the master facets each rank needs
# --------------------------------------------------------------------------------------------
class MasterExchange:
    """The master facets near this rank's slave facets, sent by their owners (module docstring, Parallel).

    ``X`` (n, nv, gdim): reference coordinates of the owned master facets; ``G`` (n, nv, gdim): global numbers of
    their displacement components; ``ids`` (n,): their global facet numbers; ``quadratic``: quadratic facets (end,
    middle, end; boxed with the middle Bezier control point). Collective construction and calls."""

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
        # Bytes the former all-gather moved into this rank: reference data and dof numbers once, then U per update.
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
        ``MPI_Alltoallv`` that also takes every rank's stretch and motion (2 numbers) to every rank: the same
        message count as the former all-gather. ``everywhere``: every facet to every rank."""
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


# --------------------------------------------------------------------------------------------
# The mirror "obstacle": the paired master facet as UFL of the mirror fields
# --------------------------------------------------------------------------------------------
class MirrorObstacle(Obstacle):
    """The paired master facet seen from the slave points: vertices ``X_k + w_k`` from the mirror
    Functions ``Xm`` (reference, fixed during a Newton iteration) and ``w`` (master displacement, the
    variable the coupling differentiates). ``active`` is 1 where a slave point has a pair, else 0.

    Quadratic master facets (``proj`` given: the local coordinate ``xi0`` of the closest point and
    ``free`` = 1 where it is inside the facet): the curve ``x(xi) = sum N_k(xi) x_k`` and, in UFL, one
    Newton correction ``xi = xi0 - free f/f'`` of the projection equation ``f = (x - x(xi)) . x'(xi) = 0``.
    Its value is ``xi0`` (the projection has converged) and its derivative the implicit-function one,
    ``dxi = -df/f'``, so UFL's second derivative of the gap is the complete consistent tangent (the
    curvature terms of the moving projection point included)."""

    def __init__(self, Xm: fem.Function, w: fem.Function, active: fem.Function, nv: int, gdim: int,
                 open_gap: float, proj: fem.Function | None = None):
        super().__init__(np.zeros(gdim))
        self.Xm, self.w, self.active, self.nv, self.gdim = Xm, w, active, nv, gdim
        self.open_gap = float(open_gap)
        self.proj = proj

    def vertices(self) -> list:
        d = self.gdim
        return [ufl.as_vector([self.Xm[k * d + i] + self.w[k * d + i] for i in range(d)]) for k in range(self.nv)]

    def _curve(self, x):
        """Closest point ``x(xi)`` and tangent ``x'(xi)`` of the quadratic facet (UFL)."""
        xs = self.vertices()

        def at(xi):
            N = (2 * (xi - 0.5) * (xi - 1), -4 * xi * (xi - 1), 2 * xi * (xi - 0.5))
            dN = (4 * xi - 3, 4 - 8 * xi, 4 * xi - 1)
            return sum(a * b for a, b in zip(N, xs)), sum(a * b for a, b in zip(dN, xs))

        xi0, free = self.proj[0], self.proj[1]
        X0, dX0 = at(xi0)
        ddX = 4 * xs[0] - 8 * xs[1] + 4 * xs[2]
        f = ufl.dot(x - X0, dX0)
        fp = ufl.dot(x - X0, ddX) - ufl.dot(dX0, dX0)
        return at(xi0 - free * f / fp)

    def gap(self, x):
        """``-(x - x_1) . n`` where paired; ``-open_gap`` (open, the search radius) where not, so that laws
        and augmentations see an open contact there."""
        if self.proj is None:
            xs = self.vertices()
            g = -ufl.dot(x - xs[0], ufl_normal(xs))
        else:
            X, dX = self._curve(x)
            g = -ufl.dot(x - X, ufl_normal([X, X + dX]))
        return self.active * g - (1.0 - self.active) * self.open_gap

    def normal(self, x):
        if self.proj is None:
            return ufl_normal(self.vertices())
        X, dX = self._curve(x)
        return ufl_normal([X, X + dX])


class TwoBodySurface(ContactSurface):
    """Contact of the slave facets ``slave_tag`` against the current master facets ``master_tag`` of the
    same mesh, with the law ``law`` (pressure per reference slave area, positive in compression).

    ``quadrature``: ``nodal`` or ``gauss`` on the slave side (degree 1); for a quadratic displacement
    (2D, any cell: curved 3-node facets) the slave points are the three nodes of each facet, ``nodal``
    then integrates with the end nodes only (the two-point element's constraint) and ``simpson`` with
    all three. ``work_quadrature``: the rule of the pressure's work term, if not ``quadrature``
    (multipliers: ``simpson`` with a constraint at the end nodes). ``weight``: factor on the residual (1/2
    for each surface of a two-pass pair). ``radius``: search radius of the projection (default: 2 x the
    longest master facet); slave points farther from the master have no pair and no force. ``exclude``
    (k, gdim): reference positions of slave points left without a pair (a node that coincides with a
    node of the other pass: node-on-node, one constraint per pair of nodes).
    """

    ufl_coupling = True  # coupling by the compiled mirror forms and I (False: a subclass assembles it)
    exchange = "boxes"  # master facets sent to the ranks whose grown slave box they overlap; "allgather": to all

    def __init__(self, u: fem.Function, facet_tags, slave_tag: int, master_tag: int, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", weight: float = 1.0,
                 radius: float | None = None, name: str = "twobody", work_quadrature: str | None = None,
                 exclude: np.ndarray | None = None):
        check(**of(law, u), kind="two-body", quadrature=work_quadrature or quadrature)  # before any assembly
        mesh = u.function_space.mesh
        if slave_tag == master_tag:
            raise ValueError(f"slave_tag and master_tag must differ, both are {slave_tag}")
        if not (np.isfinite(weight) and weight > 0):
            raise ValueError(f"weight must be a finite number > 0, got {weight!r}")
        slave = check_facet_tag(mesh, facet_tags, slave_tag, f"{name} slave_tag")
        master = check_facet_tag(mesh, facet_tags, master_tag, f"{name} master_tag")
        self.comm = mesh.comm
        V = u.function_space
        tdim, gdim = mesh.topology.dim, mesh.geometry.dim
        if is_mixed(V):  # the displacement is the first field of a mixed unknown (method lagrange)
            Vd, to_parent = V.sub(0).collapse()
            self.slave_data = FacetData(Vd, slave, (to_parent, V))
            self.master_data = FacetData(Vd, master, (to_parent, V))
        else:
            self.slave_data = FacetData(V, slave)
            self.master_data = FacetData(V, master)
        self.quadratic = self.slave_data.quadratic
        allowed = ("nodal", "simpson") if self.quadratic else ("nodal", "gauss")
        if quadrature not in allowed or (work_quadrature or quadrature) not in allowed:
            raise ValueError(f"contact quadrature must be one of {allowed} for degree-"
                             f"{2 if self.quadratic else 1} facets, got {quadrature!r} (work: {work_quadrature!r})")
        nv = 3 if self.quadratic else tdim  # nodes of a master facet
        self.V, self.gdim, self.nv = V, gdim, nv

        # Mirror space: one value per slave point (P1 at vertices, DG1 at Gauss points; quadratic: P2 at the
        # three nodes of each facet).
        family, degree = ("Lagrange", 2) if self.quadratic else ("Lagrange" if quadrature == "nodal" else "DG", 1)
        self.W = function_space(mesh, family, degree, (nv * gdim,))
        self.Ws = function_space(mesh, family, degree)
        self.Xm = fem.Function(self.W, name="mirror_X")
        self.w = fem.Function(self.W, name="mirror_u")
        self.active = fem.Function(self.Ws, name="paired")
        self.proj = fem.Function(function_space(mesh, family, degree, (2,)), name="mirror_xi") if self.quadratic \
            else None
        self.B = np.eye(3) if self.quadratic else _POINTS[(quadrature, nv)]
        self.Binv = np.linalg.inv(self.B)
        nn = self.B.shape[1]  # mirror nodes per slave facet
        sd = self.slave_data
        self._wdofs = np.array([self.W.dofmap.cell_dofs(c)[loc] for c, loc in zip(sd.cells, sd.local)],
                               dtype=np.int32).reshape(-1, nn)
        self._sdofs = np.array([self.Ws.dofmap.cell_dofs(c)[loc] for c, loc in zip(sd.cells, sd.local)],
                               dtype=np.int32).reshape(-1, nn)
        Xs = np.einsum("qk,fkj->fqj", self.B, sd.X)
        self._excluded = np.zeros(Xs.shape[:2], bool)
        if exclude is not None and len(exclude) and len(Xs):
            dmin = np.min(np.linalg.norm(Xs[:, :, None, :] - np.asarray(exclude)[None, None], axis=3), axis=2)
            self._excluded = dmin <= 1e-9 * max(1.0, float(np.abs(Xs).max()))
        if quadrature == "gauss" and len(np.unique(self._wdofs)) != self._wdofs.size:
            raise ValueError(f"{name}: a cell has two slave facets; Gauss quadrature needs one per cell "
                             "(refine the mesh at the corner or use quadrature 'nodal')")
        Wmap = self.W.dofmap.index_map
        self._wglobal = Wmap.local_to_global(self._wdofs.ravel()).reshape(self._wdofs.shape) if len(slave) else \
            np.zeros((0, nn), np.int64)

        # Master surface: each rank's owned facets, sent to the ranks whose slave facets are near (MasterExchange).
        md = self.master_data
        own = md.owned
        fmap = mesh.topology.index_map(tdim - 1)
        ids = fmap.local_to_global(md.facets[own]) if np.any(own) else np.zeros(0, np.int64)
        self._exchange = MasterExchange(self.comm, md.X[own], md.global_comp[own], ids, self.quadratic)
        self._master = None  # the facets received at the last update: X, G, U, ids (partition-independent order)
        if radius is None:
            Xo = md.X[own]
            sides = (Xo[:, -1:] - Xo[:, :1]) if self.quadratic else np.diff(Xo, axis=1)
            longest = self.comm.allreduce(float(np.max(np.linalg.norm(sides, axis=2))) if len(Xo) else 0.0,
                                          op=MPI.MAX)
            radius = 2.0 * longest if longest > 0 else 1.0
        if not (np.isfinite(radius) and radius > 0):
            raise ValueError(f"search radius must be a finite number > 0, got {radius!r}")
        self.radius = float(radius)
        self._bc_global = None  # set by bind_problem (and its sorted array _bc_array)
        self._bc_array = np.zeros(0, np.int64)
        self._problem = None  # the problem bound by bind_problem
        self.I = None
        self._pairs = None  # master facet of each local slave point: index into self._master (-1: none)
        self._pair_ids = None  # the same as global facet numbers (the pairing state between updates)
        self.exploded = False  # the last update met a master facet stretched past search.STRETCH_LIMIT
        self._exploded_seen = False  # ... or one since take_failure()
        self._timings = {"search_s": 0.0, "exchange_s": 0.0, "coupling_s": 0.0}
        self.pairing_changes = 0
        self._pattern_version = 0
        self._blocks: tuple[PETSc.Mat, PETSc.Mat, PETSc.Mat] | None = None  # A_uw, A_wu, A_ww (coupling_matrix)
        self._merged_version = -1
        self.weight = fem.Constant(mesh, float(weight))

        obstacle = MirrorObstacle(self.Xm, self.w, self.active, nv, gdim, self.radius, self.proj)
        self._set_dummy_mirror()
        self.ds_work = contact_measure(mesh, facet_tags, slave_tag, work_quadrature or quadrature)
        super().__init__(u, facet_tags, slave_tag, obstacle, law, load, quadrature, name)

        self._tmp = None
        if not self.ufl_coupling:  # the subclass assembles residual and tangent itself (mortar.SegmentSurface)
            self.update()
            return
        # Coupling forms (compiled once).
        v, vw = ufl.TestFunction(V), ufl.TestFunction(self.W)
        du, dw = ufl.TrialFunction(V), ufl.TrialFunction(self.W)
        r_u = self.residual(v)  # slave rows (and, for multipliers, the constraint rows)
        r_w = self.master_residual(vw)
        self._r_w = fem.form(r_w)
        self._a_uw = fem.form(ufl.derivative(r_u, self.w, dw))
        self._a_wu = fem.form(ufl.derivative(r_w, u, du))
        self._a_ww = fem.form(ufl.derivative(r_w, self.w, dw))
        self.update()

    def _pressure(self):
        return self.obstacle.active * super()._pressure()

    def master_residual(self, vw: ufl.Argument) -> ufl.Form:
        """Master part on the mirror test function ``vw``: ``weight F(g) dg/dw[vw] ds`` (mapped to the master
        dofs by ``I^T``)."""
        return self.weight * self.pressure * ufl.derivative(self.gap, self.w, vw) * self.ds_work

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Slave part ``weight F(g) dg/du[v] ds``; the master part is :meth:`add_residual`."""
        return self.weight * self.pressure * ufl.derivative(self.gap, self.u, v) * self.ds_work

    # --- projection --------------------------------------------------------
    def slave_points(self) -> np.ndarray:
        """Current positions of the local slave points (nf, nq, gdim)."""
        sd = self.slave_data
        ua = self.u.x.array
        x = sd.X + ua[sd.comp]
        return np.einsum("qk,fkj->fqj", self.B, x)

    def _route_master(self) -> dict | None:
        """Receive the master facets near this rank's slave facets (:class:`MasterExchange`), or None (on every
        rank) if a master facet exploded (:data:`search.STRETCH_LIMIT`). Collective."""
        md, sd = self.master_data, self.slave_data
        X = md.X[md.owned]
        U = self.u.x.array[md.comp[md.owned]]
        xs = sd.X + self.u.x.array[sd.comp]
        smax, master = self._exchange.exchange(U, xs, self.radius, stretch(X + U, X), self.exchange == "allgather")
        if master is not None:
            master["x"] = master["X"] + master["U"]
        return master

    def exchange_stats(self) -> dict:
        """This rank's master exchange: updates, bytes and master facets received from other ranks, seconds,
        and the bytes the former all-gather of the whole master surface would have received."""
        return dict(self._exchange.stats)

    def update(self) -> bool:
        """Project the slave points on the current master surface; set the mirror fields and ``I``.
        Collective. Returns True if the pairing changed."""
        start = time.perf_counter()
        master = self._route_master()
        self._timings["exchange_s"] += time.perf_counter() - start
        # An exploded iterate is rejected, not searched (every rank sees the largest stretch).
        self.exploded = master is None
        self._exploded_seen |= self.exploded
        if self.exploded:
            return False
        self._master = master
        xm, U, mX = master["x"], master["U"], master["X"]
        start = time.perf_counter()
        pts = self.slave_points()
        nf, nq, d = pts.shape if pts.size else (0, self.B.shape[0], self.gdim)
        previous = None if self._pair_ids is None else self._local_facets(self._pair_ids.ravel())
        found = project(pts.reshape(-1, d), xm, self.radius, previous, quadratic=self.quadratic)
        facet, bary, dist = found[:3]
        facet = facet.reshape(nf, nq)
        facet[self._excluded] = -1
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
            else:
                n = facet_normals(xv)
                q = xv[:, 0]
            normal[ok] = n
            gap[ok] = -np.einsum("ij,ij->i", pts[ok] - q, n)
        self.projection = {"facet": facet, "bary": bary.reshape(nf, nq, self.nv), "distance": dist.reshape(nf, nq),
                           "gap": gap, "normal": normal}
        bs = self.nv * d
        # Values at the slave points, then vertex values of the mirror space (B^-1).
        Xq = np.zeros((nf, nq, bs))
        Uq = np.zeros((nf, nq, bs))
        Aq = (facet >= 0).astype(float)
        ok = facet >= 0
        Xq[ok] = mX[facet[ok]].reshape(-1, bs)
        Uq[ok] = U[facet[ok]].reshape(-1, bs)
        dummy = self._dummy_vertices().ravel()
        Xq[~ok] = dummy
        wX = np.einsum("aq,fqb->fab", self.Binv, Xq)
        wU = np.einsum("aq,fqb->fab", self.Binv, Uq)
        wA = np.einsum("aq,fq->fa", self.Binv, Aq)
        idx = self._wdofs[..., None] * bs + np.arange(bs)
        self.Xm.x.array[idx] = wX
        self.w.x.array[idx] = wU
        self.active.x.array[self._sdofs] = wA
        if self.quadratic:  # B = identity: the mirror nodes are the slave points
            free = ok & (xi > 1e-12) & (xi < 1 - 1e-12)
            pidx = self._sdofs[..., None] * 2 + np.arange(2)
            self.proj.x.array[pidx] = np.stack([np.where(ok, xi, 0.5), free.astype(float)], axis=-1)
        self._timings["search_s"] += time.perf_counter() - start
        ids = np.full(facet.shape, -1, np.int64)
        ids[ok] = master["ids"][facet[ok]]
        same = self._pair_ids is not None and np.array_equal(self._pair_ids, ids)
        changed = self.comm.allreduce(0 if same else 1) > 0
        self._pairs, self._pair_ids = facet.copy(), ids
        if changed or self.I is None:
            self._build_I(facet)
            self.pairing_changes += 1
            self._pattern_version += 1
        return changed

    def _local_facets(self, ids: np.ndarray) -> np.ndarray:
        """Indices into the facets of the last update of global facet numbers ``ids`` (-1: none, or not received,
        i.e. beyond the search radius of every local slave facet)."""
        mid = self._master["ids"]
        order = np.argsort(mid)
        pos = np.minimum(np.searchsorted(mid[order], ids), max(len(mid) - 1, 0))
        found = (ids >= 0) & (len(mid) > 0)
        if len(mid):
            found &= mid[order][pos] == ids
        return np.where(found, order[pos] if len(mid) else -1, -1)

    def _dummy_vertices(self) -> np.ndarray:
        """A unit facet far from nothing in particular: keeps the UFL normal finite where ``active = 0``."""
        if self.quadratic:
            return np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]])
        return np.vstack([np.zeros(self.gdim), np.eye(self.gdim)])[: self.nv]

    def _set_dummy_mirror(self) -> None:
        bs = self.nv * self.gdim
        self.Xm.x.array[:] = np.tile(self._dummy_vertices().ravel(), len(self.Xm.x.array) // bs)

    def _build_I(self, facet: np.ndarray) -> None:
        """``I``: rows = mirror dofs of the local slave points (owned or not: PETSc moves off-process rows),
        columns = global displacement dofs of the paired master vertices (Dirichlet dofs left out)."""
        t0 = time.perf_counter()
        d, nv, bs = self.gdim, self.nv, self.nv * self.gdim
        Wmap, Vmap = self.W.dofmap.index_map, self.V.dofmap.index_map
        Vbs = self.V.dofmap.index_map_bs
        sizes = ((Wmap.size_local * bs, Wmap.size_global * bs), (Vmap.size_local * Vbs, Vmap.size_global * Vbs))
        nq = self.B.shape[0]
        # Entries (row, column, B^-1 weight) of every paired point, summed where two points of one mirror node share
        # a master vertex, Dirichlet columns dropped; rows of ghost slave facets are inserted by both ranks with
        # the same values (INSERT), PETSc moves the off-process ones.
        nf, nn = facet.shape[0], self.B.shape[1]
        f, a, q = (x.ravel() for x in np.meshgrid(np.arange(nf), np.arange(nn), np.arange(nq), indexing="ij"))
        m, w = facet[f, q], self.Binv[a, q]
        keep = (m >= 0) & (w != 0.0)
        f, a, m, w = f[keep], a[keep], m[keep], w[keep]
        local = (np.arange(nv)[:, None] * d + np.arange(d)).ravel()
        rows = (self._wglobal[f, a].astype(np.int64) * bs)[:, None] + local
        cols = self._master["G"][m].reshape(len(m), nv * d).astype(np.int64)
        vals = np.broadcast_to(w[:, None], rows.shape)
        fac = np.broadcast_to(f[:, None], rows.shape)
        rows, cols, vals, fac = rows.ravel(), cols.ravel(), vals.ravel(), fac.ravel()
        if self._bc_global:
            free = ~np.isin(cols, self._bc_array)
            rows, cols, vals, fac = rows[free], cols[free], vals[free], fac[free]
        if len(rows):
            # Sum over the points of one facet; a mirror node shared by two slave facets gets the same row from
            # each (one insert, as INSERT_VALUES would leave it).
            key, inverse = np.unique(np.stack([rows, cols, fac]), axis=1, return_inverse=True)
            vals = np.bincount(inverse.ravel(), weights=vals)
            rc, first = np.unique(key[:2], axis=1, return_index=True)
            rows, cols, vals = rc[0], rc[1], vals[first]
        I = aij_matrix(self.comm, sizes, rows, cols, vals, addv=PETSc.InsertMode.INSERT_VALUES)  # noqa: E741
        if self.I is not None:
            self.I.destroy()
        self.I = I
        self._timings["coupling_s"] += time.perf_counter() - t0

    def take_failure(self) -> str | None:
        seen, self._exploded_seen = self._exploded_seen, False
        return "exploded_geometry" if seen else None

    def timings(self) -> dict[str, float]:
        return dict(self._timings)

    # --- solver hooks --------------------------------------------------------
    def bind_problem(self, problem) -> None:
        """Learn the Dirichlet dofs (global numbers) of ``problem``; they are left out of ``I``."""
        Vmap, bs = self.V.dofmap.index_map, self.V.dofmap.index_map_bs
        local = np.unique(np.concatenate([bc_dofs(b) for b in problem.bcs])) if problem.bcs else np.zeros(0, int)
        local = local[local < Vmap.size_local * bs]
        glob = Vmap.local_to_global(local // bs) * bs + local % bs if len(local) else np.zeros(0, np.int64)
        self._bc_array = np.unique(np.concatenate(self.comm.allgather(glob))).astype(np.int64)
        self._bc_global = set(self._bc_array.tolist())
        self._problem = problem
        self._build_I(self._pairs)
        self._pattern_version += 1

    def prepare(self, problem) -> None:
        """Before each residual evaluation (``u`` current): re-pair and refresh the mirror fields."""
        if self._problem is not problem:
            self.bind_problem(problem)
        self.update()

    def add_residual(self, b: PETSc.Vec) -> None:
        """``b += I^T r_w`` (owned entries; before boundary conditions are set). An exploded iterate
        (:data:`search.STRETCH_LIMIT`) gets a non-finite residual: the solve fails and the step is cut."""
        if self.exploded:
            b.set(np.nan)
            return
        rw = fem_petsc.assemble_vector(self._r_w)
        rw.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        if self._tmp is None:
            self._tmp = b.duplicate()
        self.I.multTranspose(rw, self._tmp)
        b.axpy(1.0, self._tmp)
        rw.destroy()

    def coupling_matrix(self, bcs) -> PETSc.Mat:
        """``A_uw I + I^T A_wu + I^T A_ww I`` (Dirichlet rows and columns zero)."""
        # The three blocks' patterns depend on the slave facets only: made once, not per Jacobian (their rows span
        # the whole mirror space, nv gdim values per vertex: each build allocated 0.16 GB at 4e5 dofs).
        if self._blocks is None:
            self._blocks = tuple(fem_petsc.create_matrix(a) for a in (self._a_uw, self._a_wu, self._a_ww))
        A_uw, A_wu, A_ww = self._blocks
        for M, a, b in zip(self._blocks, (self._a_uw, self._a_wu, self._a_ww), (bcs, bcs, [])):
            M.zeroEntries()
            fem_petsc.assemble_matrix(M, a, bcs=b)
            M.assemble()
        C = A_uw.matMult(self.I)
        C2 = self.I.transposeMatMult(A_wu)
        C3 = A_ww.PtAP(self.I)
        C.axpy(1.0, C2, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        C.axpy(1.0, C3, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        for m in (C2, C3):
            m.destroy()
        return C

    def pattern_changes(self) -> bool:
        return self._merged_version != self._pattern_version

    def add_jacobian(self, A: PETSc.Mat, bcs) -> bool:
        """``A += coupling``; returns True when ``A``'s nonzero pattern was rebuilt (pairing changed)."""
        C = self.coupling_matrix(bcs)
        rebuild = self.pattern_changes()
        if rebuild:  # the temporaries' freed pages back to the system before A's copy is allocated
            release_free_memory()
        structure = PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN if rebuild else \
            PETSc.Mat.Structure.SUBSET_NONZERO_PATTERN
        # MatAXPY with a new pattern replaces A's header and drops its near-nullspace (GAMG's rigid-body modes):
        # put it back, else AMG runs without it from the first pairing change on.
        near = A.getNearNullSpace() if rebuild else None
        A.axpy(1.0, C, structure=structure)
        if near is not None and near.handle:
            A.setNearNullSpace(near)
        self._merged_version = self._pattern_version
        C.destroy()
        return rebuild

    # --- figures ---------------------------------------------------------------
    def _point_pressure(self, g: np.ndarray) -> np.ndarray:
        """The law's pressure at the slave points (nf, nq) from their gaps (0 where unpaired)."""
        c = {k: float(v.value) for k, v in self.constants.items()}
        for k, f in self.fields.items():
            if self.quadratic and self.quadrature == "nodal":  # fields on P1 (the end nodes); middle: their mean
                sd = self.slave_data
                ends = f.x.array[np.array([f.function_space.dofmap.cell_dofs(cell)[lo] for cell, lo in
                                           zip(sd.cells, sd.vertex_local)], dtype=np.int32).reshape(-1, 2)]
                c[k] = np.stack([ends[:, 0], ends.mean(axis=1), ends[:, 1]], axis=1) if len(ends) else \
                    np.zeros((0, 3))
            else:
                c[k] = np.einsum("qk,fk->fq", self.B, f.x.array[self._sdofs])
        gg = np.where(np.isfinite(g), g, -self.radius)  # the UFL gap of an unpaired point
        return np.where(np.isfinite(g), self.law.force(gg, c), 0.0) if g.size else np.zeros_like(g)

    def _point_area_ratio(self) -> np.ndarray:
        """``da/dA`` of the slave surface at the slave points (nf, nq): the bound material's area ratio
        (:meth:`ContactSurface.area_ratio`) projected on the surface space, as the law's fields."""
        if not hasattr(self, "_ratio_rhs"):
            self._ratio_rhs = self.projector.compile(self.area_ratio())
            self._ratio = fem.Function(self.S)
        self.projector.project(self._ratio_rhs, self._ratio)
        return np.einsum("qk,fk->fq", self.B, self._ratio.x.array[self._sdofs])

    def point_table(self, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Reference position, current position, gap and pressure at the slave points of the owned slave
        facets, gathered on every rank and sorted by reference position (a node shared by two facets once).
        Unpaired points have gap ``-inf`` and pressure 0. ``kind``: ``nominal`` (per reference slave area,
        default) or ``cauchy`` (per current slave area: nominal ``/ (da/dA)``)."""
        self._check_kind(kind)
        sd = self.slave_data
        X = np.einsum("qk,fkj->fqj", self.B, sd.X)
        x = self.slave_points()
        g = self.projection["gap"]
        p = self._point_pressure(g)
        if kind == "cauchy":
            p = p / self._point_area_ratio()
        own = sd.owned
        d = self.gdim
        data = [np.concatenate(a) for a in zip(*self.comm.allgather(
            (X[own].reshape(-1, d), x[own].reshape(-1, d), g[own].ravel(), p[own].ravel())))]
        Xr = np.round(data[0], 12)
        _, first = np.unique(Xr, axis=0, return_index=True)
        order = first[np.lexsort(Xr[first].T[::-1])]
        return tuple(a[order] for a in data)

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Current position (``reference=True``: reference position), gap and pressure (``kind``: ``nominal``
        or ``cauchy``) at the slave points (:meth:`point_table` without the other position)."""
        X, x, g, p = self.point_table(kind)
        return (X if reference else x), g, p

    def reference_points(self) -> np.ndarray:
        """Reference positions of all slave points (every rank's, on every rank)."""
        X = np.einsum("qk,fkj->fqj", self.B, self.slave_data.X).reshape(-1, self.gdim)
        return np.concatenate(self.comm.allgather(X))

    def pairing(self) -> np.ndarray:
        """The pairing the residual depends on (a copy, this rank's): the global facet number of the master facet
        of each local slave point (-1: none), flattened."""
        return self._pair_ids.ravel().copy()
