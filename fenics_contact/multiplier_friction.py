"""Exact Coulomb and Tresca friction against rigid obstacles with the contact traction an unknown (method
``lagrange`` with friction): Alart and Curnier's complementarity functions, solved with the displacement by one
semismooth Newton on the whole sparse system.

The unknown is ``w = (u, lam)`` (:func:`~fenics_contact.multipliers.unknown`): ``lam`` the traction of the
obstacle on the body, a P1 vector on the whole mesh, fixed to 0 off the contact surfaces
(:class:`~fenics_contact.multipliers.PressureUnknown`: the same field split, MUMPS on the real unknowns). At each
contact vertex (vertex rule), with ``p = lam . n`` (> 0 compression), ``q = P_T lam`` (``P_T = I - n n``), the gap
``g`` (> 0 penetration) and the slip increment ``ds = P_T (r - r_old)`` since the last accepted step (``r`` the
position relative to the obstacle):

    normal        C_n = p - max(0, p + c g)
    tangential    C_t = q - proj_b(q - c ds),   b = mu max(0, p + c g)  (Coulomb),  b = s [p + c g > 0]  (Tresca)

``proj_b`` the projection on the disk (ball) of radius ``b``; ``C = 0`` iff Signorini's conditions and Coulomb's law
(stick: ``ds = 0``, ``|q| <= b``; slip: ``|q| = b``, ``q`` against ``ds``) hold, for any ``c > 0`` (the law's
complementarity parameter, which steers the iterates only). The residual is

    u rows:    dW[v] + int (p - a C_n) dg[v] ds - int (q - a C_t) . v ds
    lam rows:  int (-C_n (mu . n) - C_t . P_T mu) ds

(forces, like the multipliers' normal rows), with ``a = AUGMENT`` (100): the u rows' tractions are augmented, ``p -
a C_n`` and ``q - a C_t``, which are ``p`` and ``q`` where ``C = 0`` (the same solution) and give the displacement
block the stiffness ``a c`` of the closed and sticking points (an iterative solve needs fewer iterations). Its
Jacobian ``ufl.derivative`` of it: the derivatives of ``max`` and of the projection are UFL's generalized ones, so
SNES ``newtonls`` is a semismooth Newton on displacements and tractions together: sparse and distributed, no
condensed (dense) block, no gather. Time discretization as the condensed method's (backward Euler in the load: slip
increments per step), so that on a flat obstacle with linear elasticity both solve the same discrete problem.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem
from scipy.spatial import cKDTree

from .compat import collapse
from .contact import ContactSurface, contact_measure, displacement
from .friction import OPEN, SLIP, STICK, Friction, FrictionalContact, friction_ops
from .laws import LagrangeMultiplier, ufl_ops
from .multipliers import PressureUnknown
from .obstacles import Obstacle
from .twobody.friction import FrictionalTwoBodySurface

__all__ = ["alart_curnier", "prescribed_traction", "MultiplierFrictionalContact", "MultiplierFrictionalTwoBody"]

# The u rows' augmentation, in units of Alart-Curnier's c: their tractions p - AUGMENT C_n, q - AUGMENT C_t give the
# displacement block the stiffness AUGMENT c (dg dg + P_T) at the closed, sticking points (about 10 E / h with the
# demos' c, E / (10 h)): the saddle point's Schur complement is then nearly the multipliers' own block, and FGMRES
# with the field split needs fewer iterations. Measured on mindlin3d, Krylov iterations per Newton iteration: 72 ->
# 39 at 72,461 dofs (AUGMENT 1 -> 100; 30: 10 % more than 100, 300: more than 1, 1000: GAMG fails).
AUGMENT = 100.0
_TINY = 1e-300  # |x| = sqrt(x . x + tiny): a finite derivative at x = 0 (the stick branch never uses it)


def alart_curnier(lam, n, g, ds, params: dict) -> dict:
    """Alart and Curnier's functions at a contact point (UFL): the traction ``lam`` (of the other side on the
    body), the unit normal ``n``, the gap ``g`` (> 0 penetration), the slip increment ``ds`` and the law's
    ``params`` (``c``; ``mu`` or ``tresca``). Returns ``p``, ``q`` (normal and tangential traction), ``bound``,
    ``C_n``, ``C_t`` (see the module), ``state`` (0 open, 1 slip, 2 stick) and ``dissipation`` (``-q . ds``)."""
    f = friction_ops(ufl_ops())
    c = params["c"]

    def tangential(a):
        return a - ufl.dot(a, n) * n

    p = ufl.dot(lam, n)
    q = tangential(lam)
    closing = p + c * g
    if "mu" in params:
        bound = params["mu"] * ufl.max_value(closing, 0.0)
    else:
        bound = ufl.conditional(ufl.gt(closing, 0.0), params["tresca"], 0.0)
    slip = tangential(ds)
    trial = q - c * slip
    norm = f.sqrt(f.dot(trial, trial) + _TINY)
    projected = f.select(norm, bound, 1.0, bound / norm) * trial
    state = f.select(0.0, closing, f.select(norm, bound, float(STICK), float(SLIP)), float(OPEN))
    return {"p": p, "q": q, "bound": bound, "C_n": p - ufl.max_value(0.0, closing), "C_t": q - projected,
            "state": state, "dissipation": -ufl.dot(q, slip)}


def _rows(rows: dict, n, mu):
    """The multiplier rows' integrand for the traction test function ``mu``: ``-C_n (mu . n) - C_t . P_T mu``."""
    return -rows["C_n"] * ufl.dot(mu, n) - ufl.dot(rows["C_t"], mu - ufl.dot(mu, n) * n)


