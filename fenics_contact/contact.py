"""A contact surface against a rigid obstacle: the one place a law becomes UFL.

``ContactSurface`` ties a law (:mod:`laws`), an obstacle (:mod:`obstacles`)
and a tagged part of the boundary. It owns the contact measure (nodal or
Gauss quadrature), the law's parameters as ``Constant`` (scalars) and
``Function`` (fields, on a space whose dofs sit at the quadrature points),
the UFL surface term ``F(g) dg[v]`` and the augmentation update.
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .closed_area import closed_measure
from .compat import (
    collapse,
    entities_to_geometry,
    facet_cell_name,
    function_space,
    interpolate_expression,
    petsc_vec,
    space_degree,
)
from .domain import check_tags, tag_value
from .laws import ContactLaw, ufl_ops
from .obstacles import Obstacle
from .projection import LumpedProjector, SurfaceProjector
from .surface import Surface

__all__ = ["QUADRATURES", "PRESSURE_KINDS", "contact_measure", "is_mixed", "displacement", "check_facet_tag",
           "ContactSurface"]

QUADRATURES = ("nodal", "gauss", "simpson")
PRESSURE_KINDS = ("nominal", "cauchy")  # per reference area, per current area

# Reference-facet vertex rules (trapezoid and its 2D analogues) by facet cell name.
_VERTEX_RULES = {
    "interval": (((0.0,), (1.0,)), (0.5, 0.5)),
    "triangle": (((0.0, 0.0), (1.0, 0.0), (0.0, 1.0)), (1 / 6,) * 3),
    "quadrilateral": (((0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)), (0.25,) * 4),
}


# Simpson's rule on a segment: the two vertices and the midpoint (the nodes of a P2 facet).
_SIMPSON = (((0.0,), (0.5,), (1.0,)), (1 / 6, 4 / 6, 1 / 6))


def contact_measure(mesh, facet_tags, tag: int | str, quadrature: str) -> ufl.Measure:
    """``ds`` on the tagged facets (``tag``: a value, or a name of :class:`domain.NamedTags`) with the vertex
    rule (``nodal``), the degree-2 Gauss rule, or Simpson's rule (``simpson``, 2D: the three nodes of a quadratic
    facet).

    Args:
        mesh: the mesh.
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: a tag value, or a region name of ``facet_tags``.
        quadrature: ``nodal``, ``gauss`` or ``simpson``.

    Returns:
        The ``ufl.Measure``.
    """
    facet_tags, tag = tag_value(facet_tags, tag)
    if quadrature == "simpson":
        if mesh.topology.dim != 2:
            raise ValueError("contact quadrature 'simpson' is for 2D meshes (segment facets)")
        pts, wts = _SIMPSON
        md = {"quadrature_rule": "custom", "quadrature_degree": 3,
              "quadrature_points": pts, "quadrature_weights": wts}
    elif quadrature == "nodal":
        facet_cell = facet_cell_name(mesh)
        pts, wts = _VERTEX_RULES[facet_cell]
        md = {"quadrature_rule": "custom", "quadrature_degree": 1,
              "quadrature_points": pts, "quadrature_weights": wts}
    elif quadrature == "gauss":
        md = {"quadrature_degree": 2}
    else:
        raise ValueError(f"contact quadrature must be one of {QUADRATURES}, got {quadrature!r}")
    return ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags, subdomain_id=tag, metadata=md)


def is_mixed(V) -> bool:
    """True for a mixed (displacement, pressure) space (the contact pressure of :mod:`multipliers`, or the bulk
    pressure of :class:`~fenics_contact.materials.MixedNeoHookean`), False for a displacement space."""
    return V.num_sub_spaces > 0 and V.sub(0).num_sub_spaces > 0


def displacement(w):
    """The displacement part of an unknown or test/trial function: ``w`` itself, or its first
    component when ``w`` lives on a mixed (displacement, pressure) space."""
    V = w.function_space if hasattr(w, "function_space") else w.ufl_function_space()
    return ufl.split(w)[0] if is_mixed(V) else w


def check_facet_tag(mesh, facet_tags, tag: int | str, name: str) -> np.ndarray:
    """Local facets with ``tag`` (a value, or a name of :class:`domain.NamedTags`); raise ``ValueError`` naming
    ``name`` if no rank has any."""
    facet_tags, tag = tag_value(facet_tags, tag)
    if facet_tags is None or facet_tags.dim != mesh.topology.dim - 1:
        raise ValueError(f"{name}: the mesh has no facet tags (need facets of dimension {mesh.topology.dim - 1})")
    check_tags(facet_tags, {name: tag}, mesh.comm)
    return facet_tags.indices[facet_tags.values == tag]


class ContactSurface(Surface):
    """Contact of the tagged boundary ``tag`` of the body with displacement ``u`` against ``obstacle``.

    The current position is ``x = X + u`` (also for linear elasticity, so a
    curved obstacle is followed exactly). ``linearized=True``: the
    small-displacement gap ``g(X) - n(X) . u`` with the normal at the
    reference point instead (the classical Signorini problem; homogeneous in
    ``u`` for an initially touching contact). ``load`` is the scalar
    ``Constant`` that moves the obstacle. ``u`` is the problem's unknown: the displacement,
    or a mixed (displacement, pressure) Function (:mod:`multipliers`).

    Why one class of this size: it is the base of every enforcement on a contact surface (the gap, the law's
    parameters as Constants and fields, the output fields and the results all share its measure and state
    space); the parts of one job each (projection, measure) are composed from :mod:`projection`.

    Args:
        u: the problem's unknown: the displacement, or the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: the contact law.
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: the surface's rule: ``nodal``, ``gauss`` or ``simpson`` (the capability grid says which).
        name: the surface's name, in messages and output.
        linearized: the small-displacement gap ``g(X) - n(X) . u`` (normal at the reference point) instead of the
            gap of the current position ``X + u``.
    """

    material = None  # the bulk material next to the surface (bind_material): its da/dA gives the Cauchy pressure
    ring_weighted = True  # every integral of the surface carries self.ring

    def __init__(self, u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False):
        mesh = u.function_space.mesh
        self.name, self.u, self.law, self.obstacle, self.quadrature = name, u, law, obstacle, quadrature
        self.facets = check_facet_tag(mesh, facet_tags, tag, name)
        self.ds = contact_measure(mesh, facet_tags, tag, quadrature)
        # The factor of every integral over the surface: 1, or 2 pi r on an axisymmetric body (_fill_ring). A
        # Function, so that forms compiled before the bulk material is bound (the two-body couplings) weight by
        # the ring too; the projections stay unweighted (a node on the axis has r = 0).
        Vu = u.function_space.sub(0) if is_mixed(u.function_space) else u.function_space
        self.ring = fem.Function(function_space(mesh, "Lagrange", space_degree(Vu)), name="ring")
        self.ring.x.array[:] = 1.0
        obstacle.bind(load)
        self.displacement_out = u  # the displacement Function for output (a collapsed copy if u is mixed)
        if is_mixed(u.function_space):
            Vd, self._v_to_w = collapse(u.function_space.sub(0))
            self.displacement_out = fem.Function(Vd, name="displacement")
        X = ufl.SpatialCoordinate(mesh)
        if linearized:  # first order in u: dg/du = -n (n points from the obstacle into the body)
            self.normal = obstacle.normal(X)
            self.gap = obstacle.gap(X) - ufl.dot(self.normal, displacement(u))
        else:
            self.gap = obstacle.gap(X + displacement(u))
            self.normal = obstacle.normal(X + displacement(u))

        # Law parameters: scalars as Constants, fields at the quadrature points.
        # One state dof per quadrature point on each facet (see projection.py).
        self.S = function_space(mesh, *{"nodal": ("Lagrange", 1), "gauss": ("DG", 1),
                                        "simpson": ("Lagrange", 2)}[quadrature])
        self.constants = {k: fem.Constant(mesh, float(v)) for k, v in law.scalars.items()}
        self.fields = {}
        for k, v in law.fields.items():
            f = fem.Function(self.S, name=k)
            f.x.array[:] = v
            self.fields[k] = f
        self.params = {**self.constants, **self.fields}
        self.pressure = self._pressure()

        self.projector = SurfaceProjector(self.S, self.ds)
        self._gap_rhs = self.projector.compile(self.gap)
        self._aug_rhs = {k: self.projector.compile(e)
                         for k, e in law.augment_fields(self.gap, self.params, ufl_ops()).items()}
        self._gap_now = fem.Function(self.S)
        self._gap_prev = None
        self._force_forms = [fem.form(self.pressure * self.normal[i] * self.ring * self.ds)
                             for i in range(mesh.geometry.dim)]
        self._area_form = fem.form(self.ring * self.ds)
        self._mean_p_form = fem.form(self.pressure * self.ring * self.ds)
        self.comm = mesh.comm

        # Output: nodal values of gap and pressure on P1, for XDMF and the figures. The gap at the vertices; the
        # pressure of a law enforced at Gauss points as their weighted mean around each vertex (LumpedProjector):
        # the law evaluated at a vertex, where nothing enforces it, gives a peak of 3D Hertz 25 % high.
        P1 = function_space(mesh, "Lagrange", 1)
        self._out = self.projector if quadrature == "nodal" else SurfaceProjector(
            P1, contact_measure(mesh, facet_tags, tag, "nodal"))
        self._recover = LumpedProjector(P1, self.ds) if quadrature == "gauss" else self._out
        self.gap_out = fem.Function(P1, name="gap")
        self.pressure_out = fem.Function(P1, name="contact_pressure")
        self._out_rhs = [(self._out.compile(self.gap), self.gap_out)]
        self._pressure_rhs = self._recover.compile(self.pressure)

    def _pressure(self) -> ufl.core.expr.Expr:
        return self.law.force(self.gap, self.params, ufl_ops())

    # --- hooks of the solver (see :class:`~fenics_contact.surface.Surface`) ------------
    @property
    def augmentable(self) -> bool:
        """The law's ``augmentable``, True when it has augmentable fields (augmented Lagrangian, Uzawa)."""
        return self.law.augmentable

    # --- forms -----------------------------------------------------------
    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Surface term ``F(g) dg[v] ds`` of the residual (``dg[v] = -n . v`` for a rigid obstacle; axisymmetric:
        ``ds`` weighted by ``2 pi r``)."""
        return self.pressure * ufl.derivative(self.gap, self.u, v) * self.ring * self.ds

    # --- state -----------------------------------------------------------
    def state(self) -> dict:
        """A copy of the augmentable state (field arrays, scalar values)."""
        return {"fields": {k: f.x.array.copy() for k, f in self.fields.items()},
                "constants": {k: float(c.value) for k, c in self.constants.items()},
                "gap_prev": None if self._gap_prev is None else self._gap_prev.copy()}

    def restore(self, state: dict) -> None:
        for k, a in state["fields"].items():
            self.fields[k].x.array[:] = a
        for k, v in state["constants"].items():
            self.constants[k].value = v
        self._gap_prev = None if state["gap_prev"] is None else state["gap_prev"].copy()

    def constraint_change(self) -> float:
        """``R = sqrt(sum (g_new - g_old)^2)`` over the state dofs since the last call (inf first).

        Nodal quadrature: the dofs are the quadrature-point values. Gauss: the
        DG1 vertex values, a fixed invertible map of the Gauss-point values."""
        self.projector.project(self._gap_rhs, self._gap_now)
        now = petsc_vec(self._gap_now)
        R = np.inf
        if self._gap_prev is not None:
            R = float(np.sqrt(self.comm.allreduce(np.sum((self._owned(now.array) - self._owned(self._gap_prev)) ** 2))))
        self._gap_prev = now.array.copy()
        return R

    def forget_gap(self) -> None:
        """Start a new augmentation sequence (a new load step)."""
        self._gap_prev = None

    def augment(self) -> None:
        """One augmentation (Box 1 / Uzawa): fields from the converged gap, then scalars."""
        new = {k: self.projector.project(rhs, fem.Function(self.S)) for k, rhs in self._aug_rhs.items()}
        for k, f in new.items():
            self.fields[k].x.array[:] = f.x.array
        for k, v in self.law.augment_scalars({k: float(c.value) for k, c in self.constants.items()}).items():
            self.constants[k].value = v

    def _owned(self, a: np.ndarray) -> np.ndarray:
        n = self.S.dofmap.index_map.size_local * self.S.dofmap.index_map_bs
        return a[:n]

    # --- per-iteration status (failure detection, see fenics_contact.solver) -------------
    def closed_points(self) -> np.ndarray:
        """Flags ``g > 0`` (closed) at this rank's contact points (owned state dofs on the surface), at the
        current ``u``. Nodal quadrature: one flag per contact vertex; Gauss: per DG1 dof (Gauss point map)."""
        if not hasattr(self, "_gap_status"):
            self._gap_status = fem.Function(self.S)
        self.projector.project(self._gap_rhs, self._gap_status)
        return self._gap_status.x.array[self.projector.surface_dofs] > 0.0

    # --- pressures: nominal (per reference area) and Cauchy (per current area) ---------------------------
    def bind_material(self, material) -> None:
        """The bulk material next to the surface (:class:`~fenics_contact.problem.ContactProblem` binds its
        own unless the surface has one): its area ratio ``da/dA`` turns nominal pressures into Cauchy ones; an
        axisymmetric material weights every integral of the surface by ``2 pi r`` (:attr:`ring`)."""
        if self.material is None:
            self.material = material
        if getattr(self.material, "axisymmetric", False):
            self._fill_ring()

    def _fill_ring(self) -> None:
        """:attr:`ring` of an axisymmetric body: ``2 pi r`` (Gauss points); for the nodal rules (vertex,
        Simpson) its nodal values ``int phi_i 2 pi r ds / int phi_i ds``, so that the rule's weight of node ``i``
        times them is the row sum ``int phi_i 2 pi r ds`` of the weighted surface mass (a uniform pressure
        then gives the bulk's consistent nodal forces: the patch test; the node on the axis keeps its share)."""
        x = ufl.SpatialCoordinate(self.ring.function_space.mesh)
        self.ring.interpolate(lambda X: 2 * np.pi * X[0])
        if self.quadrature in ("nodal", "simpson"):
            ds = self.ds.reconstruct(metadata={"quadrature_degree": 4})
            phi = ufl.TestFunction(self.ring.function_space)
            sums = []
            for f in (2 * np.pi * x[0], 1.0):
                b = fem_petsc.assemble_vector(fem.form(f * phi * ds))
                b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
                b.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
                with b.localForm() as loc:
                    sums.append(loc.array.copy())
                b.destroy()
            on = sums[1] > 0
            self.ring.x.array[on] = sums[0][on] / sums[1][on]
        self.ring.x.scatter_forward()

    def _check_kind(self, kind: str) -> None:
        if kind not in PRESSURE_KINDS:
            raise ValueError(f"pressure kind must be one of {PRESSURE_KINDS}, got {kind!r}")
        if kind == "cauchy" and self.material is None:
            raise ValueError(f"{self.name}: the Cauchy pressure needs the bulk material (bind_material, or build "
                             "the ContactProblem first)")

    def area_ratio(self) -> ufl.core.expr.Expr:
        """``da/dA`` on the surface (Nanson, ``J |F^-T N|``; 1 for a small-strain material)."""
        N = ufl.FacetNormal(self.u.function_space.mesh)
        return self.material.area_ratio(displacement(self.u), N)

    def _cauchy_forms(self) -> None:
        if not hasattr(self, "_current_area_form"):
            ratio = self.area_ratio()
            self._current_area_form = fem.form(ratio * self.ring * self.ds)
            self.pressure_cauchy_out = fem.Function(self.pressure_out.function_space, name="contact_pressure_cauchy")
            self._cauchy_rhs = self._recover.compile(self.pressure / ratio)

    def point_forces(self) -> tuple[np.ndarray, np.ndarray]:
        """Coordinates and nodal contact forces ``F(g_i) int phi_i ds`` (per unit thickness in 2D) of this
        rank's contact vertices at the current ``u`` (nodal quadrature only, where they are exact): the
        nominal pressure times the vertex's reference area, a force (no kind). Collective."""
        if self.quadrature != "nodal":
            raise ValueError("point_forces needs quadrature 'nodal' (one contact point per vertex)")
        if not hasattr(self, "_weights"):
            b = fem_petsc.assemble_vector(self.projector.compile(self.ring))
            b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
            self._weights = b.array[self.projector.surface_dofs].copy()  # int phi_i ds
            b.destroy()
            self._p_now = fem.Function(self.S)
            self._p_rhs = self.projector.compile(self.pressure)
        self.projector.project(self._p_rhs, self._p_now)
        dofs = self.projector.surface_dofs
        return self.S.tabulate_dof_coordinates()[dofs], self._p_now.x.array[dofs] * self._weights

    # --- results (see :class:`~fenics_contact.surface.Surface`) ---------------------
    def total_force(self) -> np.ndarray:
        """Force of the obstacle on the body, ``int F n ds`` (the normal contact force; a frictional surface's
        friction force is its ``tangential_force``), shape ``(gdim,)``, per unit thickness in 2D; axisymmetric:
        ``int F n 2 pi r ds``, component 1 the axial force on the whole ring (component 0 the radial sum, no
        resultant); the same on every rank. Collective."""
        return np.array([self.comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM) for f in self._force_forms])

    def update_output(self) -> None:
        """Nodal gap and pressure into ``gap_out`` and ``pressure_out`` (and a mixed unknown's displacement into
        ``displacement_out``). Collective."""
        if self.displacement_out is not self.u:
            self.displacement_out.x.array[:] = self.u.x.array[self._v_to_w]
        for rhs, f in self._out_rhs:
            self._out.project(rhs, f)
        self._recover.project(self._pressure_rhs, self.pressure_out)

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Position, gap and pressure at the contact-surface vertices, gathered on every rank and sorted by
        reference position. Collective.

        Args:
            reference: the reference position ``X`` instead of the current one ``X + u(X)``.
            kind: ``nominal`` (per reference area, default) or ``cauchy`` (per current area: nominal
                ``/ (da/dA)``; the same in small strain).

        Returns:
            ``x`` (n, gdim), the gap ``g`` (n,) (> 0 penetration) and the pressure ``p`` (n,) (> 0 compression)
            at the vertices (their nodal values; Gauss quadrature: the pressure is the weighted mean of its
            Gauss-point values around the vertex, :class:`~fenics_contact.projection.LumpedProjector`).
        """
        X, g, p, *u = self._vertex_table(kind, current=not reference)
        x = X[:, :self.u.function_space.mesh.geometry.dim]
        return (x if reference else x + u[0]), g, p

    def _vertex_table(self, kind: str = "nominal", current: bool = False) -> tuple[np.ndarray, ...]:
        """Reference coordinates (n, 3) as dolfinx tabulates them, gap and pressure (``kind``) at the
        contact-surface vertices and, if ``current``, the displacement (n, gdim) there, gathered on every rank
        and sorted by reference coordinates. :meth:`contact_zones` and :meth:`max_penetration` read these vertex
        values of the output fields on every surface, also on a two-body one whose points are its own."""
        self._check_kind(kind)
        self.update_output()
        pressure = self.pressure_out
        if kind == "cauchy":
            self._cauchy_forms()
            self._recover.project(self._cauchy_rhs, self.pressure_cauchy_out)
            pressure = self.pressure_cauchy_out
        V = self.gap_out.function_space
        dofs = self._out.surface_dofs
        x = V.tabulate_dof_coordinates()[dofs]
        local = (x, self.gap_out.x.array[dofs], pressure.x.array[dofs])
        if current:
            local += (self._vertex_displacement()[dofs],)
        data = [np.concatenate(a) for a in zip(*self.comm.allgather(local))]
        order = np.lexsort(data[0].T[::-1])
        return tuple(a[order] for a in data)

    def _vertex_displacement(self) -> np.ndarray:
        """The displacement at the dofs of the output space (P1: its vertex values), (n_dofs, gdim)."""
        if not hasattr(self, "_u_vertex"):
            gdim = self.u.function_space.mesh.geometry.dim
            self._u_vertex = [fem.Function(self.gap_out.function_space) for _ in range(gdim)]
        u = displacement(self.u)
        return np.stack([interpolate_expression(f, u[i]).x.array for i, f in enumerate(self._u_vertex)], axis=1)

    def contact_zones(self, relative: float = 1e-3) -> list[dict]:
        """Connected sets of loaded contact vertices along the surface (vertices of a common facet are
        connected), the same on every rank. Loaded: pressure above ``relative`` times the largest on the
        surface (not ``g > 0``: a law with an open-side branch carries load at a small opening). For each
        zone the number of points, the mean and range of their reference coordinates and the largest
        pressure, sorted by the mean x. Collective."""
        x, _, p = self._vertex_table()
        return _loaded_zones(x, p, self._facet_nodes(), relative)

    def _facet_nodes(self) -> np.ndarray:
        """The coordinates of the geometry nodes of every rank's contact facets (nf, nodes, 3), on every rank."""
        mesh = self.u.function_space.mesh
        fdim = mesh.topology.dim - 1
        mesh.topology.create_connectivity(fdim, 0)
        nodes = mesh.geometry.x[entities_to_geometry(mesh, fdim, self.facets)] if len(self.facets) else np.zeros(
            (0, fdim + 1, 3))
        return np.concatenate(self.comm.allgather(nodes))

    def contact_area(self, tolerance: float = 1e-8) -> float:
        """The closed part of the surface from the gap (:mod:`~fenics_contact.closed_area`): the measure, on the
        reference surface, of the set where the gap, linear between the vertices of each facet, is ``>= -tolerance
        L`` (``L``: the surface's extent; exact methods close to round-off). A length in 2D (the contact width; a
        symmetric half model's: the half-width), an area in 3D; axisymmetric: the length along the meridian (a
        flat contact's radius), not the ring's area. It ends where the gap crosses zero, between the last closed
        vertex and the first open one; the loaded vertices (``p > 0``, :meth:`contact_zones`) overstate it by up to
        an element where a Gauss rule's pressure, recovered at the vertices, spills onto the first open one.
        Collective."""
        x, g, _ = self._vertex_table()
        key = _point_key(x)
        index = {key(c): i for i, c in enumerate(x)}
        mesh = self.u.function_space.mesh
        facet = facet_cell_name(mesh)
        nodes = self._facet_nodes()[:, :{"interval": 2, "triangle": 3, "quadrilateral": 4}[facet]]  # the vertices
        ids = np.array([[index.get(key(c), -1) for c in f] for f in nodes], dtype=np.int64).reshape(len(nodes), -1)
        unique = {tuple(sorted(f)): k for k, f in enumerate(ids) if (f >= 0).all()}  # ghost facets once
        rows = np.array(sorted(unique.values()), dtype=np.int64)
        if not len(rows):
            return 0.0
        extent = float(np.ptp(x, axis=0).max()) if len(x) else 0.0
        return closed_measure(nodes[rows], g[ids[rows]] + tolerance * extent)

    def max_penetration(self) -> float:
        """Largest gap over the contact vertices (positive = penetration, negative = open). Collective."""
        return float(np.max(self._vertex_table()[1]))

    def area(self, kind: str = "nominal") -> float:
        """Area (length in 2D) of the contact surface: reference (``nominal``) or current (``cauchy``). Collective."""
        self._check_kind(kind)
        if kind == "cauchy":
            self._cauchy_forms()
        form = self._current_area_form if kind == "cauchy" else self._area_form
        return self.comm.allreduce(fem.assemble_scalar(form), op=MPI.SUM)

    def mean_pressure(self, kind: str = "nominal") -> float:
        """Mean contact pressure over the surface: ``nominal`` (default), ``int p dA / A``, the force per
        reference area, or ``cauchy``, ``int p dA / a``, the force per current area ``a = int (da/dA) dA``
        (the same in small strain). Collective."""
        return self.comm.allreduce(fem.assemble_scalar(self._mean_p_form), op=MPI.SUM) / self.area(kind)


