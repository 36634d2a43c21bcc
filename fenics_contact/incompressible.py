"""Nearly incompressible materials: mixed displacement-pressure models on Taylor-Hood elements.

Displacement-only elements lock as ``nu -> 1/2`` (too stiff: wrong forces and contact widths). Here the mean
stress ``p`` is a field of its own, the second field of the unknown (P2 displacement, P1 pressure:
:func:`~fenics_contact.multipliers.unknown` with ``model=`` one of these models' names), and the energy is a
perturbed Lagrangian ``W(u, p) = W_dev(u) + p g(u) - p^2 / (2 kappa)``, ``kappa = lambda + 2 mu / 3``: its
``p`` equation is ``g = p / kappa`` weakly, well posed at ``kappa -> inf``. The residual is the first variation
of ``int W dV`` in ``(u, p)``, its ``p`` rows (volumes) times ``mu / h``
(:meth:`~MixedNeoHookean.constraint_scale`: forces, like the ``u`` rows, so that the residual's norm does not depend
on the units): a saddle point (MUMPS LU). :class:`MixedNeoHookean` at finite strain
(``g = J - 1``), :class:`MixedLinearElastic` in small strain (Herrmann's, ``g = tr eps``).

The kinematics come from the body (:class:`Kinematics`): the 3 x 3 deformation gradient and the volume weight;
plane strain and 3D by default, axisymmetric with ``plane="axisymmetric"`` (hoop stretch ``1 + u_r / r``, every
integral weighted by ``2 pi r``). Plane stress is refused (``F_33`` is then not kinematic). Without ``p``, the
energy and stresses use the eliminated ``p``, the value at the stationary point.
"""
from __future__ import annotations

import numpy as np
import ufl

from . import kinematics as _kinematics
from .materials import Material

__all__ = ["Kinematics", "MixedNeoHookean", "MixedLinearElastic"]


class Kinematics:
    """How a body's displacement ``u`` deforms it, for the mixed models: the deformation gradient as a
    3 x 3 tensor and the weight of the volume element over ``dx`` (:mod:`~fenics_contact.kinematics`). 3D, or
    plane strain in 2D (``plane="strain"``: ``F = diag(F_2, 1)``, weight 1), or axisymmetric
    (``plane="axisymmetric"``: ``F_33`` the hoop stretch ``1 + u_r / r``, weight ``2 pi r``); the energy and
    stresses are written on the 3 x 3 ``F``.

    Args:
        plane: ``strain`` (3D or plane strain) or ``axisymmetric`` (the meridian section ``(r, z)``).
    """

    def __init__(self, plane: str = "strain"):
        if plane not in _kinematics.KINEMATICS:
            raise ValueError(f"Kinematics plane must be one of {_kinematics.KINEMATICS}, got {plane!r}")
        self.plane = plane

    def deformation_gradient(self, u) -> ufl.core.expr.Expr:
        """``F`` (3 x 3) of the displacement ``u`` (2 or 3 components)."""
        return _kinematics.deformation_gradient(u, self.plane)

    def weight(self, u) -> ufl.core.expr.Expr:
        """The volume element over ``dx``: 1 (the mesh's own measure; per unit thickness in plane strain) or
        ``2 pi r`` (axisymmetric: the whole ring)."""
        return _kinematics.weight(u, self.plane)


def _in_plane(T, d: int):
    """The ``d x d`` leading block of a 3 x 3 tensor (the components the mesh's dimension carries)."""
    return T if d == 3 else ufl.as_matrix([[T[i, j] for j in range(d)] for i in range(d)])


