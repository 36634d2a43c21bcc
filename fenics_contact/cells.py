"""Cells a mesh cannot be solved on: inverted (tangled) and degenerate (zero area or volume) cells, refused up front.

Before them, coordinates: a node whose coordinate is not finite (NaN, inf), and cells whose areas or volumes
(``h^d``) overflow or underflow floating point (a mesh in units it cannot be solved in), are refused as such.

A cell is *inverted* when it overlaps its neighbours: two cells that share an interior facet and lie on the same
side of it fold the mesh there, and of the two the one folded against at least half of its neighbours is blamed (a
cell whose node was moved through the opposite facet; both, if neither is). The orientation of a cell alone says
nothing: a mesh may mix clockwise and anticlockwise cells (dolfinx's built-in rectangles do). A quadrilateral or
hexahedron whose Jacobian determinant ``det J`` changes sign between its corners (folded, or not convex) is inverted
too. A cell is *degenerate* when ``|det J| <= DEGENERATE h^d`` at a corner (``h`` its longest distance between
corners, ``d`` the dimension): its area or volume is round-off of its size, and every form divides by it. In
parallel, a fold across the ranks' boundary is seen where the ranks share ghost cells (dolfinx's default); a surface
mesh in 3D (``gdim > tdim``) is checked for degenerate cells only.

The meridian section of an axisymmetric body lies in ``r = x[0] >= 0`` (:func:`check_meridian`): every integral
is weighted by ``2 pi r``, so a vertex at ``r < 0`` makes the ring's energy and forces negative, and a section across
the axis cancels them. Vertices on the axis within round-off of the mesh's size (``AXIS_ROUNDOFF`` times the
diagonal of its bounding box) are on it.
"""
from __future__ import annotations

import itertools

import numpy as np
from mpi4py import MPI

from .compat import entities_to_geometry, geometry_dofs

__all__ = ["AXIS_ROUNDOFF", "DEGENERATE", "MeshError", "corner_jacobians", "check_cells", "check_meridian"]

# |det J| / h^d at or below which a cell is degenerate: a triangle of aspect ratio ~1e10. Far beyond any graded
# mesh (the scenes' worst is ~1e2), far above round-off (a cell whose corners are collinear: ~1e-16).
DEGENERATE = 1e-10
# -r / (the diagonal of the mesh's bounding box) up to which a vertex of an axisymmetric section is on the axis:
# far above the round-off of coordinates (~1e-16 of the mesh's size), far below any cell of a real mesh.
AXIS_ROUNDOFF = 1e-10


class MeshError(ValueError):
    """A mesh with inverted or degenerate cells (one line: how many, and where)."""


def _corner_edges(cell: str) -> tuple[int, list[tuple[int, list[tuple[int, int]]]]]:
    """``(corners, [(corner, [(from, to) per reference axis]) ...])``: the edges whose vectors are the columns of
    ``J`` at each corner (dolfinx's vertex order: simplices from vertex 0; tensor cells vertex ``i + 2j (+ 4k)``)."""
    if cell in ("interval", "triangle", "tetrahedron"):
        n = {"interval": 2, "triangle": 3, "tetrahedron": 4}[cell]
        return n, [(0, [(0, k) for k in range(1, n)])]
    d = {"quadrilateral": 2, "hexahedron": 3}[cell]
    return 2**d, [(c, [(c & ~(1 << a), c | (1 << a)) for a in range(d)]) for c in range(2**d)]


def corner_jacobians(mesh) -> tuple[np.ndarray, np.ndarray]:
    """``det J`` at the corners of the local cells (owned, then ghost), shape (cells, corners per cell: 1 for a
    simplex), and each cell's size ``h`` (largest distance between two corners). For a mesh of a lower dimension
    than the space (``gdim > tdim``): ``sqrt(det(J^T J))`` (no sign)."""
    tdim, gdim = mesh.topology.dim, mesh.geometry.dim
    cell = mesh.topology.cell_type.name
    corners, edges = _corner_edges(cell)
    x = mesh.geometry.x[:, :gdim][geometry_dofs(mesh)[:, :corners]]  # (cells, corners, gdim)
    local = len(x)
    dets = []
    for _, axes in edges:
        J = np.stack([x[:, b] - x[:, a] for a, b in axes], axis=-1)  # (cells, gdim, tdim)
        dets.append(np.linalg.det(J) if gdim == tdim else np.sqrt(np.abs(np.linalg.det(
            np.einsum("cij,cik->cjk", J, J)))))
    h = np.zeros(local)
    for a, b in itertools.combinations(range(corners), 2):
        h = np.maximum(h, np.linalg.norm(x[:, b] - x[:, a], axis=-1))
    return np.stack(dets, axis=1) if dets else np.zeros((local, 0)), h


