"""Bulk materials as stored-energy densities of the displacement ``u``.

A 2D mesh means plane strain (``u_z = 0``, ``F_zz = 1``). Units: stresses in
the units of ``E``; lengths are the mesh's.
"""
from __future__ import annotations

import math

import ufl

__all__ = ["lame", "Material", "LinearElastic", "NeoHookean", "MODELS"]


def lame(E: float, nu: float) -> tuple[float, float]:
    """Lamé constants ``(lambda, mu)`` of Young's modulus and Poisson's ratio (3D values)."""
    E, nu = float(E), float(nu)
    if not (math.isfinite(E) and E > 0):
        raise ValueError(f"Young's modulus E must be > 0, got {E!r}")
    if not (-1.0 < nu < 0.5):
        raise ValueError(f"Poisson's ratio nu must be in (-1, 0.5), got {nu!r}")
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


class Material:
    """Isotropic material given by ``E`` and ``nu``."""

    def __init__(self, E: float, nu: float):
        self.lmbda, self.mu = lame(E, nu)
        self.E, self.nu = float(E), float(nu)

    @classmethod
    def from_lame(cls, lmbda: float, mu: float) -> Material:
        if not (mu > 0 and lmbda > -2.0 * mu / 3.0):
            raise ValueError(f"Lamé constants need mu > 0 and lambda > -2 mu/3, got {lmbda!r}, {mu!r}")
        return cls(mu * (3 * lmbda + 2 * mu) / (lmbda + mu), lmbda / (2 * (lmbda + mu)))

    def energy(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        raise NotImplementedError

    def stress(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        """Cauchy stress (in-plane components in 2D)."""
        raise NotImplementedError

    def describe(self) -> dict:
        return {"model": type(self).__name__, "E": self.E, "nu": self.nu, "lambda": self.lmbda, "mu": self.mu}


class LinearElastic(Material):
    """Small-strain isotropic elasticity: ``W = mu eps:eps + lambda/2 (tr eps)^2``."""

    def energy(self, u):
        eps = ufl.sym(ufl.grad(u))
        return self.mu * ufl.inner(eps, eps) + 0.5 * self.lmbda * ufl.tr(eps) ** 2

    def stress(self, u):
        eps = ufl.sym(ufl.grad(u))
        return 2 * self.mu * eps + self.lmbda * ufl.tr(eps) * ufl.Identity(len(u))


class NeoHookean(Material):
    """Compressible neo-Hookean of the two-body paper:
    ``W = mu/2 (tr C - 3) - mu ln J + lambda/4 (J^2 - 1 - 2 ln J)``."""

    def _kinematics(self, u):
        d = len(u)
        F = ufl.Identity(d) + ufl.grad(u)
        return F, ufl.det(F), d

    def energy(self, u):
        F, J, d = self._kinematics(u)
        trC = ufl.tr(F.T * F) + (3 - d)  # plane strain: C_zz = 1
        return 0.5 * self.mu * (trC - 3) - self.mu * ufl.ln(J) + 0.25 * self.lmbda * (J**2 - 1 - 2 * ufl.ln(J))

    def stress(self, u):
        F, J, d = self._kinematics(u)
        B = F * F.T
        return (self.mu * (B - ufl.Identity(d)) + 0.5 * self.lmbda * (J**2 - 1) * ufl.Identity(d)) / J


MODELS = {"linear": LinearElastic, "neohookean": NeoHookean}