def _work(rows: dict, gap, u, v):
    """The contact tractions' virtual work at the test displacement of ``v``, with the augmented tractions
    ``p - AUGMENT C_n`` and ``q - AUGMENT C_t``: the tractions themselves where ``C = 0`` (the same solution)."""
    return (rows["p"] - AUGMENT * rows["C_n"]) * ufl.derivative(gap, u, v) - \
        ufl.dot(rows["q"] - AUGMENT * rows["C_t"], displacement(v))


def prescribed_traction(w: fem.Function, on_surface: np.ndarray, bcs: list) -> np.ndarray:
    """The traction dofs (of the mixed unknown ``w``, among ``on_surface``) whose displacement component at the
    same vertex is prescribed by one of ``bcs``."""
    W = w.function_space
    fixed = np.unique(np.concatenate([bc.dof_indices()[0] for bc in bcs] or [np.zeros(0, np.int32)]))
    out = []
    for i in range(W.mesh.geometry.dim):  # the traction and displacement dofs of component i at one vertex
        Vi, ui = collapse(W.sub(0).sub(i))
        Qi, qi = collapse(W.sub(1).sub(i))
        held = np.isin(ui, fixed)
        surface = np.isin(qi, on_surface)
        if not (np.any(held) and np.any(surface)):
            continue
        X = Vi.tabulate_dof_coordinates()
        distance, _ = cKDTree(X[held]).query(Qi.tabulate_dof_coordinates()[surface])
        size = float(np.ptp(X, axis=0).max()) or 1.0
        out.append(qi[surface][distance <= 1e-12 * size])
    return np.unique(np.concatenate(out)).astype(np.int32) if out else np.zeros(0, np.int32)


def _check_law(law) -> None:
    if not (isinstance(law, Friction) and isinstance(law.normal, LagrangeMultiplier)):
        raise ValueError(f"friction with the traction an unknown needs friction on method 'lagrange', got {law!r}")
    if "c_t" in law.scalars:
        raise ValueError("method 'lagrange' with friction takes mu (Coulomb) or tresca, not c_t (a normal "
                         "compliance bound needs a penetration)")


