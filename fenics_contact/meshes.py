"""Meshes for the contact benchmarks, with named physical tags.

``hertz_quarter_disk``, ``pin_plate`` and the seal sections (``seal_wave_section``,
``seal_s_section``, ``seal_section``) are built with gmsh on rank 0 and distributed with
``dolfinx.io.gmshio.model_to_mesh``; ``rectangle`` uses
``dolfinx.mesh.create_rectangle``, ``ring_quarter`` maps it to polar
coordinates. All functions are collective on ``comm``.

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
from collections.abc import Mapping
from typing import TYPE_CHECKING

import gmsh
import numpy as np
from dolfinx import mesh as dmesh
from dolfinx.io import gmshio
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh
    from dolfinx.mesh import MeshTagsMetaClass as MeshTags

# Physical tags of ``hertz_quarter_disk``.
DOMAIN = 1
CONTACT = 1
SYMMETRY = 2
TOP = 3
FREE = 4  # traction-free sides of ``pin_plate``
# Facet tags of ``rectangle`` (its top is RECT_TOP: TOP is taken above).
BOTTOM = 11
RIGHT = 12
RECT_TOP = 13
LEFT = 14
# Facet tags of ``sheet_over_cylinder`` (CONTACT and SYMMETRY as above).
END = 4
# Name -> tag maps, e.g. for ``check_tags``.
HERTZ_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP}
PIN_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "top": TOP, "free": FREE}
SHEET_FACETS = {"contact": CONTACT, "symmetry": SYMMETRY, "end": END}
RECTANGLE_FACETS = {"bottom": BOTTOM, "right": RIGHT, "top": RECT_TOP, "left": LEFT}
# Facet tags of ``ring_quarter``.
RING_OUTER = 21
RING_INNER = 22
RING_AXIS = 23  # x = 0
RING_MID = 24  # the horizontal diameter y = R_out
RING_FACETS = {"outer": RING_OUTER, "inner": RING_INNER, "axis": RING_AXIS, "mid": RING_MID}
# Tags of ``seal_section``: the free boundary, the symmetry line x = 0, the cell tag.
SEAL_BOUNDARY = 31
SEAL_SYMMETRY = 32
SEAL_DOMAIN = 33

# Slope of the mesh size with distance in the graded zone (size / length).
_GRADING = 0.25


def hertz_quarter_disk(
    comm: MPI.Comm,
    R: float = 1.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    contact_width: float | None = None,
) -> tuple[Mesh, MeshTags, MeshTags]:
    """Lower-right quarter (x >= 0, y <= R) of the disk of radius R centred at (0, R).

    P1 triangles of size ``h_contact`` (default R/400) within distance
    ``contact_width`` (default R/5) of the contact point (0, 0); beyond, the size
    grows linearly, by 0.25 per unit distance, up to ``h_far`` (default R/10). Facet tags:
    CONTACT (the arc from (0, 0) to (R, R)), SYMMETRY (x = 0), TOP (y = R);
    cell tag DOMAIN. Initialises and finalises gmsh (on every rank).

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
        comm, lambda: _build_quarter_disk(R, h_contact, h_far, contact_width), "the quarter disk")
    mesh.name = "hertz_quarter_disk"
    return mesh, cell_tags, facet_tags


def _from_gmsh(comm: MPI.Comm, build, what: str) -> tuple[Mesh, MeshTags, MeshTags]:
    """Run ``build()`` (adds and meshes a 2D gmsh model) on rank 0 and distribute the mesh with its tags.

    Initialises and finalises gmsh on every rank; a gmsh failure raises ``RuntimeError`` on every rank.
    """
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error = ""
        if comm.rank == 0:
            try:
                build()
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh {what}: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        return gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()


def _build_quarter_disk(R: float, h_contact: float, h_far: float, contact_width: float) -> None:
    """Build and mesh the quarter-disk model in the current gmsh session."""
    gmsh.model.add("hertz_quarter_disk")
    geo = gmsh.model.geo
    origin = geo.addPoint(0.0, 0.0, 0.0)
    centre = geo.addPoint(0.0, R, 0.0)
    corner = geo.addPoint(R, R, 0.0)
    arc = geo.addCircleArc(origin, centre, corner)
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


