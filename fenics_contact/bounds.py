"""Exact nodal non-penetration against a flat rigid obstacle by PETSc SNES VI (method ``vi``).

The reference solver of the benchmarks: the constraint ``g <= 0`` at every
contact vertex becomes a bound on one displacement component (the obstacle
must be a half-plane with an axis-aligned normal), the residual has no
contact term, and ``vinewtonrsls`` (reduced-space active-set Newton) solves
the bound-constrained problem. The contact pressure is the nodal reaction
divided by the vertex weight ``int phi_i ds`` (the nodal quadrature's).
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .compat import bc_dofs, petsc_vec
from .contact import ContactSurface
from .laws import ContactLaw
from .obstacles import HalfPlane, Obstacle

__all__ = ["BoundContact"]

_BIG = 1e300  # "no bound" (PETSc's VI treats |bound| >= 1e20 as infinite)


class BoundContact(ContactSurface):
    """A contact surface enforced exactly by bounds; same figures and output as :class:`ContactSurface`."""

    bounded = True

    def __init__(self, u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False):
        if not isinstance(obstacle, HalfPlane) or np.count_nonzero(obstacle.n) != 1:
            raise ValueError("method 'vi' needs a half-plane obstacle with an axis-aligned normal")
        if quadrature != "nodal":
            raise ValueError("method 'vi' enforces the contact at the vertices: use quadrature 'nodal'")
        self.k = int(np.flatnonzero(obstacle.n)[0])
        self.sign = float(np.sign(obstacle.n[self.k]))
        V = u.function_space
        self._Vk, parent = V.sub(self.k).collapse()
        self._parent = np.asarray(parent, dtype=np.int32)
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name)  # a flat gap is linear already
        fdim = V.mesh.topology.dim - 1
        self._dofs = fem.locate_dofs_topological(self._Vk, fdim, self.facets)  # collapsed, local
        w = fem.Function(self._Vk)
        fem_petsc.assemble_vector(petsc_vec(w), fem.form(ufl.TestFunction(self._Vk) * self.ds))
        petsc_vec(w).ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        w.x.scatter_forward()
        self._weight = w.x.array[self._dofs]
        self._X = self._Vk.tabulate_dof_coordinates()[self._dofs, self.k]

    def _pressure(self):
        self._p = fem.Function(self._Vk, name="nodal_reaction_pressure")
        return self._p

    def residual(self, v):
        return None

    def bounds(self, t: float, like: PETSc.Vec):
        origin = self.obstacle.point[self.k] + t * self.obstacle.motion[self.k]
        lower, upper = like.duplicate(), like.duplicate()
        lower.set(-_BIG)
        upper.set(_BIG)
        owned = len(like.array)
        idx = self._parent[self._dofs]
        keep = idx < owned
        # (X_k + u_k - origin) * sign >= 0
        (lower if self.sign > 0 else upper).array[idx[keep]] = (origin - self._X)[keep]
        return lower, upper

    def after_solve(self, problem) -> None:
        r = problem.internal_force()
        idx = self._parent[self._dofs]
        # A vertex whose component k is prescribed (Dirichlet) carries the support's reaction, not contact.
        free = ~np.isin(idx, np.concatenate([bc_dofs(bc) for bc in problem.bcs] + [np.empty(0, np.int32)]))
        # ... and an open vertex carries none: its residual is an applied load (a loaded edge meeting the surface)
        origin = self.obstacle.point[self.k] + float(problem.load.value) * self.obstacle.motion[self.k]
        clearance = (self._X + problem.u.x.array[idx] - origin) * self.sign
        size = problem.comm.allreduce(float(np.max(np.abs(self._X - origin), initial=0.0)), op=MPI.MAX)
        free &= clearance <= 1e-8 * size
        self._p.x.array[:] = 0.0
        self._p.x.array[self._dofs[free]] = self.sign * r[idx[free]] / self._weight[free]
        self._p.x.scatter_forward()
