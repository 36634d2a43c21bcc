"""Nitsche's method with Tresca or Coulomb friction between two deformable bodies (method ``nitsche`` with a
:class:`~fenics_contact.friction.Friction` law): the frictional two-body surface of :mod:`~.friction` with
the normal term of :mod:`~.nitsche` and the tangential term of Chouly, Mlika, Renard & Hild (2018).

With ``t_s = P_T P_s(u) N_s`` the tangential traction the slave's own stress carries across its surface,
``ds`` the slip increment over the load step (:mod:`~.friction`: the slave point's motion relative to the
paired master point, ``P_T ds`` its tangential part) and ``gamma = gamma0 E_s / h_s`` (the normal term's), the
traction of the master on the slave is the projection of the trial ``t_s - gamma P_T ds`` on the disk of radius
``b`` (``mu p`` with Nitsche's pressure ``p`` for Coulomb, Tresca's ``s`` where ``p > 0``)::

    q = proj_b(t_s - gamma P_T ds)

(the return mapping of :class:`~fenics_contact.friction.Friction` with the stress in place of the history and
``gamma`` in place of ``omega_t``), and the tangential surface term is

    weight int [ q . (theta dt_s[v] - gamma d(P_T ds)[v]) - theta t_s . dt_s[v] ] / gamma ds,

the slave part with derivatives with respect to ``u``, the master part with respect to the mirror displacement
``w`` (as the normal term). At the exact solution (``t_s`` the traction, inside the disk where the point sticks,
on its edge against the slip where it slides) ``q = t_s`` and the term reduces to the friction force's work
``-q . d(P_T ds)[v]``: consistent at any ``gamma``, with no tangential penalty (``omega_t`` is not used). The
history is the slip increment's alone (``r_old``, ``u_old``); nothing is augmented. The tangential force and
traction reported are those of the last committed step (``q_old``); the state areas count a vertex between
a sticking and a sliding facet half to each. Coulomb (``mu``) and Tresca
(``tresca``) bounds; normal-compliance bounds are refused.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

from ..friction import OPEN, SLIP, STICK, Friction, friction_ops
from ..laws import NUMPY, ContactLaw, ufl_ops
from ..materials import Material, Materials
from .friction import FrictionalTwoBodySurface
from .nitsche import NitscheTwoBody

__all__ = ["NitscheFrictionTwoBody"]


class _NitscheReturnMapping(Friction):
    """The return mapping of Nitsche's friction on one surface: trial ``P_T (t_s - gamma ds)``, bound from
    Nitsche's pressure ``p`` (UFL of that surface). The parameters are those of the user's law."""

    def __init__(self, law: Friction, ts, gamma, pressure):
        self.__dict__.update(law.__dict__)
        self._ts, self._gamma, self._p = ts, gamma, pressure

    def trial(self, q_old, ds, n, c, ops=NUMPY):
        return self.tangential(self._ts - self._gamma * ds, n, ops)

    def bound(self, g, c, ops=NUMPY):
        if "mu" in c:
            return c["mu"] * self._p
        return friction_ops(ops).select(0.0, self._p, c["tresca"], 0.0)

    def dissipation(self, g, q_old, ds, n, c, ops=NUMPY):
        f = friction_ops(ops)
        q_tr = self.trial(q_old, ds, n, c, ops)
        q = self.traction(g, q_old, ds, n, c, ops)
        return f.dot(q, q_tr - q) / self._gamma

    def slip_state(self, g, q_old, ds, n, c, ops=NUMPY):
        f = friction_ops(ops)
        q_tr = self.trial(q_old, ds, n, c, ops)
        stick_or_slip = f.select(self._norm(q_tr, ops), self.bound(g, c, ops), float(STICK), float(SLIP))
        return f.select(0.0, self._p, stick_or_slip, float(OPEN))


class NitscheFrictionTwoBody(FrictionalTwoBodySurface, NitscheTwoBody):
    """Two-body Nitsche with friction: ``law`` a :class:`~fenics_contact.friction.Friction` on a
    :class:`~fenics_contact.laws.Nitsche` normal law with ``mu`` (Coulomb) or ``tresca``; ``material`` the bulk
    material. Other arguments as :class:`~fenics_contact.twobody.TwoBodySurface` (degree 1, ``nodal`` or
    ``gauss``). Results as :class:`~fenics_contact.twobody.friction.FrictionalTwoBodySurface`."""

    augmentable = False  # the trial starts from the stress, not from a multiplier: nothing to augment

    def __init__(self, u: fem.Function, facet_tags, slave_tag, master_tag, law: ContactLaw, load: fem.Constant,
                 quadrature: str = "nodal", weight: float = 1.0, radius: float | None = None, name: str = "twobody",
                 work_quadrature: str | None = None, exclude: np.ndarray | None = None,
                 material: Material | Materials | None = None, sliding: str = "finite"):
        if isinstance(law, Friction) and "c_t" in law.scalars:
            raise ValueError("Nitsche's friction takes a Coulomb (mu) or Tresca (tresca) bound, not c_t")
        self.material = material  # NitscheTwoBody reads it (FrictionalTwoBodySurface passes its own arguments on)
        super().__init__(u, facet_tags, slave_tag, master_tag, law, load, quadrature, weight, radius, name,
                         work_quadrature, exclude, sliding=sliding)

    def _init_friction(self, law, load, r, ds_of_r_old, factor=None, exact=None) -> None:
        """The frictional state with Nitsche's return mapping; keeps the slip increment's UFL (``_slip``)."""
        N = ufl.FacetNormal(self.u.function_space.mesh)
        self._ts = Friction.tangential(ufl.dot(self.material.piola(self.u), N), self.stress_normal, ufl_ops())
        self._slip_of = ds_of_r_old
        super()._init_friction(_NitscheReturnMapping(law, self._ts, self.gamma, self.pressure), load, r,
                               self._capture_slip, factor, exact)
        # The figures of a step are its converged traction, which commit keeps in q_old: a committed state's slip
        # increment is 0, so its live traction is the projected stress, not the step's.
        q = ufl.as_vector(self.q_old)
        self._tangential_forms = [fem.form(q[i] * self.ds) for i in range(self.gdim)]
        # State areas: the stress term's state is evaluated per facet (the stress of its cell), so a vertex between
        # a sticking and a sliding facet has the mean 1.5; it counts half to each (whole states as before).
        st = self.slip_state
        frac = {"open": ufl.max_value(1.0 - st, 0.0), "slip": ufl.max_value(1.0 - abs(st - 1.0), 0.0),
                "stick": ufl.max_value(st - 1.0, 0.0)}
        self._state_area_forms = {k: fem.form(ufl.min_value(e, 1.0) * self.ds) for k, e in frac.items()}
        outs = {id(f) for f in self._traction_out}
        self._out_rhs = [(rhs, f) for rhs, f in self._out_rhs if id(f) not in outs] + [
            (self._out.compile(q[i]), f) for i, f in enumerate(self._traction_out)]

    def _capture_slip(self, r_old):
        self._slip = Friction.tangential(self._slip_of(r_old), self.normal, ufl_ops())
        return self._slip_of(r_old)

    def _tangential(self, w, vw) -> ufl.core.expr.Expr:
        """``[q . (theta dt_s - gamma d(P_T ds)) - theta t_s . dt_s] / gamma`` with derivatives along ``vw`` with
        respect to ``w`` (``u`` or the mirror displacement)."""
        theta, gamma = self.constants["theta"], self.gamma
        dt = ufl.derivative(self._ts, w, vw)
        dd = ufl.derivative(self._slip, w, vw)
        return (ufl.dot(self.traction, theta * dt - gamma * dd) - theta * ufl.dot(self._ts, dt)) / gamma

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Slave part: Nitsche's normal term plus the tangential term (module docstring)."""
        self._ensure_friction()
        return NitscheTwoBody.residual(self, v) + self.weight * self._tangential(self.u, v) * self.ds_work

    def master_residual(self, vw: ufl.Argument) -> ufl.Form:
        """Master part: both terms differentiated with respect to the mirror displacement."""
        self._ensure_friction()
        return NitscheTwoBody.master_residual(self, vw) + self.weight * self._tangential(
            self.mirror.displacement, vw) * self.ds_work
