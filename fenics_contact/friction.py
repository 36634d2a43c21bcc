"""Quasi-static friction against rigid obstacles: a normal law plus a return mapping (formulation 1.5).

Perturbed Lagrangian with tangential penalty ``omega_t``, per contact quadrature point and load step
(incremental, backward Euler in the load parameter):

    slip increment     ds   = P_T (r - r_old),   r = x - o(t): position relative to the obstacle
    trial (stick)      q_tr = P_T q_old - omega_t ds
    friction bound     b(g) = mu <F(g)>          (Coulomb on any normal law), or
                       b(g) = c_t <g>^m_t        (normal compliance friction; m_t = m_n, c_t = mu c_n is Coulomb), or
                       b(g) = s  where F(g) > 0  (Tresca: a fixed bound on the closed points, 0 on the open ones)
    return mapping     q    = q_tr               if |q_tr| < b    (stick)
                       q    = b q_tr / |q_tr|    otherwise         (slip, opposite to the slip increment)

At ``|q_tr| = b`` both branches give the same traction; taking the slip branch there gives a point without
friction capacity (``b = 0``: open, or touching at rest) no tangential stiffness in the Jacobian, instead of
a stick spring ``omega_t`` it cannot carry.

``q`` is the **tangential traction the obstacle exerts on the body** (force per area, in the tangent
plane, global components); ``P_T = I - n n``. The residual gets ``+ F(g) dg[v] - q . v`` (the normal part
is the frictionless term unchanged). ``q_old`` and ``r_old`` are the values at the last converged load
step; they are advanced only by :meth:`FrictionalContact.commit`. The return mapping is written once
against the ``ops`` namespace of :mod:`laws` (NumPy: vectors are component-first arrays, shape
``(d, ...)``), and in UFL ``ufl.derivative`` of it is the consistent tangent in stick and in slip.
"""
from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from .compat import function_space, interpolate_expression
from .contact import ContactSurface, displacement
from .laws import NUMPY, ContactLaw, LagrangeMultiplier, Nitsche, NormalCompliance, _check_exponent, ufl_ops

__all__ = ["OPEN", "SLIP", "STICK", "friction_ops", "Friction", "FrictionHistory", "FrictionalContact"]

OPEN, SLIP, STICK = 0, 1, 2
_TINY = 1e-300  # |q| = sqrt(q.q + tiny): finite derivative at q = 0 (the stick branch never uses it)


def _numpy_ops():
    return dict(sqrt=np.sqrt, dot=lambda a, b: np.sum(np.asarray(a) * np.asarray(b), axis=0),
                select=lambda a, b, x, y: np.where(np.asarray(a) < np.asarray(b), x, y))


def _ufl_extra():
    return dict(sqrt=ufl.sqrt, dot=ufl.dot, select=lambda a, b, x, y: ufl.conditional(ufl.lt(a, b), x, y))


def friction_ops(ops: Any) -> Any:
    """``ops`` of :mod:`laws` extended by ``sqrt``, ``dot`` and ``select(a, b, x, y)`` (= x if a < b else y)."""
    if hasattr(ops, "select"):
        return ops
    extra = _numpy_ops() if ops.exp is np.exp else _ufl_extra()
    return type(ops)(**vars(ops), **extra)


