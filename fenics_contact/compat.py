"""Every dolfinx call whose spelling differs between supported versions.

Chosen by feature checks (does the attribute exist), never by version
strings. Other modules import dolfinx only for calls that are the same in
all supported versions.
"""
from __future__ import annotations

import typing

import dolfinx.fem.petsc as fem_petsc
from dolfinx import fem

if typing.TYPE_CHECKING:
    from petsc4py import PETSc

__all__ = [
    "function_space", "mixed_space", "petsc_vec", "lift_and_set_bc", "bc_dofs", "interpolate_expression", "cell_sizes",
    "entities_to_geometry", "create_mesh"
]


def function_space(mesh, family: str, degree: int, shape: tuple[int, ...] | None = None):
    """Lagrange-type space; ``shape=(gdim,)`` for a vector space."""
    if hasattr(fem, "functionspace"):  # dolfinx >= 0.8
        return fem.functionspace(mesh, (family, degree, *([shape] if shape else [])))
    if shape:
        return fem.VectorFunctionSpace(mesh, (family, degree), dim=shape[0])
    return fem.FunctionSpace(mesh, (family, degree))


def mixed_space(mesh, degree: int, pressure_degree: int = 1):
    """Lagrange (displacement, vector, ``degree``) x Lagrange (pressure, scalar) on the whole mesh."""
    gdim = mesh.geometry.dim
    if hasattr(fem, "functionspace"):  # dolfinx >= 0.8: basix.ufl elements
        import basix.ufl

        cell = mesh.topology.cell_name()
        el = basix.ufl.mixed_element([basix.ufl.element("Lagrange", cell, degree, shape=(gdim,)),
                                      basix.ufl.element("Lagrange", cell, pressure_degree)])
        return fem.functionspace(mesh, el)
    import ufl

    cell = mesh.ufl_cell()
    el = ufl.MixedElement([ufl.VectorElement("Lagrange", cell, degree, dim=gdim),
                           ufl.FiniteElement("Lagrange", cell, pressure_degree)])
    return fem.FunctionSpace(mesh, el)


def petsc_vec(f: fem.Function) -> PETSc.Vec:
    """The PETSc vector wrapping a Function's values (shares memory)."""
    return f.x.petsc_vec if hasattr(f.x, "petsc_vec") else f.vector


def lift_and_set_bc(b: PETSc.Vec, a, bcs, x0: PETSc.Vec, scale: float) -> None:
    """``b -= scale * A (g - x0)`` on free rows, ``b = scale (g - x0)`` on Dirichlet rows."""
    try:
        fem_petsc.apply_lifting(b, [a], bcs=[bcs], x0=[x0], scale=scale)
    except TypeError:  # dolfinx >= 0.8 renamed ``scale`` to ``alpha``
        fem_petsc.apply_lifting(b, [a], bcs=[bcs], x0=[x0], alpha=scale)
    b.ghostUpdate(addv=_petsc().InsertMode.ADD, mode=_petsc().ScatterMode.REVERSE)
    try:
        fem_petsc.set_bc(b, bcs, x0, scale)
    except TypeError:
        fem_petsc.set_bc(b, bcs, x0, alpha=scale)


def bc_dofs(bc) -> typing.Any:
    """Local dof indices (owned and ghost) constrained by a DirichletBC."""
    dofs, first_ghost = bc.dof_indices()
    return dofs[:first_ghost] if first_ghost is not None else dofs


def _petsc():
    from petsc4py import PETSc

    return PETSc


def interpolate_expression(f: fem.Function, expr) -> fem.Function:
    """``f`` = ``expr`` (UFL) evaluated at the interpolation points of ``f``'s space, cell by cell."""
    pts = f.function_space.element.interpolation_points
    f.interpolate(fem.Expression(expr, pts() if callable(pts) else pts))
    f.x.scatter_forward()
    return f


def cell_sizes(mesh, dim: int, entities):
    """Size ``h`` (largest edge) of the given local entities."""
    if hasattr(mesh, "h"):  # dolfinx >= 0.8
        return mesh.h(dim, entities)
    from dolfinx import cpp

    return cpp.mesh.h(mesh._mesh, dim, entities)  # dolfinx 0.5: the C++ mesh is Mesh._mesh


def entities_to_geometry(mesh, dim: int, entities):
    """Geometry node indices (rows of ``mesh.geometry.x``) of each of the given local entities."""
    from dolfinx import mesh as dmesh

    if hasattr(dmesh, "entities_to_geometry"):  # dolfinx >= 0.6
        return dmesh.entities_to_geometry(mesh, dim, entities, False)
    from dolfinx import cpp

    return cpp.mesh.entities_to_geometry(mesh._mesh, dim, entities, False)  # dolfinx 0.5: the C++ mesh
def create_mesh(comm, cells, x, cell: str, owners=None):
    """Mesh of simplices or quads from arrays given on rank 0 (``cells`` global node indices, ``x`` (n, gdim)).

    ``owners`` (rank 0 only, one rank per cell, or None): the rank each cell goes to, instead of the
    graph partitioner (used to put each body on its own rank). No ghost cells are made then."""
    import numpy as np
    import ufl
    from dolfinx import cpp
    from dolfinx import mesh as dmesh

    gdim = x.shape[1]
    cells = np.asarray(cells, dtype=np.int64)
    try:  # dolfinx >= 0.8
        import basix.ufl

        domain = ufl.Mesh(basix.ufl.element("Lagrange", cell, 1, shape=(gdim,)))
        new = True
    except ImportError:
        domain = ufl.Mesh(ufl.VectorElement("Lagrange", cell, 1))
        new = False
    if owners is None or comm.size == 1:
        return dmesh.create_mesh(comm, cells, x, domain)
    dest = np.asarray(owners, dtype=np.int32) if comm.rank == 0 else np.zeros(0, np.int32)
    if not new:
        def partitioner(comm_, nparts, tdim, local_cells, ghost_mode):
            return cpp.graph.AdjacencyList_int32(dest[: local_cells.num_nodes].copy())

        return dmesh.create_mesh(comm, cells, x, domain, dmesh.GhostMode.none, partitioner)

    def partitioner(comm_, nparts, cell_types, local_cells):  # dolfinx 0.8 / 0.9
        return cpp.graph.AdjacencyList_int32(dest.copy())

    return dmesh.create_mesh(comm, cells, x, domain, partitioner=partitioner)
