"""Bulk materials as stored-energy densities of the displacement ``u``.

A 2D mesh means plane strain (``u_z = 0``, ``F_zz = 1``) by default, plane
stress (``plane="stress"``: ``sigma_zz = 0``, the out-of-plane stretch a
function of the in-plane deformation, see each model), or axisymmetry
(``plane="axisymmetric"``: the mesh is the meridian section ``(r, z) = (x[0], x[1])``,
``r >= 0``; hoop strain ``u_r / r``, every integral weighted by ``2 pi r``, see
:mod:`~fenics_contact.kinematics`). Units: stresses in the
units of ``E``; lengths are the mesh's. :class:`Materials` gives each body
(cell tag) its own material.

Every model gives its stored energy ``W(u)``, the Cauchy stress, the first
Piola-Kirchhoff stress ``P`` (force per reference area; the Cauchy stress for
the small-strain model, whose reference and current configurations are one)
and the area ratio ``da/dA`` of a surface with reference normal ``N``
(Nanson: ``J |F^-T N|``; 1 in small strain): the contact pressures are
nominal (per reference area), their Cauchy (true) value is nominal ``/ (da/dA)``.

:meth:`Material.density` is the energy density of the problem's unknown ``w`` (a displacement, or a mixed
Function whose first field is the displacement): what :class:`~fenics_contact.problem.ContactProblem`
differentiates. The mixed displacement-pressure models of nearly incompressible bodies are in
:mod:`~fenics_contact.incompressible`; every model by name in :data:`~fenics_contact.models.MODELS`.
"""
from __future__ import annotations

import math
from typing import Mapping

import numpy as np
import ufl
from mpi4py import MPI

from .kinematics import AXISYMMETRIC, hoop_stretch, small_strain
from .kinematics import weight as _weight

__all__ = ["PLANES", "lame", "Material", "LinearElastic", "NeoHookean", "Materials"]

PLANES = ("strain", "stress", AXISYMMETRIC)


def lame(E: float, nu: float) -> tuple[float, float]:
    """Lamé constants ``(lambda, mu)`` of Young's modulus and Poisson's ratio (3D values).

    Args:
        E: Young's modulus (stress), > 0.
        nu: Poisson's ratio, in (-1, 0.5).

    Returns:
        ``(lambda, mu)``, stress (3D values; a plane-stress material uses its own ``lambda*``).
    """
    E, nu = float(E), float(nu)
    if not (math.isfinite(E) and E > 0):
        raise ValueError(f"Young's modulus E must be > 0, got {E!r}")
    if not (-1.0 < nu < 0.5):
        raise ValueError(f"Poisson's ratio nu must be in (-1, 0.5), got {nu!r}")
    return E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))