class Friction(ContactLaw):
    """A normal law (any :class:`ContactLaw` but ``vi``, or Nitsche between two bodies) with friction.

    Give exactly one of ``mu >= 0`` (Coulomb bound ``mu <F(g)>``), ``c_t > 0`` with ``m_t >= 1``
    (normal compliance bound ``c_t <g>^m_t``; ``m_t`` defaults to the normal law's ``m_n``) and
    ``tresca >= 0`` (Tresca: the fixed bound ``tresca`` where the normal force is positive).
    ``omega_t > 0``: tangential penalty (traction per unit slip) of the stick state.
    Pressures in the units of the normal law; the normal part (force, augmentation) is the normal law's.

    Args:
        normal: the normal law (a :class:`ContactLaw`).
        mu: the Coulomb coefficient, >= 0.
        omega_t: the tangential penalty (traction per length of slip), > 0.
        c_t: the normal-compliance bound's coefficient (pressure per length^m_t), > 0.
        m_t: the normal-compliance bound's exponent, >= 1.
        tresca: the Tresca bound (traction), >= 0.
    """

    name = "friction"

    def __init__(self, normal: ContactLaw, mu: float | None = None, omega_t: float = 1.0,
                 c_t: float | None = None, m_t: float | None = None, tresca: float | None = None):
        if isinstance(normal, Friction) or not isinstance(normal, (ContactLaw, Nitsche, LagrangeMultiplier)):
            raise ValueError(f"friction needs a normal law (penalty, cross, auglag, compliance, nitsche, lagrange), "
                             f"got {normal!r}")
        if sum(x is not None for x in (mu, c_t, tresca)) != 1:
            raise ValueError("friction: give exactly one of mu (Coulomb), c_t (normal compliance bound) and tresca "
                             "(Tresca bound)")
        self.normal = normal
        omega_t = float(omega_t)
        if not (math.isfinite(omega_t) and omega_t > 0):
            raise ValueError(f"tangential penalty omega_t must be a finite number > 0, got {omega_t!r}")
        tangential: dict[str, float] = {"omega_t": omega_t}
        if mu is not None:
            mu = float(mu)
            if not (math.isfinite(mu) and mu >= 0):
                raise ValueError(f"friction coefficient mu must be a finite number >= 0, got {mu!r}")
            tangential["mu"] = mu
            self.m_t = None
        elif tresca is not None:
            tresca = float(tresca)
            if not (math.isfinite(tresca) and tresca >= 0):
                raise ValueError(f"Tresca friction bound tresca must be a finite number >= 0, got {tresca!r}")
            tangential["tresca"] = tresca
            self.m_t = None
        else:
            c_t = float(c_t)
            if not (math.isfinite(c_t) and c_t > 0):
                raise ValueError(f"friction bound coefficient c_t must be a finite number > 0, got {c_t!r}")
            tangential["c_t"] = c_t
            default = normal.m if isinstance(normal, NormalCompliance) else 1.0
            self.m_t = _check_exponent("friction bound exponent m_t", default if m_t is None else m_t)
        self.scalars = {**normal.scalars, **tangential}
        self.fields = normal.fields
        self.name = f"{normal.name}+friction"

    @property
    def method(self) -> str:
        """The method of the normal law (friction is on top of it)."""
        return self.normal.method

    @property
    def has_friction(self) -> bool:
        return True

    # --- normal part: the normal law's --------------------------------------
    def force(self, g, c, ops=NUMPY):
        return self.normal.force(g, c, ops)

    def potential(self, g, c, ops=NUMPY):
        return self.normal.potential(g, c, ops)

    def stiffness(self, g, c, ops=NUMPY):
        return self.normal.stiffness(g, c, ops)

    def augment_fields(self, g, c, ops=NUMPY):
        return self.normal.augment_fields(g, c, ops)

    def augment_scalars(self, c):
        return self.normal.augment_scalars({k: v for k, v in c.items() if k in self.normal.scalars})

    @property
    def augmentable(self) -> bool:
        """Always True (the tangential multiplier, the traction the trial starts from, can be augmented)."""
        return True

    # --- tangential part -------------------------------------------------------
    def bound(self, g: Any, c: Mapping[str, Any], ops: Any = NUMPY) -> Any:
        """Friction bound ``b(g) >= 0``: ``mu <F(g)>``, ``c_t <g>^m_t`` or Tresca's ``s`` (0 when open)."""
        if "mu" in c:
            return c["mu"] * ops.max(self.normal.force(g, c, ops), 0.0)
        if "tresca" in c:
            return friction_ops(ops).select(0.0, self.normal.force(g, c, ops), c["tresca"], 0.0)
        gp = ops.max(g, 0.0)
        return c["c_t"] * (gp if self.m_t == 1.0 else gp**self.m_t)

    @staticmethod
    def tangential(a: Any, n: Any, ops: Any) -> Any:
        """``P_T a = a - (a . n) n``."""
        return a - friction_ops(ops).dot(a, n) * n

    def trial(self, q_old, ds, n, c, ops=NUMPY):
        """Trial (stick) traction ``q_tr = P_T q_old - omega_t P_T ds``."""
        return self.tangential(q_old - c["omega_t"] * ds, n, ops)

    def _norm(self, q, ops):
        f = friction_ops(ops)
        return f.sqrt(f.dot(q, q) + _TINY)

    def traction(self, g, q_old, ds, n, c, ops=NUMPY):
        """Return-mapped tangential traction on the body (see the module docstring)."""
        f = friction_ops(ops)
        q_tr = self.trial(q_old, ds, n, c, ops)
        norm, b = self._norm(q_tr, ops), self.bound(g, c, ops)
        return f.select(norm, b, 1.0, b / norm) * q_tr

    def dissipation(self, g, q_old, ds, n, c, ops=NUMPY):
        """Friction dissipation density of the increment, ``q . (q_tr - q) / omega_t >= 0`` (work per area)."""
        f = friction_ops(ops)
        q_tr = self.trial(q_old, ds, n, c, ops)
        q = self.traction(g, q_old, ds, n, c, ops)
        return f.dot(q, q_tr - q) / c["omega_t"]

    def slip_state(self, g, q_old, ds, n, c, ops=NUMPY):
        """``OPEN`` (no normal contact force, ``F(g) <= 0``: ``g <= 0`` for penalty and compliance,
        ``lam + K g <= 0`` for auglag; never for cross-constraints with ``F_hat > 0``), ``SLIP`` (trial at or
        beyond the bound; with ``mu = 0`` every closed point slides) or ``STICK``."""
        f = friction_ops(ops)
        q_tr = self.trial(q_old, ds, n, c, ops)
        stick_or_slip = f.select(self._norm(q_tr, ops), self.bound(g, c, ops), float(STICK), float(SLIP))
        return f.select(0.0, self.normal.force(g, c, ops), stick_or_slip, float(OPEN))


