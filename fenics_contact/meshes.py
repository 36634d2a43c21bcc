"""Meshes for the contact benchmarks, with named physical tags.

``hertz_quarter_disk`` is built with gmsh on rank 0 and distributed with
``dolfinx.io.gmshio.model_to_mesh``; ``rectangle`` uses
``dolfinx.mesh.create_rectangle``. All functions are collective on ``comm``.
"""
from __future__ import annotations

import math
from collections.abc import Mapping
from typing import TYPE_CHECKING

import gmsh
import numpy as np
from dolfinx import mesh as dmesh
from dolfinx.io import gmshio
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh
    from dolfinx.mesh import MeshTagsMetaClass as MeshTags

# Physical tags of ``hertz_quarter_disk``.
DOMAIN = 1
CONTACT = 1
SYMMETRY = 2
TOP = 3
# Facet tags of ``rectangle`` (its top is RECT_TOP: TOP is taken above).
BOTTOM = 11
RIGHT = 12
RECT_TOP = 13
LEFT = 14
# Facet tags of ``sheet_over_cylinder`` (CONTACT and SYMMETRY as above).
END = 4
# Name -> tag maps, e.g. for ``check_tags``.
HERTZ_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP}
SHEET_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "end": END}
RECTANGLE_FACETS = {"bottom": BOTTOM, "right": RIGHT, "top": RECT_TOP, "left": LEFT}

# Slope of the mesh size with distance in the graded zone (size / length).
_GRADING = 0.25


