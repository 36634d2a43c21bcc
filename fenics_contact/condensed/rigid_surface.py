"""The contact surface of method ``coulomb`` against a flat rigid obstacle (no residual term: a step solver)."""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ..bounds import PlaneVertices
from ..capabilities import check, of
from ..compat import collapse
from ..contact import ContactSurface
from ..laws import ContactLaw
from ..obstacles import HalfPlane, Obstacle
from .operator import check_size
from .states import classify

__all__ = ["CondensedContact"]


class CondensedContact(ContactSurface):
    """The contact surface of method ``coulomb`` against a half-plane whose normal is a coordinate axis (2D or
    3D, nodal): the contact vertices and weights ``int phi_i ds`` (:class:`~fenics_contact.bounds.PlaneVertices`,
    ``plane``), the output fields and figures of :class:`~fenics_contact.contact.ContactSurface` with the pressure
    a nodal field, and the tangential traction ``traction_out``. It has no residual term and no bounds: its load
    steps are solved by a :class:`~.rigid_solver.CondensedCoulomb` given to the problem
    (``requires_step_solver``), which writes the nodal contact forces over the vertex weights back here
    (:meth:`set_solution`). The tangent basis is the other coordinate axes (``kts``, increasing).

    Results: :meth:`total_force` the normal force of the obstacle on the body, :meth:`tangential_force` the
    friction force, :meth:`point_values` / :meth:`surface_values` at every vertex of the surface,
    :meth:`friction_profile` at the condensed vertices (those whose normal component is free).

    Args:
        u: the displacement.
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        tag: the contact boundary: a tag value, or a region name of ``facet_tags``.
        obstacle: the rigid :class:`Obstacle`.
        law: an :class:`ExactCoulomb`.
        load: the load parameter ``t`` (a scalar ``Constant``); the obstacle moves by ``t * motion``.
        quadrature: ``nodal``.
        name: the surface's name, in messages and output.
    """

    ring_weighted = False  # its own integrals (nodal weights, NumPy element) carry no 2 pi r

    requires_step_solver = True

    def __init__(self, u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact"):
        if not isinstance(obstacle, HalfPlane) or np.count_nonzero(obstacle.n) != 1:
            raise ValueError("method 'coulomb' needs a flat rigid obstacle (a half-plane with an axis-aligned "
                             f"normal): it uses the linearized normal; got {type(obstacle).__name__}")
        if quadrature != "nodal":
            raise ValueError("method 'coulomb' enforces the contact at the vertices: use quadrature 'nodal'")
        self.plane = PlaneVertices(u.function_space, obstacle)  # first: the pressure lives on its space
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name)
        self.plane.locate(self.facets, self.ds)
        owned = self.plane.Vk.dofmap.index_map.size_local
        nv = self.comm.allreduce(int(np.count_nonzero(self.plane.dofs < owned)), op=MPI.SUM)
        check_size(u.function_space.mesh.geometry.dim * nv, f"{name}: {nv} contact vertices (a coarser contact mesh "
                   "has fewer)")
        self.mu = float(law.mu)
        self.dim = u.function_space.mesh.geometry.dim
        self.kts = [j for j in range(self.dim) if j != self.plane.k]  # the tangential components
        # each one's collapsed dofs -> the unknown's (the collapsed spaces of the components share one numbering)
        self.parent_ts = [collapse(u.function_space.sub(j))[1] for j in self.kts]
        # 2D: the scalar traction along +e_kt; 3D: the traction vector (zero normal component)
        self.traction_out = fem.Function(self.plane.Vk if self.dim == 2 else u.function_space,
                                         name="tangential_traction")
        self._solution = None  # (vx, w, pn, pt, gap) of the last step, from set_solution

    def bind_material(self, material) -> None:
        """Refuse a bulk model the condensation cannot take (neo-Hookean: no constant stiffness) when the problem is
        made, through the capability grid (:class:`~fenics_contact.capabilities.UnsupportedCombination`)."""
        check(**of(self.law, material=material), kind="rigid")
        super().bind_material(material)

    def _pressure(self):
        self._p = fem.Function(self.plane.Vk, name="nodal_reaction_pressure")
        return self._p

    def residual(self, v):
        """None: the step solver enforces the contact."""
        return None

    def set_solution(self, vx: np.ndarray, w: np.ndarray, pn: np.ndarray, pt: np.ndarray, gap: np.ndarray,
                     mine: list[tuple[int, int]]) -> None:
        """A solved step at the condensed vertices (all of them, the same on every rank): positions ``vx`` (n, dim),
        weights ``w``, pressure ``pn`` (> 0 compression), tangential traction ``pt`` (n, dim - 1) (along
        ``+e_j`` for ``j`` in ``kts``) and gap ``gap`` (> 0 penetration); ``mine``: (vertex, local dof of
        ``plane.Vk``) of this rank's vertices."""
        self._solution = (vx, w, pn, pt, gap)
        self._p.x.array[:] = 0.0
        self.traction_out.x.array[:] = 0.0
        for i, dof in mine:
            self._p.x.array[dof] = pn[i]
            if self.dim == 2:
                self.traction_out.x.array[dof] = pt[i, 0]
            else:
                for m, parent in enumerate(self.parent_ts):
                    self.traction_out.x.array[parent[dof]] = pt[i, m]
        self._p.x.scatter_forward()
        self.traction_out.x.scatter_forward()

    def _need(self) -> tuple:
        if self._solution is None:
            raise RuntimeError(f"{self.name}: no step has been solved yet")
        return self._solution

    # --- results ----------------------------------------------------------------------
    def friction_profile(self) -> dict[str, np.ndarray]:
        """The condensed vertices sorted by reference position (the same on every rank): ``x`` (n, dim) reference
        position, ``gap`` (> 0 penetration), ``pressure`` (> 0 compression), ``traction`` (tangential traction of
        the obstacle on the body: 2D the scalar along ``+e_kt``, +x on a base facing +y; 3D the vector (n, 3)),
        ``state`` (0 open, 1 slip, 2 stick, by :func:`~.states.classify`). Collective."""
        vx, _, pn, pt, gap = self._need()
        if self.dim == 2:
            traction = pt[:, 0].copy()
        else:
            traction = np.zeros((len(pn), self.dim))
            traction[:, self.kts] = pt
        return {"x": vx.copy(), "gap": gap.copy(), "pressure": pn.copy(), "traction": traction,
                "state": classify(pn, np.linalg.norm(pt, axis=1), self.mu)}

    def tangential_force(self) -> np.ndarray:
        """Tangential (friction) force of the obstacle on the body, the sum of the nodal ones, shape (dim,)
        (per unit thickness in 2D). Collective."""
        _, w, _, pt, _ = self._need()
        f = np.zeros(self.dim)
        f[self.kts] = np.sum(pt * w[:, None], axis=0)
        return f

    def contact_force(self) -> np.ndarray:
        """Total force of the obstacle on the body (normal and tangential: the sum of the nodal contact forces),
        shape (dim,) (per unit thickness in 2D)."""
        _, w, pn, _, _ = self._need()
        f = self.tangential_force()
        f[self.plane.k] = self.plane.sign * float(np.sum(pn * w))
        return f
