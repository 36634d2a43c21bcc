"""Every dolfinx call whose spelling differs between supported versions.

Chosen by feature checks (does the attribute exist), never by version
strings. Other modules import dolfinx only for calls that are the same in
all supported versions. C library calls too: glibc's (:func:`release_free_memory`) and the PETSc ones that
petsc4py 3.18 does not wrap (:func:`redundant_ksp`, :func:`petsc_library`); and petsc4py's deferred destruction
(:func:`free_petsc_garbage`).
"""
from __future__ import annotations

import ctypes
import ctypes.util
import typing

import dolfinx.fem.petsc as fem_petsc
import numpy as np
from dolfinx import fem

if typing.TYPE_CHECKING:
    from petsc4py import PETSc

__all__ = [
    "function_space", "space_degree", "mixed_space", "facet_cell_name", "collapse", "petsc_vec", "create_vector",
    "assemble_matrix", "apply_lifting", "set_bc", "lift_and_set_bc", "bc_dofs", "compile_expression",
    "interpolate_expression",
    "vertex_expression", "evaluate_expression", "cell_sizes", "entities_to_geometry", "cell_dofs", "geometry_dofs",
    "cell_partitioner", "model_to_mesh", "create_mesh", "xdmf_tensor_padding", "release_free_memory",
    "free_petsc_garbage", "redundant_ksp", "petsc_library", "check_petsc"
]


def space_degree(V) -> int:
    """The polynomial degree of the function space ``V``'s element (UFL's ``degree()`` in dolfinx 0.5, basix's
    ``degree`` property in 0.9)."""
    degree = V.ufl_element().degree
    return int(degree() if callable(degree) else degree)


def function_space(mesh, family: str, degree: int, shape: tuple[int, ...] | None = None):
    """Lagrange-type space; ``shape=(gdim,)`` for a vector space, ``(d, d)`` for a tensor space.

    Args:
        mesh: the mesh.
        family: the element family (``Lagrange``, ``DG``).
        degree: the polynomial degree.
        shape: the value shape (None: scalar).

    Returns:
        The dolfinx ``FunctionSpace``.
    """
    if hasattr(fem, "functionspace"):  # dolfinx >= 0.8
        return fem.functionspace(mesh, (family, degree, *([shape] if shape else [])))
    if shape and len(shape) == 2:
        return fem.TensorFunctionSpace(mesh, (family, degree), shape=tuple(shape))
    if shape:
        return fem.VectorFunctionSpace(mesh, (family, degree), dim=shape[0])
    return fem.FunctionSpace(mesh, (family, degree))


def mixed_space(mesh, degree: int, pressure_degree: int = 1, vector: bool = False):
    """Lagrange (displacement, vector, ``degree``) x Lagrange (pressure: scalar, or ``vector`` with one component
    per axis, the contact traction) on the whole mesh."""
    gdim = mesh.geometry.dim
    if hasattr(fem, "functionspace"):  # dolfinx >= 0.8: basix.ufl elements
        import basix.ufl

        cell = mesh.topology.cell_name()
        second = basix.ufl.element("Lagrange", cell, pressure_degree, shape=(gdim,) if vector else ())
        el = basix.ufl.mixed_element([basix.ufl.element("Lagrange", cell, degree, shape=(gdim,)), second])
        return fem.functionspace(mesh, el)
    import ufl

    cell = mesh.ufl_cell()
    second = (ufl.VectorElement("Lagrange", cell, pressure_degree, dim=gdim) if vector
              else ufl.FiniteElement("Lagrange", cell, pressure_degree))
    el = ufl.MixedElement([ufl.VectorElement("Lagrange", cell, degree, dim=gdim), second])
    return fem.FunctionSpace(mesh, el)


