"""Symmetric Nitsche's method for frictionless contact against a rigid obstacle (method ``nitsche``).

A reference solver of the benchmarks (Chouly & Hild 2013, ``theta = 1``).
With the suite's convention (gap ``g > 0`` = penetration, pressure > 0 in
compression) and ``p_s(u) = -n . sigma(u) n`` the pressure the stress
carries on the surface (``n`` the obstacle's normal), the contact pressure
is ``p = <gamma g + p_s(u)>`` and the surface term of the residual is

    int [ p (gamma dg[v] + dp_s[v]) - p_s(u) dp_s[v] ] / gamma ds,

the derivative of ``int (<gamma g + p_s>^2 - p_s^2) / (2 gamma) ds``: the
Jacobian is symmetric and the method is consistent (exact for a converged
mesh at any ``gamma``), unlike penalty. ``gamma = gamma0 E / h`` with ``h``
the diameter of the cell next to the facet; ``gamma0`` must be large enough
for coercivity (the bench sweeps it). ``dp_s[v]`` is the derivative of
``p_s`` along ``v``, so a nonlinear material gets the consistent tangent.
"""
from __future__ import annotations

import ufl

from .contact import ContactSurface
from .laws import ufl_ops
from .materials import Material

__all__ = ["NitscheContact"]


class NitscheContact(ContactSurface):
    """Contact by symmetric Nitsche; same figures, output and hooks as :class:`ContactSurface`."""

    def __init__(self, u, facet_tags, tag, obstacle, law, load, quadrature: str = "nodal", name: str = "contact",
                 material: Material | None = None):
        if material is None:
            raise ValueError("method 'nitsche' needs the bulk material (material=...) for the surface stress")
        self.material = material
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name)

    def _stress_pressure(self, w) -> ufl.core.expr.Expr:
        """``-n . sigma(w) n``: compression carried across the surface by the stress of ``w``."""
        n = self.normal
        return -ufl.dot(n, ufl.dot(self.material.stress(w), n))

    def _pressure(self):
        mesh = self.u.function_space.mesh
        self.gamma = self.constants["gamma0"] * self.material.E / ufl.CellDiameter(mesh)
        self._ps = self._stress_pressure(self.u)
        return ufl_ops().max(self.gamma * self.gap + self._ps, 0.0)

    def residual(self, v):
        dps = ufl.derivative(self._ps, self.u, v)
        dg = ufl.derivative(self.gap, self.u, v)
        return (self.pressure * (self.gamma * dg + dps) - self._ps * dps) / self.gamma * self.ds
