"""Papadopoulos & Solberg's collocated two-body element (1998, section 3): 2D, quadratic (3-node) facets.

Both surfaces carry a pressure (per current length; an unknown at each vertex of each surface, P1 dofs
of the mixed unknown of :mod:`multipliers`) and each body is loaded by its own pressure on its own
current surface, integrated with Simpson's rule over each facet::

    f_k = w_k p_k (x'_y, -x'_x)(xi_k),   xi_k = 0, 1/2, 1,   w_k = 1/6, 4/6, 1/6

(``(x'_y, -x'_x)`` is the outward normal times the current length element). On a facet of surface
``alpha`` the end values are the vertex unknowns; the middle value is *collocated* from the opposite
surface: among the vertices of ``beta`` whose closest point on the facet lies inside it
(``xi*`` in ``(XI_MIN, 1 - XI_MIN)``), the one closest to the facet's middle sets
``p^alpha(xi*) = p^beta(x^beta)``, i.e. ``p_c = (p^beta - L_0(xi*) p_0 - L_2(xi*) p_2) / L_1(xi*)``
(quadratic Lagrange ``L``); with no such vertex ``p_c = (p_0 + p_2)/2``. The gap is enforced at the
vertices of both surfaces against the opposite surface's current curved facets (the closest point of
:mod:`search`), by the complementarity rows of the law: ``C(p, g)/(-c)`` (:class:`LagrangeMultiplier`,
exact) or ``p = eps <g>`` (:class:`PenaltyMultiplier`). A vertex of the second surface that coincides with
one of the first in the current configuration (node on node: closer than ``TIE`` times the first
surface's shortest facet at that vertex, the same margin that keeps a vertex out of the collocation)
gets ``p^2 = p^1`` instead of a second gap constraint (one independent constraint per pair). Current,
not reference: on the sheet (surfaces that slide) the pairs that coincide at rest separate; tied by
their reference positions, the second surface's vertex loses its gap constraint for good and
penetrates (n_arc = 8, t = 1: 6.4e-4, the penalty's Newton diverging at t = 0.53). "Coincide" is
measured along the surface (the offset along the normal is the gap, which Newton's iterates open).

Residual and tangent are assembled in NumPy from the two surfaces gathered on every rank (their
facets in a partition-independent order): every rank computes the same numbers and adds the rows it
owns, so the result does not depend on the partition. The tangent is exact except for the dependence
of ``xi*`` (the collocation point) on the displacements, left out (Newton still converges; it is
first-order small for a converged collocation point).
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from petsc4py import PETSc
from scipy.spatial import cKDTree

from .laws import LagrangeMultiplier, PenaltyMultiplier
from .multipliers import TwoBodyMultiplier
from .search import project, quadratic_normals, quadratic_shape
from .sparse import aij_matrix

__all__ = ["XI_MIN", "TIE", "collocated_surfaces", "CollocatedSurface"]

XI_MIN = 0.05  # collocation points closer than this (in xi) to a facet's end are not used
TIE = XI_MIN  # vertices of the two surfaces closer than this x the facet length coincide (node on node)
_W = np.array([1.0, 4.0, 1.0]) / 6.0  # Simpson
_XI = np.array([0.0, 0.5, 1.0])
_ROT = np.array([[0.0, 1.0], [-1.0, 0.0]])  # (t_x, t_y) -> (t_y, -t_x)


def _lagrange2(xi: np.ndarray) -> np.ndarray:
    return quadratic_shape(np.atleast_1d(xi))[0]


def collocated_surfaces(w: fem.Function, facet_tags, tag_a: int, tag_b: int, law: LagrangeMultiplier,
                        load: fem.Constant, radius: float | None = None, name: str = "collocated") -> list:
    """The two surfaces of the collocated element (each surface's pressure an unknown of ``w``, the mixed
    unknown of :func:`multipliers.unknown` with a degree-2 displacement)."""
    if not isinstance(law, LagrangeMultiplier):
        raise ValueError(f"the collocated element needs method 'lagrange' or 'penalty_multiplier', got {law.name!r}")
    # constraint at the vertices ("nodal"), work with Simpson's rule (this element assembles it itself)
    a = CollocatedSurface(w, facet_tags, tag_a, tag_b, law, load, "nodal", 1.0, radius, f"{name}_a", "simpson")
    b = CollocatedSurface(w, facet_tags, tag_b, tag_a, law, load, "nodal", 1.0, radius, f"{name}_b", "simpson")
    a._pair(b, first=True)
    b._pair(a, first=False)
    return [a, b]


class CollocatedSurface(TwoBodyMultiplier):
    """One surface of the collocated pair: its facets' Simpson work and its vertices' constraints."""

    ring_weighted = False  # its own integrals (nodal weights, NumPy element) carry no 2 pi r

    ufl_coupling = False

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        if not self.quadratic:
            raise ValueError("the collocated element needs quadratic (3-node) facets: a degree-2 displacement")
        self.other = None
        self._static = self._gather_static()
        self._tangent: PETSc.Mat | None = None  # the last coupling_matrices

    def _pair(self, other, first: bool) -> None:
        self.other, self.first = other, first
        # Node on node (the second surface ties its pressure to the first's): decided in the current
        # configuration (_ties), within TIE x the first surface's shortest facet at the node.
        oo = other._static
        h = np.linalg.norm(oo["X"][:, 2] - oo["X"][:, 0], axis=1)
        self._h_other = np.full(len(oo["VX"]), np.inf)
        np.minimum.at(self._h_other, oo["ends"][:, 0], h)
        np.minimum.at(self._h_other, oo["ends"][:, 1], h)
        self._tie = np.full(len(self._static["VX"]), -1)

    def _ties(self, xv: np.ndarray, xo: np.ndarray, facets: np.ndarray) -> np.ndarray:
        """For each vertex of this (second) surface at current positions ``xv``, the vertex of the first surface
        (current positions ``xo``, facet nodes ``facets`` (nf, 3, 2)) it coincides with along the surface: the
        nearest one, if their offset along its tangent is at most ``TIE`` x its shortest facet (the offset along
        the normal is the gap, which the iterates open and close), else -1. The first surface ties nothing.
        Current, not reference, positions: the sheet's surfaces slide along each other, and a pair that coincided
        at rest separates (on the rings nothing slides: the same pairs)."""
        tie = np.full(len(xv), -1)
        if self.first or not len(xv) or not len(xo):
            return tie
        ends = self.other._static["ends"]
        dN = quadratic_shape(_XI)[1]
        tangent = np.zeros_like(xo)  # at each vertex: the sum of its facets' unit tangents
        for k, m in ((0, 0), (1, 2)):
            t = np.einsum("m,emj->ej", dN[m], facets)
            np.add.at(tangent, ends[:, k], t / np.linalg.norm(t, axis=1, keepdims=True))
        tangent /= np.linalg.norm(tangent, axis=1, keepdims=True)
        d, j = cKDTree(xo).query(xv)
        along = np.abs(np.einsum("ij,ij->i", xv - xo[j], tangent[j]))
        near = (along <= TIE * self._h_other[j]) & (d <= self.radius)
        tie[near] = j[near]
        return tie

    def residual(self, v):
        return None  # add_residual / add_jacobian

    # --- gathered data ----------------------------------------------------
    def _gather_static(self) -> dict:
        """Reference nodes (nf, 3, 2), global displacement components (nf, 3, 2), global pressure dofs of
        the ends (nf, 2), in a partition-independent order; the unique vertices ``VX`` with their pressure
        dofs ``VP`` and the facet ends' vertex numbers ``ends`` (nf, 2)."""
        sd, comm = self.slave_data, self.comm
        Wp = self.u.function_space.sub(1)
        ploc = np.array([Wp.dofmap.cell_dofs(c)[lo] for c, lo in zip(sd.cells, sd.vertex_local)],
                        dtype=np.int32).reshape(-1, 2)
        imap = self.u.function_space.dofmap.index_map
        pglob = imap.local_to_global(ploc.ravel()).reshape(ploc.shape) if len(ploc) else ploc.astype(np.int64)
        own = sd.owned
        X = np.concatenate(comm.allgather(sd.X[own]))
        G = np.concatenate(comm.allgather(sd.global_comp[own]))
        P = np.concatenate(comm.allgather(pglob[own]))
        key = np.lexsort(np.round(X.mean(axis=1), 12).T[::-1])
        X, G, P = X[key], G[key], P[key]
        ends = X[:, [0, 2]].reshape(-1, 2)
        _, first, inverse = np.unique(np.round(ends, 12), axis=0, return_index=True, return_inverse=True)
        VX = ends[first]
        VP = P.reshape(-1)[first]
        self._ploc, self._key = ploc, key
        return {"X": X, "G": G, "P": P, "VX": VX, "VP": VP, "ends": inverse.reshape(-1, 2)}

    def _current(self) -> tuple[np.ndarray, np.ndarray]:
        """Current nodes (nf, 3, 2) and vertex pressures (nv,) of this surface (every rank)."""
        sd, comm = self.slave_data, self.comm
        a = self.u.x.array
        own = sd.owned
        U = np.concatenate(comm.allgather(a[sd.comp[own]]))[self._key]
        p = np.concatenate(comm.allgather(a[self._ploc[own]]))[self._key]
        s = self._static
        pv = np.zeros(len(s["VX"]))
        pv[s["ends"].ravel()] = p.ravel()
        return s["X"] + U, pv

    # --- the element ------------------------------------------------------
    def _assemble(self) -> tuple[tuple[list, list], tuple[list, list, list]]:
        """Residual entries (rows, values) and tangent entries (rows, cols, values), global numbers: the gap
        constraints of this surface's vertices, then the Simpson work of its pressure (the order of the
        entries fixes the order of their sums)."""
        s, o = self._static, self.other._static
        xa, pa = self._current()
        xb, pb = self.other._current()
        xo = np.zeros((len(o["VX"]), 2))  # the other surface's current vertices
        xo[o["ends"][:, 0]], xo[o["ends"][:, 1]] = xb[:, 0], xb[:, 2]
        xv = np.zeros((len(s["VX"]), 2))  # this surface's
        xv[s["ends"][:, 0]], xv[s["ends"][:, 1]] = xa[:, 0], xa[:, 2]
        res, jac = ([], []), ([], [], [])
        self._tie = self._ties(xv, xo, xb)
        self._vertex_gap = _gap_rows(s, o, xv, pa, xb, pb, self._tie, self.law, float(self.constants["c"].value),
                                     self.radius, res, jac)
        best, xio = _collocate(xa, xo, self.radius)
        self._collocation = best
        self._pmid = _simpson_work(s, o, xa, pa, pb, best, xio, res, jac)
        return res, jac

    def update(self) -> bool:
        changed = super().update()
        if getattr(self, "other", None) is not None:
            self._entries = self._assemble()
        return changed

    def _owned_rows(self, rows: np.ndarray) -> np.ndarray:
        lo, hi = self.u.function_space.dofmap.index_map.local_range
        return (rows >= lo) & (rows < hi)

    def add_residual(self, b: PETSc.Vec) -> None:
        rows, vals = (np.asarray(a) for a in self._entries[0])
        keep = self._owned_rows(rows)
        if np.any(keep):
            b.setValues(rows[keep].astype(PETSc.IntType), vals[keep], addv=PETSc.InsertMode.ADD_VALUES)
        b.assemblyBegin()
        b.assemblyEnd()

    def coupling_matrices(self, bcs) -> tuple[PETSc.Mat]:
        rows, cols, vals = (np.asarray(a) for a in self._entries[1])
        Wmap = self.u.function_space.dofmap.index_map
        sizes = ((Wmap.size_local, Wmap.size_global),) * 2
        keep = self._owned_rows(rows) & ~np.isin(rows, self._bc_array) & ~np.isin(cols, self._bc_array)
        rows, cols, vals = rows[keep], cols[keep], vals[keep]
        # one entry per (row, column): the collocated entries summed
        key, inverse = np.unique(rows.astype(np.int64) * sizes[1][1] + cols.astype(np.int64), return_inverse=True)
        vals = np.bincount(inverse.ravel(), weights=vals, minlength=len(key))
        if self._tangent is not None:  # the last call's: valid until this one
            self._tangent.destroy()
        self._tangent = aij_matrix(self.comm, sizes, key // sizes[1][1], key % sizes[1][1], vals)
        self._pattern.version += 1  # the collocation may change from one iterate to the next
        return (self._tangent,)

    # --- results ------------------------------------------------------------
    def total_force(self) -> np.ndarray:
        """Force of the other body on this surface's body, shape (2,) (per unit thickness): the element's
        Simpson sum ``-sum_e sum_k w_k p_k (x'_y, -x'_x)(xi_k)`` (this surface's pressure on its own current
        surface, the middle values of the last assembly); the same on every rank. Collective."""
        xa, pa = self._current()
        ends = self._static["ends"]
        p = np.stack([pa[ends[:, 0]], self._pmid, pa[ends[:, 1]]], axis=1)  # (nf, 3)
        nl = np.einsum("km,emj->ekj", quadratic_shape(_XI)[1], xa) @ _ROT.T  # outward normal x length element
        return -np.einsum("k,ek,ekj->j", _W, p, nl)

    def point_table(self, kind: str = "nominal"):
        """Reference position, current position, gap (vertices; middle nodes: -inf, not constrained) and
        pressure (vertex unknowns; middle nodes: the collocated or mean value) at every node of this
        surface, on every rank, sorted by reference position. ``kind``: ``cauchy`` (the element's, per current
        length) or ``nominal`` (per reference length: times the stretch ``|x'|/|X'|`` at the node, the mean of
        the two facets' at a vertex)."""
        self._check_kind(kind)
        s = self._static
        xa, pa = self._current()
        nv = len(s["VX"])
        dN = quadratic_shape(_XI)[1]
        stretch = (np.linalg.norm(np.einsum("km,emj->ekj", dN, xa), axis=2)
                   / np.linalg.norm(np.einsum("km,emj->ekj", dN, s["X"]), axis=2))  # (nf, 3)
        sv = np.zeros(nv)
        np.add.at(sv, s["ends"][:, 0], 0.5 * stretch[:, 0])
        np.add.at(sv, s["ends"][:, 1], 0.5 * stretch[:, 2])
        count = np.zeros(nv)
        np.add.at(count, s["ends"].ravel(), 0.5)
        sv /= count  # a surface's end vertex has one facet
        X = np.concatenate([s["VX"], s["X"][:, 1]])
        x = np.zeros((nv + len(xa), 2))
        x[s["ends"][:, 0]], x[s["ends"][:, 1]], x[nv:] = xa[:, 0], xa[:, 2], xa[:, 1]
        g = np.concatenate([self._vertex_gap, np.full(len(xa), -np.inf)])
        p = np.concatenate([pa, self._pmid])
        if kind == "nominal":
            p = p * np.concatenate([sv, stretch[:, 1]])
        order = np.lexsort(np.round(X, 12).T[::-1])
        return X[order], x[order], g[order], p[order]


# --- the element: residual and tangent entries, appended to res = (rows, values), jac = (rows, cols, values) ---
def _gap_rows(s: dict, o: dict, xv: np.ndarray, pa: np.ndarray, xb: np.ndarray, pb: np.ndarray, tie: np.ndarray,
              law: LagrangeMultiplier, c: float, radius: float, res: tuple[list, list],
              jac: tuple[list, list, list]) -> np.ndarray:
    """The constraint rows of one surface's vertices (``s``: its gathered data, current positions ``xv``,
    pressures ``pa``) against the other's current curves (``o``, nodes ``xb`` (nf, 3, 2), pressures ``pb``): the
    law's complementarity ``-C(p, g)/c`` where paired, ``-p/c`` (open) where not, ``p_i - p_j`` node on node
    (``tie``). Returns the vertices' gaps (> 0 penetration; ``-inf`` unpaired)."""
    rr, rv = res
    jr, jc, jv = jac
    penalty = isinstance(law, PenaltyMultiplier)
    vcomp = np.zeros((len(s["VX"]), 2), np.int64)
    vcomp[s["ends"][:, 0]], vcomp[s["ends"][:, 1]] = s["G"][:, 0], s["G"][:, 2]
    facet, N, _, xi = project(xv, xb, radius, None, quadratic=True)
    gap = np.full(len(xv), -np.inf)
    for i in range(len(xv)):
        row = s["VP"][i]
        f = facet[i]
        if f >= 0:
            n = quadratic_normals(xb[f][None], np.array([xi[i]]))[0]
            g = -float((xv[i] - N[i] @ xb[f]) @ n)
            gap[i] = g
        if tie[i] >= 0:  # node on node: p_i = p_j of the first surface
            j = tie[i]
            rr.append(row), rv.append(pa[i] - pb[j])
            jr.extend([row, row])
            jc.extend([row, o["VP"][j]])
            jv.extend([1.0, -1.0])
            continue
        if f < 0:  # no opposite facet within the radius: open
            rr.append(row), rv.append(-pa[i] / c)
            jr.append(row), jc.append(row), jv.append(-1.0 / c)
            continue
        C = float(law.complementarity(pa[i], g, {"c": c}))
        rr.append(row), rv.append(-C / c)
        if penalty:
            dp, dg = -1.0 / c, float(g > 0)
        else:
            active = pa[i] + c * g >= 0
            dp, dg = (0.0 if active else -1.0 / c), float(active)
        jr.append(row), jc.append(row), jv.append(dp)
        if dg:
            for k in range(2):  # dg = -n . (dx_i - sum_m N_m dx_m)
                jr.append(row), jc.append(vcomp[i, k]), jv.append(-dg * n[k])
                for m in range(3):
                    jr.append(row), jc.append(o["G"][f, m, k]), jv.append(dg * N[i, m] * n[k])
    return gap


def _collocate(xa: np.ndarray, xo: np.ndarray, radius: float) -> tuple[np.ndarray, np.ndarray]:
    """For each facet of a surface (current nodes ``xa``), the vertex of the other surface (current positions
    ``xo``) that collocates its middle pressure (-1: none), and every such vertex's ``xi*``."""
    fo, _, _, xio = project(xo, xa, radius, None, quadratic=True)
    best = np.full(len(xa), -1)
    for j in np.flatnonzero(fo >= 0):
        e, t = fo[j], xio[j]
        if XI_MIN < t < 1 - XI_MIN and (best[e] < 0 or abs(t - 0.5) < abs(xio[best[e]] - 0.5)):
            best[e] = j
    return best, xio


def _simpson_work(s: dict, o: dict, xa: np.ndarray, pa: np.ndarray, pb: np.ndarray, best: np.ndarray,
                  xio: np.ndarray, res: tuple[list, list], jac: tuple[list, list, list]) -> np.ndarray:
    """Simpson's rule for the work of a surface's pressure (vertex values ``pa``) on its own body (current nodes
    ``xa``), the middle values collocated (``best``, ``xio`` of :func:`_collocate`, the other's pressures ``pb``)
    or the mean of the ends. Returns the middle values."""
    rr, rv = res
    jr, jc, jv = jac
    dN = quadratic_shape(_XI)[1]  # (3 points, 3 nodes)
    pmid = np.zeros(len(xa))
    for e in range(len(xa)):
        i0, i2 = s["ends"][e]
        pdofs = [s["VP"][i0], s["VP"][i2]]
        if best[e] >= 0:
            j = best[e]
            L = _lagrange2(xio[j])[0]
            pm = (pb[j] - L[0] * pa[i0] - L[2] * pa[i2]) / L[1]
            mid = [(pdofs[0], -L[0] / L[1]), (pdofs[1], -L[2] / L[1]), (o["VP"][j], 1.0 / L[1])]
        else:
            pm = 0.5 * (pa[i0] + pa[i2])
            mid = [(pdofs[0], 0.5), (pdofs[1], 0.5)]
        pmid[e] = pm
        pk = (pa[i0], pm, pa[i2])
        dpk = ([(pdofs[0], 1.0)], mid, [(pdofs[1], 1.0)])
        for k in range(3):
            t = dN[k] @ xa[e]  # x'(xi_k)
            nl = _ROT @ t
            rows = s["G"][e, k]
            rr.extend(rows)
            rv.extend(_W[k] * pk[k] * nl)
            for d, coef in dpk[k]:
                jr.extend(rows)
                jc.extend([d, d])
                jv.extend(_W[k] * coef * nl)
            for m in range(3):
                block = _W[k] * pk[k] * dN[k, m] * _ROT
                for a_ in range(2):
                    for b_ in range(2):
                        if block[a_, b_]:
                            jr.append(rows[a_]), jc.append(s["G"][e, m, b_]), jv.append(block[a_, b_])
    return pmid
