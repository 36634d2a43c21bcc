"""Quadrature-exact projection of UFL expressions onto a state space.

With the contact measure's own quadrature rule and a state space whose
restriction to each contact facet has one degree of freedom per quadrature
point (P1 with the vertex rule, DG1 with the 2-point Gauss rule on a 2D
facet or the 3-point rule on a triangle facet), the facet mass matrix is
``Phi^T W Phi`` with ``Phi`` invertible, so solving ``M c = b`` returns the
values of the expression at the quadrature points exactly. The matrix is
block diagonal per facet (diagonal for the vertex rule), so block Jacobi
with a local LU solves it exactly, in parallel too. It is assembled from the
surface integral alone and solved on the surface dofs only (its submatrix):
a volume term in the pattern (for identity rows off the surface) made the
local LU factor the whole mesh's scalar P1 pattern, a 3D fill-in of ~2 GB at
1e6 dofs. Degrees of freedom off the contact surface get the value 0.
:class:`LumpedProjector` recovers vertex values from the points of another rule (Gauss) by their weighted mean.
"""
from __future__ import annotations

import dolfinx.fem.petsc as fem_petsc
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["SurfaceProjector", "LumpedProjector"]


class SurfaceProjector:
    """Projects expressions onto ``S`` at the quadrature points of ``ds``."""

    def __init__(self, S: fem.FunctionSpace, ds: ufl.Measure):
        self.S = S
        self.ds = ds
        q, p = ufl.TestFunction(S), ufl.TrialFunction(S)
        mesh = S.mesh
        M = fem_petsc.assemble_matrix(fem.form(ufl.inner(p, q) * ds))
        M.assemble()
        # Dofs whose basis function vanishes at every quadrature point (off the surface, or DG dofs of a
        # vertex opposite the facet) have a zero (or absent) diagonal: left out of the solve.
        d = M.getDiagonal()
        scale = d.norm(PETSc.NormType.INFINITY)
        on = np.abs(d.array) > 1e-12 * scale
        self.surface_dofs = np.flatnonzero(on).astype(np.int32)  # owned dofs only
        d.destroy()
        rows = PETSc.IS().createGeneral(M.getOwnershipRange()[0] + self.surface_dofs, comm=mesh.comm)
        self.M = M.createSubMatrix(rows, rows)  # the surface block: the pattern of the surface facets only
        M.destroy()
        rows.destroy()
        self._b, self._x = self.M.createVecs()
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

    def compile(self, expr: ufl.core.expr.Expr) -> fem.FormMetaClass:
        """Compile the right-hand side of ``expr`` once; pass it to :meth:`project`."""
        return fem.form(expr * self._q * self.ds)

    def project(self, rhs: fem.FormMetaClass, out: fem.Function) -> fem.Function:
        b = fem_petsc.assemble_vector(rhs)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self._b.array[:] = b.array[self.surface_dofs]
        b.destroy()
        self.ksp.solve(self._b, self._x)
        out.x.array[:] = 0.0
        out.x.array[self.surface_dofs] = self._x.array
        out.x.scatter_forward()
        return out


class LumpedProjector:
    """The lumped projection onto P1 at the quadrature points of ``ds``: ``c_i = int e phi_i ds / int phi_i ds``,
    the quadrature-weighted mean of ``e`` over the surface facets around vertex ``i``. The same interface as
    :class:`SurfaceProjector` (``compile``, ``project``, ``surface_dofs``). With a rule whose points are not the
    vertices (Gauss), this recovers vertex values without extrapolating: a field that alternates from point to
    point (a pressure whose law is enforced at the Gauss points only) is averaged, not amplified."""

    def __init__(self, S: fem.FunctionSpace, ds: ufl.Measure):
        self.S, self.ds = S, ds
        self._q = ufl.TestFunction(S)
        w = fem_petsc.assemble_vector(fem.form(self._q * ds))
        w.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        weights = w.array.copy()  # owned dofs
        w.destroy()
        on = np.abs(weights) > 1e-12 * max(S.mesh.comm.allreduce(float(np.abs(weights).max(initial=0.0)),
                                                                  op=MPI.MAX), 1e-300)
        self.surface_dofs = np.flatnonzero(on).astype(np.int32)  # owned dofs only
        self._weights = weights[self.surface_dofs]

    def compile(self, expr: ufl.core.expr.Expr) -> fem.FormMetaClass:
        """Compile the right-hand side of ``expr`` once; pass it to :meth:`project`."""
        return fem.form(expr * self._q * self.ds)

    def project(self, rhs: fem.FormMetaClass, out: fem.Function) -> fem.Function:
        b = fem_petsc.assemble_vector(rhs)
        b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        out.x.array[:] = 0.0
        out.x.array[self.surface_dofs] = b.array[self.surface_dofs] / self._weights
        b.destroy()
        out.x.scatter_forward()
        return out
