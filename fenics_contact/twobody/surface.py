"""Pointwise two-body contact (:class:`TwoBodySurface`): node-to-segment, Gauss-point-to-segment,
node-to-triangle; flat or quadratic (2D) facets.

The surface composes the parts of this package: the slave and master facets and the slave points
(:mod:`~.facets`), their pairing (:mod:`~.pairing`, :mod:`~.exchange`), the mirror fields the UFL gap is
written against (:mod:`~.mirror`), the coupling to the master dofs (:mod:`~.coupling`) and the figures at the
slave points (:mod:`~.report`).

Two-pass (:func:`factory.two_body_surfaces`): two surfaces, each side slave once, each with ``weight = 1/2``
(forces averaged); coinciding points of the two passes both stay on flat facets (each at weight 1/2:
together the one-pass force; leaving one out doubles the other's pressure); quadratic facets leave the
second-pass point out (node on node, ``exclude``). Two passes of multipliers are refused (:mod:`capabilities`).
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from ..capabilities import check, of
from ..contact import ContactSurface, contact_measure
from ..laws import ContactLaw
from ..search import small_sliding_warning
from .coupling import JacobianPattern, MirrorCoupling, dirichlet_columns
from .facets import SlavePoints, facet_pair
from .mirror import MirrorFields, MirrorObstacle
from .pairing import Pairing
from .report import PointReport, Timings

__all__ = ["PASSES", "QUADRATURES", "SLIDING", "TwoBodySurface"]

PASSES = ("one", "two")
SLIDING = ("finite", "small")  # the contact kinematics: current configuration, or linearized at the reference
QUADRATURES = ("nodal", "gauss", "segment")  # segment: segment-to-segment integration (:mod:`mortar`)


class TwoBodySurface(ContactSurface):
    """Contact of the slave facets ``slave_tag`` against the current master facets ``master_tag`` of the same
    mesh with the law ``law`` (pressure per reference slave area, > 0 in compression; gap > 0 penetration).

    Args:
        u: the problem's unknown (a displacement, or the mixed unknown of :mod:`multipliers`).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`~fenics_contact.domain.NamedTags`).
        slave_tag: the slave surface (a tag value, or a name of :class:`~fenics_contact.domain.NamedTags`).
        master_tag: the master surface (likewise).
        law: the contact law.
        load: the load parameter (a scalar Constant).
        quadrature: ``nodal`` or ``gauss`` on degree-1 facets; on quadratic facets (2D, curved 3-node) the slave
            points are the three nodes of each facet, ``nodal`` integrates with the end nodes only (the
            two-point element's constraint) and ``simpson`` with all three.
        weight: factor on the residual (1/2 for each surface of a two-pass pair).
        radius: search radius (default 2 x the longest master facet); farther points have no pair, no force.
        work_quadrature: the rule of the pressure's work term, if not ``quadrature`` (multipliers: ``simpson``
            with the constraint at the end nodes).
        name: the surface's name, in its error messages.
        exclude: (k, gdim) reference positions of slave points left without a pair (node on node).
        sliding: ``finite`` (the current configuration: pairing, normal and gap of the current facets, large
            sliding) or ``small`` (flat facets: the pair, its weights and the master normal of the reference
            configuration, the gap linear in the displacements: the kinematics of small strains, as the
            linear material's).
        self_contact: the surface ``slave_tag == master_tag`` against itself (finite sliding): each point paired
            with the rest of the surface beyond its own neighbourhood (:class:`~.pairing.Pairing`); with
            ``weight = 1/2`` every contact is counted from both sides, the unbiased two-pass form.

    Raises:
        ValueError: equal or absent tags, ``weight`` or ``radius`` not finite and > 0, a quadrature the facets
            do not take, ``sliding`` not in :data:`SLIDING`; ``capabilities.UnsupportedCombination`` for a
            refused combination.
    """

    ufl_coupling = True  # False: a subclass assembles residual and tangent itself (no coupling forms, no I)
    # The master exchange: "boxes" (to the ranks whose grown slave boxes a facet overlaps) or "allgather" (to every
    # rank; the same answers). The class attribute is also mortar.SegmentSurface's default.
    exchange = "boxes"

    def __init__(self, u: fem.Function, facet_tags, slave_tag: int, master_tag: int, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", weight: float = 1.0,
                 radius: float | None = None, name: str = "twobody", work_quadrature: str | None = None,
                 exclude: np.ndarray | None = None, sliding: str = "finite", self_contact: bool = False):
        if sliding not in SLIDING:
            raise ValueError(f"sliding must be one of {SLIDING}, got {sliding!r}")
        check(**of(law, u), kind="self" if self_contact else "two-body",  # before any assembly
              quadrature=work_quadrature or quadrature, sliding=sliding)
        mesh = u.function_space.mesh
        if not (np.isfinite(weight) and weight > 0):
            raise ValueError(f"weight must be a finite number > 0, got {weight!r}")
        self.comm = mesh.comm
        self.self_contact = self_contact
        self.slave_data, self.master_data = facet_pair(u, facet_tags, slave_tag, master_tag, name, self_contact)
        self.quadratic = self.slave_data.quadratic
        allowed = ("nodal", "simpson") if self.quadratic else ("nodal", "gauss")
        if quadrature not in allowed or (work_quadrature or quadrature) not in allowed:
            raise ValueError(f"contact quadrature must be one of {allowed} for degree-"
                             f"{2 if self.quadratic else 1} facets, got {quadrature!r} (work: {work_quadrature!r})")
        self.V, self.gdim, self.nv = u.function_space, mesh.geometry.dim, self.slave_data.nv
        self.points = SlavePoints(self.slave_data, quadrature, exclude)
        self.mirror = MirrorFields(mesh, self.slave_data, self.points, quadrature, name)
        self._seconds = Timings()
        self.sliding = sliding
        self.pairs = Pairing(self.comm, self.slave_data, self.master_data, self.points, radius, self._seconds, sliding,
                             self_contact)
        self.radius = self.pairs.radius
        self.report = PointReport(self.comm, self.slave_data, self.points, self.mirror.scalar_dofs)
        self._dirichlet = np.zeros(0, np.int64)  # global Dirichlet dofs, left out of I (bind_problem)
        self._problem = None  # the problem bound by bind_problem
        self._pattern = JacobianPattern()
        self.weight = fem.Constant(mesh, float(weight))
        m = self.mirror
        obstacle = MirrorObstacle(m.reference, m.displacement, m.active, self.nv, self.gdim, self.radius,
                                  m.local_coordinate, sliding)
        self.ds_work = contact_measure(mesh, facet_tags, slave_tag, work_quadrature or quadrature)
        super().__init__(u, facet_tags, slave_tag, obstacle, law, load, quadrature, name)
        self.coupling = None
        if self.ufl_coupling:  # the forms compiled once
            r_u = self.residual(ufl.TestFunction(self.V))
            r_w = self.master_residual(ufl.TestFunction(m.space))
            self.coupling = MirrorCoupling(u, m, r_u, r_w, self._seconds)
        self.update()

    # --- forms -------------------------------------------------------------------
    def _pressure(self):
        return self.obstacle.active * super()._pressure()

    def master_residual(self, vw: ufl.Argument) -> ufl.Form:
        """Master part on the mirror test function ``vw``: ``weight F(g) dg/dw[vw] ds`` (to the master dofs by
        ``I^T``)."""
        return (self.weight * self.ring * self.pressure * ufl.derivative(self.gap, self.mirror.displacement, vw)
                * self.ds_work)

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Slave part ``weight F(g) dg/du[v] ds``; the master part is :meth:`add_residual`."""
        return self.weight * self.ring * self.pressure * ufl.derivative(self.gap, self.u, v) * self.ds_work

    # --- pairing -------------------------------------------------------------------
    def update(self) -> bool:
        """Pair the slave points with the current master surface; set the mirror fields and ``I``. Collective.
        Returns True if the pairing changed."""
        changed = self.pairs.update(self.u.x.array, self.exchange == "allgather")
        if self.pairs.exploded:
            return False
        with self._seconds.measure("search_s"):
            self.mirror.fill(self.pairs.facet, self.pairs.master, self.pairs.local_coordinate)
        if changed:
            if self.coupling is not None:
                self.coupling.rebuild(self.pairs.facet, self.pairs.master["G"], self._dirichlet)
            self._pattern.version += 1
        return changed

    def pairing(self) -> np.ndarray:
        """The pairing the residual depends on (a copy, this rank's): the global facet number of the master facet
        of each local slave point (-1: none), flattened."""
        return self.pairs.ids.ravel().copy()

    @property
    def projection(self) -> dict | None:
        """The last pairing's ``facet``, ``bary``, ``distance``, ``gap`` and ``normal`` at the local slave points
        (nf, nq, ...) (:class:`~.pairing.Pairing`)."""
        return self.pairs.projection

    @property
    def exploded(self) -> bool:
        """The last update met a master facet stretched past :data:`search.STRETCH_LIMIT`."""
        return self.pairs.exploded

    def range_warning(self) -> str | None:
        """Small sliding past its range: a point within a facet size of closing slid more than
        :data:`~fenics_contact.search.SMALL_SLIDING` of its master facet's size (:meth:`.Pairing.slide`). Collective."""
        if self.sliding != "small":
            return None
        ratio = self.comm.allreduce(self.pairs.slide(self.u.x.array), op=MPI.MAX)
        return small_sliding_warning(ratio)

    @property
    def pairing_changes(self) -> int:
        """Updates that changed the pairing."""
        return self.pairs.changes

    def exchange_stats(self) -> dict:
        """This rank's master exchange: updates, bytes and master facets received from other ranks, seconds, and
        the bytes an all-gather of the whole master surface would have received."""
        return dict(self.pairs.exchange.stats)

    def take_failure(self) -> str | None:
        return self.pairs.take_failure()

    def timings(self) -> dict[str, float]:
        return dict(self._seconds)

    # --- solver hooks --------------------------------------------------------
    def bind_problem(self, problem) -> None:
        """Learn the Dirichlet dofs of ``problem``; they are left out of ``I``. Collective."""
        self._dirichlet = dirichlet_columns(self.V, self.comm, problem.bcs)
        self._problem = problem
        if self.coupling is not None:
            self.coupling.rebuild(self.pairs.facet, self.pairs.master["G"], self._dirichlet)
        self._pattern.version += 1

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
        self.coupling.add_residual(b)

    def coupling_matrices(self, bcs) -> tuple[PETSc.Mat, ...]:
        """The matrices whose sum is ``A_uw I + I^T A_wu + I^T A_ww I`` (Dirichlet rows and columns zero): the
        surface's own, valid until the next call."""
        return self.coupling.matrices(bcs)

    def pattern_changes(self) -> bool:
        return self._pattern.changed()

    def state(self) -> dict:
        return {**super().state(), "pattern": self._pattern.state()}

    def restore(self, state: dict) -> None:
        super().restore(state)
        self._pattern.restore(state.get("pattern"), self.comm)

    def add_jacobian(self, A: PETSc.Mat, bcs) -> bool:
        """``A += coupling``; returns True when ``A``'s nonzero pattern was rebuilt (pairing changed)."""
        C = self.coupling_matrices(bcs)  # first: a subclass's matrix may change the pattern (collocation)
        return self._pattern.add(A, C)

    # --- figures -------------------------------------------------------------
    def _point_pressure(self, g: np.ndarray) -> np.ndarray:
        """The pressure at the slave points (nf, nq) from their gaps ``g`` (0 where unpaired)."""
        return self.report.law_pressure(self.law, self.constants, self.fields, g, self.radius,
                                        self.quadratic and self.quadrature == "nodal")

    def _point_area_ratio(self) -> np.ndarray:
        """``da/dA`` of the slave surface at the slave points (nf, nq): the bound material's area ratio
        (:meth:`ContactSurface.area_ratio`) projected on the surface space, as the law's fields."""
        if not hasattr(self, "_ratio_rhs"):
            self._ratio_rhs = self.projector.compile(self.area_ratio())
            self._ratio = fem.Function(self.S)
        self.projector.project(self._ratio_rhs, self._ratio)
        return self.report.field_values(self._ratio)

    def point_table(self, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Reference position, current position, gap (> 0 penetration; ``-inf`` unpaired) and pressure (> 0
        compression; 0 unpaired) at the slave points of the owned slave facets, gathered on every rank and
        sorted by reference position (a node shared by two facets once). ``kind``: ``nominal`` (per reference
        slave area) or ``cauchy`` (per current slave area: nominal ``/ (da/dA)``). Collective."""
        self._check_kind(kind)
        g = self.projection["gap"]
        p = self._point_pressure(g)
        if kind == "cauchy":
            p = p / self._point_area_ratio()
        return self.report.table(self.points.current(self.u.x.array), g, p)

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Position (current; ``reference=True``: reference), gap and pressure (``kind``: ``nominal`` or
        ``cauchy``) at the slave points: :meth:`point_table` without the other position. Collective."""
        X, x, g, p = self.point_table(kind)
        return (X if reference else x), g, p

    def reference_points(self) -> np.ndarray:
        """Reference positions of all slave points (every rank's, on every rank). Collective."""
        return self.report.reference_points()

    # --- names other modules use (collocation.py, multipliers.py, factory.py) -------------------------
    @property
    def B(self) -> np.ndarray:
        """Values at the slave points of nodal values on a slave facet (:attr:`SlavePoints.at_points`)."""
        return self.points.at_points

    @property
    def _excluded(self) -> np.ndarray:
        return self.points.excluded

    @property
    def _bc_array(self) -> np.ndarray:
        return self._dirichlet
