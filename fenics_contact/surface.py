"""The interfaces the problem and the solver talk to: :class:`Surface` (a contact enforcement) and
:class:`StepSolver` (a strategy that solves a whole load step instead of SNES).

Every hook the solver may call is declared here, once; the defaults are the no-ops that are right for
a surface that needs nothing at that point. Order of the calls in a load step (see
:class:`~fenics_contact.solver.Solver`):

0. Once, building the problem: ``given_dirichlet(bcs)``, then ``bcs`` read, ``bind_material(material)``,
   ``residual(v)``.
1. ``bounds(t, like)`` on the ``bounded`` surfaces (SNES VI), ``forget_gap()`` on the ``augmentable`` ones.
2. Every residual evaluation :meth:`ContactProblem.F <fenics_contact.problem.ContactProblem.F>`: ``prepare(problem)``
   with ``u`` at the iterate, the forms (with ``residual(v)`` compiled in once), then ``add_residual(b)``; every
   Jacobian: ``pattern_changes()``, then :meth:`ContactProblem.J <fenics_contact.problem.ContactProblem.J>`:
   the forms, then ``add_jacobian(A, bcs)``. After every Newton iterate ``closed_points()`` (not ``bounded``:
   failure diagnosis).
3. After a converged solve ``after_solve(problem)``; then, while augmenting, ``constraint_change()`` and
   ``augment()``.
4. An accepted step: ``commit()``; a failed one: ``restore(state())`` of the snapshot taken before it.
5. Output: ``update_output()`` before every write.

Results (the same calls with the same signatures on every surface; figures gathered on every rank):
``total_force()``, ``tangential_force()``, ``point_values(reference, kind)``, ``surface_values(kind)``,
``friction_profile()``. They and the other results of the surfaces (:data:`COLLECTIVE`) are collective: every
rank calls them, in the same order (:mod:`~fenics_contact.collective`: ``FENICS_CONTACT_COLLECTIVE_TIMEOUT`` turns a
rank left alone in one into a message).
Sign convention: the gap is positive for penetration, the pressure positive in compression.
"""
from __future__ import annotations

import abc
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    import ufl
    from petsc4py import PETSc

from .collective import collective

__all__ = ["COLLECTIVE", "Surface", "StepSolver"]

# The surfaces' public methods that reduce or gather over the ranks: each says "Collective" in its docstring and is
# checked by :func:`~fenics_contact.collective.collective` wherever a surface class defines it.
COLLECTIVE = ("total_force", "tangential_force", "point_values", "surface_values", "friction_profile",
              "contact_zones", "contact_area", "max_penetration", "area", "mean_pressure", "point_forces",
              "state_areas", "capacity", "update_output", "range_warning")


