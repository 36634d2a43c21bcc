"""The two-body contact surface of method ``coulomb``: slave vertices paired once with the master facets.

Small sliding (2D or 3D, P1, nodal, one pass, linear elasticity): each slave vertex ``i`` is paired once, in the
reference configuration, with its closest point on the master surface (:func:`~fenics_contact.search.project`;
none past the master surface's free boundary):
master facet, shape-function weights ``N_ik`` of its vertices (two in 2D, three in 3D), the facet's outward normal
``n_i`` and tangent basis ``t_i`` (:func:`~.disk.tangent_basis`: ``(n_{i,y}, -n_{i,x})`` in 2D, two directions
in 3D), and the reference distance ``d0_i`` of the vertex from the facet's plane (> 0 open). Pairing, normals
and weights stay those of the reference configuration, so the method is exact for the linearized (small-sliding)
problem, not for slips comparable with the facets. Unpaired slave vertices (farther than the search radius) are
open: no force. The step solver is :class:`~.two_body_solver.CondensedTwoBodyCoulomb`.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem

from ..capabilities import check, of
from ..compat import function_space
from ..contact import PRESSURE_KINDS, check_facet_tag
from ..laws import ContactLaw, ExactCoulomb
from ..search import facet_normals, facet_sizes, free_sides, project, small_sliding_warning
from ..surface import Surface
from ..twobody import FacetData
from .disk import tangent_basis
from .operator import check_size
from .states import OPEN, SLIP, STICK

__all__ = ["CondensedTwoBody"]


class CondensedTwoBody(Surface):
    """The two-body contact surface of method ``coulomb`` (2D or 3D, P1, nodal; small sliding): the slave vertices
    of ``slave_tag`` paired once, in the reference configuration, with their closest point on the master facets of
    ``master_tag`` (:func:`~fenics_contact.search.project` within ``radius``, default twice the longest master
    facet edge): master facet, shape-function weights ``N``, its outward normal ``n`` and tangent basis
    ``tangent`` (n, dim - 1, dim) (:func:`~.disk.tangent_basis`: +x on a master facing +y in 2D; +x, +y on a
    master facing +z in 3D), the reference distance ``d0`` of the vertex from the facet's plane (> 0 open).
    No residual term and no bounds: its load steps are solved by a
    :class:`~.two_body_solver.CondensedTwoBodyCoulomb` (see the module), which writes the nodal contact forces
    back here (:meth:`set_solution`). Figures as the penalty two-body friction surface's: ``log`` (per committed
    step), :meth:`friction_profile`, :meth:`total_force`, :meth:`tangential_force`, :meth:`point_values`; output
    Functions ``gap_out``, ``pressure_out``, ``traction_out``, ``state_out``.

    Args:
        u: the displacement.
        facet_tags: the facet tags (dolfinx ``MeshTags`` or :class:`NamedTags`).
        slave_tag: the slave surface: a tag value, or a region name of ``facet_tags``.
        master_tag: the master surface (likewise).
        law: an :class:`ExactCoulomb`.
        load: the load parameter ``t`` (a scalar ``Constant``).
        radius: the search radius (length; default twice the longest master facet); farther points have no pair.
        name: the surface's name, in messages and output.
    """

    requires_step_solver = True

    def __init__(self, u: fem.Function, facet_tags, slave_tag, master_tag, law: ContactLaw, load: fem.Constant,
                 radius: float | None = None, name: str = "twobody"):
        if not isinstance(law, ExactCoulomb):
            raise ValueError(f"CondensedTwoBody needs the Coulomb law of method 'coulomb', got {law!r}")
        check(**of(law, u), kind="two-body", quadrature="nodal", passes="one")  # before any assembly
        V = u.function_space
        mesh = V.mesh
        dim = mesh.geometry.dim
        if V.num_sub_spaces != dim or V.sub(0).num_sub_spaces != 0:
            raise ValueError("method 'coulomb' between two bodies needs a displacement unknown (a vector space, "
                             "one component per axis)")
        if len(V.dofmap.dof_layout.entity_dofs(1, 0)):
            raise ValueError("method 'coulomb' between two bodies needs degree-1 (P1) displacements")
        if slave_tag == master_tag:
            raise ValueError(f"slave_tag and master_tag must differ, both are {slave_tag}")
        if radius is not None and not (np.isfinite(radius) and radius > 0):
            raise ValueError(f"search radius must be a finite number > 0, got {radius!r}")
        slave = check_facet_tag(mesh, facet_tags, slave_tag, f"{name} slave_tag")
        master = check_facet_tag(mesh, facet_tags, master_tag, f"{name} master_tag")
        self.u, self.law, self.load, self.name, self.comm = u, law, load, name, mesh.comm
        self.mu, self.dim = float(law.mu), dim
        comm = self.comm
        sd, md = FacetData(V, slave), FacetData(V, master)
        # This rank's (owned and ghost) vertex block dofs of the slave and of the master surface.
        self.local_dofs = (np.unique(sd.dofs), np.unique(md.dofs))

        # Slave vertices (every rank's, on every rank): global block dof, reference position, weight int phi ds
        # (a P1 facet's measure shared equally by its vertices: half a segment, a third of a triangle).
        own = sd.owned
        Xo = sd.X[own]
        if dim == 2:
            size = np.linalg.norm(Xo[:, 1] - Xo[:, 0], axis=1)
        else:
            size = 0.5 * np.linalg.norm(np.cross(Xo[:, 1] - Xo[:, 0], Xo[:, 2] - Xo[:, 0]), axis=1)
        parts = comm.allgather((sd.global_dofs[own].ravel(), Xo.reshape(-1, dim), np.repeat(size / dim, dim)))
        g, X, w = (np.concatenate(a) for a in zip(*parts))
        g, first, inverse = np.unique(g, return_index=True, return_inverse=True)
        w = np.bincount(inverse.ravel(), weights=w, minlength=len(g))
        X = X[first]
        order = np.lexsort(np.round(X, 12).T[::-1])  # by x, then y: partition-independent
        self.slave_dofs, self.X, self.weight = g[order], X[order], w[order]

        # Master facets (every rank's): global block dofs of their vertices and reference positions, outward normal.
        mparts = comm.allgather((md.global_dofs[md.owned], md.X[md.owned]))
        mG, mX = (np.concatenate(a) for a in zip(*mparts))
        key = np.lexsort(np.round(mX.mean(axis=1), 12).T[::-1])
        self.master_facets, self.master_X = mG[key], mX[key]
        if radius is None:
            radius = 2.0 * float(np.max(facet_sizes(self.master_X)))
        self.radius = float(radius)
        if np.intersect1d(self.slave_dofs, self.master_facets).size:
            raise ValueError(f"{name}: the slave and master surfaces share vertices (two bodies do not)")

        # The pairing, fixed (small sliding): closest master facet, weights N, normal, tangents, distance d0.
        facet, bary, _ = project(self.X, self.master_X, self.radius,
                                 free=free_sides(self.master_facets, self.master_facets, segments=dim == 2))
        self.facet, self.N = facet, bary
        self.paired = facet >= 0
        self.normal = np.zeros((len(facet), dim))
        self.normal[:, -1] = 1.0  # unpaired vertices: any unit normal (no force)
        self.normal[self.paired] = facet_normals(self.master_X[facet[self.paired]])
        self.tangent = tangent_basis(self.normal)
        self.d0 = np.full(len(facet), np.inf)
        self.d0[self.paired] = np.einsum("ij,ij->i", self.X[self.paired] - self.master_X[facet[self.paired], 0],
                                         self.normal[self.paired])
        nm = len(np.unique(self.master_facets[facet[self.paired]]))
        check_size(dim * (int(self.paired.sum()) + nm),
                   f"{name}: {int(self.paired.sum())} slave vertices within the search radius {self.radius:g} of "
                   f"{nm} master vertices (a coarser contact mesh or a smaller radius has fewer)")

        # Output fields on this rank's slave vertices (local dofs of a scalar P1 space and of V).
        P1 = function_space(mesh, "Lagrange", 1)
        sd1 = FacetData(P1, slave)
        where = {int(v): i for i, v in enumerate(self.slave_dofs)}
        pairs = {(int(a), int(b)): where[int(c)] for a, b, c in zip(sd1.dofs.ravel(), sd.dofs.ravel(),
                                                                   sd.global_dofs.ravel())}
        self._out = np.array([(a, b, i) for (a, b), i in pairs.items()], dtype=np.int64).reshape(-1, 3)
        self.displacement_out = u  # the displacement for output (as every surface's)
        self.gap_out = fem.Function(P1, name="gap")
        self.pressure_out = fem.Function(P1, name="pressure")
        self.state_out = fem.Function(P1, name="slip_state")
        self.traction_out = fem.Function(V, name="tangential_traction")
        self._solution = None  # (force n, force t, gap, state, slip) per slave vertex, from set_solution
        self.dissipated, self.log = 0.0, []
        self.slid = np.zeros((len(facet), dim))  # the committed steps' slip increments, summed (small sliding's range)

    def bind_material(self, material) -> None:
        """Refuse a bulk model the condensation cannot take (neo-Hookean: no constant stiffness) when the problem is
        made, through the capability grid (:class:`~fenics_contact.capabilities.UnsupportedCombination`)."""
        check(**of(self.law, material=material), kind="two-body")

    def residual(self, v):
        """None: the step solver enforces the contact."""
        return None

    def set_solution(self, fn: np.ndarray, ft: np.ndarray, gap: np.ndarray, state: np.ndarray,
                     slip: np.ndarray) -> None:
        """A solved step, per slave vertex (the same on every rank): nodal normal force ``fn`` (> 0 compression)
        and tangential force vector ``ft`` (n, dim) of the master on the slave, ``gap`` (> 0 penetration;
        ``-radius`` unpaired), ``state`` (0 open, 1 slip, 2 stick) and the slip increment vector of the step
        (n, dim)."""
        self._solution = (fn, ft, gap, state, slip)
        a, b, i = self._out.T
        for f, v in ((self.gap_out, gap), (self.pressure_out, fn / self.weight), (self.state_out, state)):
            f.x.array[:] = 0.0
            f.x.array[a] = v[i]
            f.x.scatter_forward()
        q = ft / self.weight[:, None]
        self.traction_out.x.array[:] = 0.0
        for k in range(self.dim):
            self.traction_out.x.array[self.dim * b + k] = q[i, k]
        self.traction_out.x.scatter_forward()

    def _need(self) -> tuple:
        if self._solution is None:
            raise RuntimeError(f"{self.name}: no step has been solved yet")
        return self._solution

    # --- results ----------------------------------------------------------------
    def friction_profile(self) -> dict[str, np.ndarray]:
        """Slave vertices sorted by reference position (the same on every rank): ``x`` (n, dim) reference
        position, ``gap`` (> 0 penetration), ``pressure`` (> 0 compression), ``traction`` (of the master on the
        slave: 2D the scalar along the tangent ``(n_y, -n_x)`` of the master normal, +x on a master facing +y;
        3D the vector (n, 3)), ``state`` (0 open, 1 slip, 2 stick). Collective."""
        fn, ft, gap, state, _ = self._need()
        q = ft / self.weight[:, None]
        traction = np.einsum("ij,ij->i", q, self.tangent[:, 0]) if self.dim == 2 else q
        return {"x": self.X.copy(), "gap": gap.copy(), "pressure": fn / self.weight, "traction": traction,
                "state": state.astype(int)}

    def displacement(self) -> np.ndarray:
        """The displacement of every slave vertex (n, dim), in the order of :attr:`X`, the same on every rank."""
        _, b, i = self._out.T
        ua = self.u.x.array
        out = np.zeros((len(self.X), self.dim))
        for idx, v in self.comm.allgather((i, np.stack([ua[self.dim * b + k] for k in range(self.dim)], axis=1))):
            out[idx] = v
        return out

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Current position (n, dim) (``reference=True``: reference position), gap (> 0 penetration) and pressure
        (> 0 compression) of the slave vertices, sorted by reference position (as the penalty two-body surfaces';
        small strain: the nominal and Cauchy pressures are the same). Collective."""
        if kind not in PRESSURE_KINDS:
            raise ValueError(f"pressure kind must be one of {PRESSURE_KINDS}, got {kind!r}")
        fn, _, gap, _, _ = self._need()
        return (self.X.copy() if reference else self.X + self.displacement()), gap.copy(), fn / self.weight

    def total_force(self) -> np.ndarray:
        """Normal contact force of the master on the slave body, ``sum_i f_n,i n_i``, shape (dim,) (per unit
        thickness in 2D; the friction force is :meth:`tangential_force`). Collective."""
        fn = self._need()[0]
        return np.sum(fn[:, None] * self.normal, axis=0)

    def tangential_force(self) -> np.ndarray:
        """Tangential (friction) force of the master on the slave body, the sum of the nodal ones, shape (dim,).
        Collective."""
        return np.sum(self._need()[1], axis=0)

    def capacity(self) -> float:
        """``mu sum_i f_n,i``: the largest tangential force the surface can carry at the current contact forces.
        Collective."""
        return self.mu * float(np.sum(self._need()[0]))

    def state_areas(self) -> dict[str, float]:
        """Length (2D) or area (3D) of the slave surface in each state by the vertex rule (sum of the vertex
        weights). Collective."""
        state = self._need()[3]
        return {k: float(np.sum(self.weight[state == v])) for k, v in (("open", OPEN), ("slip", SLIP),
                                                                       ("stick", STICK))}

    # --- solver hooks -------------------------------------------------------------
    def commit(self) -> None:
        """Log the accepted step (forces, capacity, dissipation, state lengths)."""
        if self._solution is None:
            return
        fn, ft, _, _, slip = self._solution
        self.dissipated += float(-np.sum(ft * slip))  # the friction force opposes the slip: >= 0
        self.slid = self.slid + slip
        self.log.append({"load": float(self.load.value), "normal_force": self.total_force().tolist(),
                         "tangential_force": self.tangential_force().tolist(), "capacity": self.capacity(),
                         "dissipated": self.dissipated, **self.state_areas()})

    def state(self) -> dict:
        return {"solution": self._solution, "dissipated": self.dissipated, "slid": self.slid}

    def restore(self, state: dict) -> None:
        if self._solution is not state["solution"] and state["solution"] is not None:
            self.set_solution(*state["solution"])
        self._solution, self.dissipated = state["solution"], state["dissipated"]
        self.slid = state.get("slid", np.zeros_like(self.slid))

    def range_warning(self) -> str | None:
        """Small sliding (the fixed pairs) past its range: a slave vertex within a facet size of closing slid more
        than :data:`~fenics_contact.search.SMALL_SLIDING` of its master facet's size over the committed steps. The
        same on every rank. Collective."""
        if self._solution is None or not self.paired.any():
            return None
        gap = self._solution[2][self.paired]
        h = facet_sizes(self.master_X[self.facet[self.paired]])
        near = gap > -h
        slid = np.linalg.norm(self.slid[self.paired], axis=1) / h
        return small_sliding_warning(float(slid[near].max()) if near.any() else 0.0)

