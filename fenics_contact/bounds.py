"""Exact nodal non-penetration against a flat rigid obstacle by PETSc SNES VI (method ``vi``).

The reference solver of the benchmarks: the constraint ``g <= 0`` at every
contact vertex becomes a bound on one displacement component (the obstacle
must be a half-plane with an axis-aligned normal), the residual has no
contact term, and ``vinewtonrsls`` (reduced-space active-set Newton) solves
the bound-constrained problem. The contact pressure is the nodal reaction
divided by the vertex weight ``int phi_i ds`` (the nodal quadrature's).

:class:`PlaneVertices` (the contact vertices of such an obstacle, their normal
component and weights) is shared with the condensed method
(:class:`~fenics_contact.condensed.CondensedContact`).
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .compat import bc_dofs, collapse, petsc_vec
from .contact import ContactSurface
from .laws import ContactLaw
from .obstacles import HalfPlane, Obstacle

__all__ = ["PlaneVertices", "BoundContact"]

_BIG = 1e300  # "no bound" (PETSc's VI treats |bound| >= 1e20 as infinite)


class PlaneVertices:
    """The nodal geometry of a half-plane ``obstacle`` whose normal is a coordinate axis, for the unknown's
    space ``V``: the normal component ``k`` (the obstacle's normal is ``sign e_k``, into the body), its collapsed
    space ``Vk`` and the map ``parent`` of ``Vk``'s dofs to ``V``'s. After :meth:`locate`: this rank's contact
    vertices as local dofs ``dofs`` of ``Vk``, their weights ``weight = int phi_i ds`` (length in 2D, area in
    3D) and reference coordinate ``X`` along ``e_k``."""

    def __init__(self, V: fem.FunctionSpace, obstacle: HalfPlane):
        self.obstacle = obstacle
        self.k = int(np.flatnonzero(obstacle.n)[0])
        self.sign = float(np.sign(obstacle.n[self.k]))
        self.Vk, parent = collapse(V.sub(self.k))
        self.parent = np.asarray(parent, dtype=np.int32)
        self.dofs = self.weight = self.X = None

    def locate(self, facets: np.ndarray, ds: ufl.Measure) -> None:
        """The vertices of the local contact ``facets`` and their weights by the nodal measure ``ds``."""
        fdim = self.Vk.mesh.topology.dim - 1
        self.dofs = fem.locate_dofs_topological(self.Vk, fdim, facets)  # collapsed, local
        w = fem.Function(self.Vk)
        fem_petsc.assemble_vector(petsc_vec(w), fem.form(ufl.TestFunction(self.Vk) * ds))
        petsc_vec(w).ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        w.x.scatter_forward()
        self.weight = w.x.array[self.dofs]
        self.X = self.Vk.tabulate_dof_coordinates()[self.dofs, self.k]

    def origin(self, t: float) -> float:
        """Coordinate ``k`` of the obstacle's surface at load ``t`` (it moves with ``motion``)."""
        return self.obstacle.point[self.k] + self.obstacle.factor(t) * self.obstacle.motion[self.k]


class BoundContact(ContactSurface):
    """A contact surface enforced exactly by bounds; same figures and output as :class:`ContactSurface`, its
    pressure (> 0 compression) the nodal reaction over the vertex weight.

    Args:
        u: the problem's unknown: the displacement, or the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: a :class:`SnesVI`.
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: the surface's rule: ``nodal``, ``gauss`` or ``simpson`` (the capability grid says which).
        name: the surface's name, in messages and output.
        linearized: the small-displacement gap ``g(X) - n(X) . u`` (normal at the reference point) instead of the
            gap of the current position ``X + u``.
    """

    ring_weighted = False  # its own integrals (nodal weights, NumPy element) carry no 2 pi r

    bounded = True

    def __init__(self, u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False):
        if not isinstance(obstacle, HalfPlane) or np.count_nonzero(obstacle.n) != 1:
            raise ValueError("method 'vi' needs a half-plane obstacle with an axis-aligned normal")
        if quadrature != "nodal":
            raise ValueError("method 'vi' enforces the contact at the vertices: use quadrature 'nodal'")
        self.plane = PlaneVertices(u.function_space, obstacle)  # first: the pressure lives on its space
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name)  # a flat gap is linear already
        self.plane.locate(self.facets, self.ds)

    def _pressure(self):
        self._p = fem.Function(self.plane.Vk, name="nodal_reaction_pressure")
        return self._p

    def residual(self, v):
        """None: the bounds enforce the contact."""
        return None

    def bounds(self, t: float, like: PETSc.Vec):
        plane = self.plane
        origin = plane.origin(t)
        lower, upper = like.duplicate(), like.duplicate()
        lower.set(-_BIG)
        upper.set(_BIG)
        owned = len(like.array)
        idx = plane.parent[plane.dofs]
        keep = idx < owned
        # (X_k + u_k - origin) * sign >= 0
        (lower if plane.sign > 0 else upper).array[idx[keep]] = (origin - plane.X)[keep]
        return lower, upper

    def after_solve(self, problem) -> None:
        """The pressure from the nodal reaction of the converged state."""
        plane = self.plane
        r = problem.internal_force()
        idx = plane.parent[plane.dofs]
        # A vertex whose component k is prescribed (Dirichlet) carries the support's reaction, not contact.
        free = ~np.isin(idx, np.concatenate([bc_dofs(bc) for bc in problem.bcs] + [np.empty(0, np.int32)]))
        # ... and an open vertex carries none: its residual is an applied load (a loaded edge meeting the surface)
        origin = plane.origin(float(problem.load.value))
        clearance = (plane.X + problem.u.x.array[idx] - origin) * plane.sign
        size = problem.comm.allreduce(float(np.max(np.abs(plane.X - origin), initial=0.0)), op=MPI.MAX)
        free &= clearance <= 1e-8 * size
        self._p.x.array[:] = 0.0
        self._p.x.array[plane.dofs[free]] = plane.sign * r[idx[free]] / plane.weight[free]
        self._p.x.scatter_forward()