def facet_cell_name(mesh) -> str:
    """The UFL name of the facets' cell (``interval``, ``triangle``, ``quadrilateral``) of a mesh of one cell type
    (UFL's ``facet_types`` and ``cellname`` methods before UFL 2025.2, properties after)."""
    types = mesh.ufl_cell().facet_types
    name = (types() if callable(types) else types)[0].cellname
    return name() if callable(name) else name


def collapse(V) -> tuple[typing.Any, np.ndarray]:
    """The subspace ``V`` collapsed: the new space and the map of its dofs to ``V``'s parent's (local, int32).
    dolfinx >= 0.11 gives one map per cell type: a mesh of one cell type has one."""
    Vc, dofs = V.collapse()
    dofs = np.asarray(dofs, dtype=np.int32)
    return Vc, (dofs[0] if dofs.ndim == 2 else dofs)


def petsc_vec(f: fem.Function) -> PETSc.Vec:
    """The PETSc vector wrapping a Function's values (shares memory)."""
    return f.x.petsc_vec if hasattr(f.x, "petsc_vec") else f.vector


def create_vector(L) -> PETSc.Vec:
    """A PETSc vector for the compiled linear form ``L`` (dolfinx >= 0.10 takes its function space instead)."""
    import inspect

    if "V" in inspect.signature(fem_petsc.create_vector).parameters:  # dolfinx >= 0.10
        return fem_petsc.create_vector(L.function_spaces[0])
    return fem_petsc.create_vector(L)


def assemble_matrix(A: PETSc.Mat, a, bcs, diagonal: float) -> None:
    """Add the compiled bilinear form ``a`` into ``A``, with ``diagonal`` on the rows and columns of the Dirichlet
    conditions ``bcs`` (dolfinx >= 0.10 calls it ``diag``; passed by position, the same in every version)."""
    fem_petsc.assemble_matrix(A, a, bcs, diagonal)


def apply_lifting(b: PETSc.Vec, a, bcs, x0: PETSc.Vec | None, scale: float) -> None:
    """``b -= scale * A (g - x0)`` (``x0`` None: zero) into ``b``'s local form, ghosts included (``A`` the compiled
    bilinear form ``a``, ``g`` the values of the Dirichlet conditions ``bcs``); dolfinx >= 0.8 calls ``scale``
    ``alpha``."""
    x0 = [] if x0 is None else [x0]
    try:
        fem_petsc.apply_lifting(b, [a], bcs=[bcs], x0=x0, scale=scale)
    except TypeError:
        fem_petsc.apply_lifting(b, [a], bcs=[bcs], x0=x0, alpha=scale)


def set_bc(b: PETSc.Vec, bcs, x0: PETSc.Vec | None = None, scale: float = 1.0) -> None:
    """``b = scale * (g - x0)`` on the owned Dirichlet rows of ``bcs`` (``x0`` None: zero)."""
    try:
        fem_petsc.set_bc(b, bcs, x0, scale)
    except TypeError:
        fem_petsc.set_bc(b, bcs, x0, alpha=scale)


def lift_and_set_bc(b: PETSc.Vec, a, bcs, x0: PETSc.Vec, scale: float, diagonal: float = 1.0) -> None:
    """``b -= scale * A (g - x0)`` on free rows, ``b = scale * diagonal * (g - x0)`` on Dirichlet rows (``diagonal``:
    the Jacobian's diagonal on those rows). ``a``: the Jacobian form, or a list of forms whose sum it is."""
    for form in (a if isinstance(a, (list, tuple)) else [a]):
        apply_lifting(b, form, bcs, x0, scale)
    b.ghostUpdate(addv=_petsc().InsertMode.ADD, mode=_petsc().ScatterMode.REVERSE)
    set_bc(b, bcs, x0, scale * diagonal)


def bc_dofs(bc) -> typing.Any:
    """Local dof indices (owned and ghost) constrained by a DirichletBC."""
    dofs, first_ghost = bc.dof_indices()
    return dofs[:first_ghost] if first_ghost is not None else dofs