def _point_key(x: np.ndarray):
    """A function of a point's coordinates whose value is the same for points closer than 1e-9 of the extent of
    the points ``x`` (n, 3): a dictionary key that finds a vertex by its coordinates."""
    extent = float(np.ptp(x)) if x.size else 0.0
    scale = 1e-9 * (extent if extent > 0 else 1.0)
    return lambda c: tuple(np.round(np.asarray(c) / scale).astype(np.int64))


def _loaded_zones(x: np.ndarray, p: np.ndarray, facets: np.ndarray, relative: float) -> list[dict]:
    """Connected sets of the points ``x`` (n, 3) whose pressure ``p`` is above ``relative`` times the largest,
    points of a common facet (``facets``: (nf, nodes, 3) coordinates) connected; see
    :meth:`ContactSurface.contact_zones`."""
    key = _point_key(x)
    index = {key(c): i for i, c in enumerate(x)}
    parent = list(range(len(x)))

    def root(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    closed = p > relative * p.max() if p.size and p.max() > 0 else np.zeros(len(p), bool)
    for f in facets:
        ids = [index.get(key(c)) for c in f]
        ids = [i for i in ids if i is not None and closed[i]]
        for a, b in zip(ids[:-1], ids[1:]):
            parent[root(a)] = root(b)
    groups: dict[int, list[int]] = {}
    for i in np.flatnonzero(closed):
        groups.setdefault(root(i), []).append(i)
    zones = [{"points": len(ids), "X_mean": x[ids].mean(axis=0).tolist(), "X_min": x[ids].min(axis=0).tolist(),
              "X_max": x[ids].max(axis=0).tolist(), "pressure_max": float(p[ids].max())}
             for ids in groups.values()]
    return sorted(zones, key=lambda z: z["X_mean"][0])
