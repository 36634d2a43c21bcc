"""Half plate with a hole for the pin scene (gmsh, graded toward the hole)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ..domain import NamedTags

from .gmshutil import _from_gmsh, _grade_toward, _graded, _physical, _positive, gmsh

# Physical group values (private: regions are referred to by name).
CONTACT, SYMMETRY, TOP, FREE, DOMAIN = 1, 2, 3, 4, 1

__all__ = ["pin_plate"]


def pin_plate(
    comm: MPI.Comm,
    R: float = 1.0,
    half_width: float = 5.0,
    below: float = 5.0,
    above: float = 5.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    band: float | None = None,
) -> tuple[Mesh, NamedTags, NamedTags]:
    """Right half (x >= 0) of a rectangular plate with a circular hole of radius R centred at the origin.

    The plate spans ``0 <= x <= half_width``, ``-below <= y <= above``. P1
    triangles of size ``h_contact`` (default R/50) within ``band`` (default
    R/10) of the hole, then growing by 0.25 per unit distance up to ``h_far``
    (default R/2). Facets: ``contact`` (the half hole, from (0, -R) through
    (R, 0) to (0, R)), ``symmetry`` (the two pieces of x = 0), ``top`` (y = above),
    ``free`` (y = -below and x = half_width); cells ``plate``.

    Returns:
        ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    h_contact = R / 50 if h_contact is None else h_contact
    h_far = R / 2 if h_far is None else h_far
    band = R / 10 if band is None else band
    _positive(R=R, half_width=half_width, below=below, above=above, h_contact=h_contact, h_far=h_far, band=band)
    if not (half_width > R and below > R and above > R):
        raise ValueError(f"the plate (half_width={half_width}, below={below}, above={above}) must extend "
                         f"beyond the hole radius R={R} on every side")
    _graded(h_contact, h_far)
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
    _physical(1, arcs, "contact", CONTACT)
    _physical(1, [sym_upper, sym_lower], "symmetry", SYMMETRY)
    _physical(1, [top], "top", TOP)
    _physical(1, [bottom, right], "free", FREE)
    _physical(2, [surface], "plate", DOMAIN)

    # Exact distance to the hole (a gmsh Distance field samples the curve).
    distance = gmsh.model.mesh.field.add("MathEval")
    gmsh.model.mesh.field.setString(distance, "F", f"Sqrt(x*x + y*y) - {R!r}")
    _grade_toward(distance, h_contact, h_far, band)
    gmsh.model.mesh.generate(2)
