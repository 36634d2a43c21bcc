"""The nonlinear problem: bulk energy, loads, Dirichlet data and contact surfaces.

All forms are compiled once here; the load parameter ``t`` is a ``Constant``,
and Dirichlet values and traction factors are ``Constant``s set from their load paths by :meth:`set_load`.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field
from typing import Sequence

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .capabilities import check, of
from .cells import check_cells, check_meridian
from .compat import (
    assemble_matrix,
    create_vector,
    evaluate_expression,
    lift_and_set_bc,
    petsc_vec,
    space_degree,
    vertex_expression,
)
from .condensed import step_solver_for
from .contact import displacement, is_mixed
from .domain import tag_value
from .form_inputs import form_inputs
from .kept import BULK_PATTERN, AffineResidual, KeptJacobian
from .kinematics import AXISYMMETRIC, hoop_stretch
from .materials import Material, Materials
from .models import locking_warning
from .paths import LoadPath, check_path, load_factor
from .sparse import trimmed_matrix
from .surface import StepSolver, Surface

__all__ = ["DIRICHLET_WEIGHT", "load_factor", "Dirichlet", "ContactProblem", "Stabilised"]

logger = logging.getLogger(__name__)

# The Dirichlet rows' weight against the bodies' stiffness: small, so that the l2 line search (the residual norm
# along the step) follows the equilibrium rows; a Dirichlet row is linear and met by any full step (weight 1 took
# the mindlin scene 22 Newton iterations in its first step instead of 7).
DIRICHLET_WEIGHT = 1e-3

@dataclass
class Dirichlet:
    """``u_i = amplitude * f(t)`` on ``dofs`` of the (sub)space ``V``.

    Args:
        V: the (sub)space of the constrained component.
        dofs: its constrained dofs (local indices).
        amplitude: the value at ``f(t) = 1`` (length).
        path: the load path ``f`` (:func:`load_factor`): ``None`` for ``f(t) = t``, a callable ``f(t)``, or
            piecewise linear ``(t_k, f_k)`` (``t_k`` increasing; constant beyond its ends). It may be set after
            construction; :meth:`at` reads it.
    """

    V: fem.FunctionSpace
    dofs: np.ndarray
    amplitude: float = 0.0
    path: LoadPath = None
    value: fem.Constant = field(init=False)
    bc: object = field(init=False)

    def __post_init__(self):
        check_path(self.path, "Dirichlet path")
        self.value = fem.Constant(self.V.mesh, 0.0)
        self.bc = fem.dirichletbc(self.value, self.dofs, self.V)

    @classmethod
    def on_facets(cls, V: fem.FunctionSpace, facet_tags, tag: int | str, component: int,
                  amplitude: float = 0.0, path: LoadPath = None) -> Dirichlet:
        """``u_component = amplitude * f(t)`` on the facets tagged ``tag``.

        Args:
            V: the displacement space (vector).
            facet_tags: facet tags (dolfinx ``MeshTags`` or :class:`~fenics_contact.domain.NamedTags`).
            tag: a tag value, or a name of ``facet_tags``.
            component: the displacement component constrained (0: x, 1: y, 2: z).
            amplitude: the value at ``f = 1`` (length); 0: a roller, a symmetry plane.
            path: the load path ``f`` (:func:`load_factor`); None: ``f(t) = t``.

        Returns:
            The :class:`Dirichlet`.
        """
        facet_tags, tag = tag_value(facet_tags, tag)
        Vi = V.sub(component)
        facets = facet_tags.indices[facet_tags.values == tag]
        return cls(Vi, fem.locate_dofs_topological(Vi, V.mesh.topology.dim - 1, facets), amplitude, path)

    def at(self, t: float) -> float:
        """The prescribed value at load ``t``: ``amplitude * f(t)``."""
        check_path(self.path, "Dirichlet path")
        return self.amplitude * load_factor(self.path, t)


def _scaled_rows(residual: ufl.Form, v: ufl.Argument, material) -> ufl.Form:
    """The bulk's ``residual`` in the test function ``v``, its pressure rows times the mixed material's
    ``constraint_scale`` (forces, like the displacement's rows); as it is for a displacement model."""
    from ufl.algorithms import expand_derivatives

    if not material.mixed:
        return residual
    n = v.ufl_shape[0] - 1
    scale = material.constraint_scale(v.ufl_domain())
    return ufl.replace(expand_derivatives(residual), {v: ufl.as_vector([v[i] for i in range(n)] + [scale * v[n]])})


def _displacement_diagonal(A: PETSc.Mat, V) -> np.ndarray:
    """The nonzero absolute values of ``A``'s diagonal in this rank's rows of the displacement (of a mixed unknown
    on ``V``: its first field; all rows of a displacement)."""
    d = A.getDiagonal()
    diagonal = np.abs(d.array)
    if is_mixed(V):
        rows = np.asarray(V.sub(0).collapse()[1])
        diagonal = diagonal[rows[rows < len(diagonal)]]
    d.destroy()
    return diagonal[diagonal > 0]


def _vertex_kinematics(u: fem.Function, material) -> tuple:
    """The compiled expression of :meth:`ContactProblem.vertex_kinematics` (``det F`` and the small strain's
    components of ``u``'s displacement), its mesh and the owned cells. At one vertex where the values are the same
    at every point of a cell (a linear displacement on straight-sided triangles or tetrahedra, not axisymmetric)."""
    w = displacement(u)
    d = len(w)
    detF = ufl.det(ufl.Identity(d) + ufl.grad(w))
    axisymmetric = getattr(material, "axisymmetric", False)
    if axisymmetric:
        detF = detF * hoop_stretch(w, AXISYMMETRIC)
    eps = ufl.sym(ufl.grad(w))
    values = [detF] + [eps[i, j] for i in range(d) for j in range(i, d)]
    mesh = u.function_space.mesh
    cells = np.arange(mesh.topology.index_map(mesh.topology.dim).size_local, dtype=np.int32)
    V = u.function_space
    constant = (space_degree(V.sub(0) if is_mixed(V) else V) == 1 and int(mesh.geometry.cmap.degree) == 1
                and mesh.topology.cell_name() in ("triangle", "tetrahedron") and not axisymmetric)
    return vertex_expression(ufl.as_vector(values), mesh, 1 if constant else None), mesh, cells


def _check_axisymmetric(contacts, u, material) -> None:
    """Refuse, before any form is compiled, a mesh past the axis and a contact the capability grid or the surface's
    integrals do not allow on an axisymmetric body."""
    check_meridian(u.function_space.mesh)  # r < 0: the 2 pi r weight turns negative
    for c in contacts:
        if c.law is not None:  # the entry points checked the rest; the quadrature matters here for segments
            segment = getattr(c, "quadrature", None) == "segment"
            check(**of(c.law, u, material), quadrature="segment" if segment else None)
        if not c.ring_weighted:
            raise ValueError(f"contact {c.name}: {type(c).__name__} does not weight its integrals by 2 pi r; "
                             "an axisymmetric body needs a surface that does (capabilities: geometry)")


def setup_warnings(material, V) -> list[str]:
    """What a set-up says of its answer before any solve, logged (WARNING, rank 0): a displacement-only model
    on the space ``V`` at ``nu >=`` :data:`~fenics_contact.models.LOCKING_NU` locks
    (:func:`~fenics_contact.models.locking_warning`). Not failures: the solver's run warnings start with them."""
    warnings = [w for w in [locking_warning(material, space_degree(V.sub(0) if is_mixed(V) else V))] if w]
    if V.mesh.comm.rank == 0:
        for w in warnings:
            logger.warning(w)
    return warnings


class ContactProblem:
    """Residual ``F(u; v) = dW[v] - sum_k f_k(t) f_ext,k[v] + sum_c F_c(g) dg[v]`` and its Jacobian; on an
    axisymmetric body (``material.axisymmetric``) every integral, the loads' too, is weighted by ``2 pi r``.

    ``stiffness``: :data:`DIRICHLET_WEIGHT` times the mean absolute diagonal of the bodies' Jacobian at ``u = 0``
    (a force per length). The Dirichlet rows of the residual are ``stiffness (x - g)`` and their Jacobian diagonal
    ``stiffness``: every row is a force, so the residual's norm and the Newton iterates do not depend on the units.

    Args:
        u: the unknown: the displacement, or a mixed (displacement, pressure) Function when a contact surface
            has its pressure as an unknown or the material is mixed (:mod:`~fenics_contact.incompressible`;
            :func:`~fenics_contact.unknown` makes it; the contact terms act on its displacement field).
        material: the bulk material, or :class:`~fenics_contact.Materials` (one per body).
        load: the load parameter ``t`` (a scalar ``Constant``; :meth:`set_load` sets it).
        dirichlet: the :class:`Dirichlet` conditions.
        contacts: the contact surfaces (:class:`~fenics_contact.surface.Surface`).
        tractions: external loads, each ``(vector, measure)`` or ``(vector, measure, path)``: the term
            ``f(t) * vector . v`` integrated over ``measure`` (``ds(tag)``: a traction, force per area of the
            reference configuration (a dead load at finite strain); ``dx``: a body force, force per volume).
            ``path`` is the load path of :func:`load_factor`: ``None`` (default) for ``f(t) = t``, a callable
            ``f(t)``, or piecewise linear ``(t_k, f_k)``, as :attr:`Dirichlet.path`. Sign: ``vector`` is the
            force on the body (``(0, -q)`` on a top face presses it down).
        step_solver: a :class:`~fenics_contact.surface.StepSolver` that solves each load step instead of SNES;
            None: the one a surface with ``requires_step_solver`` (method ``coulomb``) needs
            (:func:`~fenics_contact.condensed.step_solver_for`), else SNES.
    ``warnings``: what the set-up says of the answer (:func:`setup_warnings`), the first of the run's warnings.
    """

    def __init__(self, u: fem.Function, material: Material | Materials, load: fem.Constant,
                 dirichlet: Sequence[Dirichlet] = (), contacts: Sequence[Surface] = (),
                 tractions: Sequence[tuple] = (),
                 step_solver: StepSolver | None = None):
        check_cells(u.function_space.mesh)  # a tangled or flat cell: no answer to solve for
        self.u, self.material, self.load = u, material, load
        for i, entry in enumerate(tractions):
            if not isinstance(entry, (tuple, list)) or len(entry) not in (2, 3):
                raise ValueError(f"tractions[{i}] must be (vector, measure) or (vector, measure, path), got {entry!r}")
            if len(entry) == 3:
                check_path(entry[2], f"tractions[{i}] path")
        self.dirichlet, self.contacts = list(dirichlet), list(contacts)
        if step_solver is None:
            step_solver = step_solver_for(self.contacts)
        self.step_solver = step_solver  # solves whole load steps instead of SNES (None: SNES)
        for c in self.contacts:
            c.given_dirichlet([d.bc for d in self.dirichlet])
        self.bcs = [d.bc for d in self.dirichlet] + [bc for c in self.contacts for bc in c.bcs]
        V = u.function_space
        if material.mixed and not is_mixed(V):
            raise ValueError(f"model {material.model!r} needs the mixed unknown of unknown(mesh, 2, law, "
                             f"model={material.model!r}), got a displacement")
        for c in self.contacts:  # the capability grid with the model (a surface built without the material)
            if getattr(c, "law", None) is not None:
                check(**of(c.law, material=material))
        if getattr(material, "axisymmetric", False):
            _check_axisymmetric(self.contacts, u, material)
        self.warnings = setup_warnings(material, V)
        v, du = ufl.TestFunction(V), ufl.TrialFunction(V)
        bulk = _scaled_rows(ufl.derivative(material.bulk_form(u), u, v), v, material)  # per body with Materials
        body = bulk
        # 2 pi r on an axisymmetric body: loads over the whole ring (a material without weight(): 1)
        ring = material.weight(displacement(u)) if hasattr(material, "weight") else 1.0
        # each traction with a path has its own factor f(t) (a Constant set by set_load); the others follow t
        self._traction_factors = []
        for vector, measure, *path in tractions:
            factor = load
            if path and path[0] is not None:
                factor = fem.Constant(V.mesh, 0.0)
                self._traction_factors.append((factor, path[0]))
            body -= factor * ufl.dot(vector, displacement(v)) * ring * measure
        surface = None
        for c in self.contacts:
            c.bind_material(material)  # for the Cauchy pressure (da/dA)
            term = c.residual(v)
            if term is not None:  # exact enforcement adds bounds, not a term
                surface = term if surface is None else surface + term
        # The bodies' and the contacts' terms are separate forms, assembled one after the other: dolfinx packs
        # every coefficient of a form for each of its integrals, so in one form the contacts' fields (two-body:
        # the mirror points, 76 values per cell) were packed for every cell of the bulk (0.15 GB per assembly at
        # 1.2e5 dofs, 1.2 GB at 1e6). The facet terms couple dofs of one cell: the bulk's pattern holds them.
        self._residual_ufl = body if surface is None else body + surface
        self._du = du
        self._L_parts = [fem.form(body)] + ([fem.form(surface)] if surface is not None else [])
        self._a_parts = [fem.form(ufl.derivative(body, u, du))] + \
            ([fem.form(ufl.derivative(surface, u, du))] if surface is not None else [])
        self._bulk = self._L_parts[0] if not tractions else fem.form(bulk)
        # A multiplier's Jacobian: the bodies couple the displacement alone (sparse.trimmed_matrix)
        self._trimmed = is_mixed(V) and not material.mixed
        self.bulk_jacobian = KeptJacobian(self._a_parts[0], form_inputs(ufl.derivative(body, u, du)), u,
                                          self.create_matrix)
        self.bulk_residual = AffineResidual(self._L_parts[0], form_inputs(body), self.bulk_jacobian)
        self.comm = V.mesh.comm
        self.stiffness = self._reference_stiffness()
        self._vertex_expr = _vertex_kinematics(u, material)  # compiled with the forms: the checks of every step
        if self.step_solver is not None:
            self.jacobian_inputs()  # analysed with the forms: a step solver reads it at its first step

    def _reference_stiffness(self) -> float:
        """:data:`DIRICHLET_WEIGHT` times the mean absolute diagonal of the bodies' Jacobian at ``u = 0`` over its
        displacement rows' nonzero entries (a force per length, ~ ``E h^(d-2)``), over all ranks. Collective."""
        saved = self.u.x.array.copy()
        self.u.x.array[:] = 0.0
        A = fem_petsc.assemble_matrix(self._a_parts[0])
        A.assemble()
        diagonal = _displacement_diagonal(A, self.u.function_space)
        total = self.comm.allreduce(float(diagonal.sum()), op=MPI.SUM)
        count = self.comm.allreduce(diagonal.size, op=MPI.SUM)
        A.destroy()
        self.u.x.array[:] = saved
        return DIRICHLET_WEIGHT * (total / count if count and total > 0 and np.isfinite(total) else 1.0)

    @property
    def L(self) -> fem.Form:
        """The whole residual as one form (dolfinx's ``NonlinearProblem.L``), compiled on first use; :meth:`F`
        assembles its parts."""
        if not hasattr(self, "_L"):
            self._L = self._L_parts[0] if len(self._L_parts) == 1 else fem.form(self._residual_ufl)
        return self._L

    @property
    def a(self) -> fem.Form:
        """The Jacobian of :attr:`L` as one form (``NonlinearProblem.a``), compiled on first use; :meth:`J`
        assembles its parts."""
        if not hasattr(self, "_a"):
            self._a = self._a_parts[0] if len(self._a_parts) == 1 else \
                fem.form(ufl.derivative(self._residual_ufl, self.u, self._du))
        return self._a

    def jacobian_inputs(self) -> tuple[list, list]:
        """The Constants and the Functions the Jacobian form depends on (after expanding the derivative): what
        can change the Jacobian between two assemblies (``u`` among the Functions: a nonlinear Jacobian).
        Analysed once per problem."""
        if not hasattr(self, "_jacobian_inputs"):
            self._jacobian_inputs = form_inputs(ufl.derivative(self._residual_ufl, self.u, self._du))
        return self._jacobian_inputs

    def F(self, x: PETSc.Vec, b: PETSc.Vec) -> None:
        """The residual at ``x`` into ``b``, as dolfinx's ``NonlinearProblem.F``: sets ``u`` to ``x``, lets every
        contact prepare (two-body contact re-pairs), assembles the forms, adds the contacts' terms outside the
        forms, and sets the Dirichlet rows to ``k (x - g)`` (``k``: :attr:`stiffness`; lifting on the free rows); a
        linear bulk's part is a product with its kept Jacobian (:class:`~fenics_contact.kept.AffineResidual`)."""
        x.ghostUpdate(addv=PETSc.InsertMode.INSERT, mode=PETSc.ScatterMode.FORWARD)
        x.copy(petsc_vec(self.u))
        self.u.x.scatter_forward()
        for c in self.contacts:  # e.g. two-body contact re-pairs at the current state
            c.prepare(self)
        with b.localForm() as bl:
            bl.set(0.0)
        first = 1 if self.bulk_residual.ready() else 0  # the bodies' residual as a product with their kept Jacobian
        for L in self._L_parts[first:]:
            fem_petsc.assemble_vector(b, L)
        for c in self.contacts:  # coupling terms outside the forms (owned entries)
            c.add_residual(b)
        if first:
            self.bulk_residual.add(b, x, self.bcs)
        lift_and_set_bc(b, self._a_parts[first:], self.bcs, x, -1.0, self.stiffness)

    def J(self, x: PETSc.Vec, A: PETSc.Mat) -> bool:
        """The Jacobian at ``x`` into ``A`` (Dirichlet rows and columns: ``k`` times the identity), as dolfinx's
        ``NonlinearProblem.J``: the state (``u``, contact pairing) is that of the last :meth:`F` at the same
        ``x``, as in a Newton iteration. Returns True when a contact's coupling changed ``A``'s nonzero pattern
        (a solver must then factor from scratch)."""
        self.bulk_jacobian.give_pattern(A, self.bcs, self.stiffness)  # A's first Jacobian: the sums of every later one
        A.zeroEntries()
        if self._trimmed:  # the bodies' zero blocks stay out (a contact's coupling may have rebuilt A)
            A.setOption(PETSc.Mat.Option.NEW_NONZERO_LOCATIONS, False)
        for a in self._a_parts[1:]:  # Dirichlet diagonal 0 (added or inserted, the bulk's 1 follows)
            assemble_matrix(A, a, self.bcs, 0.0)
            A.assemble(PETSc.Mat.AssemblyType.FLUSH)  # its inserted diagonal before the bulk's added values
        self.bulk_jacobian.add(A, self.bcs, self.stiffness)
        # PETSc >= 3.20 keeps a stale symbolic factorization across MatAXPY's pattern change: report it.
        return any([c.add_jacobian(A, self.bcs) for c in self.contacts])

    def pattern_changes(self) -> bool:
        """True when the next :meth:`J` will change ``A``'s nonzero pattern (a contact's pairing changed)."""
        return any([c.pattern_changes() for c in self.contacts])

    def create_vector(self) -> PETSc.Vec:
        """A vector for :meth:`F` (the residual's layout)."""
        return create_vector(self._L_parts[0])

    def create_matrix(self) -> PETSc.Mat:
        """A matrix for :meth:`J` (the Jacobian form's sparsity; contact couplings widen it when needed; a
        multiplier's: :func:`~fenics_contact.sparse.trimmed_matrix`)."""
        if not self._trimmed:  # preallocated: the first assembly gives it its pattern
            return fem_petsc.create_matrix(self._a_parts[0])
        A = trimmed_matrix(self.u.function_space, 0, self._a_parts[1:])
        A.setAttr(BULK_PATTERN, True)  # its pattern explicit: the kept bulk Jacobian is added, not assembled again
        return A

    def set_load(self, t: float) -> None:
        """Load parameter ``t``: obstacles move by ``t * motion``; Dirichlet values and tractions follow their load
        paths (:func:`load_factor`; ``f(t) = t`` without one)."""
        self.load.value = t
        for d in self.dirichlet:
            d.value.value = d.at(t)
        for factor, path in self._traction_factors:
            factor.value = load_factor(path, t)

    def mesh_size(self) -> float:
        """The size of the mesh: the diagonal of its bounding box (a length), over all ranks. Collective."""
        if not hasattr(self, "_mesh_size"):
            x = self.u.function_space.mesh.geometry.x
            lo, hi = np.full(3, np.inf), np.full(3, -np.inf)  # buffers: allreduce's MIN of arrays is not elementwise
            self.comm.Allreduce(x.min(axis=0) if len(x) else lo.copy(), lo, op=MPI.MIN)
            self.comm.Allreduce(x.max(axis=0) if len(x) else hi.copy(), hi, op=MPI.MAX)
            self._mesh_size = float(np.linalg.norm(hi - lo))
        return self._mesh_size

    def vertex_kinematics(self) -> tuple[np.ndarray, np.ndarray]:
        """At the vertices of every owned cell (one where the values are constant on a cell: P1 on straight simplices,
        not axisymmetric), at the current displacement: ``det F`` (``F = I + grad u``; axisymmetric: times ``1 + u_r /
        r``), shape (cells, vertices), and the components ``(i, j)``, ``i <= j`` in row order, of ``sym(grad u)``.
        One expression, compiled with the problem's forms, serves both (the solver's checks after every step),
        evaluated once per displacement (the values of the last call are kept with the displacement they belong to)."""
        u = self.u.x.array
        kept = getattr(self, "_kinematics_at", None)
        if kept is None or not np.array_equal(kept[0], u):
            expr, mesh, cells = self._vertex_expr
            kept = self._kinematics_at = (u.copy(), evaluate_expression(expr, mesh, cells))
        values = kept[1]
        return values[:, :, 0], values[:, :, 1:]

    def min_jacobian(self) -> float:
        """Smallest ``J = det F`` of the displacement (:meth:`vertex_kinematics`) at the cells' vertices, over all
        ranks: ``J <= 0``, an inverted element, is no answer even if Newton converged to it. Not a measure of
        incompressibility: a mixed model meets ``J = 1`` weakly (on average over a cell); at the vertices of a
        nearly incompressible body ``J`` is a few per cent off 1 (0.93-0.99 under a rigid sphere). Collective."""
        local = self.vertex_kinematics()[0].min(axis=1)  # each owned cell's smallest
        return self.comm.allreduce(float(local.min()) if local.size else np.inf, op=MPI.MIN)

    def inverted_cells(self) -> tuple[int, int]:
        """``(cells with det F <= 0 at a vertex, cells)`` at the current displacement, over all ranks. Collective."""
        local = self.vertex_kinematics()[0].min(axis=1)  # each owned cell's smallest
        return (self.comm.allreduce(int(np.count_nonzero(local <= 0.0)), op=MPI.SUM),
                self.comm.allreduce(local.size, op=MPI.SUM))

    def internal_force(self) -> np.ndarray:
        """Internal forces ``dW[phi_i]`` at the current state, local array (owned and ghost dofs)."""
        r = fem.Function(self.u.function_space)
        vec = petsc_vec(r)
        fem_petsc.assemble_vector(vec, self._bulk)
        vec.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        r.x.scatter_forward()
        return r.x.array.copy()

    def reaction(self, dofs: np.ndarray) -> float:
        """Sum of the internal forces over ``dofs`` (local, owned-or-ghost indices of ``u``'s space),
        summed over ranks: the force the support exerts on the body. Collective."""
        n_owned = self.u.function_space.dofmap.index_map.size_local * self.u.function_space.dofmap.index_map_bs
        return self.comm.allreduce(float(np.sum(self.internal_force()[dofs[dofs < n_owned]])), op=MPI.SUM)


class Stabilised(ContactProblem):
    """Force control from rest: a :class:`ContactProblem` with the vanishing spring ``k (1 - t) u`` on
    ``dx_body``, for a body held only by contact under a load (tractions) that grows with ``t``.

    The spring makes the steps before the last well posed from rest (the body is not yet held) and is exactly 0
    at ``t = 1``, so the last step's state is the unstabilised problem's. It enters as a load-scaled body force
    (``t * spring * u`` with ``spring = k (1 - t) / t``), like the ``tractions``. Solve over loads ending at 1.

    Args:
        u: the unknown, as :class:`ContactProblem`.
        material: the bulk material(s).
        load: the load parameter ``t`` (a scalar ``Constant``).
        dirichlet: the Dirichlet conditions.
        contacts: the contact surfaces.
        tractions: as :class:`ContactProblem`; the spring is 0 at ``t = 1``, where the loads are ``f(1) * vector``.
        k: the spring's stiffness per unit volume (stress per length); about ``E / L^2`` for a body of size
            ``L`` keeps the first steps well conditioned without masking the contact.
        dx_body: the measure of the body the spring holds (``ufl.dx`` for all bodies, or a tagged part).
        step_solver: as :class:`ContactProblem`.
    """

    def __init__(self, u: fem.Function, material, load: fem.Constant, dirichlet, contacts, tractions,
                 k: float, dx_body: ufl.Measure, step_solver=None):
        self.spring, self.k = fem.Constant(u.function_space.mesh, 0.0), float(k)
        super().__init__(u, material, load, dirichlet, contacts,
                         [*tractions, (-self.spring * displacement(u), dx_body)], step_solver=step_solver)

    def set_load(self, t: float) -> None:
        super().set_load(t)
        self.spring.value = self.k * (1.0 - t) / t if 0.0 < t < 1.0 else 0.0