class MultiplierFrictionalContact(PressureUnknown, FrictionalContact):
    """A contact surface (rigid obstacle) with exact Coulomb or Tresca friction, its traction (of the obstacle on
    the body) the second field of the mixed unknown ``w``; the results of
    :class:`~fenics_contact.friction.FrictionalContact` (forces, profile, slip states, dissipation).

    Args:
        w: the mixed unknown of :func:`~fenics_contact.multipliers.unknown` (a traction vector).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: a :class:`~fenics_contact.friction.Friction` on a
            :class:`~fenics_contact.laws.LagrangeMultiplier` (``mu`` or ``tresca``; its ``c`` steers Newton only).
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: ``nodal`` (the vertex rule; the only one).
        name: the surface's name, in messages and output.
        linearized: the small-displacement gap ``g(X) - n(X) . u`` (normal at the reference point).

    Raises:
        ValueError: the law is not friction on multipliers, or has a normal-compliance bound (``c_t``).
    """

    def __init__(self, w: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: Friction,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False):
        _check_law(law)
        if quadrature != "nodal":
            raise ValueError(f"method 'lagrange' with friction enforces its conditions at the vertices: quadrature "
                             f"'nodal', got {quadrature!r}")
        ContactSurface.__init__(self, w, facet_tags, tag, obstacle, law, load, "nodal", name, linearized)
        self._pressure_setup(w, self.facets)
        self._n = self._coefficient_normal()
        self.work_quadrature = quadrature
        self.ds_work = contact_measure(w.function_space.mesh, facet_tags, tag, quadrature)
        r = ufl.SpatialCoordinate(w.function_space.mesh) + displacement(w) - obstacle.origin()
        self._init_friction(law, load, r, lambda r_old: r - r_old, exact=self._exact)

    # --- the unknown traction ------------------------------------------------------------------------------
    def _coefficient_normal(self):
        """The obstacle's normal; a flat obstacle's (literal numbers) as a ``Constant``: with literal normals some
        blocks of the Jacobian are literal numbers, for which FFCx 0.5 generates no code."""
        gdim = self.u.function_space.mesh.geometry.dim
        try:
            values = np.array([float(self.normal[i]) for i in range(gdim)])
        except (TypeError, ValueError, ufl.UFLException):
            return self.normal
        return fem.Constant(self.u.function_space.mesh, values)

    def _lam(self):
        return ufl.split(self.u)[1]

    def _pressure(self):
        return ufl.dot(self._lam(), self.normal)

    def _exact(self, ds):
        """The traction ``q``, the slip state, the dissipation density and the bound (UFL) at slip increment
        ``ds`` (:func:`alart_curnier`)."""
        self._rows = alart_curnier(self._lam(), self._n, self.gap, ds, self.params)
        r = self._rows
        return r["q"], r["state"], r["dissipation"], r["bound"]

    def given_dirichlet(self, bcs: list) -> None:
        """A flat obstacle whose normal is a coordinate axis (the condensed method's case): at a contact vertex
        whose displacement component ``i`` is prescribed, the traction component ``i`` is no unknown (fixed to 0:
        the support takes that force; the vertex sticks and slips along its free axes only). Otherwise its
        constraint row would be empty (``u_i`` fixed) and the system singular."""
        self._prescribed = np.zeros(0, np.int32)
        if not isinstance(self._n, fem.Constant):
            return
        n = np.asarray(self._n.value, dtype=float)
        if np.all(np.isclose(np.abs(n), 0.0) | np.isclose(np.abs(n), 1.0)):
            self._prescribed = prescribed_traction(self.u, self._on_surface, bcs)

    @property
    def augmentable(self) -> bool:
        """False: the multipliers are exact (nothing to augment)."""
        return False

    # --- residual ------------------------------------------------------------------------------------------
    def residual(self, v: ufl.Argument) -> ufl.Form:
        """``int (p - a C_n) dg[v] ds - int (q - a C_t) . v ds + int (-C_n (mu . n) - C_t . P_T mu) ds`` (``v`` the
        mixed test function, ``mu`` its traction part, ``a`` :data:`AUGMENT`; the vertex rule)."""
        r = self._rows
        return (_work(r, self.gap, self.u, v) * self.ring) * self.ds_work + _rows(r, self._n, ufl.split(v)[1]) * self.ds


