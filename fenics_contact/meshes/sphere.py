"""Ball octant for the 3D Hertz (sphere) scene and the scaling run (gmsh, graded toward the contact)."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from mpi4py import MPI

from .gmshutil import _from_gmsh, _grade_toward, _graded, _positive, gmsh
from .tags import CONTACT, DOMAIN, PLATE, PLATE_BOTTOM, PLATE_TOP, SYMMETRY, SYMMETRY_Y, TOP

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh
    from dolfinx.mesh import MeshTagsMetaClass as MeshTags

__all__ = ["sphere_octant"]


def sphere_octant(comm: MPI.Comm, R: float = 1.0, h_contact: float = 0.02, h_far: float = 0.15,
                  contact_width: float = 0.15, plate: tuple[float, float] | None = None
                  ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Octant ``x >= 0, y >= 0, z <= R`` of the ball of radius ``R`` centred at ``(0, 0, R)`` (P1 tetrahedra).

    Size ``h_contact`` within ``contact_width`` of the contact point (0, 0, 0), growing by 0.25 per
    unit distance up to ``h_far``. Facet tags: CONTACT (the spherical surface), SYMMETRY (x = 0),
    SYMMETRY_Y (y = 0), TOP (z = R); cell tag DOMAIN. gmsh meshes on rank 0 (in a child process).
    ``plate=(width, depth)``: the octant and, in the same mesh (no shared node), the block
    ``[0, width]^2 x [-depth, 0]`` under it (cell tag PLATE; facets PLATE_TOP at z = 0, PLATE_BOTTOM, and
    its faces x = 0 and y = 0 in SYMMETRY and SYMMETRY_Y with the octant's), graded toward (0, 0, 0) too.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    _positive(R=R, h_contact=h_contact, h_far=h_far, contact_width=contact_width)
    _graded(h_contact, h_far)
    if plate is not None:
        _positive(plate_width=plate[0], plate_depth=plate[1])
    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_sphere_octant(R, h_contact, h_far, contact_width, plate), "the sphere octant",
        gdim=3, isolate=True, key=repr((R, h_contact, h_far, contact_width, plate)))
    mesh.name = "sphere_octant"
    return mesh, cell_tags, facet_tags


def _build_sphere_octant(R: float, h_contact: float, h_far: float, contact_width: float,
                         plate: tuple[float, float] | None = None) -> None:
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
    gmsh.model.addPhysicalGroup(3, [ball], DOMAIN)
    if plate is not None:  # its own entities: the block shares no node with the ball
        width, depth = plate
        block = occ.addBox(0.0, 0.0, -depth, width, width, depth)
        occ.synchronize()
        faces = {SYMMETRY: [], SYMMETRY_Y: [], PLATE_TOP: [], PLATE_BOTTOM: []}
        for dim, s in gmsh.model.getBoundary([(3, block)], oriented=False):
            x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, s)
            if x1 < tol:
                faces[SYMMETRY].append(s)
            elif y1 < tol:
                faces[SYMMETRY_Y].append(s)
            elif z0 > -tol:
                faces[PLATE_TOP].append(s)
            elif z1 < -depth + tol:
                faces[PLATE_BOTTOM].append(s)
        for tag, surfaces in faces.items():
            tags.setdefault(tag, []).extend(surfaces)
        gmsh.model.addPhysicalGroup(3, [block], PLATE)
    for tag, surfaces in tags.items():
        gmsh.model.addPhysicalGroup(2, surfaces, tag)
    origin = occ.addPoint(0.0, 0.0, 0.0)
    occ.synchronize()
    distance = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(distance, "PointsList", [origin])
    _grade_toward(distance, h_contact, h_far, contact_width)
    gmsh.option.setNumber("Mesh.Algorithm3D", 1)  # Delaunay: the same mesh every run (HXT's varies; 1e6 dofs ~4 min)
    gmsh.model.mesh.generate(3)