class FrictionHistory:
    """The friction state of a contact surface, written once for rigid and two-body contact (a mixin before
    the surface class: ``class X(FrictionHistory, SomeContactSurface)``).

    :meth:`_init_friction` takes the slip increment ``ds`` since the last accepted step and the tracked position
    ``r`` (UFL); ``r_old`` (one Function of the law's state space ``S`` per global component) is ``r`` at the last
    accepted step, ``q_old`` the traction there. ``factor`` multiplies the return-mapped traction (two-body: 1 on
    paired points, 0 on the others); ``exact(ds)`` replaces the return mapping where the traction is an unknown
    (:mod:`~fenics_contact.multiplier_friction`): it returns the traction, the slip state, the dissipation
    density and the friction bound (UFL) at the slip increment ``ds``. ``dissipated`` is the friction work
    dissipated up to the last committed step (energy per unit thickness in 2D); ``log`` has the forces, capacity,
    dissipation and state areas of every committed step.
    """

    def _init_friction(self, law: Friction, load: fem.Constant, r, ds_of_r_old, factor=None, exact=None) -> None:
        if not isinstance(law, Friction):
            raise ValueError(f"{type(self).__name__} needs a Friction law")
        mesh = self.u.function_space.mesh
        self.gdim = gdim = mesh.geometry.dim
        self.q_old = [fem.Function(self.S, name=f"q_old_{i}") for i in range(gdim)]
        self.r_old = [fem.Function(self.S, name=f"r_old_{i}") for i in range(gdim)]
        args = (self.gap, ufl.as_vector(self.q_old), ds_of_r_old(ufl.as_vector(self.r_old)), self.normal, self.params,
                ufl_ops())
        if exact is not None:  # the traction an unknown: traction, slip state, dissipation, bound at the increment
            self.traction, self.slip_state_expr, dissipation, bound = exact(args[2])
        else:
            self.traction = law.traction(*args) if factor is None else factor * law.traction(*args)
            self.slip_state_expr = law.slip_state(*args)  # UFL: 0 open, 1 slip, 2 stick at the current u
            dissipation = law.dissipation(*args) if factor is None else factor * law.dissipation(*args)
            bound = law.bound(self.gap, self.params, ufl_ops())
        self._dissipation_form = fem.form(dissipation * self.ring * self.ds)
        self._tangential_forms = [fem.form(self.traction[i] * self.ring * self.ds) for i in range(gdim)]
        self._capacity_form = fem.form(bound * self.ring * self.ds)
        # The state of the last accepted step, kept at commit: after a commit the next trial starts at
        # the bound, so the current expression would call a sliding point sticking.
        self.slip_state = fem.Function(self.S, name="slip_state_committed")
        near = lambda v: ufl.conditional(ufl.lt(abs(self.slip_state - v), 0.5), 1.0, 0.0)  # noqa: E731
        self._state_area_forms = {k: fem.form(near(v) * self.ds)
                                  for k, v in (("open", OPEN), ("slip", SLIP), ("stick", STICK))}
        self.history = [self.slip_state, *self.q_old, *self.r_old]  # what commit advances and restore resets
        self._history_rhs = [self.projector.compile(e) for e in [self.slip_state_expr, *self.traction, *r]]
        self._load = load
        self._r_prev = None
        self.dissipated, self.log = 0.0, []
        self.commit()  # r_old = the initial position; q_old = 0
        self.dissipated, self.log = 0.0, []

        P1 = self.gap_out.function_space
        self.state_out = fem.Function(P1, name="slip_state")
        self._traction_out = [fem.Function(P1) for _ in range(gdim)]
        self.traction_out = fem.Function(function_space(mesh, "Lagrange", 1, (gdim,)), name="tangential_traction")
        self._out_rhs += [(self._out.compile(self.slip_state), self.state_out)]
        self._out_rhs += [(self._out.compile(self.traction[i]), f) for i, f in enumerate(self._traction_out)]

    # --- augmentation (Uzawa on the tangential multiplier, with the normal law's own) ----------
    def augment(self) -> None:
        """``q_old <- q`` (the trial restarts from the current traction) with ``r_old`` kept at the last
        accepted step: at the fixed point a sticking point has not moved (``r = r_old``, no elastic slip
        ``q / omega_t``) and a sliding one slides against its traction: exact Coulomb for any ``omega_t``.
        Then the normal law's augmentation."""
        gdim = self.gdim
        new = [self.projector.project(rhs, fem.Function(self.S)) for rhs in self._history_rhs[1:1 + gdim]]
        super().augment()
        for f, n in zip(self.q_old, new):
            f.x.array[:] = n.x.array

    def constraint_change(self) -> float:
        """The larger of the normal law's gap change and ``sqrt(sum |r_new - r_old|^2)`` (the contact points'
        motion) since the last call, over the state dofs (inf first)."""
        R = super().constraint_change()
        now = [self.projector.project(rhs, fem.Function(self.S)).x.array.copy()
               for rhs in self._history_rhs[1 + self.gdim:]]
        if self._r_prev is not None:
            R = max(R, float(np.sqrt(self.comm.allreduce(sum(
                np.sum((self._owned(a) - self._owned(b)) ** 2) for a, b in zip(now, self._r_prev))))))
        self._r_prev = now
        return R

    def forget_gap(self) -> None:
        super().forget_gap()
        self._r_prev = None

    def commit(self) -> None:
        """Accept the current (converged) state: add its dissipation, keep its slip state, advance ``q_old``
        and ``r_old``."""
        self.dissipated += self.comm.allreduce(fem.assemble_scalar(self._dissipation_form), op=MPI.SUM)
        new = [self.projector.project(rhs, fem.Function(self.S)) for rhs in self._history_rhs]
        for f, n in zip(self.history, new):
            f.x.array[:] = n.x.array
        self._commit_more()
        self.log.append({"load": float(self._load.value), "normal_force": self.total_force().tolist(),
                         "tangential_force": self.tangential_force().tolist(), "capacity": self.capacity(),
                         "dissipated": self.dissipated, **self.state_areas()})

    def _commit_more(self) -> None:
        """Advance history kept outside ``history`` (before the committed step's figures are logged)."""
        return None  # rigid obstacles: nothing more

    def state(self) -> dict:
        return {**super().state(), "history": [f.x.array.copy() for f in self.history],
                "dissipated": self.dissipated}

    def restore(self, state: dict) -> None:
        super().restore(state)
        for f, a in zip(self.history, state["history"]):
            f.x.array[:] = a
        self.dissipated = state["dissipated"]

    def tangential_force(self) -> np.ndarray:
        """Tangential force of the other side on the body, ``int q ds`` (global components). Collective."""
        return np.array([self.comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM) for f in self._tangential_forms])

    def update_output(self) -> None:
        """The gap, pressure and tangential traction into the output Functions. Collective."""
        super().update_output()
        interpolate_expression(self.traction_out, ufl.as_vector(self._traction_out))

    def friction_profile(self) -> dict[str, np.ndarray]:
        """Vertex values on the contact surface, gathered on every rank and sorted by reference position.
        Collective.

        ``x`` (n, gdim) reference position, ``gap`` (> 0 penetration), ``pressure`` (> 0 compression), ``traction``
        (tangential traction of the other side on the body: 2D scalar along the tangent ``(n_y, -n_x)``,
        which is +x for the plane y = 0; 3D vector (n, 3)) and ``state`` (0 open, 1 slip, 2 stick) of the
        last committed step (``gauss`` quadrature: the state field's vertex value, rounded)."""
        self.update_output()
        V = self.gap_out.function_space
        dofs = self._out.surface_dofs
        x = V.tabulate_dof_coordinates()[dofs][:, :self.gdim]
        q = np.stack([f.x.array[dofs] for f in self._traction_out], axis=1)
        if self.gdim == 2:
            n = self._normal_at(x)  # at this rank's vertices (two-body: the master normal's vertex values)
            q = q[:, 0] * n[:, 1] - q[:, 1] * n[:, 0]
        local = (x, self.gap_out.x.array[dofs], self.pressure_out.x.array[dofs], q, self.state_out.x.array[dofs])
        x, g, p, q, s = (np.concatenate(a) for a in zip(*self.comm.allgather(local)))
        order = np.lexsort(x.T[::-1])
        return {"x": x[order], "gap": g[order], "pressure": p[order], "traction": q[order],
                "state": np.clip(np.rint(s[order]), OPEN, STICK).astype(int)}

    def capacity(self) -> float:
        """``int b(g) ds``: the largest tangential force the surface can carry at the current gap. Collective."""
        return self.comm.allreduce(fem.assemble_scalar(self._capacity_form), op=MPI.SUM)

    def state_areas(self) -> dict[str, float]:
        """Area (length in 2D) of the contact surface in each state, by the contact quadrature rule. Collective."""
        return {k: self.comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM) for k, f in self._state_area_forms.items()}