class MultiplierFrictionalTwoBody(PressureUnknown, FrictionalTwoBodySurface):
    """Two-body contact with exact Coulomb or Tresca friction, the slave points' traction (of the master body on
    the slave) the second field of the mixed unknown: Alart and Curnier's functions at the slave vertices against
    the master facets (finite or small sliding, :class:`~fenics_contact.twobody.TwoBodySurface`), the slip
    increment relative to the paired master point
    (:class:`~fenics_contact.twobody.friction.FrictionalTwoBodySurface`); ``-q`` acts on the master point. Results
    of the frictional two-body surface.

    Args:
        args: the arguments of :class:`~fenics_contact.twobody.TwoBodySurface`, in its order; ``u`` is the mixed
            unknown of :func:`~fenics_contact.multipliers.unknown`, ``law`` friction on a
            :class:`~fenics_contact.laws.LagrangeMultiplier`.
        kwargs: its keyword arguments.
    """

    def __init__(self, *args, **kwargs):
        _check_law(args[4] if len(args) > 4 else kwargs["law"])
        super().__init__(*args, **kwargs)
        self._pressure_setup(self.u, self.facets)

    def _pressure(self):
        return ufl.dot(ufl.split(self.u)[1], self.normal)

    def given_dirichlet(self, bcs: list) -> None:
        """At a slave vertex whose displacement component ``i`` is prescribed (a symmetry plane across the
        surface), the traction component ``i`` is no unknown (fixed to 0: the vertex slips along its free
        directions only, as the condensed method's); otherwise its row would be empty where the master point's is
        prescribed too."""
        self._prescribed = prescribed_traction(self.u, self._on_surface, bcs)

    def _exact_friction(self, ds):
        """The traction ``q``, the slip state, the dissipation density and the bound (UFL) at the slip increment
        ``ds`` (:func:`alart_curnier`, against the master normal)."""
        self._rows = alart_curnier(ufl.split(self.u)[1], self.normal, self.gap, ds, self.params)
        r = self._rows
        return r["q"], r["state"], r["dissipation"], r["bound"]

    @property
    def augmentable(self) -> bool:
        """False: the multipliers are exact (nothing to augment)."""
        return False

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Slave part ``weight ((p - a C_n) dg/du[v] - (q - a C_t) . v) ds + int (-C_n (mu . n) - C_t . P_T mu) ds``
        (``a`` :data:`AUGMENT`); the master part
        is :meth:`master_residual`."""
        self._ensure_friction()
        r = self._rows
        return self.weight * self.ring * _work(r, self.gap, self.u, v) * self.ds_work + \
            _rows(r, self.normal, ufl.split(v)[1]) * self.ds

    def _point_pressure(self, g):
        """The normal traction ``lam . n`` at the slave points (the vertices), ``n`` the paired master normal."""
        sd, W = self.slave_data, self.u.function_space
        pr = self.projection
        lam = []
        for i in range(self.gdim):
            Wi = W.sub(1).sub(i)
            dofs = np.array([Wi.dofmap.cell_dofs(c)[lo] for c, lo in zip(sd.cells, sd.local)],
                            dtype=np.int32).reshape(-1, sd.local.shape[1])
            lam.append(np.einsum("qk,fk->fq", self.B, self.u.x.array[dofs]) if len(dofs) else np.zeros_like(g))
        return np.einsum("ifq,fqi->fq", np.array(lam), pr["normal"]) if len(g) else np.zeros_like(g)
