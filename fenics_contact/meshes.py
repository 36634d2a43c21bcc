"""Meshes for the contact benchmarks, with named physical tags.

``hertz_quarter_disk`` and ``pin_plate`` are built with gmsh on rank 0 and distributed with
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
FREE = 4  # traction-free sides of ``pin_plate``
# Facet tags of ``rectangle`` (its top is RECT_TOP: TOP is taken above).
BOTTOM = 11
RIGHT = 12
RECT_TOP = 13
LEFT = 14
# Name -> tag maps, e.g. for ``check_tags``.
HERTZ_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP}
PIN_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP, "free": FREE}
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

    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_quarter_disk(R, h_contact, h_far, contact_width), "the quarter disk")
    mesh.name = "hertz_quarter_disk"
    return mesh, cell_tags, facet_tags


def _from_gmsh(comm: MPI.Comm, build, what: str) -> tuple[Mesh, MeshTags, MeshTags]:
    """Run ``build()`` (adds and meshes a 2D gmsh model) on rank 0 and distribute the mesh with its tags.

    Initialises and finalises gmsh on every rank; a gmsh failure raises ``RuntimeError`` on every rank.
    """
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error = ""
        if comm.rank == 0:
            try:
                build()
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh {what}: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        return gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()


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

    distance = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(distance, "PointsList", [origin])
    _grade_toward(distance, h_contact, h_far, contact_width)
    gmsh.model.mesh.generate(2)


def pin_plate(
    comm: MPI.Comm,
    R: float = 1.0,
    half_width: float = 5.0,
    below: float = 5.0,
    above: float = 5.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    band: float | None = None,
) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right half (x >= 0) of a rectangular plate with a circular hole of radius R centred at the origin.

    The plate spans ``0 <= x <= half_width``, ``-below <= y <= above``. P1
    triangles of size ``h_contact`` (default R/50) within ``band`` (default
    R/10) of the hole, then growing by 0.25 per unit distance up to ``h_far``
    (default R/2). Facet tags: CONTACT (the half hole, from (0, -R) through
    (R, 0) to (0, R)), SYMMETRY (the two pieces of x = 0), TOP (y = above),
    FREE (y = -below and x = half_width); cell tag DOMAIN.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    h_contact = R / 50 if h_contact is None else h_contact
    h_far = R / 2 if h_far is None else h_far
    band = R / 10 if band is None else band
    for name, value in (("R", R), ("half_width", half_width), ("below", below), ("above", above),
                        ("h_contact", h_contact), ("h_far", h_far), ("band", band)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if not (half_width > R and below > R and above > R):
        raise ValueError(f"the plate (half_width={half_width}, below={below}, above={above}) must extend "
                         f"beyond the hole radius R={R} on every side")
    if h_far < h_contact:
        raise ValueError(f"h_far={h_far} must be >= h_contact={h_contact}")
    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_pin_plate(R, half_width, below, above, h_contact, h_far, band), "the pin plate")
    mesh.name = "pin_plate"
    return mesh, cell_tags, facet_tags


def _build_pin_plate(R: float, half_width: float, below: float, above: float, h_contact: float,
                     h_far: float, band: float) -> None:
    """Build and mesh the half plate with a hole in the current gmsh session."""
    gmsh.model.add("pin_plate")
    geo = gmsh.model.geo
    centre = geo.addPoint(0.0, 0.0, 0.0)
    corners = [geo.addPoint(x, y, 0.0) for x, y in
               ((0.0, -below), (half_width, -below), (half_width, above), (0.0, above))]
    hole_top, hole_side, hole_bottom = (geo.addPoint(x, y, 0.0) for x, y in ((0.0, R), (R, 0.0), (0.0, -R)))
    bottom = geo.addLine(corners[0], corners[1])
    right = geo.addLine(corners[1], corners[2])
    top = geo.addLine(corners[2], corners[3])
    sym_upper = geo.addLine(corners[3], hole_top)
    arcs = [geo.addCircleArc(hole_top, centre, hole_side), geo.addCircleArc(hole_side, centre, hole_bottom)]
    sym_lower = geo.addLine(hole_bottom, corners[0])
    loop = geo.addCurveLoop([bottom, right, top, sym_upper, *arcs, sym_lower])
    surface = geo.addPlaneSurface([loop])
    geo.synchronize()
    gmsh.model.addPhysicalGroup(1, arcs, CONTACT)
    gmsh.model.addPhysicalGroup(1, [sym_upper, sym_lower], SYMMETRY)
    gmsh.model.addPhysicalGroup(1, [top], TOP)
    gmsh.model.addPhysicalGroup(1, [bottom, right], FREE)
    gmsh.model.addPhysicalGroup(2, [surface], DOMAIN)

    # Exact distance to the hole (a gmsh Distance field samples the curve).
    distance = gmsh.model.mesh.field.add("MathEval")
    gmsh.model.mesh.field.setString(distance, "F", f"Sqrt(x*x + y*y) - {R!r}")
    _grade_toward(distance, h_contact, h_far, band)
    gmsh.model.mesh.generate(2)


def _grade_toward(distance: int, h_near: float, h_far: float, width: float) -> None:
    """Background size: ``h_near`` where the gmsh field ``distance`` is below ``width``, then growing
    by ``_GRADING`` per unit distance up to ``h_far``."""
    field = gmsh.model.mesh.field
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", h_near)
    field.setNumber(threshold, "SizeMax", h_far)
    field.setNumber(threshold, "DistMin", width)
    field.setNumber(threshold, "DistMax", width + (h_far - h_near) / _GRADING)
    field.setAsBackgroundMesh(threshold)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)


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