def hertz_quarter_disk(
    comm: MPI.Comm,
    R: float = 1.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    contact_width: float | None = None,
) -> tuple[Mesh, MeshTags, MeshTags]:
    """Lower-right quarter (x >= 0, y <= R) of the disk of radius R centred at (0, R).

    P1 triangles of size ``h_contact`` (default R/400) within distance
    ``contact_width`` (default R/5) of the contact point (0, 0); beyond, the size
    grows linearly, by 0.25 per unit distance, up to ``h_far`` (default R/10). Facet tags:
    CONTACT (the arc from (0, 0) to (R, R)), SYMMETRY (x = 0), TOP (y = R);
    cell tag DOMAIN. Initialises and finalises gmsh (on every rank).

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    h_contact = R / 400 if h_contact is None else h_contact
    h_far = R / 10 if h_far is None else h_far
    contact_width = R / 5 if contact_width is None else contact_width
    for name, value in (("R", R), ("h_contact", h_contact), ("h_far", h_far),
                        ("contact_width", contact_width)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if h_far < h_contact:
        raise ValueError(f"h_far={h_far} must be >= h_contact={h_contact}")

    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error = ""
        if comm.rank == 0:
            try:
                _build_quarter_disk(R, h_contact, h_far, contact_width)
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh the quarter disk: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    mesh.name = "hertz_quarter_disk"
    return mesh, cell_tags, facet_tags


def _build_quarter_disk(R: float, h_contact: float, h_far: float, contact_width: float) -> None:
    """Build and mesh the quarter-disk model in the current gmsh session."""
    gmsh.model.add("hertz_quarter_disk")
    geo = gmsh.model.geo
    origin = geo.addPoint(0.0, 0.0, 0.0)
    centre = geo.addPoint(0.0, R, 0.0)
    corner = geo.addPoint(R, R, 0.0)
    arc = geo.addCircleArc(origin, centre, corner)
    top = geo.addLine(corner, centre)
    symmetry = geo.addLine(centre, origin)
    surface = geo.addPlaneSurface([geo.addCurveLoop([arc, top, symmetry])])
    geo.synchronize()
    gmsh.model.addPhysicalGroup(1, [arc], CONTACT)
    gmsh.model.addPhysicalGroup(1, [symmetry], SYMMETRY)
    gmsh.model.addPhysicalGroup(1, [top], TOP)
    gmsh.model.addPhysicalGroup(2, [surface], DOMAIN)

    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", [origin])
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", h_contact)
    field.setNumber(threshold, "SizeMax", h_far)
    field.setNumber(threshold, "DistMin", contact_width)
    field.setNumber(threshold, "DistMax", contact_width + (h_far - h_contact) / _GRADING)
    field.setAsBackgroundMesh(threshold)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)
    gmsh.model.mesh.generate(2)


def sheet_over_cylinder(comm: MPI.Comm, R: float = 3.0, thickness: float = 1.0, leg: float = 2.0,
                        n_arc: int = 24, n_thick: int = 2, n_leg: int = 8, order: int = 2
                        ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right half of a sheet wrapped over the top of a cylinder of radius ``R`` (centre at the origin).

    A quarter annulus ``R <= r <= R + thickness``, ``0 <= theta <= 90 deg`` (``theta`` from the x axis),
    continued by a vertical leg ``R <= x <= R + thickness``, ``-leg <= y <= 0``. Structured
    quadrilaterals: ``n_arc`` along the arc, ``n_leg`` along the leg, ``n_thick`` through the
    thickness; geometry of ``order`` (2: 9-node quadrilaterals whose edges follow the circles
    exactly at their three nodes). Facet tags: CONTACT (inner arc and inner side of the leg),
    SYMMETRY (x = 0), END (y = -leg). Initialises and finalises gmsh (on every rank).
    """
    for name, value in (("R", R), ("thickness", thickness), ("leg", leg)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    for name, value in (("n_arc", n_arc), ("n_thick", n_thick), ("n_leg", n_leg)):
        if int(value) < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        if comm.rank == 0:
            gmsh.model.add("sheet")
            geo = gmsh.model.geo
            Ro = R + thickness
            c, a, b, a2, b2 = (geo.addPoint(*xy, 0.0) for xy in ((0, 0), (0, R), (R, 0), (0, Ro), (Ro, 0)))
            e, e2 = geo.addPoint(R, -leg, 0.0), geo.addPoint(Ro, -leg, 0.0)
            arc_in, arc_out = geo.addCircleArc(a, c, b), geo.addCircleArc(a2, c, b2)
            sym, mid, end = geo.addLine(a, a2), geo.addLine(b, b2), geo.addLine(e, e2)
            leg_in, leg_out = geo.addLine(b, e), geo.addLine(b2, e2)
            s1 = geo.addPlaneSurface([geo.addCurveLoop([arc_in, mid, -arc_out, -sym])])
            s2 = geo.addPlaneSurface([geo.addCurveLoop([leg_in, end, -leg_out, -mid])])
            geo.synchronize()
            for curves, n in (((arc_in, arc_out), n_arc), ((sym, mid, end), n_thick), ((leg_in, leg_out), n_leg)):
                for curve in curves:
                    gmsh.model.mesh.setTransfiniteCurve(curve, int(n) + 1)
            for surface in (s1, s2):
                gmsh.model.mesh.setTransfiniteSurface(surface)
                gmsh.model.mesh.setRecombine(2, surface)
            gmsh.model.addPhysicalGroup(1, [arc_in, leg_in], CONTACT)
            gmsh.model.addPhysicalGroup(1, [sym], SYMMETRY)
            gmsh.model.addPhysicalGroup(1, [end], END)
            gmsh.model.addPhysicalGroup(2, [s1, s2], DOMAIN)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(order)
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    mesh.name = "sheet"
    return mesh, cell_tags, facet_tags


def rectangle(
    comm: MPI.Comm,
    width: float,
    height: float,
    nx: int,
    ny: int,
    quadrilateral: bool = False,
) -> tuple[Mesh, None, MeshTags]:
    """Rectangle [0, width] x [0, height] with nx x ny cells (triangles or quadrilaterals).

    Facet tags: BOTTOM (y = 0), RIGHT (x = width), RECT_TOP (y = height), LEFT (x = 0).

    Returns:
        ``(mesh, None, facet_tags)``.
    """
    cell_type = dmesh.CellType.quadrilateral if quadrilateral else dmesh.CellType.triangle
    msh = dmesh.create_rectangle(
        comm, [np.array([0.0, 0.0]), np.array([width, height])], [nx, ny], cell_type)
    tol = 1e-10 * max(width, height)
    sides = ((BOTTOM, 1, 0.0), (RIGHT, 0, width), (RECT_TOP, 1, height), (LEFT, 0, 0.0))
    fdim = msh.topology.dim - 1
    indices, values = [], []
    for tag, axis, coord in sides:
        facets = dmesh.locate_entities_boundary(
            msh, fdim, lambda x, a=axis, c=coord: np.abs(x[a] - c) < tol)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    index = np.concatenate(indices).astype(np.int32)
    order = np.argsort(index)
    facet_tags = dmesh.meshtags(msh, fdim, index[order], np.concatenate(values)[order])
    facet_tags.name = "facet_tags"
    return msh, None, facet_tags


def check_tags(facet_tags: MeshTags, tags: Mapping[str, int],
               comm: MPI.Comm) -> None:
    """Raise ValueError if a tag of ``tags`` (name -> value) marks no facet on any rank."""
    local = np.asarray(facet_tags.values)
    present = sorted(set().union(*comm.allgather(set(np.unique(local).tolist()))))
    for name, value in tags.items():
        if comm.allreduce(int(np.count_nonzero(local == value)), op=MPI.SUM) == 0:
            raise ValueError(f"facet tag {name!r}={value} is absent from the mesh; "
                             f"tags present: {present}")


# Tags of ``stacked_blocks``: cells of the lower and the upper block, and facets.
LOWER, UPPER = 1, 2
LOWER_BOTTOM, LOWER_TOP, UPPER_BOTTOM, UPPER_TOP, BLOCK_LEFT, BLOCK_FRONT = 21, 22, 23, 24, 25, 26
STACKED_FACETS = {"lower_bottom": LOWER_BOTTOM, "lower_top": LOWER_TOP, "upper_bottom": UPPER_BOTTOM,
                  "upper_top": UPPER_TOP, "left": BLOCK_LEFT, "front": BLOCK_FRONT}


def stacked_blocks(comm: MPI.Comm, width: float, h_lower: float, h_upper: float, n_lower: tuple[int, ...],
                   n_upper: tuple[int, ...], overlap: float = 0.0, by_body: bool = False
                   ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Two blocks in one mesh, not sharing nodes: ``[0, width] x [0, h_lower]`` with ``n_lower = (nx, ny)``
    triangles pairs, and ``[0, width] x [h_lower - overlap, h_lower - overlap + h_upper]`` with ``n_upper``.
    Three counts ``(nx, ny, nz)`` give boxes ``[0, width]^2 x [..]`` of tetrahedra (6 per hexahedron), the
    height along z. Different ``nx`` give non-matching interfaces. ``by_body``: the lower block on rank 0,
    the upper on rank 1 (with 2 or more ranks; the test of a slave/master pair on different ranks).

    Returns ``(mesh, cell_tags LOWER/UPPER, facet_tags STACKED_FACETS)`` (``front``: y = 0, in 3D only)."""
    from .compat import create_mesh

    for name, v in (("width", width), ("h_lower", h_lower), ("h_upper", h_upper)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    dim = len(n_lower)
    for name, n in (("n_lower", n_lower), ("n_upper", n_upper)):
        if len(n) not in (2, 3) or len(n) != dim or min(n) < 1:
            raise ValueError(f"{name} must be 2 (2D) or 3 (3D) cell counts >= 1, the same number for both, got {n!r}")
    xs, cs, body = [], [], []
    offset = 0
    for b, (y0, h, n) in enumerate(((0.0, h_lower, n_lower), (h_lower - overlap, h_upper, n_upper))):
        axes = [np.linspace(0, width, m + 1) for m in n[:-1]] + [np.linspace(y0, y0 + h, n[-1] + 1)]
        grid = np.meshgrid(*axes, indexing="ij")
        xs.append(np.stack([g.ravel() for g in grid], axis=1))
        idx = np.arange(grid[0].size).reshape(grid[0].shape) + offset
        if dim == 2:
            a, bb, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
            cs.append(np.concatenate([np.stack([a, bb, c], 1), np.stack([a, c, d], 1)]))
        else:  # Kuhn: 6 tetrahedra along the main diagonal, conforming across faces
            corner = {(i, j, k): idx[i:idx.shape[0] - 1 + i, j:idx.shape[1] - 1 + j, k:idx.shape[2] - 1 + k].ravel()
                      for i in (0, 1) for j in (0, 1) for k in (0, 1)}
            tets = []
            for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
                p, path = [0, 0, 0], [corner[(0, 0, 0)]]
                for ax in perm:
                    p[ax] = 1
                    path.append(corner[tuple(p)])
                tets.append(np.stack(path, 1))
            cs.append(np.concatenate(tets))
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
    return msh, cell_tags, facet_tags


# Tags of ``two_half_disks`` (cells: LOWER / UPPER as for ``stacked_blocks``).
DISK_SYMMETRY, LOWER_ARC_BOTTOM, LOWER_ARC_TOP, UPPER_ARC_BOTTOM, UPPER_ARC_TOP = 31, 32, 33, 34, 35
DISKS_FACETS = {"symmetry": DISK_SYMMETRY, "lower_bottom": LOWER_ARC_BOTTOM, "lower_top": LOWER_ARC_TOP,
                "upper_bottom": UPPER_ARC_BOTTOM, "upper_top": UPPER_ARC_TOP}


def two_half_disks(comm: MPI.Comm, R_lower: float, R_upper: float, h_contact: float, h_far: float,
                   contact_width: float, overlap: float = 0.0, grading: float = _GRADING
                   ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right halves (x >= 0) of two disks stacked on the y axis, in one mesh without shared nodes: the lower
    disk centred at ``(0, R_lower)``, the upper at ``(0, 2 R_lower + R_upper - overlap)``. P1 triangles of
    size ``h_contact`` within ``contact_width`` of the four points on the y axis where the disks touch each
    other and the plates, growing by ``grading`` per unit distance up to ``h_far``. Facet tags: DISKS_FACETS
    (each arc split at its widest point into a bottom and a top quarter). Collective."""
    for name, v in (("R_lower", R_lower), ("R_upper", R_upper), ("h_contact", h_contact), ("h_far", h_far),
                    ("contact_width", contact_width)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error = ""
        if comm.rank == 0:
            try:
                _build_two_half_disks(R_lower, R_upper, h_contact, h_far, contact_width, overlap, grading)
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh the two half disks: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    mesh.name = "two_half_disks"
    return mesh, cell_tags, facet_tags


def _build_two_half_disks(R1, R2, h_contact, h_far, width, overlap, grading):
    gmsh.model.add("two_half_disks")
    geo = gmsh.model.geo
    touch = []
    tags = {k: [] for k in DISKS_FACETS.values()}
    surfaces = []
    for cy, R in ((R1, R1), (2 * R1 + R2 - overlap, R2)):
        bottom = geo.addPoint(0.0, cy - R, 0.0)
        centre = geo.addPoint(0.0, cy, 0.0)
        side = geo.addPoint(R, cy, 0.0)
        top = geo.addPoint(0.0, cy + R, 0.0)
        a1 = geo.addCircleArc(bottom, centre, side)
        a2 = geo.addCircleArc(side, centre, top)
        s1 = geo.addLine(top, centre)
        s2 = geo.addLine(centre, bottom)
        surfaces.append(geo.addPlaneSurface([geo.addCurveLoop([a1, a2, s1, s2])]))
        lower = len(surfaces) == 1
        tags[LOWER_ARC_BOTTOM if lower else UPPER_ARC_BOTTOM].append(a1)
        tags[LOWER_ARC_TOP if lower else UPPER_ARC_TOP].append(a2)
        tags[DISK_SYMMETRY] += [s1, s2]
        touch += [bottom, top]
    geo.synchronize()
    for tag, curves in tags.items():
        gmsh.model.addPhysicalGroup(1, curves, tag)
    gmsh.model.addPhysicalGroup(2, [surfaces[0]], LOWER)
    gmsh.model.addPhysicalGroup(2, [surfaces[1]], UPPER)
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", touch)
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", h_contact)
    field.setNumber(threshold, "SizeMax", h_far)
    field.setNumber(threshold, "DistMin", width)
    field.setNumber(threshold, "DistMax", width + (h_far - h_contact) / grading)
    field.setAsBackgroundMesh(threshold)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)
    gmsh.model.mesh.generate(2)
