"""Two-body contact with segment-to-segment integration (:class:`SegmentSurface`), 2D and 3D.

The surface uses the projection, master exchange, nodal state, augmentation and outputs of
:class:`twobody.TwoBodySurface` with nodal points; the contact residual and tangent on slave and master dofs
come from the element (:mod:`~.element`) on the facet pairs (:mod:`~.pairs`), assembled in NumPy and added by
the solver hooks. Each rank integrates its *owned* slave facets (each once) against the master facets
:class:`twobody.MasterExchange` brings; the entries go to PETSc with global indices (``ADD``; the assembly
moves off-process entries), so a master facet on another rank is a column.
"""
from __future__ import annotations

import numpy as np
from petsc4py import PETSc

from ..search import STRETCH_LIMIT, stretch
from ..sparse import aij_matrix
from ..twobody import TwoBodySurface
from .element import segment_element, triangle_element
from .pairs import pair_segments, pair_triangles

__all__ = ["SegmentSurface"]


def _same(a: tuple, b: tuple) -> bool:
    """Whether two element inputs ``(x, scalars, fields, weight, dofs)`` are equal (arrays exactly)."""
    xa, sa, fa, wa, da = a
    xb, sb, fb, wb, db = b
    return (wa == wb and sa == sb and xa.shape == xb.shape and np.array_equal(xa, xb) and np.array_equal(da, db)
            and fa.keys() == fb.keys() and all(np.array_equal(fa[k], fb[k]) for k in fa))


