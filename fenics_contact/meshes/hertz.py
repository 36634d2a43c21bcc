"""Quarter disk for the Hertz scene: gmsh, graded toward the contact point."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh
    from dolfinx.mesh import MeshTagsMetaClass as MeshTags

from .gmshutil import _from_gmsh, _grade_toward, _graded, _positive, gmsh
from .tags import CONTACT, CONTACT_UPPER, DOMAIN, PLATE, PLATE_BOTTOM, PLATE_SYMMETRY, PLATE_TOP, SYMMETRY, TOP

__all__ = ["hertz_quarter_disk"]


def hertz_quarter_disk(
    comm: MPI.Comm,
    R: float = 1.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    contact_width: float | None = None,
    half: bool = False,
    full: bool = False,
    plate: tuple[float, float] | None = None,
) -> tuple[Mesh, MeshTags, MeshTags]:
    """Lower-right quarter (x >= 0, y <= R) of the disk of radius R centred at (0, R).

    P1 triangles of size ``h_contact`` (default R/400) within distance
    ``contact_width`` (default R/5) of the contact point (0, 0); beyond, the size
    grows linearly, by 0.25 per unit distance, up to ``h_far`` (default R/10). Facet tags:
    CONTACT (the arc from (0, 0) to (R, R)), SYMMETRY (x = 0), TOP (y = R);
    cell tag DOMAIN. Initialises and finalises gmsh (on every rank).
    ``half=True``: the lower half disk ``y <= R`` instead (CONTACT: the arc from
    (-R, R) to (R, R); no SYMMETRY facets), for the model-reduction check.
    ``full=True``: the whole disk (CONTACT: the lower half of the circle, CONTACT_UPPER: the upper half,
    graded toward both poles; the centre (0, R) and the poles are vertices; no SYMMETRY or TOP facets).
    ``plate=(width, depth)``: the quarter disk and, in the same mesh (no shared node), the plate
    ``[0, width] x [-depth, 0]`` (cell tag PLATE, facets PLATE_TOP, PLATE_BOTTOM, PLATE_SYMMETRY at x = 0),
    graded toward (0, 0) like the disk.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    h_contact = R / 400 if h_contact is None else h_contact
    h_far = R / 10 if h_far is None else h_far
    contact_width = R / 5 if contact_width is None else contact_width
    _positive(R=R, h_contact=h_contact, h_far=h_far, contact_width=contact_width)
    _graded(h_contact, h_far)

    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_quarter_disk(R, h_contact, h_far, contact_width, half, full, plate), "the quarter disk")
    mesh.name = "hertz_quarter_disk"
    return mesh, cell_tags, facet_tags


def _build_quarter_disk(R: float, h_contact: float, h_far: float, contact_width: float, half: bool = False,
                        full: bool = False, plate: tuple[float, float] | None = None) -> None:
    """Build and mesh the quarter-disk (or half-disk, full disk, quarter disk on a plate) model in the
    current gmsh session."""
    gmsh.model.add("hertz_quarter_disk")
    geo = gmsh.model.geo
    origin = geo.addPoint(0.0, 0.0, 0.0)
    centre = geo.addPoint(0.0, R, 0.0)
    corner = geo.addPoint(R, R, 0.0)
    arc = geo.addCircleArc(origin, centre, corner)
    poles = [origin]
    if full:
        left, pole = geo.addPoint(-R, R, 0.0), geo.addPoint(0.0, 2 * R, 0.0)
        lower = [geo.addCircleArc(left, centre, origin), arc]
        upper = [geo.addCircleArc(corner, centre, pole), geo.addCircleArc(pole, centre, left)]
        surface = geo.addPlaneSurface([geo.addCurveLoop([*lower, *upper])])
        geo.synchronize()
        gmsh.model.mesh.embed(0, [centre], 2, surface)
        gmsh.model.addPhysicalGroup(1, lower, CONTACT)
        gmsh.model.addPhysicalGroup(1, upper, CONTACT_UPPER)
        poles.append(pole)
    elif half:
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
    if plate is not None:  # its own corner points: the plate shares no node with the disk
        width, depth = plate
        p = [geo.addPoint(0.0, 0.0, 0.0), geo.addPoint(width, 0.0, 0.0), geo.addPoint(width, -depth, 0.0),
             geo.addPoint(0.0, -depth, 0.0)]
        lines = [geo.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]  # top, right, bottom, symmetry
        block = geo.addPlaneSurface([geo.addCurveLoop(lines)])
        geo.synchronize()
        gmsh.model.addPhysicalGroup(1, [lines[0]], PLATE_TOP)
        gmsh.model.addPhysicalGroup(1, [lines[2]], PLATE_BOTTOM)
        gmsh.model.addPhysicalGroup(1, [lines[3]], PLATE_SYMMETRY)
        gmsh.model.addPhysicalGroup(2, [block], PLATE)
        poles.append(p[0])
    gmsh.model.addPhysicalGroup(2, [surface], DOMAIN)

    distance = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(distance, "PointsList", poles)
    _grade_toward(distance, h_contact, h_far, contact_width)
    gmsh.model.mesh.generate(2)