def _petsc():
    from petsc4py import PETSc

    return PETSc


def compile_expression(expr, V) -> fem.Expression:
    """``expr`` (UFL) compiled for evaluation at the interpolation points of the space ``V`` (for
    :func:`interpolate_expression`: compiled once, evaluated many times)."""
    pts = V.element.interpolation_points
    return fem.Expression(expr, pts() if callable(pts) else pts)


def vertex_expression(expr, mesh, vertices: int | None = None) -> fem.Expression:
    """``expr`` (UFL) compiled for evaluation at the vertices of the reference cell of ``mesh`` (the first
    ``vertices`` of them; None: all) (no function space: :func:`evaluate_expression` returns its values)."""
    import basix

    return fem.Expression(expr, basix.geometry(getattr(basix.CellType, mesh.topology.cell_name()))[:vertices])


def evaluate_expression(expr: fem.Expression, mesh, cells: np.ndarray) -> np.ndarray:
    """The compiled ``expr`` at its points in each of the local ``cells``: shape (cells, points, value size)."""
    import inspect

    if "mesh" in inspect.signature(expr.eval).parameters:  # dolfinx 0.9: eval(mesh, entities)
        values = expr.eval(mesh, cells)
    else:
        values = expr.eval(cells)
    return np.asarray(values).reshape(len(cells), -1, expr.value_size)


def interpolate_expression(f: fem.Function, expr) -> fem.Function:
    """``f`` = ``expr`` evaluated at the interpolation points of ``f``'s space, cell by cell.

    Args:
        f: the Function to set.
        expr: the UFL expression, or one compiled by :func:`compile_expression` for ``f``'s space (compiled once,
            evaluated many times).

    Returns:
        ``f``.
    """
    f.interpolate(expr if isinstance(expr, fem.Expression) else compile_expression(expr, f.function_space))
    f.x.scatter_forward()
    return f


def cell_dofs(V) -> typing.Any:
    """The dofmap as an array (local cells, dofs per cell) of local (block) dof numbers."""
    import numpy as np

    dofs = V.dofmap.list
    if hasattr(dofs, "offsets"):  # dolfinx 0.5: an AdjacencyList
        return np.asarray(dofs.array).reshape(len(dofs.offsets) - 1, -1)
    return np.asarray(dofs)


def geometry_dofs(mesh) -> typing.Any:
    """The geometry dofmap as an array (local cells, nodes per cell) of rows of ``mesh.geometry.x``."""
    import numpy as np

    dofs = mesh.geometry.dofmap
    if hasattr(dofs, "offsets"):  # dolfinx 0.5: an AdjacencyList
        return np.asarray(dofs.array).reshape(len(dofs.offsets) - 1, -1)
    return np.asarray(dofs[0] if isinstance(dofs, (list, tuple)) else dofs)


def cell_sizes(mesh, dim: int, entities):
    """Size ``h`` (largest edge) of the given local entities."""
    if hasattr(mesh, "h"):  # dolfinx >= 0.8
        return mesh.h(dim, entities)
    from dolfinx import cpp

    return cpp.mesh.h(mesh._mesh, dim, entities)  # dolfinx 0.5: the C++ mesh is Mesh._mesh


def entities_to_geometry(mesh, dim: int, entities):
    """Geometry node indices (rows of ``mesh.geometry.x``) of each of the given local entities."""
    import numpy as np
    from dolfinx import mesh as dmesh

    def call(ents):
        if hasattr(dmesh, "entities_to_geometry"):  # dolfinx >= 0.6
            return dmesh.entities_to_geometry(mesh, dim, ents, False)
        from dolfinx import cpp

        return cpp.mesh.entities_to_geometry(mesh._mesh, dim, ents, False)  # dolfinx 0.5: the C++ mesh

    entities = np.asarray(entities, dtype=np.int32)
    if len(entities) == 0:  # dolfinx 0.9 divides by zero (SIGFPE) on an empty list: the shape from entity 0
        imap = mesh.topology.index_map(dim)
        if imap is None or imap.size_local + imap.num_ghosts == 0:
            return np.zeros((0, 0), dtype=np.int32)
        return np.zeros((0, call(np.zeros(1, np.int32)).shape[1]), dtype=np.int32)
    return call(entities)
