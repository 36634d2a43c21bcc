"""Half plate with a hole for the pin scene (gmsh, graded toward the hole)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

from .gmshutil import _GRADING, _from_gmsh, _graded, _load_geo, _positive, geo_path, gmsh

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
    ``free`` (y = -below and x = half_width); cells ``plate``. The geometry: ``geo/pin.geo``.

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
    geo_path("pin")  # a missing source: a clear error on every rank
    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_pin_plate(1.0, half_width / R, below / R, above / R, h_contact / R, h_far / R, band / R),
        "the pin plate", scale=R)
    mesh.name = "pin_plate"
    return mesh, cell_tags, facet_tags


def _build_pin_plate(R: float, half_width: float, below: float, above: float, h_contact: float,
                     h_far: float, band: float) -> None:
    """Mesh ``geo/pin.geo`` (the half plate with a hole) in the current gmsh session."""
    gmsh.model.add("pin_plate")
    _load_geo(geo_path("pin"), R=R, half_width=half_width, below=below, above=above, h_contact=h_contact,
              h_far=h_far, band=band, grading=_GRADING)
    gmsh.model.mesh.generate(2)
