"""Seal sections for the seal scene (gmsh, structured quadrilaterals).

Seal geometry (the paper's Figure 17 is not available, so this is our
design from its data: "two circular arcs with outer radius 10 and inner
radius 9", plates 7 apart, closed at 6.0, i.e. at plates 1 apart = a band
of thickness R_out - R_in = 1; the seal scene uses the wave by default).

Wave (``seal_wave_section``): the band bent into three annular sectors
(arcs R_out = 10 and R_in = 9) of alternating curvature: a crown convex
upward in the middle, centre C1 = (0, -3), whose outer arc touches the
upper plate y = 7 at (0, 7), between two humps convex downward, centres
C2 = (+-13.86, 10), whose outer arcs touch the lower plate y = 0 at
(+-13.86, 0). Neighbouring sectors join tangentially across the segment of
the line C1-C2 between radii 9 and 10 (|C1 C2| = 19 = R_out + R_in, so the
outer arc of one continues the inner arc of the other), at 43.2 degrees
above the horizontal from C1; each hump spans 93.7 degrees symmetric about
its vertical and ends cut radially, its upper right corner (on the inner
arc) at (20.42, 3.84). Symmetric about x = 0: ``seal_wave_section`` meshes
the right half (the crown's half and one hump), with a vertex at the
crown's top and at the hump's bottom (the initial contact points). It is
the S below (``seal_s_section``) mirrored about the top of its left sector:
the same arcs, but the symmetry holds the crown's section against
rotation, so the band is a structure between the plates, not a mechanism.
Squeezed, each half pivots on its hump (contact point moving toward the
middle), the end rises until its upper right corner touches the upper
plate, the crown's contact zone leaves the middle, then the zone under each
hump splits in two. The band cannot fold onto itself in this loading, so
no self-contact is needed.

S (``seal_s_section``): a band of thickness 1 bent into an S lying on its
side: two annular sectors bounded by arcs of radii R_out = 10 and R_in = 9
and of opposite curvature, the left one (centre C1) convex upward, the
right one (centre C2) convex downward, joined tangentially across the
segment of the line C1-C2 between radii 9 and 10 (|C1 C2| = 19 =
R_out + R_in, so the outer arc of one continues the inner arc of the
other). The top of the left outer arc touches the upper plate y = 7, the
bottom of the right outer arc the lower plate y = 0 (plates 7 apart). Each
sector spans 93.7 degrees, symmetric about its vertical, ends cut radially;
the section is point-symmetric about the middle of the junction, (0, 3.5).
Squeezed, the S rolls (contacts travel toward the middle), then its ends
touch the opposite plates at their corners, then the zone under each hump
splits in two. The rolling is a mechanism: two vertical contact forces at
different x make a couple, so until the ends touch the S turns at (almost)
no force and only the contact law's open branch fixes its position. The
band cannot fold onto itself in this loading, so no self-contact is needed
(the suite has no self-contact).

U (``seal_section``): a band of thickness 1, the annular
sector between the concentric circular arcs R_out = 10 and R_in = 9 (the
"two circular arcs"), curved as a valley (U) between the plates y = 0 and
y = 7: centre (0, R_out), so the outer arc touches the lower plate at its
bottom (0, 0); the ends are cut radially where the inner arc reaches the
upper plate, at the angle phi from the bottom with ``R_out - R_in cos phi =
7`` (phi = 70.5 degrees), so the two inner (upper) corners touch the upper
plate. The section is symmetric about x = 0; ``seal_section`` meshes the
right half. Flattening to plates 1 apart (= the thickness) straightens the
band: the upper plate holds the two inner corners throughout, and the
bottom contact zone splits into two that move apart as the middle lifts
(t = 4.5). The band cannot fold onto itself in this loading, so no
self-contact is needed (the suite has no self-contact).
"""
from __future__ import annotations

import math
from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

from .gmshutil import _from_gmsh, _load_geo, geo_path, gmsh

__all__ = [
    "seal_geometry", "seal_section", "seal_s_geometry", "seal_s_section", "seal_wave_geometry", "seal_wave_section"
]


def seal_geometry(R_out: float = 10.0, R_in: float = 9.0, gap: float = 7.0) -> dict:
    """The U-shaped seal section (see the module docstring): arc centre ``C``, half-angle ``phi`` (radians,
    from the bottom), the corners of the right end. Lower plate y = 0, upper plate y = ``gap``."""
    if not (0 < R_in < R_out):
        raise ValueError(f"seal radii need 0 < R_in < R_out, got R_in={R_in!r}, R_out={R_out!r}")
    if not (R_out - R_in < gap < R_out):
        raise ValueError(f"plate distance gap must be in (R_out - R_in, R_out), got {gap!r}")
    phi = math.acos((R_out - gap) / R_in)
    C = (0.0, R_out)
    corner = lambda r: (C[0] + r * math.sin(phi), C[1] - r * math.cos(phi))  # noqa: E731
    return {"C": C, "phi": phi, "corner_out": corner(R_out), "corner_in": corner(R_in), "R_out": R_out,
            "R_in": R_in, "gap": gap}


