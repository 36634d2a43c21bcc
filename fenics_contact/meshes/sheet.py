"""Sheet wrapped over a cylinder (structured quadrilaterals, optionally 9-node) for the sheet scene."""
from __future__ import annotations

from typing import TYPE_CHECKING

from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ..domain import NamedTags

from .gmshutil import _from_gmsh, _physical, _positive, gmsh

# Physical group values (private: regions are referred to by name).
CONTACT, SYMMETRY, END, CYLINDER_SURFACE, CYLINDER_FIXED, DOMAIN, CYLINDER_DOMAIN = 1, 2, 4, 5, 6, 1, 2

__all__ = ["sheet_over_cylinder"]


def sheet_over_cylinder(comm: MPI.Comm, R: float = 3.0, thickness: float = 1.0, leg: float = 2.0,
                        n_arc: int = 24, n_thick: int = 2, n_leg: int = 8, order: int = 2,
                        cylinder: tuple[float, int, int] | None = None) -> tuple[Mesh, NamedTags, NamedTags]:
    """Right half of a sheet wrapped over the top of a cylinder of radius ``R`` (centre at the origin).

    A quarter annulus ``R <= r <= R + thickness``, ``0 <= theta <= 90 deg`` (``theta`` from the x axis),
    continued by a vertical leg ``R <= x <= R + thickness``, ``-leg <= y <= 0``. Structured
    quadrilaterals: ``n_arc`` along the arc, ``n_leg`` along the leg, ``n_thick`` through the
    thickness; geometry of ``order`` (2: 9-node quadrilaterals whose edges follow the circles
    exactly at their three nodes). Facets: ``contact`` (inner arc and inner side of the leg),
    ``symmetry`` (x = 0), ``end`` (y = -leg); cells ``sheet``.

    ``cylinder = (R_in, n_cyl, n_rad)``: the mesh also holds the right half of the hollow cylinder
    ``R_in <= r <= R`` (cells ``cylinder``), ``n_cyl`` elements along
    each of its two quarter arcs, ``n_rad`` through its wall; facets ``cylinder_surface`` (its outer arc
    ``r = R``), ``cylinder_fixed`` (``r = R_in``), ``symmetry`` (its two segments on ``x = 0``). The two bodies
    touch along ``r = R`` but share no node (``n_cyl != n_arc``: non-matching interface meshes).
    Initialises and finalises gmsh (on every rank).
    """
    _positive(R=R, thickness=thickness, leg=leg)
    for name, value in (("n_arc", n_arc), ("n_thick", n_thick), ("n_leg", n_leg)):
        if int(value) < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if cylinder is not None and not (0 < cylinder[0] < R and int(cylinder[1]) >= 1 and int(cylinder[2]) >= 1):
        raise ValueError(f"cylinder must be (R_in in (0, R), n_cyl >= 1, n_rad >= 1), got {cylinder!r}")
    if order not in (1, 2):
        raise ValueError(f"order must be 1 or 2, got {order!r}")
    def build() -> None:
        gmsh.model.add("sheet")
        gmsh.option.setNumber("Geometry.AutoCoherence", 0)  # the two bodies touch: keep their points apart
        geo = gmsh.model.geo
        Ro = R + thickness
        c, a, b, a2, b2 = (geo.addPoint(*xy, 0.0) for xy in ((0, 0), (0, R), (R, 0), (0, Ro), (Ro, 0)))
        e, e2 = geo.addPoint(R, -leg, 0.0), geo.addPoint(Ro, -leg, 0.0)
        arc_in, arc_out = geo.addCircleArc(a, c, b), geo.addCircleArc(a2, c, b2)
        sym, mid, end = geo.addLine(a, a2), geo.addLine(b, b2), geo.addLine(e, e2)
        leg_in, leg_out = geo.addLine(b, e), geo.addLine(b2, e2)
        s1 = geo.addPlaneSurface([geo.addCurveLoop([arc_in, mid, -arc_out, -sym])])
        s2 = geo.addPlaneSurface([geo.addCurveLoop([leg_in, end, -leg_out, -mid])])
        if cylinder is not None:
            Ri, n_cyl, n_rad = cylinder
            i_top, i_r, i_bot = geo.addPoint(0, Ri, 0.0), geo.addPoint(Ri, 0, 0.0), geo.addPoint(0, -Ri, 0.0)
            o_top, o_r, o_bot = geo.addPoint(0, R, 0.0), geo.addPoint(R, 0, 0.0), geo.addPoint(0, -R, 0.0)
            in_up, in_lo = geo.addCircleArc(i_top, c, i_r), geo.addCircleArc(i_r, c, i_bot)
            out_up, out_lo = geo.addCircleArc(o_top, c, o_r), geo.addCircleArc(o_r, c, o_bot)
            ax_up, ax_lo, eq = geo.addLine(i_top, o_top), geo.addLine(i_bot, o_bot), geo.addLine(i_r, o_r)
            c1 = geo.addPlaneSurface([geo.addCurveLoop([in_up, eq, -out_up, -ax_up])])
            c2 = geo.addPlaneSurface([geo.addCurveLoop([in_lo, ax_lo, -out_lo, -eq])])
        geo.synchronize()
        for curves, n in (((arc_in, arc_out), n_arc), ((sym, mid, end), n_thick), ((leg_in, leg_out), n_leg)):
            for curve in curves:
                gmsh.model.mesh.setTransfiniteCurve(curve, int(n) + 1)
        for surface in (s1, s2):
            gmsh.model.mesh.setTransfiniteSurface(surface)
            gmsh.model.mesh.setRecombine(2, surface)
        symmetry = [sym]
        if cylinder is not None:
            for curve, n in ((in_up, n_cyl), (in_lo, n_cyl), (out_up, n_cyl), (out_lo, n_cyl), (ax_up, n_rad),
                             (ax_lo, n_rad), (eq, n_rad)):
                gmsh.model.mesh.setTransfiniteCurve(curve, int(n) + 1)
            for surface in (c1, c2):
                gmsh.model.mesh.setTransfiniteSurface(surface)
                gmsh.model.mesh.setRecombine(2, surface)
            _physical(1, [out_up, out_lo], "cylinder_surface", CYLINDER_SURFACE)
            _physical(1, [in_up, in_lo], "cylinder_fixed", CYLINDER_FIXED)
            _physical(2, [c1, c2], "cylinder", CYLINDER_DOMAIN)
            symmetry += [ax_up, ax_lo]
        _physical(1, [arc_in, leg_in], "contact", CONTACT)
        _physical(1, symmetry, "symmetry", SYMMETRY)
        _physical(1, [end], "end", END)
        _physical(2, [s1, s2], "sheet", DOMAIN)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.setOrder(order)

    mesh, cell_tags, facet_tags = _from_gmsh(comm, build, "the sheet")
    mesh.name = "sheet"
    return mesh, cell_tags, facet_tags
