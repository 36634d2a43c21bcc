"""Friction between two deformable bodies: the pointwise (node-to-segment, node-to-triangle) two-body surface of
:mod:`twobody` with the return mapping of :mod:`~fenics_contact.friction` (formulation 1.5, the seed paper's
element: a slave point against a master facet of another deformable body).

Slip. The slip increment of a slave point over the load step is its motion relative to the master material
point it is paired with now (backward Euler; large sliding: the master point moves with its facet)::

    ds = (x_s - x_s_old) - sum_k N_k(xi) (w_k - w_k_old)

``x_s = X + u`` the slave point (``x_s_old = r_old``: its position at the last accepted step, per slave point
in the law's state space), ``w_k`` the displacements of the current master facet's vertices (the mirror field
of :mod:`twobody`), ``w_k_old`` their values at the last accepted step and ``N_k(xi)`` the linear shape
functions at the closest point, written in UFL from the current vertex positions (2D: ``xi = (x_s - x_1) . t /
t . t``; 3D: the 2x2 normal equations on the triangle), so UFL differentiates the slip with respect to the
slave and the master dofs. Small sliding (``sliding="small"``): the weights of the reference closest point, fixed,
and the reference normal (:class:`~fenics_contact.twobody.mirror.MirrorObstacle`). The return mapping sees ``P_T
ds`` (:meth:`Friction.trial`); on the same facet it is the convected increment ``(xi - xi_old) t`` to first order,
and a point whose master facet changes keeps its history (``q_old``, ``r_old`` live with the slave point; ``w_old``
is re-read for the new pair from the master displacement at the last accepted step, ``u_old``).

Forces. ``q`` (the return-mapped traction, per reference slave area, 0 on unpaired points) acts on the slave
point, ``-q`` on the master point ``sum_k N_k(xi) x_k``::

    R_slave  += -weight q . v ds,       R_master += +weight q . sum_k N_k(xi) vw_k ds   (then I^T)

so the contact forces on the two bodies are equal and opposite for any pairing (``sum_k N_k = 1``). The
derivatives of these forms with respect to ``u`` and ``w`` (through :mod:`twobody`'s coupling ``I``) are the
consistent tangent including the master dofs, in stick and in slip. History advances only in
:meth:`commit` (the solver's accepted-step hook) and is rolled back by :meth:`restore`.

Degree-1 (flat) facets with ``nodal`` or ``gauss`` quadrature; the other two-body options are refused with
friction by :mod:`capabilities`.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

from ..contact import displacement
from ..friction import Friction, FrictionHistory
from ..laws import ContactLaw
from .surface import TwoBodySurface

__all__ = ["FrictionalTwoBodySurface"]


class FrictionalTwoBodySurface(FrictionHistory, TwoBodySurface):
    """:class:`~fenics_contact.twobody.TwoBodySurface` with friction: ``law`` is a
    :class:`~fenics_contact.friction.Friction` (Coulomb, compliance or Tresca bound on a penalty-type normal law).
    Arguments as :class:`~fenics_contact.twobody.TwoBodySurface` (degree-1 facets, ``nodal`` or ``gauss``).

    Args:
        u: the displacement.
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        slave_tag: the slave surface: a tag value, or a region name of ``facet_tags``.
        master_tag: the master surface (likewise).
        law: a :class:`Friction`.
        load: the load parameter ``t`` (a scalar ``Constant``).
        quadrature: ``nodal`` or ``gauss``.
        weight: factor on the residual (1/2 for each surface of a two-pass pair).
        radius: the search radius (length; default twice the longest master facet); farther points have no pair.
        name: the surface's name, in messages and output.
        work_quadrature: the rule of the work term, if not ``quadrature``.
        exclude: (k, gdim) reference positions of slave points left without a pair.
        sliding: ``finite`` or ``small`` (see :class:`~fenics_contact.twobody.TwoBodySurface`).
    """

    def __init__(self, u: fem.Function, facet_tags, slave_tag, master_tag, law: ContactLaw, load: fem.Constant,
                 quadrature: str = "nodal", weight: float = 1.0, radius: float | None = None, name: str = "twobody",
                 work_quadrature: str | None = None, exclude: np.ndarray | None = None, sliding: str = "finite"):
        if not isinstance(law, Friction):
            raise ValueError(f"FrictionalTwoBodySurface needs a Friction law, got {law!r}")
        if work_quadrature not in (None, quadrature):
            raise ValueError(f"two-body friction integrates with one rule: work_quadrature must be None or "
                             f"{quadrature!r}, got {work_quadrature!r}")
        self._friction_load = load
        super().__init__(u, facet_tags, slave_tag, master_tag, law, load, quadrature, weight, radius, name,
                         work_quadrature, exclude, sliding=sliding)
        if self.quadratic:  # capabilities refuses it first; kept for a direct construction
            raise ValueError("two-body friction needs degree-1 (flat) facets")

    # --- friction terms, built once on the first call of the coupling's forms ----------------
    def _ensure_friction(self) -> None:
        if hasattr(self, "traction"):
            return
        mesh = self.u.function_space.mesh
        d = self.gdim
        self.u_old = fem.Function(self.u.function_space, name="u_old")  # the displacement at the last accepted step
        self.w_old = fem.Function(self.mirror.space, name="mirror_u_old")  # its values at the current master vertices
        x = ufl.SpatialCoordinate(mesh) + displacement(self.u)
        self._N = self.obstacle.weights(x)
        w = self.mirror.displacement
        dw = [ufl.as_vector([w[k * d + i] - self.w_old[k * d + i] for i in range(d)]) for k in range(self.nv)]
        master_motion = sum(N * v for N, v in zip(self._N, dw))
        self._init_friction(self.law, self._friction_load, x, lambda r_old: x - r_old - master_motion,
                            factor=self.obstacle.active, exact=self._exact_friction)
        # Master normal at the output vertices (the 2D traction profile's tangent).
        P1 = self.gap_out.function_space
        self._normal_out = [fem.Function(P1) for _ in range(d)]
        self._out_rhs += [(self._out.compile(self.normal[i]), f) for i, f in enumerate(self._normal_out)]

    # the traction an unknown (multipliers): its (traction, state, dissipation, bound) of the slip increment
    _exact_friction = None

    def residual(self, v: ufl.Argument) -> ufl.Form:
        """Slave part ``weight (F(g) dg/du[v] - q . v) ds``; the master part is :meth:`master_residual`."""
        self._ensure_friction()
        return (super().residual(v)
                - self.weight * self.ring * ufl.dot(self.traction, displacement(v)) * self.ds_work)

    def master_residual(self, vw: ufl.Argument) -> ufl.Form:
        """Master part ``weight (F(g) dg/dw[vw] + q . sum_k N_k(xi) vw_k) ds`` on the mirror test function."""
        self._ensure_friction()
        d = self.gdim
        vm = sum(N * ufl.as_vector([vw[k * d + i] for i in range(d)]) for k, N in enumerate(self._N))
        return super().master_residual(vw) + self.weight * self.ring * ufl.dot(self.traction, vm) * self.ds_work

    # --- history -----------------------------------------------------------------
    def update(self) -> bool:
        """:meth:`TwoBodySurface.update`, then the master's last accepted displacement at the new pairs."""
        changed = super().update()
        if not self.exploded and hasattr(self, "w_old"):
            self._fill_w_old()
        return changed

    def _fill_w_old(self) -> None:
        """``w_old``: the master's last accepted displacement at the current pairs. Collective."""
        md = self.master_data
        # The owned master facets' values on the facets of the last update, in its order.
        U = self.pairs.exchange.values(self.u_old.x.array[md.comp[md.owned]])
        self.mirror.set(self.w_old, self.mirror.nodal(self.pairs.facet, U))

    def _commit_more(self) -> None:
        """``u_old <- u`` (and the mirror ``w_old``): after a commit the slip increment is 0."""
        self.u_old.x.array[:] = self.u.x.array
        if self.pairs.facet is not None:
            self._fill_w_old()

    def state(self) -> dict:
        return {**super().state(), "u_old": self.u_old.x.array.copy()}

    def restore(self, state: dict) -> None:
        super().restore(state)
        self.u_old.x.array[:] = state["u_old"]
        if self.pairs.facet is not None:
            self._fill_w_old()

    # --- figures -------------------------------------------------------------------
    def _normal_at(self, x: np.ndarray) -> np.ndarray:
        """The master normal's vertex values at this rank's output vertices (``update_output`` refreshed them)."""
        dofs = self._out.surface_dofs
        return np.stack([f.x.array[dofs] for f in self._normal_out], axis=1)