class Material:
    """Isotropic material given by ``E`` and ``nu``; ``plane``: ``strain``, ``stress`` or ``axisymmetric``, the
    2D assumption (a 3D displacement with ``plane="stress"`` or ``"axisymmetric"`` is refused).

    Args:
        E: Young's modulus (stress), > 0.
        nu: Poisson's ratio, in (-1, 0.5).
        plane: the 2D assumption, ``strain``, ``stress`` or ``axisymmetric`` (the meridian section
            ``(r, z) = (x[0], x[1])``; every integral weighted by ``2 pi r``); 3D: ``strain``.
    """

    linear = False  # True: small strain (a constant stiffness; reference and current configurations are one)
    mixed = False  # True: the unknown is (displacement, pressure), :meth:`density` reads both
    model = ""  # the capability grid's name of the model (:data:`~fenics_contact.models.MODELS`)
    quadrature_degree: int | None = None  # of the bulk integrals; None: UFL's estimate from the energy's form

    def __init__(self, E: float, nu: float, plane: str = "strain"):
        if plane not in PLANES:
            raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
        self.lmbda, self.mu = lame(E, nu)
        self.E, self.nu, self.plane = float(E), float(nu), plane

    @classmethod
    def from_lame(cls, lmbda: float, mu: float, plane: str = "strain") -> Material:
        if not (mu > 0 and lmbda > -2.0 * mu / 3.0):
            raise ValueError(f"Lamé constants need mu > 0 and lambda > -2 mu/3, got {lmbda!r}, {mu!r}")
        return cls(mu * (3 * lmbda + 2 * mu) / (lmbda + mu), lmbda / (2 * (lmbda + mu)), plane)

    def _dim(self, u) -> int:
        d = len(u)
        if self.plane != "strain" and d != 2:
            raise ValueError(f"plane={self.plane!r} is a 2D assumption, got a {d}D displacement")
        return d

    @property
    def axisymmetric(self) -> bool:
        """True for an axisymmetric body (integrals over the ring, :meth:`weight`)."""
        return self.plane == AXISYMMETRIC

    def weight(self, u) -> ufl.core.expr.Expr:
        """The factor of every integral over the body: ``2 pi r`` if axisymmetric, else 1 (per unit
        thickness in 2D)."""
        return _weight(u, self.plane if self.axisymmetric else "strain")

    def energy(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        raise NotImplementedError

    def energy_form(self, u: ufl.core.expr.Expr) -> ufl.Form:
        """The bulk stored energy ``int W(u) dx`` (axisymmetric: ``int W(u) 2 pi r dx``, the whole ring's)."""
        return self.energy(u) * self.weight(u) * self._dx()

    def density(self, w) -> ufl.core.expr.Expr:
        """The stored energy per ``dx`` of the problem's unknown ``w`` (its displacement field)."""
        from .contact import displacement

        return self.energy(displacement(w))

    def bulk_form(self, w) -> ufl.Form:
        """``int density(w) dx``: the bulk energy :class:`~fenics_contact.problem.ContactProblem` differentiates
        (axisymmetric: weighted by ``2 pi r``)."""
        from .contact import displacement

        return self.density(w) * self.weight(displacement(w)) * self._dx()

    def _dx(self) -> ufl.Measure:
        """The bulk measure, with :attr:`quadrature_degree` when set (UFL's estimate for a non-polynomial energy,
        ``J^(-2/3)`` or the hoop term ``u_r / r``, is far above what the displacement's degree needs)."""
        q = self.quadrature_degree
        return ufl.dx if q is None else ufl.dx(metadata={"quadrature_degree": int(q)})

    def stress(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        """Cauchy stress (in-plane components in 2D; axisymmetric: the (r, z) components)."""
        raise NotImplementedError

    def piola(self, u: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        """First Piola-Kirchhoff stress ``P = dW/dF`` (in-plane components in 2D): ``P N dA`` is the force
        on a reference surface element ``N dA``."""
        raise NotImplementedError

    def area_ratio(self, u: ufl.core.expr.Expr, N: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        """``da/dA`` of the surface with reference unit normal ``N`` (per unit thickness in plane strain)."""
        raise NotImplementedError

    def describe(self) -> dict:
        return {"model": type(self).__name__, "E": self.E, "nu": self.nu, "lambda": self.lmbda, "mu": self.mu,
                "plane": self.plane}


# The strain (largest principal value of sym(grad u)) past which a small-strain model is out of its depth: the
# quadratic term it drops from the Green-Lagrange strain, grad u^T grad u / 2, is then 2.5 % of it or more.
SMALL_STRAIN = 0.05


class LinearElastic(Material):
    """Small-strain isotropic elasticity: ``W = mu eps:eps + lambda/2 (tr eps)^2``; plane stress in 2D with
    ``lambda* = 2 lambda mu / (lambda + 2 mu)`` (``sigma_zz = 0`` eliminates ``eps_zz``). Valid for strains
    (and rotations) well below :data:`SMALL_STRAIN`; the solver flags a run that goes past it. Axisymmetric: the
    3x3 strain with the hoop strain ``u_r / r``, every integral weighted by ``2 pi r``.

    Args:
        E: Young's modulus (stress), > 0.
        nu: Poisson's ratio, in (-1, 0.5).
        plane: the 2D assumption, ``strain``, ``stress`` or ``axisymmetric`` (the meridian section ``(r, z)``);
            3D: ``strain`` (a 3D body with ``stress`` or ``axisymmetric`` is refused).
    """

    linear = True
    model = "linear"

    def _lambda(self, d: int):
        return 2 * self.lmbda * self.mu / (self.lmbda + 2 * self.mu) if self.plane == "stress" else self.lmbda

    def _strain(self, u):
        """The strain whose energy is the body's: 3x3 with the hoop strain if axisymmetric, else ``sym grad u``."""
        d = self._dim(u)
        return small_strain(u, AXISYMMETRIC) if self.axisymmetric else ufl.sym(ufl.grad(u)), d

    def energy(self, u):
        eps, d = self._strain(u)
        lmbda = self._lambda(d)
        return self.mu * ufl.inner(eps, eps) + 0.5 * lmbda * ufl.tr(eps) ** 2

    def stress(self, u):
        eps, d = self._strain(u)
        lmbda = self._lambda(d)
        sigma = 2 * self.mu * eps + lmbda * ufl.tr(eps) * ufl.Identity(eps.ufl_shape[0])
        return ufl.as_matrix([[sigma[i, j] for j in range(d)] for i in range(d)]) if self.axisymmetric else sigma

    def hoop_stress(self, u):
        """``sigma_tt`` of an axisymmetric body (UFL)."""
        if not self.axisymmetric:
            raise ValueError(f"hoop_stress is for plane='axisymmetric', got plane={self.plane!r}")
        eps, _ = self._strain(u)
        return 2 * self.mu * eps[2, 2] + self.lmbda * ufl.tr(eps)

    def piola(self, u):
        return self.stress(u)

    def area_ratio(self, u, N):
        return ufl.as_ufl(1.0)


class NeoHookean(Material):
    """Compressible neo-Hookean of the two-body paper:
    ``W = mu/2 (tr C - 3) - mu ln J + lambda/4 (J^2 - 1 - 2 ln J)``.

    2D: ``F = diag(F_2, lambda_3)``, ``lambda_3 = 1`` in plane strain, ``1 + u_r / r`` (the hoop stretch) in
    axisymmetry; in plane stress ``P_33 = 0``, i.e.
    ``mu (lambda_3^2 - 1) + lambda/2 (J^2 - 1) = 0`` with ``J = J_2 lambda_3``, solved in closed form per
    point: ``lambda_3^2 = (mu + lambda/2) / (mu + lambda J_2^2 / 2)``. ``W(F_2, lambda_3(F_2))`` is then the
    plane-stress energy: its derivative is ``P_2`` (``dW/dlambda_3 = P_33 = 0``), and UFL differentiates
    through ``lambda_3`` for the consistent tangent.

    Args:
        E: Young's modulus (stress), > 0.
        nu: Poisson's ratio, in (-1, 0.5).
        plane: the 2D assumption, ``strain`` or ``stress`` (3D: ``strain``, a 3D body with ``stress`` is refused).
    """

    model = "neohookean"

    def _kinematics(self, u):
        d = self._dim(u)
        F = ufl.Identity(d) + ufl.grad(u)
        J2 = ufl.det(F)
        if d == 3:
            return F, J2, ufl.as_ufl(1.0), d
        if self.plane == "stress":
            l3 = ufl.sqrt((self.mu + 0.5 * self.lmbda) / (self.mu + 0.5 * self.lmbda * J2**2))
        else:
            l3 = hoop_stretch(u, AXISYMMETRIC if self.axisymmetric else "strain")
        return F, J2 * l3, l3, d

    def energy(self, u):
        F, J, l3, d = self._kinematics(u)
        trC = ufl.tr(F.T * F) + (l3**2 if d == 2 else 0.0)
        return 0.5 * self.mu * (trC - 3) - self.mu * ufl.ln(J) + 0.25 * self.lmbda * (J**2 - 1 - 2 * ufl.ln(J))

    def stress(self, u):
        F, J, _, d = self._kinematics(u)
        B = F * F.T
        return (self.mu * (B - ufl.Identity(d)) + 0.5 * self.lmbda * (J**2 - 1) * ufl.Identity(d)) / J

    def piola(self, u):
        F, J, _, _ = self._kinematics(u)
        FinvT = ufl.inv(F).T
        return self.mu * (F - FinvT) + 0.5 * self.lmbda * (J**2 - 1) * FinvT

    def area_ratio(self, u, N):
        F, J, _, _ = self._kinematics(u)  # J includes lambda_3: the thickness changes in plane stress
        FinvTN = ufl.dot(ufl.inv(F).T, N)
        return J * ufl.sqrt(ufl.dot(FinvTN, FinvTN))


class Materials:
    """One material per body: ``by_tag`` maps each cell tag of ``cell_tags`` (on ``mesh``) to its :class:`Material`
    (a tag is an integer value, or a region name of :class:`~fenics_contact.domain.NamedTags`).

    The bulk energy is ``sum over tags of int W_tag dx(tag)``; every cell must carry one of the tags; the bodies
    are all axisymmetric or none (one mesh, one meaning of ``x[0]``). The
    stress, Piola stress, area ratio and ``E`` (for Nitsche's parameter) are the tag's, through a DG0
    indicator per tag, so they evaluate on cells and on boundary facets alike. ``linear`` if every body is.

    Args:
        mesh: the mesh.
        cell_tags: the cell tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        by_tag: cell tag (value or region name) -> its :class:`Material`.
    """

    def __init__(self, mesh, cell_tags, by_tag: Mapping[int | str, Material]):
        from dolfinx import fem

        from .compat import function_space
        from .domain import tag_value

        if not by_tag:
            raise ValueError("Materials needs at least one (cell tag, material) pair, got none")
        for tag, m in by_tag.items():
            if not isinstance(m, Material):
                raise ValueError(f"Materials: tag {tag!r} maps to {type(m).__name__}, not a Material")
        if cell_tags is None:
            raise ValueError("Materials needs the mesh's cell tags, got None")
        values = {tag: tag_value(cell_tags, tag)[1] for tag in by_tag}
        cell_tags = tag_value(cell_tags, 0)[0]  # the dolfinx MeshTags
        tdim = mesh.topology.dim
        if cell_tags.dim != tdim:
            raise ValueError(f"Materials needs cell tags (dimension {tdim}), got tags of dimension {cell_tags.dim}")
        self.by_tag = {values[k]: v for k, v in by_tag.items()}
        axisymmetric = {m.axisymmetric for m in self.by_tag.values()}
        if len(axisymmetric) > 1:
            raise ValueError("Materials: the bodies of one mesh are all axisymmetric or none, got "
                             f"planes {sorted({m.plane for m in self.by_tag.values()})}")
        self.axisymmetric = axisymmetric.pop()
        self.cell_tags, self.mesh = cell_tags, mesh
        n_owned = mesh.topology.index_map(tdim).size_local
        covered = np.unique(cell_tags.indices[np.isin(cell_tags.values, list(self.by_tag))])
        missing = mesh.comm.allreduce(int(n_owned - np.count_nonzero(covered < n_owned)), op=MPI.SUM)
        if missing:
            raise ValueError(f"Materials: {missing} cells carry none of the tags {sorted(self.by_tag)}; "
                             "every cell needs a material")
        self.dx = ufl.Measure("dx", domain=mesh, subdomain_data=cell_tags)
        D = function_space(mesh, "DG", 0)
        self.indicator = {}
        for tag in self.by_tag:
            chi = fem.Function(D, name=f"body_{tag}")
            cells = cell_tags.indices[cell_tags.values == tag]
            chi.x.array[[D.dofmap.cell_dofs(c)[0] for c in cells]] = 1.0
            chi.x.scatter_forward()
            self.indicator[tag] = chi
        self.linear = all(m.linear for m in self.by_tag.values())
        self.mixed = any(m.mixed for m in self.by_tag.values())
        if self.mixed and not all(m.mixed for m in self.by_tag.values()):
            raise ValueError("Materials: a mixed model on some bodies only; the pressure field spans the mesh, give "
                             "every body a mixed model or none")
        self.model = "linear" if self.linear else next(m.model for m in self.by_tag.values() if not m.linear)

    def _sum(self, f):
        return sum(self.indicator[t] * f(m) for t, m in self.by_tag.items())

    def energy_form(self, u) -> ufl.Form:
        """``sum over tags of int W_tag dx(tag)`` (what :class:`~fenics_contact.problem.ContactProblem` uses;
        axisymmetric: weighted by ``2 pi r``)."""
        return sum(m.energy(u) * m.weight(u) * self.dx(t) for t, m in self.by_tag.items())

    def weight(self, u) -> ufl.core.expr.Expr:
        """The factor of every integral over the bodies (:meth:`Material.weight`, the same for all)."""
        return next(iter(self.by_tag.values())).weight(u)

    def bulk_form(self, w) -> ufl.Form:
        """``sum over tags of int density_tag(w) dx(tag)`` (what :class:`~fenics_contact.problem.ContactProblem`
        differentiates)."""
        from .contact import displacement

        return sum(m.density(w) * m.weight(displacement(w)) * self.dx(t) for t, m in self.by_tag.items())

    def energy(self, u):
        """The energy density per body (through the indicators): ``energy(u) * dx`` equals :meth:`energy_form`."""
        return self._sum(lambda m: m.energy(u))

    def stress(self, u):
        return self._sum(lambda m: m.stress(u))

    def piola(self, u):
        return self._sum(lambda m: m.piola(u))

    def area_ratio(self, u, N):
        return self._sum(lambda m: m.area_ratio(u, N))

    @property
    def E(self):
        """Young's modulus per body (UFL)."""
        return self._sum(lambda m: m.E)

    def describe(self) -> dict:
        return {"model": "Materials", "bodies": {str(t): m.describe() for t, m in self.by_tag.items()}}
