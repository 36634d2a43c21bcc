"""Nitsche's method between two deformable bodies (method ``nitsche``, two-body): the pointwise two-body surface
of :mod:`twobody` with the stress term of :mod:`~fenics_contact.nitsche`.

On the slave side ``s`` paired with the master facets (closest point, :mod:`twobody`), with ``g`` the gap
(> 0 penetration), ``n`` the master facet's unit normal (into the slave body) and ``p_s = n . P_s(u_s) N_s``
the nominal pressure the slave's own stress carries across its reference surface (:func:`nitsche.stress_pressure`),
the pressure is ``p = <gamma g + p_s>`` with ``gamma = gamma0 E_s / h_s`` (the slave side's Young's modulus and
cell diameter) and the surface term (:func:`nitsche.nitsche_residual`, ``theta`` 1 symmetric, 0 incomplete, -1
skew-symmetric) is

    weight int_s [ p (gamma dg[v] + theta dp_s[v]) - theta p_s dp_s[v] ] / gamma ds,

where ``v`` moves both the slave point and the paired master facet: the master part is the same integrand
differentiated with respect to the master facet's displacement ``w`` (through the gap and through ``n`` in
``p_s``), taken to the master dofs by :mod:`twobody`'s coupling.

Unbiased (Chouly, Mlika, Renard & Hild 2018, ``passes="two"``): each body's surface is slave once with
``weight = 1/2`` and its own stress, so both bodies' stresses enter and neither side is privileged. One pass
(``weight = 1``, the slave's stress only) is the biased variant. The exact solution (``P_s N_s = p n``,
``p g = 0``) satisfies the surface term at any ``gamma`` on either side: the method is consistent, and its forces
reduce to ``p dg[v]`` there. Where a slave point has no pair the normal is the slave's own (``-N_s``) and the
pressure 0: the term ``-theta p_s dp_s / gamma`` is the consistent traction-free condition there.

Non-matching meshes: the master part ``int_s p v_m(Pi x) ds`` is integrated with the slave's rule across the kinks
of the master's shape functions, so a uniform pressure is not reproduced exactly (the patch test is passed to
the quadrature's error, not to round-off). Quadrature ``segment`` (2D, P1, frictionless:
:class:`~fenics_contact.mortar.NitscheSegmentSurface`) integrates each part of a slave facet that projects on
one master facet with its own rule: the patch test to round-off.

Degree 1 (flat facets), ``nodal`` or ``gauss`` quadrature here (:mod:`capabilities`).
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

from ..laws import ContactLaw, ufl_ops
from ..materials import Material, Materials
from ..nitsche import nitsche_residual, stress_pressure
from .surface import TwoBodySurface

__all__ = ["NitscheTwoBody"]


class NitscheTwoBody(TwoBodySurface):
    """:class:`~fenics_contact.twobody.TwoBodySurface` with Nitsche's pressure ``<gamma g + p_s(u)>`` (nominal,
    > 0 compression). Arguments as :class:`~fenics_contact.twobody.TwoBodySurface`, and ``material``: the bulk
    material (a :class:`~fenics_contact.materials.Materials` for two materials: ``P`` and ``E`` are the slave
    cells')."""

    ring_weighted = False  # its stress terms carry no 2 pi r: refused on an axisymmetric body

    def __init__(self, u: fem.Function, facet_tags, slave_tag, master_tag, law: ContactLaw, load: fem.Constant,
                 quadrature: str = "nodal", weight: float = 1.0, radius: float | None = None, name: str = "twobody",
                 work_quadrature: str | None = None, exclude: np.ndarray | None = None,
                 material: Material | Materials | None = None, sliding: str = "finite", self_contact: bool = False):
        material = material if material is not None else getattr(self, "material", None)  # a subclass's
        if material is None:
            raise ValueError("method 'nitsche' needs the bulk material (material=...) for the surface stress")
        if work_quadrature not in (None, quadrature):
            raise ValueError(f"two-body Nitsche integrates with one rule: work_quadrature must be None or "
                             f"{quadrature!r}, got {work_quadrature!r}")
        self.material = material
        super().__init__(u, facet_tags, slave_tag, master_tag, law, load, quadrature, weight, radius, name,
                         work_quadrature, exclude, sliding=sliding, self_contact=self_contact)

    def _pressure(self):
        mesh = self.u.function_space.mesh
        self.gamma = self.constants["gamma0"] * self.material.E / ufl.CellDiameter(mesh)
        active = self.obstacle.active
        # unpaired points: the slave's own inward normal (the mirror's placeholder facet has none of its own)
        self.stress_normal = active * self.normal - (1.0 - active) * ufl.FacetNormal(mesh)
        self._ps = stress_pressure(self.material, self.u, self.stress_normal)
        return active * ufl_ops().max(self.gamma * self.gap + self._ps, 0.0)

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Slave part ``weight [p (gamma dg[v] + theta dp_s[v]) - theta p_s dp_s[v]] / gamma ds``; the master
        part is :meth:`master_residual`."""
        theta = self.constants["theta"]
        return self.weight * nitsche_residual(self.pressure, self.gamma, self.gap, self._ps, theta, self.u,
                                              v) * self.ds_work

    def master_residual(self, vw: ufl.Argument) -> ufl.Form:
        """Master part on the mirror test function ``vw``: the same integrand with the derivatives taken with respect
        to the mirror displacement ``w`` (the gap's, and the stress pressure's through the master normal ``n``)."""
        theta = self.constants["theta"]
        return self.weight * nitsche_residual(self.pressure, self.gamma, self.gap, self._ps, theta,
                                              self.mirror.displacement, vw) * self.ds_work

    def _point_pressure(self, g: np.ndarray) -> np.ndarray:
        """Nitsche's pressure at the slave points (nf, nq): projected on the surface space (it is not a law of the
        gap alone); 0 where unpaired."""
        if not hasattr(self, "_nitsche_rhs"):
            self._nitsche_rhs = self.projector.compile(self.pressure)
            self._pressure_now = fem.Function(self.S)
        self.projector.project(self._nitsche_rhs, self._pressure_now)
        return np.where(np.isfinite(g), self.report.field_values(self._pressure_now), 0.0)