def pin_plate(
    comm: MPI.Comm,
    R: float = 1.0,
    half_width: float = 5.0,
    below: float = 5.0,
    above: float = 5.0,
    h_contact: float | None = None,
    h_far: float | None = None,
    band: float | None = None,
) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right half (x >= 0) of a rectangular plate with a circular hole of radius R centred at the origin.

    The plate spans ``0 <= x <= half_width``, ``-below <= y <= above``. P1
    triangles of size ``h_contact`` (default R/50) within ``band`` (default
    R/10) of the hole, then growing by 0.25 per unit distance up to ``h_far``
    (default R/2). Facet tags: CONTACT (the half hole, from (0, -R) through
    (R, 0) to (0, R)), SYMMETRY (the two pieces of x = 0), TOP (y = above),
    FREE (y = -below and x = half_width); cell tag DOMAIN.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    h_contact = R / 50 if h_contact is None else h_contact
    h_far = R / 2 if h_far is None else h_far
    band = R / 10 if band is None else band
    for name, value in (("R", R), ("half_width", half_width), ("below", below), ("above", above),
                        ("h_contact", h_contact), ("h_far", h_far), ("band", band)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    if not (half_width > R and below > R and above > R):
        raise ValueError(f"the plate (half_width={half_width}, below={below}, above={above}) must extend "
                         f"beyond the hole radius R={R} on every side")
    if h_far < h_contact:
        raise ValueError(f"h_far={h_far} must be >= h_contact={h_contact}")
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
    gmsh.model.addPhysicalGroup(1, arcs, CONTACT)
    gmsh.model.addPhysicalGroup(1, [sym_upper, sym_lower], SYMMETRY)
    gmsh.model.addPhysicalGroup(1, [top], TOP)
    gmsh.model.addPhysicalGroup(1, [bottom, right], FREE)
    gmsh.model.addPhysicalGroup(2, [surface], DOMAIN)

    # Exact distance to the hole (a gmsh Distance field samples the curve).
    distance = gmsh.model.mesh.field.add("MathEval")
    gmsh.model.mesh.field.setString(distance, "F", f"Sqrt(x*x + y*y) - {R!r}")
    _grade_toward(distance, h_contact, h_far, band)
    gmsh.model.mesh.generate(2)


def _grade_toward(distance: int, h_near: float, h_far: float, width: float) -> None:
    """Background size: ``h_near`` where the gmsh field ``distance`` is below ``width``, then growing
    by ``_GRADING`` per unit distance up to ``h_far``."""
    field = gmsh.model.mesh.field
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", h_near)
    field.setNumber(threshold, "SizeMax", h_far)
    field.setNumber(threshold, "DistMin", width)
    field.setNumber(threshold, "DistMax", width + (h_far - h_near) / _GRADING)
    field.setAsBackgroundMesh(threshold)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)


