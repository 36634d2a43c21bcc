"""Symmetric Nitsche's method for frictionless contact against a rigid obstacle (method ``nitsche``).

A reference solver of the benchmarks (Chouly & Hild 2013, ``theta = 1``),
written in the reference configuration so that it is consistent at finite
strain. With the suite's convention (gap ``g > 0`` = penetration, pressure
> 0 in compression), ``n`` the obstacle's unit normal at the current point
``x = X + u`` (into the body) and ``N`` the body's outward unit normal on the
reference surface, the force on a reference surface element is ``P N dA``
(``P`` the first Piola-Kirchhoff stress). Frictionless contact with the
nominal pressure ``p`` (force per reference area) means ``P N = p n``, so the
pressure the stress carries across the surface is

    p_s(u) = n . P(u) N            (nominal: per reference area),

the contact pressure is ``p = <gamma g + p_s(u)>`` and the surface term of
the residual, on the reference surface ``ds``, is

    int [ p (gamma dg[v] + dp_s[v]) - p_s(u) dp_s[v] ] / gamma ds,

the derivative of ``int (<gamma g + p_s>^2 - p_s^2) / (2 gamma) ds``: the
Jacobian is symmetric, and the exact solution (``P N = p n``, ``p g = 0``)
satisfies it at any ``gamma`` (consistent), unlike penalty. Every quantity is
per reference area, so ``gamma = gamma0 E / h`` with ``h`` the diameter of the
reference cell next to the facet; ``gamma0`` must be large enough for
coercivity (the bench sweeps it). ``dp_s[v]`` is the derivative of ``p_s``
along ``v`` (also through ``n`` on a curved obstacle), so a nonlinear material
gets the consistent tangent. In small strain ``P`` is the Cauchy stress; on a
flat reference surface facing the obstacle (``N = -n``) ``p_s = -n . sigma n``.
The reported pressure is nominal (:meth:`ContactSurface.mean_pressure` gives
the Cauchy one too).

Measured on the neo-Hookean block (16 % compression, ``tests/test_nitsche.py``):
the closed-form nominal pressure to 2e-14 (gamma0 = 10, 100, 1000), where the
Cauchy stress in place of ``P`` (not consistent at finite strain) penetrates by
4.6e-6 at gamma0 = 1000, 7e-4 at 10. At finite strain the functional is not
convex for small gamma0: from rest in one load step gamma0 = 1 and 3 converge
to a spurious state (gap -0.12 and +0.12); with 8 load steps gamma0 = 1 reaches
the exact one.
"""
from __future__ import annotations

import ufl

from .contact import ContactSurface
from .laws import ufl_ops
from .materials import Material, Materials

__all__ = ["NitscheContact"]


class NitscheContact(ContactSurface):
    """Contact by symmetric Nitsche; same results, output and hooks as :class:`ContactSurface`, its pressure
    the nominal ``<gamma g + p_s(u)>`` (> 0 compression). ``material``: the bulk material (for ``P``).

    Args:
        u: the problem's unknown: the displacement, or the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: a :class:`Nitsche`.
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: the surface's rule: ``nodal``, ``gauss`` or ``simpson`` (the capability grid says which).
        name: the surface's name, in messages and output.
        material: the bulk material(s).
    """

    def __init__(self, u, facet_tags, tag, obstacle, law, load, quadrature: str = "nodal", name: str = "contact",
                 material: Material | Materials | None = None):
        if material is None:
            raise ValueError("method 'nitsche' needs the bulk material (material=...) for the surface stress")
        self.material = material
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name)

    def _stress_pressure(self, w) -> ufl.core.expr.Expr:
        """``n . P(w) N``: the nominal pressure carried across the reference surface by the stress of ``w``."""
        N = ufl.FacetNormal(self.u.function_space.mesh)
        return ufl.dot(self.normal, ufl.dot(self.material.piola(w), N))

    def _pressure(self):
        mesh = self.u.function_space.mesh
        self.gamma = self.constants["gamma0"] * self.material.E / ufl.CellDiameter(mesh)
        self._ps = self._stress_pressure(self.u)
        return ufl_ops().max(self.gamma * self.gap + self._ps, 0.0)

    def residual(self, v):
        dps = ufl.derivative(self._ps, self.u, v)
        dg = ufl.derivative(self.gap, self.u, v)
        return (self.pressure * (self.gamma * dg + dps) - self._ps * dps) / self.gamma * self.ds
