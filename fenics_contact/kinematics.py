"""Kinematics of a body by its modelling assumption: the 3x3 deformation gradient and small strain of a 3D,
plane-strain or axisymmetric displacement, and the volume weight of its integrals.

Axisymmetric (``plane="axisymmetric"``): the mesh is the half meridian section ``r = x[0] >= 0``, ``z = x[1]``;
the displacement is ``(u_r, u_z)`` with no ``theta`` component and no ``theta`` dependence. The hoop terms are
``eps_tt = u_r / r`` and ``F_tt = 1 + u_r / r``; every volume and surface integral over the body of revolution
is ``int f 2 pi r dA`` (:func:`weight`): energies, tractions and contact forces are totals over the whole ring.
Cell quadrature points are interior, so ``r > 0`` there; at a point on the axis (a vertex or facet
quadrature point, a nodal interpolation) ``u_r / r`` is its limit ``d u_r / d r`` (with ``u_r = 0`` on the
axis), so no expression divides by zero. ``u_r = 0`` on the axis is the user's Dirichlet condition (e.g.
:meth:`~fenics_contact.problem.Dirichlet.on_facets` on the axis facets, component 0).

A formulation of its own (a mixed displacement-pressure one) takes :func:`deformation_gradient` and
:func:`weight` and writes ``W(F) * weight * dx``: the same in 3D, plane strain and axisymmetry.
"""
from __future__ import annotations

import math

import ufl
from ufl.domain import extract_unique_domain

__all__ = ["AXISYMMETRIC", "KINEMATICS", "radius", "weight", "deformation_gradient", "small_strain",
           "hoop_strain", "hoop_stretch"]

AXISYMMETRIC = "axisymmetric"
KINEMATICS = ("strain", AXISYMMETRIC)  # what this module computes (plane stress: materials.py, it needs the law)


def _check(u, plane: str) -> int:
    d = len(u)
    if plane not in KINEMATICS:
        raise ValueError(f"plane must be one of {KINEMATICS}, got {plane!r}")
    if plane == AXISYMMETRIC and d != 2:
        raise ValueError(f"plane='axisymmetric' needs a 2D (r, z) displacement, got a {d}D one")
    return d


def radius(u) -> ufl.core.expr.Expr:
    """The reference radius ``r = x[0]`` of the mesh ``u`` lives on (UFL)."""
    return ufl.SpatialCoordinate(extract_unique_domain(u))[0]


def weight(u, plane: str = "strain") -> ufl.core.expr.Expr:
    """The factor of every integral over the body: ``2 pi r`` (axisymmetric: totals over the ring), 1
    otherwise (per unit thickness in plane strain and stress)."""
    return 2 * math.pi * radius(u) if plane == AXISYMMETRIC else ufl.as_ufl(1.0)


def hoop_strain(u) -> ufl.core.expr.Expr:
    """``u_r / r`` of an axisymmetric displacement; on the axis ``r = 0`` its limit ``d u_r / d r``."""
    r = radius(u)
    return ufl.conditional(ufl.gt(r, 0), u[0] / r, u[0].dx(0))


def hoop_stretch(u, plane: str = "strain") -> ufl.core.expr.Expr:
    """``F_33``: ``1 + u_r / r`` (axisymmetric, the hoop stretch), 1 in plane strain."""
    return 1 + hoop_strain(u) if _check(u, plane) == 2 and plane == AXISYMMETRIC else ufl.as_ufl(1.0)


def deformation_gradient(u, plane: str = "strain") -> ufl.core.expr.Expr:
    """The 3x3 deformation gradient ``F = I + grad u`` of the 3D body: in 2D ``diag(F_2, F_33)`` with ``F_33``
    of :func:`hoop_stretch` (the third axis ``z`` in plane strain, ``theta`` in axisymmetry)."""
    d = _check(u, plane)
    if d == 3:
        return ufl.Identity(3) + ufl.grad(u)
    F2 = ufl.Identity(2) + ufl.grad(u)
    return ufl.as_matrix([[F2[0, 0], F2[0, 1], 0], [F2[1, 0], F2[1, 1], 0], [0, 0, hoop_stretch(u, plane)]])


def small_strain(u, plane: str = "strain") -> ufl.core.expr.Expr:
    """The 3x3 small strain ``sym grad u`` of the 3D body: in 2D ``diag(eps_2, eps_33)`` with ``eps_33`` 0
    (plane strain) or ``u_r / r`` (axisymmetric)."""
    d = _check(u, plane)
    e = ufl.sym(ufl.grad(u))
    if d == 3:
        return e
    e33 = hoop_strain(u) if plane == AXISYMMETRIC else 0
    return ufl.as_matrix([[e[0, 0], e[0, 1], 0], [e[1, 0], e[1, 1], 0], [0, 0, e33]])