def sheet_over_cylinder(comm: MPI.Comm, R: float = 3.0, thickness: float = 1.0, leg: float = 2.0,
                        n_arc: int = 24, n_thick: int = 2, n_leg: int = 8, order: int = 2
                        ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right half of a sheet wrapped over the top of a cylinder of radius ``R`` (centre at the origin).

    A quarter annulus ``R <= r <= R + thickness``, ``0 <= theta <= 90 deg`` (``theta`` from the x axis),
    continued by a vertical leg ``R <= x <= R + thickness``, ``-leg <= y <= 0``. Structured
    quadrilaterals: ``n_arc`` along the arc, ``n_leg`` along the leg, ``n_thick`` through the
    thickness; geometry of ``order`` (2: 9-node quadrilaterals whose edges follow the circles
    exactly at their three nodes). Facet tags: CONTACT (inner arc and inner side of the leg),
    SYMMETRY (x = 0), END (y = -leg). Initialises and finalises gmsh (on every rank).
    """
    for name, value in (("R", R), ("thickness", thickness), ("leg", leg)):
        if not (math.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {value!r}")
    for name, value in (("n_arc", n_arc), ("n_thick", n_thick), ("n_leg", n_leg)):
        if int(value) < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        if comm.rank == 0:
            gmsh.model.add("sheet")
            geo = gmsh.model.geo
            Ro = R + thickness
            c, a, b, a2, b2 = (geo.addPoint(*xy, 0.0) for xy in ((0, 0), (0, R), (R, 0), (0, Ro), (Ro, 0)))
            e, e2 = geo.addPoint(R, -leg, 0.0), geo.addPoint(Ro, -leg, 0.0)
            arc_in, arc_out = geo.addCircleArc(a, c, b), geo.addCircleArc(a2, c, b2)
            sym, mid, end = geo.addLine(a, a2), geo.addLine(b, b2), geo.addLine(e, e2)
            leg_in, leg_out = geo.addLine(b, e), geo.addLine(b2, e2)
            s1 = geo.addPlaneSurface([geo.addCurveLoop([arc_in, mid, -arc_out, -sym])])
            s2 = geo.addPlaneSurface([geo.addCurveLoop([leg_in, end, -leg_out, -mid])])
            geo.synchronize()
            for curves, n in (((arc_in, arc_out), n_arc), ((sym, mid, end), n_thick), ((leg_in, leg_out), n_leg)):
                for curve in curves:
                    gmsh.model.mesh.setTransfiniteCurve(curve, int(n) + 1)
            for surface in (s1, s2):
                gmsh.model.mesh.setTransfiniteSurface(surface)
                gmsh.model.mesh.setRecombine(2, surface)
            gmsh.model.addPhysicalGroup(1, [arc_in, leg_in], CONTACT)
            gmsh.model.addPhysicalGroup(1, [sym], SYMMETRY)
            gmsh.model.addPhysicalGroup(1, [end], END)
            gmsh.model.addPhysicalGroup(2, [s1, s2], DOMAIN)
            gmsh.model.mesh.generate(2)
            gmsh.model.mesh.setOrder(order)
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    mesh.name = "sheet"
    return mesh, cell_tags, facet_tags


def rectangle(
    comm: MPI.Comm,
    width: float,
    height: float,
    nx: int,
    ny: int,
    quadrilateral: bool = False,
) -> tuple[Mesh, None, MeshTags]:
    """Rectangle [0, width] x [0, height] with nx x ny cells (triangles or quadrilaterals).

    Facet tags: BOTTOM (y = 0), RIGHT (x = width), RECT_TOP (y = height), LEFT (x = 0).

    Returns:
        ``(mesh, None, facet_tags)``.
    """
    cell_type = dmesh.CellType.quadrilateral if quadrilateral else dmesh.CellType.triangle
    msh = dmesh.create_rectangle(
        comm, [np.array([0.0, 0.0]), np.array([width, height])], [nx, ny], cell_type)
    tol = 1e-10 * max(width, height)
    sides = ((BOTTOM, 1, 0.0), (RIGHT, 0, width), (RECT_TOP, 1, height), (LEFT, 0, 0.0))
    fdim = msh.topology.dim - 1
    indices, values = [], []
    for tag, axis, coord in sides:
        facets = dmesh.locate_entities_boundary(
            msh, fdim, lambda x, a=axis, c=coord: np.abs(x[a] - c) < tol)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    index = np.concatenate(indices).astype(np.int32)
    order = np.argsort(index)
    facet_tags = dmesh.meshtags(msh, fdim, index[order], np.concatenate(values)[order])
    facet_tags.name = "facet_tags"
    return msh, None, facet_tags


def check_tags(facet_tags: MeshTags, tags: Mapping[str, int],
               comm: MPI.Comm) -> None:
    """Raise ValueError if a tag of ``tags`` (name -> value) marks no facet on any rank."""
    local = np.asarray(facet_tags.values)
    present = sorted(set().union(*comm.allgather(set(np.unique(local).tolist()))))
    for name, value in tags.items():
        if comm.allreduce(int(np.count_nonzero(local == value)), op=MPI.SUM) == 0:
            raise ValueError(f"facet tag {name!r}={value} is absent from the mesh; "
                             f"tags present: {present}")


def ring_quarter(comm: MPI.Comm, R_out: float, R_in: float, n_theta: int, n_r: int,
                 quadrilateral: bool = True) -> tuple[Mesh, None, MeshTags]:
    """Lower-right quarter (x >= 0, y <= R_out) of the ring R_in <= r <= R_out centred at (0, R_out).

    Structured polar mesh: ``n_theta`` cells along the quarter circle (equal angles), ``n_r``
    through the thickness; quadrilaterals (default) or triangles. The ring touches y = 0 at (0, 0).
    Facet tags: RING_OUTER, RING_INNER (arcs), RING_AXIS (x = 0), RING_MID (y = R_out).

    Returns:
        ``(mesh, None, facet_tags)``.
    """
    for name, value in (("n_theta", n_theta), ("n_r", n_r)):
        if int(value) != value or value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if not (0 < R_in < R_out):
        raise ValueError(f"ring radii need 0 < R_in < R_out, got R_in={R_in!r}, R_out={R_out!r}")
    msh, _, _ = rectangle(comm, 1.0, 1.0, n_theta, n_r, quadrilateral)
    x = msh.geometry.x
    theta, r = -0.5 * np.pi * (1.0 - x[:, 0]), R_in + (R_out - R_in) * x[:, 1]
    x[:, 0], x[:, 1] = r * np.cos(theta), R_out + r * np.sin(theta)
    x[np.abs(x[:, 0]) < 1e-12 * R_out, 0] = 0.0  # exact zeros on the axis
    tol = 1e-8 * R_out
    fdim = msh.topology.dim - 1
    radius = lambda p: np.hypot(p[0], p[1] - R_out)  # noqa: E731
    sides = ((RING_OUTER, lambda p: np.abs(radius(p) - R_out) < tol),
             (RING_INNER, lambda p: np.abs(radius(p) - R_in) < tol),
             (RING_AXIS, lambda p: np.abs(p[0]) < tol),
             (RING_MID, lambda p: np.abs(p[1] - R_out) < tol))
    indices, values = [], []
    for tag, where in sides:
        facets = dmesh.locate_entities_boundary(msh, fdim, where)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    index = np.concatenate(indices).astype(np.int32)
    order = np.argsort(index)
    facet_tags = dmesh.meshtags(msh, fdim, index[order], np.concatenate(values)[order])
    facet_tags.name = "facet_tags"
    msh.name = "ring_quarter"
    return msh, None, facet_tags


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
                 gap: float = 7.0) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right half (x >= 0) of the U-shaped seal section (module docstring), structured quadrilaterals of size
    about ``h`` (at least 2 through the thickness). Facet tags SEAL_BOUNDARY (outer arc, end, inner arc),
    SEAL_SYMMETRY (x = 0); cell tag SEAL_DOMAIN.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    if not (math.isfinite(h) and 0 < h <= (R_out - R_in) / 2):
        raise ValueError(f"h must be in (0, (R_out - R_in)/2], got {h!r}")
    geo_data = seal_geometry(R_out, R_in, gap)
    mesh, cell_tags, facet_tags = _from_gmsh(comm, lambda: _build_seal(geo_data, h), "the seal")
    mesh.name = "seal_section"
    return mesh, cell_tags, facet_tags


def _build_seal(d: dict, h: float) -> None:
    gmsh.model.add("seal")
    geo = gmsh.model.geo
    Ro, Ri, phi = d["R_out"], d["R_in"], d["phi"]
    C = geo.addPoint(*d["C"], 0.0)
    bottom_out, bottom_in = geo.addPoint(0.0, d["C"][1] - Ro, 0.0), geo.addPoint(0.0, d["C"][1] - Ri, 0.0)
    end_out, end_in = geo.addPoint(*d["corner_out"], 0.0), geo.addPoint(*d["corner_in"], 0.0)
    outer = geo.addCircleArc(bottom_out, C, end_out)
    end = geo.addLine(end_out, end_in)
    inner = geo.addCircleArc(end_in, C, bottom_in)
    symmetry = geo.addLine(bottom_in, bottom_out)
    surface = geo.addPlaneSurface([geo.addCurveLoop([outer, end, inner, symmetry])])
    n_t = max(2, round((Ro - Ri) / h))
    n_l = max(4, round(0.5 * (Ro + Ri) * phi / h))
    for c in (outer, inner):
        geo.mesh.setTransfiniteCurve(c, n_l + 1)
    for c in (end, symmetry):
        geo.mesh.setTransfiniteCurve(c, n_t + 1)
    geo.mesh.setTransfiniteSurface(surface)
    geo.mesh.setRecombine(2, surface)
    geo.synchronize()
    gmsh.model.addPhysicalGroup(1, [outer, end, inner], SEAL_BOUNDARY)
    gmsh.model.addPhysicalGroup(1, [symmetry], SEAL_SYMMETRY)
    gmsh.model.addPhysicalGroup(2, [surface], SEAL_DOMAIN)
    gmsh.model.mesh.generate(2)


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
                   gap: float = 7.0) -> tuple[Mesh, MeshTags, MeshTags]:
    """The S-shaped seal section: a band of thickness R_out - R_in made of two annular sectors (arcs R_out and
    R_in) of opposite curvature joined tangentially across the segment of the line C1-C2 between radii R_in and
    R_out (|C1 C2| = R_out + R_in, so the outer arc of one continues the inner arc of the other). The top of
    the left sector's outer arc touches y = ``gap``, the bottom of the right one's touches y = 0; each sector
    spans pi - 2 beta, symmetric about its vertical, ends cut radially; point-symmetric about ``P0``, the middle
    of the junction, where a mesh vertex sits. Structured quadrilaterals of size about ``h``. Facet tag
    SEAL_BOUNDARY (the whole boundary), cell tag SEAL_DOMAIN.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    if not (math.isfinite(h) and 0 < h <= (R_out - R_in) / 2):
        raise ValueError(f"h must be in (0, (R_out - R_in)/2], got {h!r}")
    data = seal_s_geometry(R_out, R_in, gap)
    mesh, cell_tags, facet_tags = _from_gmsh(comm, lambda: _build_seal_s(data, h), "the seal")
    mesh.name = "seal_s_section"
    return mesh, cell_tags, facet_tags


def _build_seal_s(d: dict, h: float) -> None:
    gmsh.model.add("seal_s")
    geo = gmsh.model.geo
    (c1x, c1y), (c2x, c2y), beta, end = d["C1"], d["C2"], d["beta"], d["end"]
    Ro, Ri = d["R_out"], d["R_in"]

    def polar(cx, cy, r, a):
        return geo.addPoint(cx + r * math.cos(a), cy + r * math.sin(a), 0.0)

    C1, C2 = geo.addPoint(c1x, c1y, 0.0), geo.addPoint(c2x, c2y, 0.0)
    j_up, j_low = polar(c1x, c1y, Ro, beta), polar(c1x, c1y, Ri, beta)
    p0 = geo.addPoint(*d["P0"], 0.0)
    l_out, l_in = polar(c1x, c1y, Ro, end), polar(c1x, c1y, Ri, end)
    r_out, r_in = polar(c2x, c2y, Ro, end + math.pi), polar(c2x, c2y, Ri, end + math.pi)
    n_t = max(2, 2 * round((Ro - Ri) / h / 2))
    n_l = max(4, round(0.5 * (Ro + Ri) * (end - beta) / h))
    a1, e1, b1 = geo.addCircleArc(j_up, C1, l_out), geo.addLine(l_out, l_in), geo.addCircleArc(l_in, C1, j_low)
    m1, m2 = geo.addLine(j_low, p0), geo.addLine(p0, j_up)
    a2, e2, b2 = geo.addCircleArc(j_low, C2, r_out), geo.addLine(r_out, r_in), geo.addCircleArc(r_in, C2, j_up)
    s1 = geo.addPlaneSurface([geo.addCurveLoop([a1, e1, b1, m1, m2])])
    s2 = geo.addPlaneSurface([geo.addCurveLoop([a2, e2, b2, -m2, -m1])])
    for c in (a1, b1, a2, b2):
        geo.mesh.setTransfiniteCurve(c, n_l + 1)
    for c in (e1, e2):
        geo.mesh.setTransfiniteCurve(c, n_t + 1)
    for c in (m1, m2):
        geo.mesh.setTransfiniteCurve(c, n_t // 2 + 1)
    geo.mesh.setTransfiniteSurface(s1, cornerTags=[j_up, l_out, l_in, j_low])
    geo.mesh.setTransfiniteSurface(s2, cornerTags=[j_low, r_out, r_in, j_up])
    for surface in (s1, s2):
        geo.mesh.setRecombine(2, surface)
    geo.synchronize()
    gmsh.model.addPhysicalGroup(1, [a1, e1, b1, a2, e2, b2], SEAL_BOUNDARY)
    gmsh.model.addPhysicalGroup(2, [s1, s2], SEAL_DOMAIN)
    gmsh.model.mesh.generate(2)


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
                      gap: float = 7.0) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right half (x >= 0) of the wave-shaped seal section (module docstring): the right half of the crown
    sector (centre C1 = (0, gap - R_out), from its top at x = 0 to the junction direction ``beta``) and the
    whole right hump (centre C2, |C1 C2| = R_out + R_in, spanning pi - 2 beta symmetric about its vertical,
    bottom of the outer arc on y = 0, end cut radially). Structured quadrilaterals of size about ``h``. Facet
    tags SEAL_BOUNDARY (arcs and end), SEAL_SYMMETRY (x = 0); cell tag SEAL_DOMAIN.

    Returns:
        ``(mesh, cell_tags, facet_tags)``.
    """
    if not (math.isfinite(h) and 0 < h <= (R_out - R_in) / 2):
        raise ValueError(f"h must be in (0, (R_out - R_in)/2], got {h!r}")
    data = seal_wave_geometry(R_out, R_in, gap)
    mesh, cell_tags, facet_tags = _from_gmsh(comm, lambda: _build_seal_wave(data, h), "the seal")
    mesh.name = "seal_wave_section"
    return mesh, cell_tags, facet_tags


def _build_seal_wave(d: dict, h: float) -> None:
    gmsh.model.add("seal_wave")
    geo = gmsh.model.geo
    (c1x, c1y), (c2x, c2y), beta, end = d["C1"], d["C2"], d["beta"], d["end"]
    Ro, Ri = d["R_out"], d["R_in"]

    def polar(cx, cy, r, a):
        return geo.addPoint(cx + r * math.cos(a), cy + r * math.sin(a), 0.0)

    C1, C2 = geo.addPoint(c1x, c1y, 0.0), geo.addPoint(c2x, c2y, 0.0)
    top_out, top_in = polar(c1x, c1y, Ro, math.pi / 2), polar(c1x, c1y, Ri, math.pi / 2)
    j_up, j_low = polar(c1x, c1y, Ro, beta), polar(c1x, c1y, Ri, beta)
    r_out, r_in = polar(c2x, c2y, Ro, end), polar(c2x, c2y, Ri, end)
    n_t = max(2, round((Ro - Ri) / h))
    n_1 = max(2, round(0.5 * (Ro + Ri) * (math.pi / 2 - beta) / h))
    n_2 = max(4, 2 * round(0.25 * (Ro + Ri) * (math.pi - 2 * beta) / h))  # even: a vertex at the hump's bottom
    sym, a1, b1 = geo.addLine(top_in, top_out), geo.addCircleArc(top_out, C1, j_up), geo.addCircleArc(j_low, C1, top_in)
    m = geo.addLine(j_up, j_low)
    a2, e2, b2 = geo.addCircleArc(j_low, C2, r_out), geo.addLine(r_out, r_in), geo.addCircleArc(r_in, C2, j_up)
    s1 = geo.addPlaneSurface([geo.addCurveLoop([sym, a1, m, b1])])
    s2 = geo.addPlaneSurface([geo.addCurveLoop([a2, e2, b2, m])])
    for c, n in ((a1, n_1), (b1, n_1), (a2, n_2), (b2, n_2), (sym, n_t), (m, n_t), (e2, n_t)):
        geo.mesh.setTransfiniteCurve(c, n + 1)
    geo.mesh.setTransfiniteSurface(s1, cornerTags=[top_in, top_out, j_up, j_low])
    geo.mesh.setTransfiniteSurface(s2, cornerTags=[j_low, r_out, r_in, j_up])
    for surface in (s1, s2):
        geo.mesh.setRecombine(2, surface)
    geo.synchronize()
    gmsh.model.addPhysicalGroup(1, [a1, b1, a2, e2, b2], SEAL_BOUNDARY)
    gmsh.model.addPhysicalGroup(1, [sym], SEAL_SYMMETRY)
    gmsh.model.addPhysicalGroup(2, [s1, s2], SEAL_DOMAIN)
    gmsh.model.mesh.generate(2)


# Tags of ``stacked_blocks``: cells of the lower and the upper block, and facets.
LOWER, UPPER = 1, 2
LOWER_BOTTOM, LOWER_TOP, UPPER_BOTTOM, UPPER_TOP, BLOCK_LEFT, BLOCK_FRONT = 21, 22, 23, 24, 25, 26
STACKED_FACETS = {"lower_bottom": LOWER_BOTTOM, "lower_top": LOWER_TOP, "upper_bottom": UPPER_BOTTOM,
                  "upper_top": UPPER_TOP, "left": BLOCK_LEFT, "front": BLOCK_FRONT}


def stacked_blocks(comm: MPI.Comm, width: float, h_lower: float, h_upper: float, n_lower: tuple[int, ...],
                   n_upper: tuple[int, ...], overlap: float = 0.0, by_body: bool = False
                   ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Two blocks in one mesh, not sharing nodes: ``[0, width] x [0, h_lower]`` with ``n_lower = (nx, ny)``
    triangles pairs, and ``[0, width] x [h_lower - overlap, h_lower - overlap + h_upper]`` with ``n_upper``.
    Three counts ``(nx, ny, nz)`` give boxes ``[0, width]^2 x [..]`` of tetrahedra (6 per hexahedron), the
    height along z. Different ``nx`` give non-matching interfaces. ``by_body``: the lower block on rank 0,
    the upper on rank 1 (with 2 or more ranks; the test of a slave/master pair on different ranks).

    Returns ``(mesh, cell_tags LOWER/UPPER, facet_tags STACKED_FACETS)`` (``front``: y = 0, in 3D only)."""
    from .compat import create_mesh

    for name, v in (("width", width), ("h_lower", h_lower), ("h_upper", h_upper)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    dim = len(n_lower)
    for name, n in (("n_lower", n_lower), ("n_upper", n_upper)):
        if len(n) not in (2, 3) or len(n) != dim or min(n) < 1:
            raise ValueError(f"{name} must be 2 (2D) or 3 (3D) cell counts >= 1, the same number for both, got {n!r}")
    xs, cs, body = [], [], []
    offset = 0
    for b, (y0, h, n) in enumerate(((0.0, h_lower, n_lower), (h_lower - overlap, h_upper, n_upper))):
        axes = [np.linspace(0, width, m + 1) for m in n[:-1]] + [np.linspace(y0, y0 + h, n[-1] + 1)]
        grid = np.meshgrid(*axes, indexing="ij")
        xs.append(np.stack([g.ravel() for g in grid], axis=1))
        idx = np.arange(grid[0].size).reshape(grid[0].shape) + offset
        if dim == 2:
            a, bb, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
            cs.append(np.concatenate([np.stack([a, bb, c], 1), np.stack([a, c, d], 1)]))
        else:  # Kuhn: 6 tetrahedra along the main diagonal, conforming across faces
            corner = {(i, j, k): idx[i:idx.shape[0] - 1 + i, j:idx.shape[1] - 1 + j, k:idx.shape[2] - 1 + k].ravel()
                      for i in (0, 1) for j in (0, 1) for k in (0, 1)}
            tets = []
            for perm in ((0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)):
                p, path = [0, 0, 0], [corner[(0, 0, 0)]]
                for ax in perm:
                    p[ax] = 1
                    path.append(corner[tuple(p)])
                tets.append(np.stack(path, 1))
            cs.append(np.concatenate(tets))
        body.append(np.full(len(cs[-1]), b))
        offset += grid[0].size
    x, cells, owner = np.concatenate(xs), np.concatenate(cs), np.concatenate(body)
    if comm.rank != 0:
        x, cells, owner = np.zeros((0, dim)), np.zeros((0, dim + 1), np.int64), np.zeros(0, np.int32)
    msh = create_mesh(comm, cells, x, "triangle" if dim == 2 else "tetrahedron", owner if by_body else None)
    tdim = msh.topology.dim
    # Cell tags by centroid height (the lower block is below h_lower - overlap/2).
    msh.topology.create_connectivity(tdim, 0)
    ncell = msh.topology.index_map(tdim).size_local + msh.topology.index_map(tdim).num_ghosts
    mid = dmesh.compute_midpoints(msh, tdim, np.arange(ncell, dtype=np.int32))
    split = h_lower - overlap / 2
    up = dim - 1  # the stacking axis
    upper = mid[:, up] > split
    cell_tags = dmesh.meshtags(msh, tdim, np.arange(ncell, dtype=np.int32),
                               np.where(upper, UPPER, LOWER).astype(np.int32))
    # Facet tags: boundary facets by position and by the block of their cell.
    fdim = tdim - 1
    msh.topology.create_connectivity(fdim, tdim)
    facets = dmesh.exterior_facet_indices(msh.topology)
    f2c = msh.topology.connectivity(fdim, tdim)
    fmid = dmesh.compute_midpoints(msh, fdim, facets)
    ub = np.array([upper[f2c.links(f)[0]] for f in facets], dtype=bool)
    tol = 1e-9 * max(width, h_lower, h_upper)
    values = np.zeros(len(facets), np.int32)
    values[(np.abs(fmid[:, up]) < tol) & ~ub] = LOWER_BOTTOM
    values[(np.abs(fmid[:, up] - h_lower) < tol) & ~ub] = LOWER_TOP
    values[(np.abs(fmid[:, up] - (h_lower - overlap)) < tol) & ub] = UPPER_BOTTOM
    values[(np.abs(fmid[:, up] - (h_lower - overlap + h_upper)) < tol) & ub] = UPPER_TOP
    values[np.abs(fmid[:, 0]) < tol] = BLOCK_LEFT
    if dim == 3:
        values[np.abs(fmid[:, 1]) < tol] = BLOCK_FRONT
    keep = values > 0
    facet_tags = dmesh.meshtags(msh, fdim, facets[keep].astype(np.int32), values[keep])
    facet_tags.name = "facet_tags"
    return msh, cell_tags, facet_tags


# Tags of ``two_half_disks`` (cells: LOWER / UPPER as for ``stacked_blocks``).
DISK_SYMMETRY, LOWER_ARC_BOTTOM, LOWER_ARC_TOP, UPPER_ARC_BOTTOM, UPPER_ARC_TOP = 31, 32, 33, 34, 35
DISKS_FACETS = {"symmetry": DISK_SYMMETRY, "lower_bottom": LOWER_ARC_BOTTOM, "lower_top": LOWER_ARC_TOP,
                "upper_bottom": UPPER_ARC_BOTTOM, "upper_top": UPPER_ARC_TOP}


def two_half_disks(comm: MPI.Comm, R_lower: float, R_upper: float, h_contact: float, h_far: float,
                   contact_width: float, overlap: float = 0.0, grading: float = _GRADING
                   ) -> tuple[Mesh, MeshTags, MeshTags]:
    """Right halves (x >= 0) of two disks stacked on the y axis, in one mesh without shared nodes: the lower
    disk centred at ``(0, R_lower)``, the upper at ``(0, 2 R_lower + R_upper - overlap)``. P1 triangles of
    size ``h_contact`` within ``contact_width`` of the four points on the y axis where the disks touch each
    other and the plates, growing by ``grading`` per unit distance up to ``h_far``. Facet tags: DISKS_FACETS
    (each arc split at its widest point into a bottom and a top quarter). Collective."""
    for name, v in (("R_lower", R_lower), ("R_upper", R_upper), ("h_contact", h_contact), ("h_far", h_far),
                    ("contact_width", contact_width)):
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error = ""
        if comm.rank == 0:
            try:
                _build_two_half_disks(R_lower, R_upper, h_contact, h_far, contact_width, overlap, grading)
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh the two half disks: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        mesh, cell_tags, facet_tags = gmshio.model_to_mesh(gmsh.model, comm, 0, gdim=2)
    finally:
        gmsh.finalize()
    mesh.name = "two_half_disks"
    return mesh, cell_tags, facet_tags


def _build_two_half_disks(R1, R2, h_contact, h_far, width, overlap, grading):
    gmsh.model.add("two_half_disks")
    geo = gmsh.model.geo
    touch = []
    tags = {k: [] for k in DISKS_FACETS.values()}
    surfaces = []
    for cy, R in ((R1, R1), (2 * R1 + R2 - overlap, R2)):
        bottom = geo.addPoint(0.0, cy - R, 0.0)
        centre = geo.addPoint(0.0, cy, 0.0)
        side = geo.addPoint(R, cy, 0.0)
        top = geo.addPoint(0.0, cy + R, 0.0)
        a1 = geo.addCircleArc(bottom, centre, side)
        a2 = geo.addCircleArc(side, centre, top)
        s1 = geo.addLine(top, centre)
        s2 = geo.addLine(centre, bottom)
        surfaces.append(geo.addPlaneSurface([geo.addCurveLoop([a1, a2, s1, s2])]))
        lower = len(surfaces) == 1
        tags[LOWER_ARC_BOTTOM if lower else UPPER_ARC_BOTTOM].append(a1)
        tags[LOWER_ARC_TOP if lower else UPPER_ARC_TOP].append(a2)
        tags[DISK_SYMMETRY] += [s1, s2]
        touch += [bottom, top]
    geo.synchronize()
    for tag, curves in tags.items():
        gmsh.model.addPhysicalGroup(1, curves, tag)
    gmsh.model.addPhysicalGroup(2, [surfaces[0]], LOWER)
    gmsh.model.addPhysicalGroup(2, [surfaces[1]], UPPER)
    field = gmsh.model.mesh.field
    distance = field.add("Distance")
    field.setNumbers(distance, "PointsList", touch)
    threshold = field.add("Threshold")
    field.setNumber(threshold, "InField", distance)
    field.setNumber(threshold, "SizeMin", h_contact)
    field.setNumber(threshold, "SizeMax", h_far)
    field.setNumber(threshold, "DistMin", width)
    field.setNumber(threshold, "DistMax", width + (h_far - h_contact) / grading)
    field.setAsBackgroundMesh(threshold)
    for option in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{option}", 0)
    gmsh.model.mesh.generate(2)
