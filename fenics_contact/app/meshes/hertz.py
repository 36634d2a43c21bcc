"""Quarter disk for the Hertz scene: gmsh, graded toward the contact point."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

from .gmshutil import _GRADING, _from_gmsh, _graded, _load_geo, _positive, geo_path, gmsh

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
    cells ``disk``. The geometry: ``geo/hertz.geo``. Initialises and finalises gmsh (on every rank).
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
    geo_path("hertz")  # a missing source: a clear error on every rank

    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_quarter_disk(1.0, h_contact / R, h_far / R, contact_width / R, half, full,
                                          None if plate is None else (plate[0] / R, plate[1] / R)),
        "the quarter disk", scale=R)
    mesh.name = "hertz_quarter_disk"
    return mesh, cell_tags, facet_tags


def _build_quarter_disk(R: float, h_contact: float, h_far: float, contact_width: float, half: bool = False,
                        full: bool = False, plate: tuple[float, float] | None = None) -> None:
    """Mesh ``geo/hertz.geo`` (the quarter disk, half disk, full disk or quarter disk on a plate) in the
    current gmsh session."""
    gmsh.model.add("hertz_quarter_disk")
    width, depth = plate if plate is not None else (0.5 * R, 0.25 * R)
    _load_geo(geo_path("hertz"), R=R, h_contact=h_contact, h_far=h_far, contact_width=contact_width,
              grading=_GRADING, half=int(half), full=int(full), plate=int(plate is not None), plate_width=width,
              plate_depth=depth)
    gmsh.model.mesh.generate(2)
