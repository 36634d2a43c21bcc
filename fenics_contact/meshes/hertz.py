"""Quarter disk for the Hertz scene: gmsh, graded toward the contact point."""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

import gmsh
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh
    from dolfinx.mesh import MeshTagsMetaClass as MeshTags

from .gmshutil import _from_gmsh, _grade_toward
from .tags import CONTACT, DOMAIN, SYMMETRY, TOP


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

    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_quarter_disk(R, h_contact, h_far, contact_width, half), "the quarter disk")
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

    distance = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(distance, "PointsList", [origin])
    _grade_toward(distance, h_contact, h_far, contact_width)
    gmsh.model.mesh.generate(2)