class _Mixed(Material):
    """What both mixed models share: ``kappa``, the kinematics, the plane, the density of ``w = (u, p)``."""

    mixed = True

    def __init__(self, E: float, nu: float, plane: str = "strain", kinematics: Kinematics | None = None):
        if plane not in _kinematics.KINEMATICS:
            raise ValueError(f"model {self.model!r} is plane strain, 3D or axisymmetric, got plane {plane!r}")
        if kinematics is not None and kinematics.plane != plane:
            raise ValueError(f"model {self.model!r}: kinematics of plane {kinematics.plane!r} given for plane "
                             f"{plane!r}")
        super().__init__(E, nu, plane)
        self.kappa = self.lmbda + 2.0 * self.mu / 3.0
        self.kinematics = kinematics or Kinematics(plane)

    def weight(self, u) -> ufl.core.expr.Expr:
        """The kinematics' volume weight (``2 pi r`` if axisymmetric, else 1): every integral over the body."""
        return self.kinematics.weight(u)

    def constraint_scale(self, domain) -> ufl.core.expr.Expr:
        """The factor of the ``p`` rows of the residual, ``mu / h`` (``h`` the cell's diameter; a stress per
        length): the rows ``int (g - p / kappa) q dx`` are volumes, the displacement rows forces; times it they
        are forces too, of a shear stress over a cell, and the residual's norm (the line search, the convergence
        test) does not depend on the units. Newton's step does not depend on it.

        Args:
            domain: the mesh's UFL domain.
        """
        return self.mu / ufl.CellDiameter(domain)

    def density(self, w):
        """``W(u, p)`` of the mixed unknown ``w = (u, p)`` (per ``dx``; :meth:`bulk_form` weights it)."""
        u, p = ufl.split(w)
        return self.energy(u, p)

    def describe(self) -> dict:
        return {**super().describe(), "kappa": self.kappa}


class MixedNeoHookean(_Mixed):
    """Nearly incompressible neo-Hookean, finite strain, in the mixed displacement-pressure form:

        ``W(F, p) = mu/2 (J^(-2/3) tr C - 3) + p (J - 1) - p^2 / (2 kappa)``,  ``kappa = lambda + 2 mu / 3``,

    the u/p formulation of Sussman & Bathe (1987, Computers & Structures 26, 357-409) with the decoupled
    (isochoric/volumetric) neo-Hookean energy of Simo & Taylor (1991, CMAME 85, 273-310). ``p`` is a field of
    its own (the second field of the unknown, Taylor-Hood P2-P1: :func:`~fenics_contact.multipliers.unknown` with
    ``model="neohookean-mixed"``): the mean Cauchy stress, > 0 in tension, in the units of ``E``. Its equation is
    ``J - 1 = p / kappa`` weakly. Eliminating ``p`` gives ``mu/2 (I1_bar - 3) + kappa/2 (J - 1)^2`` (``energy(u)``
    without ``p``), whose small-strain limit is linear elasticity of ``E``, ``nu``.

    Args:
        E: Young's modulus (stress), > 0.
        nu: Poisson's ratio, in (-1, 0.5); up to 0.4999 and beyond without locking.
        plane: ``strain`` (plane strain in 2D; 3D) or ``axisymmetric`` (the meridian section ``(r, z)``);
            ``stress`` is refused.
        kinematics: the body's :class:`Kinematics` (None: that of ``plane``).
    """

    model = "neohookean-mixed"

    def _pressure(self, J, p):
        return self.kappa * (J - 1) if p is None else p

    def energy(self, u, p=None):
        """``W`` per unit reference volume of the displacement ``u`` and the pressure ``p`` (None: eliminated)."""
        F = self.kinematics.deformation_gradient(u)
        J = ufl.det(F)
        iso = 0.5 * self.mu * (J ** (-2.0 / 3.0) * ufl.tr(F.T * F) - 3)
        if p is None:
            return iso + 0.5 * self.kappa * (J - 1) ** 2
        return iso + p * (J - 1) - p**2 / (2 * self.kappa)

    def stress(self, u, p=None):
        """Cauchy stress ``mu J^(-5/3) dev(B) + p I`` (in-plane components in 2D)."""
        F = self.kinematics.deformation_gradient(u)
        J = ufl.det(F)
        B = F * F.T
        s = self.mu * J ** (-5.0 / 3.0) * (B - ufl.tr(B) / 3 * ufl.Identity(3)) + self._pressure(J, p) * ufl.Identity(3)
        return _in_plane(s, len(u))

    def piola(self, u, p=None):
        """``P = mu J^(-2/3) (F - tr C / 3 F^-T) + p J F^-T`` (in-plane components in 2D)."""
        F = self.kinematics.deformation_gradient(u)
        J = ufl.det(F)
        FinvT = ufl.inv(F).T
        P = self.mu * J ** (-2.0 / 3.0) * (F - ufl.tr(F.T * F) / 3 * FinvT) + self._pressure(J, p) * J * FinvT
        return _in_plane(P, len(u))

    def area_ratio(self, u, N):
        F = self.kinematics.deformation_gradient(u)
        N3 = ufl.as_vector([N[i] for i in range(len(u))] + [0.0] * (3 - len(u)))
        FinvTN = ufl.dot(ufl.inv(F).T, N3)
        return ufl.det(F) * ufl.sqrt(ufl.dot(FinvTN, FinvTN))

    def uniaxial(self, a: float, c: float, dim: int) -> tuple[float, float]:
        """Nominal stresses ``(P_lateral, P_axial)`` of the homogeneous ``F = diag(a, .., c)`` (``a`` in the
        ``dim - 1`` lateral directions of the mesh; plane strain: ``F_33 = 1``) at the eliminated pressure
        ``p = kappa (J - 1)``: the closed form the scenes' exact states solve for."""
        s = [a] * (dim - 1) + [c] + [1.0] * (3 - dim)
        J, I1 = float(np.prod(s)), float(np.sum(np.square(s)))
        p = self.kappa * (J - 1)
        P = [self.mu * J ** (-2 / 3) * (x - I1 / (3 * x)) + p * J / x for x in s]
        return P[0], P[dim - 1]