def _where(points: np.ndarray, comm: MPI.Comm) -> str:
    """``"at (x, y)"`` (one cell) or ``"in the box (lo) to (hi)"`` around the centroids ``points`` of all ranks."""
    boxes = [b for b in comm.allgather((points.min(axis=0), points.max(axis=0)) if len(points) else None) if b]
    lo, hi = np.min([b[0] for b in boxes], axis=0), np.max([b[1] for b in boxes], axis=0)

    def fmt(p):
        return "(" + ", ".join(f"{v:.4g}" for v in p) + ")"

    return f"at {fmt(lo)}" if np.array_equal(lo, hi) else f"in the box {fmt(lo)} to {fmt(hi)}"


def _folded(mesh, degenerate: np.ndarray) -> np.ndarray:
    """Flags of the local cells (owned and ghost) that lie on the same side of an interior facet as the other
    cell of that facet (module docstring); a ``degenerate`` cell (flags of the local cells) has no side."""
    tdim = mesh.topology.dim
    fdim = tdim - 1
    corners = _corner_edges(mesh.topology.cell_type.name)[0]
    x = mesh.geometry.x[:, :tdim]
    centroid = x[geometry_dofs(mesh)[:, :corners]].mean(axis=1)
    mesh.topology.create_connectivity(fdim, tdim)
    f2c = mesh.topology.connectivity(fdim, tdim)
    offsets, cells = np.asarray(f2c.offsets), np.asarray(f2c.array)
    interior = np.flatnonzero(np.diff(offsets) == 2)
    folded = np.zeros(len(centroid), dtype=bool)
    if len(interior) == 0:
        return folded
    c1, c2 = cells[offsets[interior]], cells[offsets[interior] + 1]
    nodes = x[entities_to_geometry(mesh, fdim, interior.astype(np.int32))[:, :tdim]]  # (facets, tdim, tdim)
    if tdim == 2:
        edge = nodes[:, 1] - nodes[:, 0]
        normal = np.stack([-edge[:, 1], edge[:, 0]], axis=1)
    elif tdim == 3:
        normal = np.cross(nodes[:, 1] - nodes[:, 0], nodes[:, 2] - nodes[:, 0])
    else:
        return folded  # intervals: a node moved past its neighbour makes a degenerate or overlapping pair
    side1 = np.einsum("fi,fi->f", normal, centroid[c1] - nodes[:, 0])
    side2 = np.einsum("fi,fi->f", normal, centroid[c2] - nodes[:, 0])
    same = (np.sign(side1) * np.sign(side2) > 0) & ~degenerate[c1] & ~degenerate[c2]  # no overflow
    # The cell that turned over is on a fold with most of its neighbours, the one it overlaps with few of its
    # own: blame a cell on a fold with at least half of its neighbours, and both cells of a fold that blames none.
    n = len(centroid)
    folds = np.bincount(c1[same], minlength=n) + np.bincount(c2[same], minlength=n)
    neighbours = np.bincount(c1, minlength=n) + np.bincount(c2, minlength=n)
    folded = (folds > 0) & (2 * folds >= neighbours)
    orphan = same & ~folded[c1] & ~folded[c2]
    folded[c1[orphan]] = folded[c2[orphan]] = True
    return folded


_MEASURE = {1: "lengths", 2: "areas", 3: "volumes"}


def _check_coordinates(mesh, what: str) -> None:
    """:class:`MeshError` (on every rank) if a node of ``mesh`` has a coordinate that is not finite (NaN, inf), or
    if the cells' sizes to the power of the dimension (their areas or volumes) leave the floating-point range
    (overflow above, underflow to zero below): the mesh is then in units it cannot be solved in. Collective."""
    comm = mesh.comm
    tdim, gdim = mesh.topology.dim, mesh.geometry.dim
    x = mesh.geometry.x[:, :gdim]
    used = np.unique(geometry_dofs(mesh))
    bad = int(np.count_nonzero(~np.all(np.isfinite(x[used]), axis=1)))
    if comm.allreduce(bad, op=MPI.MAX):
        count = comm.allreduce(bad, op=MPI.SUM)  # a node shared by ranks may be counted on each
        raise MeshError(f"{what} has {count} node{'s' * (count > 1)} with a coordinate that is not finite (NaN or "
                        "inf): fix the mesh")
    local = np.abs(x[used]).max() if len(used) else 0.0
    reach = comm.allreduce(float(local), op=MPI.MAX)
    corners = _corner_edges(mesh.topology.cell_type.name)[0]
    edges = x[geometry_dofs(mesh)[:, :corners]]
    sizes = np.abs(edges[:, 1:] - edges[:, :1]).max(axis=(1, 2)) if len(edges) else np.zeros(0)  # no overflow
    finite = sizes[sizes > 0]
    low = comm.allreduce(float(finite.min()) if len(finite) else np.inf, op=MPI.MIN)
    high = comm.allreduce(float(sizes.max()) if len(sizes) else 0.0, op=MPI.MAX)
    with np.errstate(over="ignore", under="ignore"):
        over = not np.isfinite(high) or not np.isfinite(np.float64(high) ** tdim)
        under = np.isfinite(low) and np.float64(low) ** tdim < np.finfo(float).tiny / DEGENERATE
    if over:
        raise MeshError(f"{what} has coordinates up to {reach:.3g}: its cells' {_MEASURE[tdim]} (size^{tdim}, up to "
                        f"{high:.3g}^{tdim}) overflow floating point: scale it to other units")
    if under:
        raise MeshError(f"{what} has cells of size {low:.3g}: their {_MEASURE[tdim]} (size^{tdim}) underflow floating "
                        "point: scale it to other units")


