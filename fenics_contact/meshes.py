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
# Facet tag of ``sphere_octant``'s second symmetry plane (y = 0; x = 0 is SYMMETRY).
SYMMETRY_Y = 4
# Name -> tag maps, e.g. for ``check_tags``.
HERTZ_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP}
RECTANGLE_FACETS = {"bottom": BOTTOM, "right": RIGHT, "top": RECT_TOP, "left": LEFT}

# Slope of the mesh size with distance in the graded zone (size / length).
_GRADING = 0.25


def hertz_quarter_disk(
    comm: MPI.Comm,
    R: float = 1.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    contact_width: float | None = None,
    half: bool = False,
) -> tuple[Mesh, MeshTags, MeshTags]:
    """Lower-right quarter (x >= 0, y <= R) of the disk of radius R centred at (0, R).

    P1 triangles of size ``h_contact`` (default R/400) within distance
    ``contact_width`` (default R/5) of the contact point (0, 0); beyond, the size
    grows linearly, by 0.25 per unit distance, up to ``h_far`` (default R/10). Facet tags:
    CONTACT (the arc from (0, 0) to (R, R)), SYMMETRY (x = 0), TOP (y = R);
    cell tag DOMAIN. Initialises and finalises gmsh (on every rank).
    ``half=True``: the lower half disk ``y <= R`` instead (CONTACT: the arc from
    (-R, R) to (R, R); no SYMMETRY facets), for the model-reduction check.

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
                _build_quarter_disk(R, h_contact, h_far, contact_width, half)
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


def _build_quarter_disk(R: float, h_contact: float, h_far: float, contact_width: float, half: bool = False) -> None:
    """Build and mesh the quarter-disk (or half-disk) model in the current gmsh session."""
    gmsh.model.add("hertz_quarter_disk")
    geo = gmsh.model.geo
    origin = geo.addPoint(0.0, 0.0, 0.0)
    centre = geo.addPoint(0.0, R, 0.0)
    corner = geo.addPoint(R, R, 0.0)
    arc = geo.addCircleArc(origin, centre, corner)
    if half:
        left = geo.addPoint(-R, R, 0.0)
        arcs = [geo.addCircleArc(left, centre, origin), arc]
        top = [geo.addLine(corner, centre), geo.addLine(centre, left)]
        surface = geo.addPlaneSurface([geo.addCurveLoop([*arcs, *top])])
        geo.synchronize()
        gmsh.model.addPhysicalGroup(1, arcs, CONTACT)
        gmsh.model.addPhysicalGroup(1, top, TOP)
    else:
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


def sphere_octant(comm: MPI.Comm, R: float = 1.0, h_contact: float = 0.02, h_far: float = 0.15,
                  contact_width: float = 0.15) -> tuple[Mesh, MeshTags, MeshTags]:
    """Octant ``x >= 0, y >= 0, z <= R`` of the ball of radius ``R`` centred at ``(0, 0, R)`` (P1 tetrahedra).

    Size ``h_contact`` within ``contact_width`` of the contact point (0, 0, 0), growing by 0.25 per
    unit distance up to ``h_far``. Facet tags: CONTACT (the spherical surface), SYMMETRY (x = 0),
    SYMMETRY_Y (y = 0), TOP (z = R); cell tag DOMAIN. gmsh meshes on rank 0.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    for name, value in (("R", R), ("h_contact", h_contact), ("h_far", h_far), ("contact_width", contact_width)):
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
                _build_sphere_octant(R, h_contact, h_far, contact_width)
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh the sphere octant: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=3)
    finally:
        gmsh.finalize()
    mesh.name = "sphere_octant"
    return mesh, cell_tags, facet_tags


def _build_sphere_octant(R: float, h_contact: float, h_far: float, contact_width: float) -> None:
    gmsh.model.add("sphere_octant")
    occ = gmsh.model.occ
    ball = occ.addSphere(0.0, 0.0, R, R, -1, -math.pi / 2, 0.0, math.pi / 2)
    occ.synchronize()
    tags = {CONTACT: [], SYMMETRY: [], SYMMETRY_Y: [], TOP: []}
    tol = 1e-6 * R
    for dim, s in gmsh.model.getBoundary([(3, ball)], oriented=False):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, s)
        if x1 - x0 < tol:
            tags[SYMMETRY].append(s)
        elif y1 - y0 < tol:
            tags[SYMMETRY_Y].append(s)
        elif z1 - z0 < tol:
            tags[TOP].append(s)
        else:
            tags[CONTACT].append(s)
    for tag, surfaces in tags.items():
        gmsh.model.addPhysicalGroup(2, surfaces, tag)
    gmsh.model.addPhysicalGroup(3, [ball], DOMAIN)
    origin = occ.addPoint(0.0, 0.0, 0.0)
    occ.synchronize()
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
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay: the same mesh every run (HXT's varies; 1e6 dofs ~4 min)
    gmsh.model.mesh.generate(3)


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
