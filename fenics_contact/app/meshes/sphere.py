"""Ball octant for the 3D Hertz (sphere) scene and the scaling run (gmsh, graded toward the contact)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

from .gmshutil import _GRADING, _from_gmsh, _graded, _load_geo, _positive, geo_path, gmsh

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

__all__ = ["sphere_octant"]


def sphere_octant(comm: MPI.Comm, R: float = 1.0, h_contact: float = 0.02, h_far: float = 0.15,
                  contact_width: float = 0.15, plate: tuple[float, float] | None = None
                  ) -> tuple[Mesh, NamedTags, NamedTags]:
    """Octant ``x >= 0, y >= 0, z <= R`` of the ball of radius ``R`` centred at ``(0, 0, R)`` (P1 tetrahedra).

    Size ``h_contact`` within ``contact_width`` of the contact point (0, 0, 0), growing by 0.25 per
    unit distance up to ``h_far``. Facets: ``contact`` (the spherical surface), ``symmetry`` (x = 0),
    ``symmetry_y`` (y = 0), ``top`` (z = R); cells ``ball``. ``plate=(width, depth)``: the octant and, in the
    same mesh (no shared node), the block ``[0, width]^2 x [-depth, 0]`` under it (cells ``plate``; facets
    ``plate_top`` at z = 0, ``plate_bottom``, and its faces x = 0 and y = 0 in ``symmetry`` and ``symmetry_y``
    with the octant's), graded toward (0, 0, 0) too. The geometry: ``geo/sphere.geo``. gmsh meshes on rank 0,
    in a child process (its peak memory stays out of this one).

    Returns:
        ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    _positive(R=R, h_contact=h_contact, h_far=h_far, contact_width=contact_width)
    _graded(h_contact, h_far)
    if plate is not None:
        _positive(plate_width=plate[0], plate_depth=plate[1])
    source = geo_path("sphere").read_text()  # a missing source: a clear error on every rank
    mesh, cell_tags, facet_tags = _from_gmsh(
        comm, lambda: _build_sphere_octant(1.0, h_contact / R, h_far / R, contact_width / R,
                                           None if plate is None else (plate[0] / R, plate[1] / R)),
        "the sphere octant", gdim=3, isolate=True, key=repr((1.0, h_contact / R, h_far / R, contact_width / R, plate
                                                             and (plate[0] / R, plate[1] / R))) + source, scale=R)
    mesh.name = "sphere_octant"
    return mesh, cell_tags, facet_tags


def _build_sphere_octant(R: float, h_contact: float, h_far: float, contact_width: float,
                         plate: tuple[float, float] | None = None) -> None:
    """Mesh ``geo/sphere.geo`` in the current gmsh session."""
    gmsh.model.add("sphere_octant")
    width, depth = plate if plate is not None else (0.0, 0.0)
    _load_geo(geo_path("sphere"), R=R, h_contact=h_contact, h_far=h_far, contact_width=contact_width,
              grading=_GRADING, plate_width=width, plate_depth=depth)
    gmsh.model.mesh.generate(3)
