"""Meshes of two bodies in one dolfinx mesh: stacked blocks with non-matching interfaces, two half disks."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh


from ...domain import NamedTags
from .gmshutil import _GRADING, _from_gmsh, _load_geo, _positive, geo_path, gmsh
from .structured import kuhn_tetrahedra

__all__ = ["stacked_blocks", "two_half_disks"]

# Values of the regions (private: regions are referred to by name). ``stacked_blocks``: cells of the lower and
# the upper block, and facets.
LOWER, UPPER = 1, 2
BODIES = {"lower": LOWER, "upper": UPPER}


LOWER_BOTTOM, LOWER_TOP, UPPER_BOTTOM, UPPER_TOP, BLOCK_LEFT, BLOCK_FRONT = 21, 22, 23, 24, 25, 26


STACKED_FACETS = {"lower_bottom": LOWER_BOTTOM, "lower_top": LOWER_TOP, "upper_bottom": UPPER_BOTTOM,
                  "upper_top": UPPER_TOP, "left": BLOCK_LEFT, "front": BLOCK_FRONT}


def stacked_blocks(comm: MPI.Comm, width: float, h_lower: float, h_upper: float, n_lower: tuple[int, ...],
                   n_upper: tuple[int, ...], overlap: float = 0.0, by_body: bool = False,
                   upper_span: tuple[float, float] | None = None) -> tuple[Mesh, NamedTags, NamedTags]:
    """Two blocks in one mesh, not sharing nodes: ``[0, width] x [0, h_lower]`` with ``n_lower = (nx, ny)``
    triangles pairs, and ``[0, width] x [h_lower - overlap, h_lower - overlap + h_upper]`` with ``n_upper``
    (``upper_span = (a, b)``: the upper block spans ``[a, b]`` instead of ``[0, width]`` along each horizontal
    axis: an overhang where it is wider).
    Three counts ``(nx, ny, nz)`` give boxes ``[0, width]^2 x [..]`` of tetrahedra (6 per hexahedron), the
    height along z. Different ``nx`` give non-matching interfaces. ``by_body``: the lower block on rank 0,
    the upper on rank 1 (with 2 or more ranks; the test of a slave/master pair on different ranks).

    Returns ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`): cells ``lower``, ``upper``;
    facets ``lower_bottom``, ``lower_top``, ``upper_bottom``, ``upper_top``, ``left`` (x = 0), ``front`` (y = 0,
    in 3D only)."""
    from ...compat import create_mesh

    _positive(width=width, h_lower=h_lower, h_upper=h_upper)
    dim = len(n_lower)
    for name, n in (("n_lower", n_lower), ("n_upper", n_upper)):
        if len(n) not in (2, 3) or len(n) != dim or min(n) < 1:
            raise ValueError(f"{name} must be 2 (2D) or 3 (3D) cell counts >= 1, the same number for both, got {n!r}")
    xs, cs, body = [], [], []
    offset = 0
    if upper_span is not None and not (np.all(np.isfinite(upper_span)) and upper_span[1] > upper_span[0]):
        raise ValueError(f"upper_span must be two finite numbers a < b, got {upper_span!r}")
    spans = ((0.0, width), (0.0, width) if upper_span is None else tuple(map(float, upper_span)))
    for b, (y0, h, n) in enumerate(((0.0, h_lower, n_lower), (h_lower - overlap, h_upper, n_upper))):
        axes = [np.linspace(*spans[b], m + 1) for m in n[:-1]] + [np.linspace(y0, y0 + h, n[-1] + 1)]
        grid = np.meshgrid(*axes, indexing="ij")
        xs.append(np.stack([g.ravel() for g in grid], axis=1))
        idx = np.arange(grid[0].size).reshape(grid[0].shape) + offset
        if dim == 2:
            a, bb, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
            cs.append(np.concatenate([np.stack([a, bb, c], 1), np.stack([a, c, d], 1)]))
        else:  # the 6 tetrahedra of each hexahedron, one subdivision pattern after the other
            cs.append(np.moveaxis(kuhn_tetrahedra(idx), 3, 0).reshape(-1, 4))
        body.append(np.full(len(cs[-1]), b))
        offset += grid[0].size
    x, cells, owner = np.concatenate(xs), np.concatenate(cs), np.concatenate(body)
    if comm.rank != 0:
        x, cells, owner = np.zeros((0, dim)), np.zeros((0, dim + 1), np.int64), np.zeros(0, np.int32)
    msh = create_mesh(comm, cells, x, "triangle" if dim == 2 else "tetrahedron", owner if by_body else None)
    tdim = msh.topology.dim
    # Cell tags by centroid height (the lower block is below h_lower - overlap/2).
    msh.topology.create_connectivity(tdim, 0)
    ncell = msh.topology.index_map(tdim).size_local + msh.topology.index_map(tdim).num_ghosts
    mid = dmesh.compute_midpoints(msh, tdim, np.arange(ncell, dtype=np.int32))
    split = h_lower - overlap / 2
    up = dim - 1  # the stacking axis
    upper = mid[:, up] > split
    cell_tags = dmesh.meshtags(msh, tdim, np.arange(ncell, dtype=np.int32),
                               np.where(upper, UPPER, LOWER).astype(np.int32))
    # Facet tags: boundary facets by position and by the block of their cell.
    fdim = tdim - 1
    msh.topology.create_connectivity(fdim, tdim)
    facets = dmesh.exterior_facet_indices(msh.topology)
    f2c = msh.topology.connectivity(fdim, tdim)
    fmid = dmesh.compute_midpoints(msh, fdim, facets)
    ub = np.array([upper[f2c.links(f)[0]] for f in facets], dtype=bool)
    tol = 1e-9 * max(width, h_lower, h_upper)
    values = np.zeros(len(facets), np.int32)
    values[(np.abs(fmid[:, up]) < tol) & ~ub] = LOWER_BOTTOM
    values[(np.abs(fmid[:, up] - h_lower) < tol) & ~ub] = LOWER_TOP
    values[(np.abs(fmid[:, up] - (h_lower - overlap)) < tol) & ub] = UPPER_BOTTOM
    values[(np.abs(fmid[:, up] - (h_lower - overlap + h_upper)) < tol) & ub] = UPPER_TOP
    values[np.abs(fmid[:, 0]) < tol] = BLOCK_LEFT
    if dim == 3:
        values[np.abs(fmid[:, 1]) < tol] = BLOCK_FRONT
    keep = values > 0
    facet_tags = dmesh.meshtags(msh, fdim, facets[keep].astype(np.int32), values[keep])
    facet_tags.name = "facet_tags"
    return msh, NamedTags(cell_tags, BODIES), NamedTags(facet_tags, STACKED_FACETS)


def two_half_disks(comm: MPI.Comm, R_lower: float, R_upper: float, h_contact: float, h_far: float,
                   contact_width: float, overlap: float = 0.0, grading: float = _GRADING, full: bool = False,
                   quarters: bool = False) -> tuple[Mesh, NamedTags, NamedTags]:
    """Right halves (x >= 0) of two disks stacked on the y axis, in one mesh without shared nodes: the lower
    disk centred at ``(0, R_lower)``, the upper at ``(0, 2 R_lower + R_upper - overlap)``. P1 triangles of
    size ``h_contact`` within ``contact_width`` of the four points on the y axis where the disks touch each
    other and the plates, growing by ``grading`` per unit distance up to ``h_far``. Facets ``symmetry`` (x = 0),
    ``lower_bottom``, ``lower_top``, ``upper_bottom``, ``upper_top`` (each arc split at its widest point into a
    bottom and a top quarter); cells ``lower``, ``upper``. Collective.
    ``full=True``: the whole disks (model-reduction check): ``*_bottom`` / ``*_top`` are the lower /
    upper half circles, no ``symmetry`` facets; the poles are vertices. ``quarters=True``: only the quarters that
    face each other (the lower disk above its centre, the upper below its own; graded toward their contact point
    only), facets ``symmetry``, ``lower_top``, ``upper_bottom`` and the cuts ``lower_equator``, ``upper_equator``.
    The geometry: ``geo/two_disks.geo``."""
    _positive(R_lower=R_lower, R_upper=R_upper, h_contact=h_contact, h_far=h_far, contact_width=contact_width)
    geo_path("two_disks")  # a missing source: a clear error on every rank
    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_two_half_disks(R_lower / R_upper, 1.0, h_contact / R_upper, h_far / R_upper,
                                            contact_width / R_upper, overlap / R_upper, grading, full, quarters),
        "the two half disks", scale=R_upper)
    mesh.name = "two_half_disks"
    return mesh, cell_tags, facet_tags


def _build_two_half_disks(R1, R2, h_contact, h_far, width, overlap, grading, full=False, quarters=False):
    """Mesh ``geo/two_disks.geo`` in the current gmsh session."""
    gmsh.model.add("two_half_disks")
    _load_geo(geo_path("two_disks"), R_lower=R1, R_upper=R2, h_contact=h_contact, h_far=h_far, contact_width=width,
              overlap=overlap, grading=grading, full=int(full), quarters=int(quarters))
    gmsh.model.mesh.generate(2)
