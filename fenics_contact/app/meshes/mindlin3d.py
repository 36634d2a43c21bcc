"""Mesh of the ``mindlin3d`` scene: the half ``y >= 0`` of a spherical cap on a block (gmsh, graded toward the
contact point), one dolfinx mesh, no shared node. Regions by name (:class:`~fenics_contact.domain.NamedTags`)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

from .gmshutil import _GRADING, _from_gmsh, _graded, _load_geo, _positive, geo_path, gmsh

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

__all__ = ["cap_on_block"]


def cap_on_block(comm: MPI.Comm, R: float = 1.0, H: float = 0.5, L: float = 1.0, D: float = 0.5,
                 h_contact: float = 0.01, h_far: float = 0.15, contact_width: float = 0.1, overlap: float = 0.0,
                 balance: tuple[str, ...] = ("cap_surface", "block_top")) -> tuple[Mesh, NamedTags, NamedTags]:
    """The cap ``z <= H`` of the ball of radius ``R`` centred at ``(0, 0, R - overlap)`` and the block
    ``[-L, L] x [0, L] x [-D, 0]``, both cut to ``y >= 0`` (P1 tetrahedra; both bodies are split by the plane
    ``x = 0``, so the contact surfaces have a line of vertices along each axis).

    Size ``h_contact`` within ``contact_width`` of the origin, growing by 0.25 per unit distance up to ``h_far``.
    Cells ``cap``, ``block``; facets ``cap_surface`` (the spherical surface), ``cap_top`` (z = H), ``block_top``
    (z = 0), ``block_bottom`` (z = -D), ``symmetry`` (y = 0, both bodies). The geometry:
    ``geo/mindlin3d.geo``. gmsh meshes on rank 0, in a child process. ``balance``: the facet regions whose cells
    are split evenly over the ranks too (:func:`~fenics_contact.domain.distribute`; default the contact
    surfaces, ``()`` the graph partition alone). Collective.
    """
    _positive(R=R, H=H, L=L, D=D, h_contact=h_contact, h_far=h_far, contact_width=contact_width)
    _graded(h_contact, h_far)
    if not H < R:
        raise ValueError(f"H must be in (0, R) (the cap below the ball's equator), got H={H}, R={R}")
    if not (0.0 <= overlap < 1e-3 * R):
        raise ValueError(f"overlap must be in [0, 1e-3 R), got {overlap!r}")
    source = geo_path("mindlin3d").read_text()
    args = (1.0, H / R, L / R, D / R, h_contact / R, h_far / R, contact_width / R, overlap / R)
    mesh, cells, facets = _from_gmsh(comm, lambda: _build(*args), "the cap on a block", gdim=3, isolate=True,
                                     key=repr(args) + source, scale=R, balance=balance)
    mesh.name = "cap_on_block"
    return mesh, cells, facets


def _build(R: float, H: float, L: float, D: float, h_contact: float, h_far: float, contact_width: float,
           overlap: float) -> None:
    """Mesh ``geo/mindlin3d.geo`` in the current gmsh session."""
    gmsh.model.add("cap_on_block")
    _load_geo(geo_path("mindlin3d"), R=R, H=H, L=L, D=D, overlap=overlap, h_contact=h_contact, h_far=h_far,
              contact_width=contact_width, grading=_GRADING)
    gmsh.model.mesh.generate(3)