def _rcm_partition(comm, nparts: int, graph, ghosting: bool, owners=None):
    """Deterministic graph partitioner (the same partition on every run, unlike PT-SCOTCH, whose threads make
    the 2-rank partition differ from run to run: measured 6 different partitions of a unit square in 6 runs,
    and 1 in 5 with a fixed seed). The distributed dual graph is gathered on rank 0, ordered by reverse
    Cuthill-McKee (scipy's csgraph: level sets of a breadth-first search) and cut into ``nparts`` contiguous
    chunks of equal size: bands separated by one level-set front; or, given ``owners`` (one rank per cell in the
    gathered order, rank 0's cells first: the input order of a mesh built on rank 0), those. With ``ghosting`` each
    cell also goes to the ranks of its facet neighbours (shared-facet ghost mode). Gathering is fine for meshes
    built on one rank (gmsh, dolfinx's builtin meshes): their cells start on rank 0 anyway."""
    import numpy as np
    from dolfinx import cpp
    from scipy.sparse import csr_matrix
    from scipy.sparse.csgraph import reverse_cuthill_mckee

    if nparts == 1:  # everything stays: no gathered graph, no ordering (~0.3 GB of temporaries at 2e6 cells)
        return cpp.graph.AdjacencyList_int32(np.zeros(len(graph.offsets) - 1, np.int32))
    offsets, links = np.asarray(graph.offsets, dtype=np.int64), np.asarray(graph.array, dtype=np.int64)
    parts = comm.gather((offsets, links), root=0)
    if comm.rank == 0:
        counts = [len(o) - 1 for o, _ in parts]
        n = int(sum(counts))
        rows = np.concatenate([np.repeat(np.arange(c, dtype=np.int64) + s, np.diff(o))
                               for (o, _), c, s in zip(parts, counts, np.cumsum([0] + counts[:-1]))])
        cols = np.concatenate([a for _, a in parts])
        if owners is not None and len(owners) == n:
            owner = np.asarray(owners, np.int32)
        else:
            adj = csr_matrix((np.ones(len(cols), np.int8), (rows, cols)), shape=(n, n))
            order = reverse_cuthill_mckee(adj, symmetric_mode=True)
            owner = np.empty(n, np.int32)
            owner[order] = (np.arange(n, dtype=np.int64) * nparts // max(n, 1)).astype(np.int32)
        # Destinations per cell, as flat arrays (Python lists per cell: ~0.5 GB at 2e6 cells): the owner
        # first, then the other ranks of its facet neighbours in increasing order (ghosting).
        counts_per_cell = np.ones(n, np.int64)
        extra_cell = extra_rank = np.zeros(0, np.int64)
        if ghosting and nparts > 1:
            others = owner[cols] != owner[rows]
            pairs = np.unique(rows[others] * nparts + owner[cols[others]])
            extra_cell, extra_rank = pairs // nparts, pairs % nparts
            counts_per_cell += np.bincount(extra_cell, minlength=n)
        offsets = np.zeros(n + 1, np.int64)
        np.cumsum(counts_per_cell, out=offsets[1:])
        data = np.empty(offsets[-1], np.int32)
        data[offsets[:-1]] = owner
        if len(extra_cell):
            within = np.arange(len(extra_cell)) - np.searchsorted(extra_cell, extra_cell, side="left")
            data[offsets[extra_cell] + 1 + within] = extra_rank
        chunks, start = [], 0
        for c in counts:
            chunks.append((data[offsets[start]:offsets[start + c]].copy(),
                           (offsets[start:start + c + 1] - offsets[start]).astype(np.int32)))
            start += c
    else:
        chunks = None
    data, offs = comm.scatter(chunks, root=0)
    return cpp.graph.AdjacencyList_int32(data, offs)


def cell_partitioner(owners=None):
    """The deterministic cell partitioner (:func:`_rcm_partition`; ``owners``: rank 0's rank for each input cell
    instead of its ordering) in the form ``dolfinx.mesh.create_mesh`` and the builtin mesh builders take
    (``partitioner=``); no ghost cells."""
    from dolfinx import mesh as dmesh

    def partition(comm, nparts, graph, ghosting):
        return _rcm_partition(comm, nparts, graph, ghosting, owners)

    try:
        return dmesh.create_cell_partitioner(partition)
    except TypeError:  # dolfinx >= 0.11: the ghost mode and the most cells a facet joins are required
        return dmesh.create_cell_partitioner(partition, dmesh.GhostMode.none, 2)


def model_to_mesh(model, comm, rank: int, gdim: int, owners=None):
    """``dolfinx.io.gmsh.model_to_mesh`` (``gmshio`` before dolfinx 0.10) with the deterministic partitioner
    (:func:`cell_partitioner`; ``owners``: on rank 0, the rank of each of the model's cells in dolfinx's input
    order, e.g. :func:`~fenics_contact.partition.balanced_owners` of a first distribution).

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    import inspect

    try:  # dolfinx >= 0.10: dolfinx.io.gmsh, returning a MeshData
        from dolfinx.io import gmsh as dgmsh
    except ImportError:
        dgmsh = None
    if dgmsh is not None and hasattr(dgmsh, "MeshData"):
        data = dgmsh.model_to_mesh(model, comm, rank, gdim=gdim, partitioner=cell_partitioner(owners))
        return data.mesh, data.cell_tags, data.facet_tags
    from dolfinx.io import gmshio

    if "partitioner" in inspect.signature(gmshio.model_to_mesh).parameters:  # dolfinx >= 0.7
        return gmshio.model_to_mesh(model, comm, rank, gdim=gdim, partitioner=cell_partitioner(owners))
    # dolfinx 0.5: no partitioner argument; its module-level create_mesh is swapped for the call.
    create = gmshio.create_mesh
    gmshio.create_mesh = lambda *a, **k: create(*a, **k, partitioner=cell_partitioner(owners))
    try:
        return gmshio.model_to_mesh(model, comm, rank, gdim=gdim)
    finally:
        gmshio.create_mesh = create


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
        partitioner = cell_partitioner()
    else:
        dest = np.asarray(owners, dtype=np.int32) if comm.rank == 0 else np.zeros(0, np.int32)
        if not new:
            def partitioner(comm_, nparts, tdim, local_cells, ghost_mode):
                return cpp.graph.AdjacencyList_int32(dest[: local_cells.num_nodes].copy())

            return dmesh.create_mesh(comm, cells, x, domain, dmesh.GhostMode.none, partitioner)

        def partitioner(comm_, nparts, cell_types, local_cells):  # dolfinx >= 0.8
            return cpp.graph.AdjacencyList_int32(dest.copy())
    if not new:
        return dmesh.create_mesh(comm, cells, x, domain, partitioner=partitioner)
    # By name: dolfinx 0.10 put the coordinate element ``e`` before ``x``.
    return dmesh.create_mesh(comm, cells=cells, x=x, e=domain, partitioner=partitioner)


_TENSOR_PADDING: list[str] = []


def xdmf_tensor_padding() -> str:
    """How dolfinx's XDMF output pads a 2 x 2 tensor to XDMF's 9 components: ``rows`` (each row to 3 values, then a
    zero row: dolfinx 0.5, 0.6) or ``end`` (the 4 values, then 5 zeros: 0.7 on). Found once per process by writing
    one such tensor (ASCII, into a temporary folder, on this rank alone)."""
    if not _TENSOR_PADDING:
        import tempfile
        import xml.etree.ElementTree as ET

        from dolfinx import io
        from dolfinx import mesh as dmesh
        from mpi4py import MPI

        mesh = dmesh.create_unit_square(MPI.COMM_SELF, 1, 1)
        f = fem.Function(function_space(mesh, "DG", 0, (2, 2)))
        f.x.array[:] = np.tile([1.0, 2.0, 3.0, 4.0], f.x.array.size // 4)
        with tempfile.TemporaryDirectory() as folder:
            path = f"{folder}/tensor.xdmf"
            with io.XDMFFile(MPI.COMM_SELF, path, "w", encoding=io.XDMFFile.Encoding.ASCII) as out:
                out.write_mesh(mesh)
                out.write_function(f)
            item = ET.parse(path).getroot().find(".//Attribute/DataItem")
            values = np.array(item.text.split(), dtype=float)[:9]
        _TENSOR_PADDING.append("rows" if values[3] == 3.0 else "end")
    return _TENSOR_PADDING[0]


def _malloc_trim():
    """glibc's ``malloc_trim``, or None (another C library)."""
    try:
        return ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6").malloc_trim
    except (OSError, AttributeError):
        return None


_MALLOC_TRIM = _malloc_trim()


def release_free_memory() -> None:
    """Give the process's freed heap pages back to the system (glibc ``malloc_trim(0)``; a no-op elsewhere).
    glibc keeps freed blocks inside its heap, resident: at 4e5 two-body dofs the assembly's, search's and
    coupling's temporaries kept 0.3-0.5 GB under the next matrix rebuild and multigrid set-up. Called after
    every residual and Jacobian, it took that run's peak from 1.76 to 1.54 GB (a few ms per call)."""
    if _MALLOC_TRIM is not None:
        _MALLOC_TRIM(0)


def free_petsc_garbage(comm) -> None:
    """Destroy the PETSc objects whose last Python reference is gone, on ``comm`` and on this rank's own
    communicator (``PETSC_COMM_SELF``: the condensed method's gathered factorization). petsc4py (>= 3.18) does not
    destroy them when that reference goes (destruction is collective): it lists them per communicator, until this.
    Collective on ``comm``."""
    from petsc4py import PETSc

    PETSc.garbage_cleanup(comm)
    PETSc.garbage_cleanup(PETSc.COMM_SELF)


def redundant_ksp(pc: PETSc.PC) -> PETSc.KSP:
    """The inner KSP of a ``redundant`` preconditioner ``pc`` (``PCRedundantGetKSP``), made if not yet there."""
    ksp = ctypes.c_void_p()
    check_petsc(petsc_library().PCRedundantGetKSP(ctypes.c_void_p(pc.handle), ctypes.byref(ksp)), "PCRedundantGetKSP")
    # petsc4py wraps a raw handle only through an object query: compose it on pc (pc keeps the reference) and query.
    check_petsc(petsc_library().PetscObjectCompose(ctypes.c_void_p(pc.handle), b"fc_redundant_ksp", ksp),
           "PetscObjectCompose")
    return pc.query("fc_redundant_ksp")


_PETSC_LIBRARY = None


def petsc_library():
    """petsc4py's extension module as a C library (for the few PETSc calls petsc4py 3.18 does not wrap): dlsym
    also searches its dependency, the PETSc library."""
    global _PETSC_LIBRARY
    if _PETSC_LIBRARY is None:
        from petsc4py import PETSc as _PETSc

        _PETSC_LIBRARY = ctypes.CDLL(_PETSc.__file__)
    return _PETSC_LIBRARY


def check_petsc(code: int, name: str) -> None:
    """Raise ``RuntimeError`` if the PETSc C call ``name`` returned the error ``code`` (non-zero)."""
    if code != 0:
        raise RuntimeError(f"PETSc {name} failed with error code {code}")
