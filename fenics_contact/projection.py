"""Quadrature-exact projection of UFL expressions onto a state space.

With the contact measure's own quadrature rule and a state space whose
restriction to each contact facet has one degree of freedom per quadrature
point (P1 with the vertex rule, DG1 with the 2-point Gauss rule on a 2D
facet or the 3-point rule on a triangle facet), the facet mass matrix is
``Phi^T W Phi`` with ``Phi`` invertible, so solving ``M c = b`` returns the
values of the expression at the quadrature points exactly. The matrix is
block diagonal per facet (diagonal for the vertex rule), so block Jacobi
with a local LU solves it exactly, in parallel too. Degrees of freedom off
the contact surface get an identity row and the value 0.
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from petsc4py import PETSc

from .compat import petsc_vec

__all__ = ["SurfaceProjector"]


class SurfaceProjector:
    """Projects expressions onto ``S`` at the quadrature points of ``ds``."""

    def __init__(self, S: fem.FunctionSpace, ds: ufl.Measure):
        self.S = S
        self.ds = ds
        q, p = ufl.TestFunction(S), ufl.TrialFunction(S)
        mesh = S.mesh
        zero = fem.Constant(mesh, 0.0)
        # The zero cell term only widens the pattern so that every dof has a diagonal entry.
        self.M = fem_petsc.assemble_matrix(fem.form(ufl.inner(p, q) * ds + zero * ufl.inner(p, q) * ufl.dx))
        self.M.assemble()
        # Dofs whose basis function vanishes at every quadrature point (off the
        # surface, or DG dofs of a vertex opposite the facet) get an identity row.
        d = self.M.getDiagonal()
        scale = d.norm(PETSc.NormType.INFINITY)
        off = np.abs(d.array) <= 1e-12 * scale
        self.surface_dofs = np.flatnonzero(~off).astype(np.int32)  # owned dofs only
        self._off = np.flatnonzero(off)
        d.array[:] = off.astype(float)
        self.M.setDiagonal(d, addv=PETSc.InsertMode.ADD)
        self.M.assemble()
        self.ksp = PETSc.KSP().create(mesh.comm)
        self.ksp.setOperators(self.M)
        prefix = f"fc_projection_{id(self)}_"
        opts = PETSc.Options()
        solver = {"ksp_type": "preonly", "pc_type": "bjacobi", "sub_ksp_type": "preonly", "sub_pc_type": "lu"}
        for k, v in solver.items():
            opts[prefix + k] = v
        self.ksp.setOptionsPrefix(prefix)
        self.ksp.setFromOptions()
        self.ksp.setUp()
        for k in solver:
            opts.delValue(prefix + k)
        self._q = q
        self._b = None

    def compile(self, expr: ufl.core.expr.Expr) -> fem.FormMetaClass:
        """Compile the right-hand side of ``expr`` once; pass it to :meth:`project`."""
        return fem.form(expr * self._q * self.ds)

    def project(self, rhs: fem.FormMetaClass, out: fem.Function) -> fem.Function:
        b = fem_petsc.assemble_vector(rhs)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        b.array[self._off] = 0.0
        self.ksp.solve(b, petsc_vec(out))
        out.x.scatter_forward()
        b.destroy()
        return out
