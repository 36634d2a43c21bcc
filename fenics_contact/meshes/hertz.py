"""Quarter disk for the Hertz scene: gmsh, graded toward the contact point."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ..domain import NamedTags

from .gmshutil import _from_gmsh, _grade_toward, _graded, _physical, _positive, gmsh

# Physical group values (private: regions are referred to by name).
CONTACT, SYMMETRY, TOP, CONTACT_UPPER, PLATE_TOP, PLATE_BOTTOM, PLATE_SYMMETRY = 1, 2, 3, 5, 6, 7, 8
DOMAIN, PLATE = 1, 2

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
) -> tuple[Mesh, NamedTags, NamedTags]:
    """Lower-right quarter (x >= 0, y <= R) of the disk of radius R centred at (0, R).

    P1 triangles of size ``h_contact`` (default R/400) within distance
    ``contact_width`` (default R/5) of the contact point (0, 0); beyond, the size
    grows linearly, by 0.25 per unit distance, up to ``h_far`` (default R/10). Facets:
    ``contact`` (the arc from (0, 0) to (R, R)), ``symmetry`` (x = 0), ``top`` (y = R);
    cells ``disk``. Initialises and finalises gmsh (on every rank).
    ``half=True``: the lower half disk ``y <= R`` instead (``contact``: the arc from
    (-R, R) to (R, R); no ``symmetry`` facets), for the model-reduction check.
    ``full=True``: the whole disk (``contact``: the lower half of the circle, ``contact_upper``: the upper half,
    graded toward both poles; the centre (0, R) and the poles are vertices; no ``symmetry`` or ``top`` facets).
    ``plate=(width, depth)``: the quarter disk and, in the same mesh (no shared node), the plate
    ``[0, width] x [-depth, 0]`` (cells ``plate``, facets ``plate_top``, ``plate_bottom``, ``plate_symmetry`` at x = 0),
    graded toward (0, 0) like the disk.

    Returns:
        ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
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
        _physical(1, lower, "contact", CONTACT)
        _physical(1, upper, "contact_upper", CONTACT_UPPER)
        poles.append(pole)
    elif half:
        left = geo.addPoint(-R, R, 0.0)
        arcs = [geo.addCircleArc(left, centre, origin), arc]
        top = [geo.addLine(corner, centre), geo.addLine(centre, left)]
        surface = geo.addPlaneSurface([geo.addCurveLoop([*arcs, *top])])
        geo.synchronize()
        _physical(1, arcs, "contact", CONTACT)
        _physical(1, top, "top", TOP)
    else:
        top = geo.addLine(corner, centre)
        symmetry = geo.addLine(centre, origin)
        surface = geo.addPlaneSurface([geo.addCurveLoop([arc, top, symmetry])])
        geo.synchronize()
        _physical(1, [arc], "contact", CONTACT)
        _physical(1, [symmetry], "symmetry", SYMMETRY)
        _physical(1, [top], "top", TOP)
    if plate is not None:  # its own corner points: the plate shares no node with the disk
        width, depth = plate
        p = [geo.addPoint(0.0, 0.0, 0.0), geo.addPoint(width, 0.0, 0.0), geo.addPoint(width, -depth, 0.0),
             geo.addPoint(0.0, -depth, 0.0)]
        lines = [geo.addLine(p[i], p[(i + 1) % 4]) for i in range(4)]  # top, right, bottom, symmetry
        block = geo.addPlaneSurface([geo.addCurveLoop(lines)])
        geo.synchronize()
        _physical(1, [lines[0]], "plate_top", PLATE_TOP)
        _physical(1, [lines[2]], "plate_bottom", PLATE_BOTTOM)
        _physical(1, [lines[3]], "plate_symmetry", PLATE_SYMMETRY)
        _physical(2, [block], "plate", PLATE)
        poles.append(p[0])
    _physical(2, [surface], "disk", DOMAIN)

    distance = gmsh.model.mesh.field.add("Distance")
    gmsh.model.mesh.field.setNumbers(distance, "PointsList", poles)
    _grade_toward(distance, h_contact, h_far, contact_width)
    gmsh.model.mesh.generate(2)