class Surface(abc.ABC):
    """A contact enforcement: its term of the residual and the hooks the solver calls.

    Class attributes (override as needed): ``bcs`` the Dirichlet conditions the surface adds to the problem
    (multipliers: ``p = 0`` off the surface); ``solver_options`` PETSc defaults the formulation needs (the
    user's options still win); ``direct_solver_options`` what replaces them when the linear solver is a direct
    LU (multipliers: the exact additive field split); ``iterative_solver_options`` what replaces them when the
    linear solver is the iterative one (multipliers: the Schur complement field split);
    ``constant_bulk_solver_options`` what the iterative ones add where the bodies' stiffness is the same at every
    iterate (a linear material; multipliers: the displacement block's multigrid kept); ``pinned_dofs`` global
    number of unknowns fixed by ``bcs`` that are not real unknowns (not counted in reported sizes); ``bounded``
    True when the surface is
    enforced by variable bounds (SNES VI) instead of a residual term; ``requires_step_solver`` True when its
    steps must be solved by a :class:`StepSolver` given to the problem (no residual term, no bounds);
    ``ring_weighted`` True when every integral of the surface takes the ``2 pi r`` of an axisymmetric body
    (:meth:`bind_material`): the problem refuses an axisymmetric body with a surface that does not.
    """

    name: str = "contact"
    comm = None  # the communicator of the mesh (the ranks that call the collective methods together)
    law = None  # the ContactLaw the surface enforces (a method without a law of the gap: its marker law)
    bcs: tuple = ()
    solver_options: dict = {}
    direct_solver_options: dict = {}
    iterative_solver_options: dict = {}
    constant_bulk_solver_options: dict = {}
    pinned_dofs: int = 0
    bounded: bool = False
    requires_step_solver: bool = False
    ring_weighted: bool = False

    # --- the problem's forms ------------------------------------------------------
    @abc.abstractmethod
    def residual(self, v: ufl.Argument) -> ufl.Form | None:
        """The surface's term of the residual for the test function ``v`` (compiled once into the problem's
        forms, its derivative into the Jacobian), or None when it has none (bounds, step solver, or a term
        assembled entirely by :meth:`add_residual` / :meth:`add_jacobian`)."""

    def bind_material(self, material) -> None:
        """Called once by the problem with its bulk material(s), before :meth:`residual` (a surface whose
        figures need the bulk, e.g. the Cauchy pressure at finite strain)."""
        return None  # a no-op unless a surface needs it

    def given_dirichlet(self, bcs: list) -> None:
        """Called once by the problem with its own Dirichlet conditions, before it reads :attr:`bcs` (multipliers
        with friction: a traction component whose displacement component is prescribed is not an unknown)."""
        return None  # a no-op unless a surface needs it

    @property
    def augmentable(self) -> bool:
        """True when :meth:`augment` improves the solution (augmented Lagrangian, Uzawa); the solver then runs
        the augmentation loop on this surface."""
        return False

    # --- linear solver ------------------------------------------------------------
    def field_split(self) -> list[tuple[str, PETSc.IS]] | None:
        """Named global index sets of a ``fieldsplit`` preconditioner, or None (the solver then uses LU)."""
        return None

    def schur_split(self) -> tuple[list[tuple[str, PETSc.IS]], PETSc.NullSpace | None] | None:
        """The two fields of a Schur complement split of the first block of :meth:`field_split`, as index sets in
        that block's own numbering, and the first field's near-nullspace (or None); None when there is none."""
        return None

    # --- SNES VI --------------------------------------------------------------------
    def bounds(self, t: float, like: PETSc.Vec) -> tuple[PETSc.Vec, PETSc.Vec] | None:
        """Variable bounds ``(lower, upper)`` on the unknowns at load ``t`` (vectors like ``like``), for a
        ``bounded`` surface; None otherwise."""
        return None

    # --- every residual and Jacobian evaluation -------------------------------------
    def prepare(self, problem) -> None:
        """Before every residual evaluation, with ``problem.u`` at the iterate (two-body contact re-pairs)."""
        return None  # a no-op unless a surface needs it

    def add_residual(self, b: PETSc.Vec) -> None:
        """Add terms outside the problem's forms to the assembled residual ``b`` (owned entries, before the
        Dirichlet rows are set)."""
        return None  # a no-op unless a surface needs it

    def pattern_changes(self) -> bool:
        """True when the next :meth:`add_jacobian` will change ``A``'s nonzero pattern (known after
        :meth:`prepare`): the solver then frees its preconditioner before the larger matrix is allocated."""
        return False

    def add_jacobian(self, A: PETSc.Mat, bcs: list) -> bool:
        """Add blocks outside the problem's forms to the assembled Jacobian ``A`` (Dirichlet rows and columns
        left zero); True if ``A``'s nonzero pattern changed (the solver then factors from scratch)."""
        return False

    def take_failure(self) -> str | None:
        """A failure kind this surface detected since the last call (e.g. ``"exploded_geometry"``: an iterate
        stretched a facet past :data:`~fenics_contact.search.STRETCH_LIMIT`), or None; the call clears it. The
        solver names a failed solve by it."""
        return None

    def timings(self) -> dict[str, float]:
        """Seconds this rank spent in the surface's own work since it was made, by name (two-body: ``search_s``,
        ``exchange_s``, ``coupling_s``); added to the solver's time split."""
        return {}

    def closed_points(self) -> np.ndarray:
        """Flags ``g > 0`` (closed) at this rank's contact points at the current ``u`` (failure diagnosis)."""
        return np.zeros(0, dtype=bool)

    # --- after a solve, augmentation ---------------------------------------------------
    def after_solve(self, problem) -> None:
        """After every converged Newton solve (e.g. the nodal reaction pressure of SNES VI)."""
        return None  # a no-op unless a surface needs it

    def forget_gap(self) -> None:
        """Start a new augmentation sequence (a new load step)."""
        return None  # a no-op unless a surface needs it

    def constraint_change(self) -> float:
        """Change of the constraint since the last call (``inf`` the first time); the augmentation loop stops
        when it is below the tolerance."""
        return 0.0

    def augment(self) -> None:
        """One augmentation (multipliers from the converged state)."""
        return None  # a no-op unless a surface needs it

    # --- load steps ------------------------------------------------------------------
    def commit(self) -> None:
        """A load step was accepted: advance history variables (friction)."""
        return None  # a no-op unless a surface needs it

    def state(self) -> dict:
        """A copy of everything a failed step may change (taken before each step)."""
        return {}

    def restore(self, state: dict) -> None:
        """Go back to a :meth:`state` (the step failed and is cut)."""
        return None  # a no-op unless a surface needs it

    def range_warning(self) -> str | None:
        """At an accepted state: what puts the surface's model past its range there, in one line (small sliding:
        a pair slid off its master facet, :data:`~fenics_contact.search.SMALL_SLIDING`), or None. Collective."""
        return None

    # --- output ---------------------------------------------------------------------------
    def update_output(self) -> None:
        """Refresh the output Functions (gap, pressure, ...) from the current state before they are written.
        Collective."""
        return None  # a no-op unless a surface needs it

    # --- results ----------------------------------------------------------------------------
    def total_force(self) -> np.ndarray:
        """Resultant of the contact pressure on this surface's body from the other side (the obstacle, or the
        master body): the normal part of the contact force, global components, shape ``(gdim,)``; per unit
        thickness in 2D. The same on every rank. Friction's part: :meth:`tangential_force`. Collective."""
        raise NotImplementedError(f"{type(self).__name__} does not report its total force")

    def tangential_force(self) -> np.ndarray:
        """Resultant of the friction traction on this surface's body, like :meth:`total_force` (zero on a
        frictionless surface). Collective."""
        return np.zeros_like(self.total_force())

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Position ``x`` (n, gdim) of the contact points (current configuration; ``reference=True``: reference
        configuration), gap ``g`` (n,) (> 0 penetration) and pressure ``p`` (n,) (> 0 compression; ``kind``
        ``nominal``: per reference area, ``cauchy``: per current area), gathered on every rank and sorted by
        reference position. Collective."""
        raise NotImplementedError(f"{type(self).__name__} does not report point values")

    def surface_values(self, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Reference position, gap and pressure along the surface: ``point_values(reference=True, kind)``.
        Collective."""
        return self.point_values(reference=True, kind=kind)

    def friction_profile(self) -> dict[str, np.ndarray]:
        """Friction figures at the contact points, sorted by reference position: ``x`` (n, gdim) reference
        position, ``gap``, ``pressure``, ``traction`` (tangential traction of the other side on the body: 2D
        a scalar along the tangent ``(n_y, -n_x)``, 3D a vector (n, 3)) and ``state`` (0 open, 1 slip, 2
        stick). ``ValueError`` on a frictionless surface. Collective."""
        raise ValueError(f"{self.name}: this surface has no friction (no friction profile)")


    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        _check_collective(cls)