class SegmentSurface(TwoBodySurface):
    """Two-body contact with segment-to-segment integration (``quadrature="segment"``, 2D and 3D): the same
    projection, master exchange, nodal state, augmentation and outputs as
    :class:`twobody.TwoBodySurface` with nodal points, but the contact residual and tangent on slave and
    master dofs come from :func:`segment_element`, assembled in NumPy and added by the solver hooks."""

    ufl_coupling = False

    def __init__(self, u, facet_tags, slave_tag, master_tag, law, load, weight=1.0, radius=None,
                 name="twobody"):
        if u.function_space.num_sub_spaces > 0 and u.function_space.sub(0).num_sub_spaces > 0:
            raise ValueError("contact quadrature 'segment' needs a displacement unknown (not a mixed space)")
        self._segment_pairs = None  # (owned slave facet, index into the received master facets)
        self._segment_ids = None  # the same with global master facet numbers (the pairing state)
        self._element_cache = None  # (inputs, (residuals, tangents)) of the last element evaluation
        super().__init__(u, facet_tags, slave_tag, master_tag, law, load, "nodal", weight, radius, name)
        self.quadrature = "segment"
        sd = self.slave_data
        if len(sd.X) == 0:
            self._J = np.zeros(0)
        elif self.gdim == 2:  # reference length
            self._J = np.linalg.norm(sd.X[:, 1] - sd.X[:, 0], axis=1)
        else:  # twice the reference area
            self._J = np.linalg.norm(np.cross(sd.X[:, 1] - sd.X[:, 0], sd.X[:, 2] - sd.X[:, 0]), axis=1)

    def residual(self, v):
        return None  # everything is in add_residual / add_jacobian

    # --- pairing -------------------------------------------------------------
    def _slave_current(self) -> np.ndarray:
        sd = self.slave_data
        return sd.X + self.u.x.array[sd.comp]

    def update(self) -> bool:
        """Nodal projection (state, outputs) and the sub-segments of the owned slave facets. Collective."""
        changed = super().update()
        # Slave facets are local: an exploded slave facet on any rank rejects the iterate on every rank.
        if self.pairs.reject(stretch(self._slave_current(), self.slave_data.X) > STRETCH_LIMIT):
            return False
        xm = self.pairs.master["x"]
        own = np.flatnonzero(self.slave_data.owned)
        pair = pair_segments if self.gdim == 2 else pair_triangles
        fs, ms = pair(self._slave_current()[own], xm, self.radius)
        pairs = np.stack([own[fs], ms], axis=1)
        ids = np.stack([own[fs], self.pairs.master["ids"][ms]], axis=1)  # the state: global master facet numbers
        same = self._segment_ids is not None and np.array_equal(self._segment_ids, ids)
        seg_changed = self.comm.allreduce(0 if same else 1) > 0
        self._segment_pairs, self._segment_ids = pairs, ids
        if seg_changed:
            self._pattern.version += 1
        self._xm = xm
        return changed or seg_changed

    def pairing(self) -> np.ndarray:
        """The point pairs (:meth:`TwoBodySurface.pairing`) followed by the (slave facet, master facet) pairs of
        the sub-segments, flattened."""
        return np.concatenate([super().pairing(), self._segment_ids.ravel()])

    def _elements(self, points: bool = False):
        """Element residuals, tangents and global dof indices (n, 8) of the current sub-segments."""
        f, m = self._segment_pairs[:, 0], self._segment_pairs[:, 1]
        x = np.concatenate([self._slave_current()[f], self._xm[m]], axis=1)
        scalars = {k: float(c.value) for k, c in self.constants.items()}
        fields = {k: fn.x.array[self.mirror.scalar_dofs[f]] for k, fn in self.fields.items()}
        weight = float(self.weight.value)
        k = self.nv * self.gdim
        dofs = np.concatenate([self.slave_data.global_comp[f].reshape(-1, k), self.pairs.master["G"][m].reshape(-1, k)],
                              axis=1)
        # The residual and the Jacobian of one state (a Newton iteration's F then J) share one evaluation: the
        # element routine gives both; it is reused while its inputs are unchanged (compared, not assumed).
        inputs = (x, scalars, fields, weight, dofs)
        if not points and self._element_cache is not None and _same(self._element_cache[0], inputs):
            return self._element_cache[1], dofs
        element = segment_element if self.gdim == 2 else triangle_element
        out = element(x, self._J[f], self.law, scalars, fields, weight, points=points)
        if not points:
            self._element_cache = (inputs, out)
        return out, dofs

    # --- solver hooks ----------------------------------------------------------
    def add_residual(self, b: PETSc.Vec) -> None:
        if self.exploded:  # a non-finite residual: the solve fails and the step is cut (search.STRETCH_LIMIT)
            b.set(np.nan)
            return
        (r, _), dofs = self._elements()
        if len(r):
            b.setValues(dofs.ravel().astype(PETSc.IntType), r.ravel(), addv=PETSc.InsertMode.ADD_VALUES)
        b.assemblyBegin()
        b.assemblyEnd()

    def coupling_matrix(self, bcs) -> PETSc.Mat:
        """The whole contact tangent (slave and master rows and columns; Dirichlet rows and columns zero)."""
        (_, K), dofs = self._elements()
        Vmap, bs = self.V.dofmap.index_map, self.V.dofmap.index_map_bs
        n_local, N = Vmap.size_local * bs, Vmap.size_global * bs
        # The element entries summed per (row, column) here, Dirichlet rows and columns left out.
        rows = cols = np.zeros(0, np.int64)
        vals = np.zeros(0)
        if len(K):
            idx = np.where(np.isin(dofs, self._dirichlet), -1, dofs).astype(np.int64)
            m = idx.shape[1]
            rows, cols = np.repeat(idx, m, axis=1).ravel(), np.tile(idx, (1, m)).ravel()
            keep = (rows >= 0) & (cols >= 0)
            key, inverse = np.unique(rows[keep] * N + cols[keep], return_inverse=True)
            vals = np.bincount(inverse.ravel(), weights=K.ravel()[keep], minlength=len(key))
            rows, cols = key // N, key % N
        return aij_matrix(self.comm, ((n_local, N),) * 2, rows, cols, vals)

    # --- figures ---------------------------------------------------------------
    def segment_points(self) -> dict:
        """Sub-segment Gauss points of the owned slave facets (local): reference and current position,
        weight (reference length, without the two-pass factor), gap, pressure, master normal."""
        d = self.gdim
        if len(self._segment_pairs) == 0:
            z = np.zeros((0, d))
            return {"X": z, "x": z, "weight": np.zeros(0), "gap": np.zeros(0), "pressure": np.zeros(0), "normal": z}
        (_, _, pts), _ = self._elements(points=True)
        f = self._segment_pairs[pts["pair"], 0]
        N = pts["N"]
        X = np.einsum("qa,qaj->qj", N, self.slave_data.X[f])
        x = np.einsum("qa,qaj->qj", N, self._slave_current()[f])
        return {"X": X, "x": x, "weight": pts["weight"], "gap": pts["gap"], "pressure": pts["pressure"],
                "normal": pts["normal"]}

    def point_values(self, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Current position, gap and nominal pressure (per reference slave area) at every sub-segment Gauss
        point, gathered on every rank and sorted by reference position. ``kind="cauchy"`` is refused here
        (use the pointwise quadratures' :meth:`TwoBodySurface.point_values`)."""
        if kind != "nominal":
            raise ValueError(f"{self.name}: segment integration reports the nominal pressure only (kind "
                             f"'nominal'), got kind {kind!r}; the pointwise quadratures give 'cauchy' too")
        p = self.segment_points()
        data = [np.concatenate(a) for a in zip(*self.comm.allgather((p["X"], p["x"], p["gap"], p["pressure"])))]
        order = np.lexsort(np.round(data[0], 12).T[::-1])
        return data[1][order], data[2][order], data[3][order]

    def total_force(self) -> np.ndarray:
        """Force of the master on the slave body, ``sum_q w_q F_q n_m`` (per unit thickness)."""
        p = self.segment_points()
        local = np.einsum("q,q,qj->j", p["weight"], p["pressure"], p["normal"]) if len(p["weight"]) else \
            np.zeros(self.gdim)
        return np.array(self.comm.allreduce(local))