class MixedLinearElastic(_Mixed):
    """Nearly incompressible small-strain elasticity in Herrmann's mixed form (Herrmann 1965, AIAA J. 3,
    1896-1900):

        ``W(eps, p) = mu dev(eps) : dev(eps) + p tr(eps) - p^2 / (2 kappa)``,  ``eps = sym(F - I)`` (3 x 3),

    ``p`` the mean stress (> 0 in tension), the second field of the Taylor-Hood unknown
    (``model="linear-mixed"``); its equation is ``tr eps = p / kappa`` weakly. Eliminating ``p`` gives
    ``mu eps : eps + lambda/2 (tr eps)^2``, :class:`~fenics_contact.materials.LinearElastic`'s energy.

    Args:
        E: Young's modulus (stress), > 0.
        nu: Poisson's ratio, in (-1, 0.5); up to 0.4999 and beyond without locking.
        plane: ``strain`` (plane strain in 2D; 3D) or ``axisymmetric`` (the meridian section ``(r, z)``);
            ``stress`` is refused.
        kinematics: the body's :class:`Kinematics` (None: that of ``plane``).
    """

    linear = True
    model = "linear-mixed"

    def _strain(self, u):
        eps = ufl.sym(self.kinematics.deformation_gradient(u) - ufl.Identity(3))
        return eps, eps - ufl.tr(eps) / 3 * ufl.Identity(3)

    def energy(self, u, p=None):
        """``W`` per unit volume of the displacement ``u`` and the pressure ``p`` (None: eliminated)."""
        eps, dev = self._strain(u)
        if p is None:
            return self.mu * ufl.inner(dev, dev) + 0.5 * self.kappa * ufl.tr(eps) ** 2
        return self.mu * ufl.inner(dev, dev) + p * ufl.tr(eps) - p**2 / (2 * self.kappa)

    def stress(self, u, p=None):
        """``2 mu dev(eps) + p I`` (in-plane components in 2D)."""
        eps, dev = self._strain(u)
        p = self.kappa * ufl.tr(eps) if p is None else p
        return _in_plane(2 * self.mu * dev + p * ufl.Identity(3), len(u))

    def piola(self, u, p=None):
        return self.stress(u, p)

    def area_ratio(self, u, N):
        return ufl.as_ufl(1.0)