def _check_collective(cls) -> None:
    """Wrap the :data:`COLLECTIVE` methods ``cls`` defines itself (:func:`~fenics_contact.collective.collective`)."""
    for name in COLLECTIVE:
        method = vars(cls).get(name)
        if callable(method) and not getattr(method, "collective", False):
            setattr(cls, name, collective(method))


_check_collective(Surface)


class StepSolver(abc.ABC):
    """A strategy that solves a whole load step itself instead of SNES (e.g.
    :class:`~fenics_contact.condensed.CondensedCoulomb`). Given to the problem (``ContactProblem(...,
    step_solver=...)``); the solver calls :meth:`solve_step` at each load value, :meth:`commit` on accepted
    steps, :meth:`state` / :meth:`restore` around failed ones."""

    @abc.abstractmethod
    def solve_step(self, problem) -> tuple[int, list[float], str]:
        """Solve at ``problem.load`` and set ``problem.u``: ``(reason as SNES's: > 0 converged, residual
        history, failure message or "")``."""

    def commit(self) -> None:
        """The step just solved was accepted."""
        return None  # a no-op unless a surface needs it

    def state(self) -> dict:
        """A copy of the strategy's state (taken before each step)."""
        return {}

    def restore(self, state: dict) -> None:
        """Go back to a :meth:`state`."""
        return None  # a no-op unless a surface needs it
