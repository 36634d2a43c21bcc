"""Two-body contact with segment-to-segment integration (:class:`SegmentSurface`), 2D and 3D.

The surface composes :mod:`twobody`'s parts at the slave vertices (facets, pairing, master exchange, mirror
fields: the nodal state that the law's fields, the augmentation and the outputs use) with the facet pairs
(:mod:`~.pairs`) and the element (:mod:`~.element`). Each rank integrates its *owned* slave facets (each
once) against the master facets :class:`twobody.MasterExchange` brings; the entries go to PETSc with global
indices (``ADD``; the assembly moves off-process entries), so a master facet on another rank is a column.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from petsc4py import PETSc

from ..capabilities import check, of
from ..contact import ContactSurface, is_mixed
from ..laws import ContactLaw
from ..search import STRETCH_LIMIT, stretch
from ..sparse import aij_matrix
from ..twobody.coupling import JacobianPattern, dirichlet_columns
from ..twobody.facets import SlavePoints, facet_pair
from ..twobody.mirror import MirrorFields, MirrorObstacle
from ..twobody.pairing import Pairing
from ..twobody.report import Timings
from ..twobody.surface import TwoBodySurface
from .element import reference_measure, segment_element, triangle_element
from .pairs import SegmentPairs

__all__ = ["SegmentSurface"]


def _same(a: tuple, b: tuple) -> bool:
    """Whether two element inputs ``(x, scalars, fields, weight, dofs)`` are equal (arrays exactly)."""
    xa, sa, fa, wa, da = a
    xb, sb, fb, wb, db = b
    return (wa == wb and sa == sb and xa.shape == xb.shape and np.array_equal(xa, xb) and np.array_equal(da, db)
            and fa.keys() == fb.keys() and all(np.array_equal(fa[k], fb[k]) for k in fa))


class SegmentSurface(ContactSurface):
    """Contact of the slave facets ``slave_tag`` against the current master facets ``master_tag`` of the same
    mesh, integrated segment to segment (``quadrature="segment"``; flat facets: segments, triangles), with the
    law ``law`` (pressure per reference slave area, > 0 in compression; gap > 0 penetration).

    Args and errors as :class:`twobody.TwoBodySurface` (``u`` a displacement: a mixed unknown raises
    ValueError). The law's fields live at the slave vertices, interpolated linearly at the sub-segment points.

    Args:
        u: the displacement.
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        slave_tag: the slave surface: a tag value, or a region name of ``facet_tags``.
        master_tag: the master surface (likewise).
        law: the contact law.
        load: the load parameter ``t`` (a scalar ``Constant``).
        weight: factor on the residual (1/2 for each surface of a two-pass pair).
        radius: the search radius (length; default twice the longest master facet); farther points have no pair.
        name: the surface's name, in messages and output.
    """

    ring_weighted = False  # its own integrals (nodal weights, NumPy element) carry no 2 pi r

    exchange: str | None = None  # the master exchange (see TwoBodySurface); None: TwoBodySurface.exchange's

    def __init__(self, u: fem.Function, facet_tags, slave_tag: int, master_tag: int, law: ContactLaw,
                 load: fem.Constant, weight: float = 1.0, radius: float | None = None, name: str = "twobody"):
        if is_mixed(u.function_space):
            raise ValueError("contact quadrature 'segment' needs a displacement unknown (not a mixed space)")
        check(**of(law, u), kind="two-body", quadrature="segment")  # before any assembly
        mesh = u.function_space.mesh
        if not (np.isfinite(weight) and weight > 0):
            raise ValueError(f"weight must be a finite number > 0, got {weight!r}")
        self.comm = mesh.comm
        self.slave_data, self.master_data = facet_pair(u, facet_tags, slave_tag, master_tag, name)
        self.V, self.gdim, self.nv = u.function_space, mesh.geometry.dim, self.slave_data.nv
        # The nodal state: the points at the slave vertices.
        self.points = SlavePoints(self.slave_data, "nodal")
        self.mirror = MirrorFields(mesh, self.slave_data, self.points, "nodal", name)
        self._seconds = Timings()
        self.pairs = Pairing(self.comm, self.slave_data, self.master_data, self.points, radius, self._seconds)
        self.radius = self.pairs.radius
        self._dirichlet = np.zeros(0, np.int64)  # global Dirichlet dofs, left out of the tangent (bind_problem)
        self._problem = None
        self._pattern = JacobianPattern()
        self._tangent: PETSc.Mat | None = None  # the last coupling_matrices
        self.weight = fem.Constant(mesh, float(weight))
        m = self.mirror
        obstacle = MirrorObstacle(m.reference, m.displacement, m.active, self.nv, self.gdim, self.radius)
        super().__init__(u, facet_tags, slave_tag, obstacle, law, load, "nodal", name)
        self.quadrature = "segment"
        self.segments = SegmentPairs(self.comm)
        self._element_cache = None  # (inputs, (residuals, tangents)) of the last element evaluation
        self._J = reference_measure(self.slave_data.X)
        self.update()

    def _pressure(self):
        return self.obstacle.active * super()._pressure()

    def residual(self, v):
        return None  # everything is in add_residual / add_jacobian

    # --- pairing -------------------------------------------------------------
    def update(self) -> bool:
        """The nodal pairing (state, outputs) and the sub-segment pairs of the owned slave facets. Collective.
        Returns True if either changed."""
        everywhere = (self.exchange or TwoBodySurface.exchange) == "allgather"
        changed = self.pairs.update(self.u.x.array, everywhere)
        if not self.pairs.exploded:
            with self._seconds.measure("search_s"):
                self.mirror.fill(self.pairs.facet, self.pairs.master, None)
            if changed:
                self._pattern.version += 1
        xs = self.slave_data.current(self.u.x.array)
        # Slave facets are local: an exploded slave facet on any rank rejects the iterate on every rank.
        if self.pairs.reject(stretch(xs, self.slave_data.X) > STRETCH_LIMIT):
            return False
        segments_changed = self.segments.update(xs, self.slave_data.owned, self.pairs.master, self.radius)
        if segments_changed:
            self._pattern.version += 1
        return changed or segments_changed

    def pairing(self) -> np.ndarray:
        """The point pairs (:meth:`twobody.TwoBodySurface.pairing`) followed by the (slave facet, master facet)
        pairs of the sub-segments, flattened."""
        return np.concatenate([self.pairs.ids.ravel().copy(), self.segments.ids.ravel()])

    @property
    def projection(self) -> dict | None:
        """The nodal pairing's ``facet``, ``bary``, ``distance``, ``gap`` and ``normal`` at the local slave vertices
        (:class:`twobody.Pairing`)."""
        return self.pairs.projection

    @property
    def exploded(self) -> bool:
        """The last update met a facet stretched past :data:`search.STRETCH_LIMIT`."""
        return self.pairs.exploded

    @property
    def pairing_changes(self) -> int:
        """Updates that changed the nodal pairing."""
        return self.pairs.changes

    def exchange_stats(self) -> dict:
        """This rank's master exchange (:meth:`twobody.TwoBodySurface.exchange_stats`)."""
        return dict(self.pairs.exchange.stats)

    def take_failure(self) -> str | None:
        return self.pairs.take_failure()

    def timings(self) -> dict[str, float]:
        """Seconds by kind; ``coupling_s``: the element evaluations and their assembly."""
        return dict(self._seconds)

    def _elements(self, points: bool = False):
        """Element residuals, tangents and global dof indices (n, 2 nv gdim) of the current sub-segments."""
        sd, seg = self.slave_data, self.segments
        f, m = seg.pairs[:, 0], seg.pairs[:, 1]
        x = np.concatenate([sd.current(self.u.x.array)[f], seg.master_x[m]], axis=1)
        scalars = {k: float(c.value) for k, c in self.constants.items()}
        fields = {k: fn.x.array[self.mirror.scalar_dofs[f]] for k, fn in self.fields.items()}
        weight = float(self.weight.value)
        k = self.nv * self.gdim
        dofs = np.concatenate([sd.global_comp[f].reshape(-1, k), seg.master_dofs[m].reshape(-1, k)], axis=1)
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
    def bind_problem(self, problem) -> None:
        """Learn the Dirichlet dofs of ``problem``; their rows and columns are left out of the tangent."""
        self._dirichlet = dirichlet_columns(self.V, self.comm, problem.bcs)
        self._problem = problem
        self._pattern.version += 1

    def prepare(self, problem) -> None:
        """Before each residual evaluation (``u`` current): re-pair."""
        if self._problem is not problem:
            self.bind_problem(problem)
        self.update()

    def add_residual(self, b: PETSc.Vec) -> None:
        """Add the element residuals (slave and master rows). An exploded iterate gets a non-finite residual:
        the solve fails and the step is cut (:data:`search.STRETCH_LIMIT`)."""
        if self.exploded:
            b.set(np.nan)
            return
        with self._seconds.measure("coupling_s"):
            (r, _), dofs = self._elements()
            if len(r):
                keep = dofs.ravel() >= 0  # -1: no dof (an element with fewer entries)
                b.setValues(dofs.ravel()[keep].astype(PETSc.IntType), r.ravel()[keep],
                            addv=PETSc.InsertMode.ADD_VALUES)
        b.assemblyBegin()
        b.assemblyEnd()

    def coupling_matrices(self, bcs) -> tuple[PETSc.Mat]:
        """The whole contact tangent (slave and master rows and columns; Dirichlet rows and columns zero): the
        surface's own matrix (alone in the tuple), valid until the next call."""
        with self._seconds.measure("coupling_s"):
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
        if self._tangent is not None:
            self._tangent.destroy()
        self._tangent = aij_matrix(self.comm, ((n_local, N),) * 2, rows, cols, vals)
        return (self._tangent,)

    def pattern_changes(self) -> bool:
        return self._pattern.changed()

    def state(self) -> dict:
        return {**super().state(), "pattern": self._pattern.state()}

    def restore(self, state: dict) -> None:
        super().restore(state)
        self._pattern.restore(state.get("pattern"), self.comm)

    def add_jacobian(self, A: PETSc.Mat, bcs) -> bool:
        """``A += tangent``; returns True when ``A``'s nonzero pattern was rebuilt (pairs changed)."""
        return self._pattern.add(A, self.coupling_matrices(bcs))

    # --- figures ---------------------------------------------------------------
    def segment_points(self) -> dict:
        """Sub-segment Gauss points of the owned slave facets (local): reference and current position ``X``,
        ``x`` (n, gdim), ``weight`` (reference length or area, without the two-pass factor), ``gap`` (> 0
        penetration), ``pressure`` (> 0 compression, per reference area), master unit ``normal`` (n, gdim)."""
        d = self.gdim
        if len(self.segments.pairs) == 0:
            z = np.zeros((0, d))
            return {"X": z, "x": z, "weight": np.zeros(0), "gap": np.zeros(0), "pressure": np.zeros(0), "normal": z}
        (_, _, pts), _ = self._elements(points=True)
        f = self.segments.pairs[pts["pair"], 0]
        N = pts["N"]
        X = np.einsum("qa,qaj->qj", N, self.slave_data.X[f])
        x = np.einsum("qa,qaj->qj", N, self.slave_data.current(self.u.x.array)[f])
        return {"X": X, "x": x, "weight": pts["weight"], "gap": pts["gap"], "pressure": pts["pressure"],
                "normal": pts["normal"]}

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Position (current; ``reference=True``: reference), gap (> 0 penetration) and nominal pressure (> 0
        compression, per reference slave area) at every sub-segment Gauss point, gathered on every rank and
        sorted by reference position. Collective.

        Raises:
            ValueError: ``kind`` is not ``nominal`` (the pointwise quadratures give ``cauchy`` too).
        """
        if kind != "nominal":
            raise ValueError(f"{self.name}: segment integration reports the nominal pressure only (kind "
                             f"'nominal'), got kind {kind!r}; the pointwise quadratures give 'cauchy' too")
        p = self.segment_points()
        data = [np.concatenate(a) for a in zip(*self.comm.allgather((p["X"], p["x"], p["gap"], p["pressure"])))]
        order = np.lexsort(np.round(data[0], 12).T[::-1])
        return data[0 if reference else 1][order], data[2][order], data[3][order]

    def total_force(self) -> np.ndarray:
        """Force of the master on the slave body, ``sum_q w_q F_q n_m`` (global components; per unit thickness
        in 2D), the same on every rank. Collective."""
        p = self.segment_points()
        local = np.einsum("q,q,qj->j", p["weight"], p["pressure"], p["normal"]) if len(p["weight"]) else \
            np.zeros(self.gdim)
        return np.array(self.comm.allreduce(local))

    @property
    def _segment_pairs(self) -> np.ndarray:  # scripts/segment_cost.py counts them
        return self.segments.pairs