class FrictionalContact(FrictionHistory, ContactSurface):
    """A :class:`ContactSurface` with friction against a rigid obstacle: ``law`` is a :class:`Friction`.
    Results: :meth:`total_force` the normal force of the obstacle on the body, :meth:`tangential_force` the
    friction force, :meth:`point_values` / :meth:`surface_values` and :meth:`friction_profile` at the vertices.

    History (traction ``q_old`` and relative position ``r_old = x - o(t)`` at the last converged step, one
    scalar Function per global component) lives in the law's state space ``S`` (exact values at the
    contact quadrature points); see :class:`FrictionHistory`.

    Args:
        u: the problem's unknown: the displacement, or the mixed unknown of :func:`unknown` (method ``lagrange``).
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: a :class:`Friction`.
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: the surface's rule: ``nodal``, ``gauss`` or ``simpson`` (the capability grid says which).
        name: the surface's name, in messages and output.
        linearized: the small-displacement gap ``g(X) - n(X) . u`` (normal at the reference point) instead of the
            gap of the current position ``X + u``.
    """

    def __init__(self, u: fem.Function, facet_tags, tag: int, obstacle, law: Friction,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact", linearized: bool = False):
        if not isinstance(law, Friction):
            raise ValueError("FrictionalContact needs a Friction law")
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name, linearized)
        r = ufl.SpatialCoordinate(u.function_space.mesh) + displacement(u) - obstacle.origin()
        self._init_friction(law, load, r, lambda r_old: r - r_old)

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """``F(g) dg[v] ds - q . v ds``."""
        return super().residual(v) - ufl.dot(self.traction, displacement(v)) * self.ring * self.ds

    def _normal_at(self, x: np.ndarray) -> np.ndarray:
        """Obstacle normal at the vertices (half-planes: constant; else the reference direction)."""
        n = getattr(self.obstacle, "n", None)
        if n is not None:
            return np.tile(n, (len(x), 1))
        d = x - self.obstacle.point
        return self.obstacle.sign * d / np.linalg.norm(d, axis=1, keepdims=True)