def seal_section(comm: MPI.Comm, h: float = 0.25, R_out: float = 10.0, R_in: float = 9.0,
                 gap: float = 7.0) -> tuple[Mesh, NamedTags, NamedTags]:
    """Right half (x >= 0) of the U-shaped seal section (module docstring), structured quadrilaterals of size
    about ``h`` (at least 2 through the thickness). Facets ``boundary`` (outer arc, end, inner arc),
    ``symmetry`` (x = 0); cells ``seal``.

    Returns:
        ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    return _seal_mesh(comm, h, seal_geometry(R_out, R_in, gap), 0, "seal_section")


def seal_s_geometry(R_out: float = 10.0, R_in: float = 9.0, gap: float = 7.0) -> dict:
    """Key points of the S-shaped seal section (see ``seal_s_section``): arc centres ``C1``, ``C2``, the
    junction direction ``beta`` (radians, from C1 toward C2), the end angle ``end`` of the left sector (from C1)
    and the centre of symmetry ``P0``. Lower plate y = 0, upper plate y = ``gap``."""
    if not (0 < R_in < R_out):
        raise ValueError(f"seal radii need 0 < R_in < R_out, got R_in={R_in!r}, R_out={R_out!r}")
    dy, d = R_out - gap / 2, (R_out + R_in) / 2
    if not (0 < dy < d):
        raise ValueError(f"plate distance gap must be in ({2 * (R_out - d)!r}, {2 * R_out!r}), got {gap!r}")
    dx = math.sqrt(d**2 - dy**2)
    beta = math.atan2(dy, dx)
    return {"C1": (-dx, gap / 2 - dy), "C2": (dx, gap / 2 + dy), "beta": beta, "end": math.pi - beta,
            "P0": (0.0, gap / 2), "R_out": R_out, "R_in": R_in, "gap": gap}


def seal_s_section(comm: MPI.Comm, h: float = 0.25, R_out: float = 10.0, R_in: float = 9.0,
                   gap: float = 7.0) -> tuple[Mesh, NamedTags, NamedTags]:
    """The S-shaped seal section: a band of thickness R_out - R_in made of two annular sectors (arcs R_out and
    R_in) of opposite curvature joined tangentially across the segment of the line C1-C2 between radii R_in and
    R_out (|C1 C2| = R_out + R_in, so the outer arc of one continues the inner arc of the other). The top of
    the left sector's outer arc touches y = ``gap``, the bottom of the right one's touches y = 0; each sector
    spans pi - 2 beta, symmetric about its vertical, ends cut radially; point-symmetric about ``P0``, the middle
    of the junction, where a mesh vertex sits. Structured quadrilaterals of size about ``h``. Facets
    ``boundary`` (the whole boundary), cells ``seal``.

    Returns:
        ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    return _seal_mesh(comm, h, seal_s_geometry(R_out, R_in, gap), 1, "seal_s_section")


def seal_wave_geometry(R_out: float = 10.0, R_in: float = 9.0, gap: float = 7.0) -> dict:
    """Key points of the wave-shaped seal section (see ``seal_wave_section``): centre ``C1`` of the middle
    (crown) sector, centre ``C2`` of the right hump, the junction direction ``beta`` (radians, from C1 toward
    C2) and the end corners of the right hump (``corner_out`` on R_out, ``corner_in`` on R_in). Lower plate
    y = 0, upper plate y = ``gap``."""
    s = seal_s_geometry(R_out, R_in, gap)
    shift = -s["C1"][0]  # the crown on x = 0
    C1, C2 = (0.0, s["C1"][1]), (s["C2"][0] + shift, s["C2"][1])
    end = 2 * math.pi - s["beta"]
    corner = lambda r: (C2[0] + r * math.cos(end), C2[1] + r * math.sin(end))  # noqa: E731
    return {"C1": C1, "C2": C2, "beta": s["beta"], "end": end, "corner_out": corner(R_out),
            "corner_in": corner(R_in), "R_out": R_out, "R_in": R_in, "gap": gap}


def seal_wave_section(comm: MPI.Comm, h: float = 0.25, R_out: float = 10.0, R_in: float = 9.0,
                      gap: float = 7.0) -> tuple[Mesh, NamedTags, NamedTags]:
    """Right half (x >= 0) of the wave-shaped seal section (module docstring): the right half of the crown
    sector (centre C1 = (0, gap - R_out), from its top at x = 0 to the junction direction ``beta``) and the
    whole right hump (centre C2, |C1 C2| = R_out + R_in, spanning pi - 2 beta symmetric about its vertical,
    bottom of the outer arc on y = 0, end cut radially). Structured quadrilaterals of size about ``h``. Facets
    ``boundary`` (arcs and end), ``symmetry`` (x = 0); cells ``seal``.

    Returns:
        ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    return _seal_mesh(comm, h, seal_wave_geometry(R_out, R_in, gap), 2, "seal_wave_section")


def _seal_mesh(comm: MPI.Comm, h: float, data: dict, shape: int, name: str) -> tuple[Mesh, NamedTags, NamedTags]:
    """Check ``h`` against the band's thickness, mesh ``geo/seal.geo`` (``shape`` 0: U, 1: S, 2: wave; ``data``
    the checked geometry) with gmsh and name the mesh."""
    if not (math.isfinite(h) and 0 < h <= (data["R_out"] - data["R_in"]) / 2):
        raise ValueError(f"h must be in (0, (R_out - R_in)/2], got {h!r}")
    path = geo_path("seal")  # a missing source: a clear error on every rank

    def build() -> None:
        gmsh.model.add(name)
        s = data["R_out"]
        _load_geo(path, shape=shape, R_out=1.0, R_in=data["R_in"] / s, gap=data["gap"] / s, h=h / s)
        gmsh.model.mesh.generate(2)

    mesh, cell_tags, facet_tags = _from_gmsh(comm, build, "the seal", scale=data["R_out"])
    mesh.name = name
    return mesh, cell_tags, facet_tags