def check_cells(mesh, what: str = "the mesh") -> None:
    """Raise :class:`MeshError` (on every rank) if ``mesh`` has a coordinate that is not finite, cells whose areas or
    volumes overflow or underflow floating point, or inverted or degenerate cells (module docstring);
    the message counts them and says where they are (the centroid of the one cell, or the box around the
    centroids). Collective.

    Args:
        mesh: the dolfinx mesh.
        what: how the message names the mesh.
    """
    comm = mesh.comm
    tdim, gdim = mesh.topology.dim, mesh.geometry.dim
    _check_coordinates(mesh, what)
    det, h = corner_jacobians(mesh)
    owned = mesh.topology.index_map(tdim).size_local
    degenerate = np.any(np.abs(det) <= DEGENERATE * h[:, None] ** tdim, axis=1)
    inverted = np.zeros_like(degenerate)
    if gdim == tdim:
        mixed = np.any(det > 0, axis=1) & np.any(det < 0, axis=1)  # a folded or non-convex tensor cell
        inverted = (mixed | _folded(mesh, degenerate)) & ~degenerate
    inverted, degenerate = inverted[:owned], degenerate[:owned]
    total = comm.allreduce(owned, op=MPI.SUM)
    problems = []
    for name, bad in (("inverted (tangled)", inverted), ("degenerate (zero area or volume)", degenerate)):
        count = comm.allreduce(int(np.count_nonzero(bad)), op=MPI.SUM)
        if count:
            x = mesh.geometry.x[:, :gdim][geometry_dofs(mesh)[:owned][bad]].mean(axis=1)
            problems.append(f"{count} {name} cell{'s' if count > 1 else ''} of {total} {_where(x, comm)}")
    if problems:
        raise MeshError(f"{what} has {' and '.join(problems)}: fix the mesh")


def check_meridian(mesh, what: str = "the axisymmetric mesh") -> None:
    """Raise :class:`MeshError` (on every rank) if a vertex of ``mesh``, the meridian section ``(r, z) = (x[0],
    x[1])`` of an axisymmetric body, lies at ``r < 0`` beyond round-off (module docstring); the message counts them
    and says where they are. Collective.

    Args:
        mesh: the dolfinx mesh (2D).
        what: how the message names the mesh.
    """
    comm = mesh.comm
    x = mesh.geometry.x[:, :2]
    lo, hi = np.full(2, np.inf), np.full(2, -np.inf)  # buffers: allreduce's MIN of arrays is not elementwise
    comm.Allreduce(x.min(axis=0) if len(x) else lo.copy(), lo, op=MPI.MIN)
    comm.Allreduce(x.max(axis=0) if len(x) else hi.copy(), hi, op=MPI.MAX)
    if lo[0] >= -AXIS_ROUNDOFF * float(np.linalg.norm(hi - lo)):
        return
    owned = np.arange(mesh.topology.index_map(0).size_local, dtype=np.int32)  # each vertex counted once
    mesh.topology.create_connectivity(0, mesh.topology.dim)
    nodes = entities_to_geometry(mesh, 0, owned).reshape(-1)
    r = x[nodes, 0]
    bad = r < -AXIS_ROUNDOFF * float(np.linalg.norm(hi - lo))
    count = comm.allreduce(int(np.count_nonzero(bad)), op=MPI.SUM)
    total = comm.allreduce(len(owned), op=MPI.SUM)
    raise MeshError(f"{what} has {count} of {total} vertices at r = x[0] < 0 {_where(x[nodes[bad]], comm)}: the "
                    f"meridian section (r, z) of an axisymmetric body lies in r >= 0 (the axis at r = 0)")
