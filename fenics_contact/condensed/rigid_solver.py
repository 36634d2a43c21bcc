"""Method ``coulomb`` against a flat rigid obstacle: the step solver of :class:`~.rigid_surface.CondensedContact`.

Formulation 1.6 (Renaud & Feng 2003): linear elasticity, small displacements, nodal (vertex) contact, 2D or 3D,
against a half-plane whose normal is a coordinate axis ``sign e_k`` (so the normal is the linearized, fixed one);
the tangent basis is the other axes. The contact dofs are the normal and tangential components of every contact
vertex whose normal component is free (not Dirichlet); a prescribed tangential component has no unknown (its
support takes that friction force: the vertex slips and sticks along its free axes only). Per vertex the
distance from the obstacle is ``d = d0 + t d_motion + sign u_n`` (>= 0 open), the normal force ``R_n = sign
R_k`` (> 0 compression), the slip increment ``s = u_t - u_t(previous converged step)``; the rows are
Alart-Curnier's (:mod:`.newton`, the Coulomb disk of :mod:`.disk`).
"""
from __future__ import annotations

import numpy as np

from .disk import disk_rows
from .operator import CondensedStiffness
from .rigid_surface import CondensedContact
from .step import CondensedStepSolver

__all__ = ["CondensedCoulomb"]


class CondensedCoulomb(CondensedStepSolver):
    """Signorini contact with Coulomb friction of ``contact`` against a flat rigid obstacle, solved exactly on the
    condensed system (see the module): the problem's step solver (``ContactProblem(...,
    step_solver=CondensedCoulomb(contact))``). ``max_it`` semismooth Newton iterations at most per try, converged
    at the relative residual ``tol``.

    Args:
        contact: the :class:`CondensedContact`.
        max_it: semismooth Newton iterations per try.
        tol: the relative residual at convergence.
    """

    def __init__(self, contact: CondensedContact, max_it: int = 50, tol: float = 1e-11):
        if not isinstance(contact, CondensedContact):
            raise ValueError(f"contact must be the CondensedContact of method 'coulomb', got {type(contact).__name__}")
        super().__init__(contact.comm, max_it, tol)
        self.contact, self.mu = contact, contact.mu
        # the obstacle's geometry: normal component k (its sign), tangential components kts
        self.k, self.kts, self.sign, self.dim = contact.plane.k, contact.kts, contact.plane.sign, contact.dim

    def _contact_dofs(self, problem, K: CondensedStiffness) -> np.ndarray:
        """Normal and tangential components of every contact vertex whose normal one is free (owned rows, gathered
        on every rank, sorted by position): the normal components of all vertices, then the free tangential ones
        along each axis of ``kts`` in turn."""
        comm, plane, parents = self.comm, self.contact.plane, self.contact.parent_ts
        V = problem.u.function_space
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        r0 = K.A.getOwnershipRange()[0]
        dirichlet_local = set((K.dir_idx - r0).tolist())
        Xall = plane.Vk.tabulate_dof_coordinates()[:, :self.dim]
        rows = []
        for j, dof in enumerate(plane.dofs):
            ln = int(plane.parent[dof])
            if ln >= n_owned or ln in dirichlet_local:
                continue
            lts = [int(parent[dof]) for parent in parents]
            gts = tuple(lt + r0 if (lt < n_owned and lt not in dirichlet_local) else -1 for lt in lts)
            rows.append((tuple(Xall[dof]), ln + r0, gts, plane.weight[j], comm.rank, int(dof)))
        rows = [r for part in comm.allgather(rows) for r in part]
        # by position, rounded: a vertex's coordinates may differ in the last bit between partitions
        rows.sort(key=lambda r: tuple(np.round(r[0], 12)))
        self._vx = np.array([r[0] for r in rows]).reshape(-1, self.dim)
        self._gn = np.array([r[1] for r in rows], dtype=np.int64)
        self._gt = np.array([r[2] for r in rows], dtype=np.int64).reshape(-1, self.dim - 1)  # -1: prescribed
        self._w = np.array([r[3] for r in rows])
        self._mine = [(i, r[5]) for i, r in enumerate(rows) if r[4] == comm.rank]  # (vertex, local dof)
        nv = len(rows)
        self._has = self._gt >= 0  # (nv, m): the vertex's free tangential components
        # position of each tangential unknown in u_c: after the normal ones, direction by direction
        self._tpos = np.zeros(self._has.shape, np.int64)
        self._tpos.T[self._has.T] = nv + np.arange(int(self._has.sum()))
        obstacle = self.contact.obstacle
        self._d0 = self.sign * (self._vx[:, self.k] - obstacle.point[self.k])
        self._dmotion = -self.sign * obstacle.motion[self.k]  # d0(t) = d0 + f(t) * dmotion (the obstacle's path)
        self._ref = np.zeros(self._has.shape)  # tangential displacement at the last converged step
        return np.concatenate([self._gn, self._gt.T[self._has.T]])

    def _tangential(self, v: np.ndarray) -> np.ndarray:
        """The tangential components (nv, m) of a vector ``v`` over the condensed dofs (0 where prescribed)."""
        return np.where(self._has, v[self._tpos], 0.0)

    def _residual(self, uc: np.ndarray, t: float, c: float):
        """Alart-Curnier residual, its generalized Jacobian, the per-vertex contact state (open, closed, slip or
        stick, in 2D with the slip direction: for the cycle detection) and ``R``."""
        sgn, nv, S, has = self.sign, len(self._gn), self.S, self._has
        R = S @ uc + self._r
        Rn = sgn * R[:nv]
        d = self._d0 + self.contact.obstacle.factor(t) * self._dmotion + sgn * uc[:nv]
        F, J = np.zeros_like(uc), np.zeros((len(uc), len(uc)))
        lam = Rn - c * d
        active = lam > 0
        F[:nv] = np.where(active, c * d, Rn)
        J[:nv] = sgn * S[:nv]
        an = np.flatnonzero(active)
        J[an] = 0.0
        J[an, an] = c * sgn
        Ft, A, B, g, stick, e = disk_rows(self._tangential(R), self._tangential(uc) - self._ref, lam, self.mu, c,
                                          has)
        v, j = np.nonzero(has)  # (vertex, direction) of each tangential row
        rows = self._tpos[v, j]
        F[rows] = Ft[v, j]
        # d lam = sgn dR_n - c sgn du_n; dR_t = S[tangential rows]; ds = du_t
        Jt = np.einsum("rk,rkc->rc", A[v, j] * has[v], S[np.where(has, self._tpos, 0)[v]])
        Jt += g[v, j][:, None] * sgn * S[v]
        Jt[np.arange(len(v)), v] -= g[v, j] * c * sgn
        for k in range(has.shape[1]):
            on = has[v, k]
            Jt[np.flatnonzero(on), self._tpos[v[on], k]] += B[v[on], j[on], k]
        J[rows] = Jt
        state = np.where(active, 1, 0)
        state = np.where(active & stick, 2, state)
        if has.shape[1] == 1:  # 2D: the slip direction too
            state = np.where(active & ~stick & (e[:, 0] < 0), -1, state)
        return F, J, state, R

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        """Nodal pressure ``sign R_k / w`` (> 0 compression), tangential traction ``R_t / w`` and gap (> 0
        penetration) of every condensed vertex to the surface."""
        nv = len(self._gn)
        R = self.S @ uc + self._r
        pn = self.sign * R[:nv] / self._w
        pt = self._tangential(R) / self._w[:, None]
        gap = -(self._d0 + self.contact.obstacle.factor(t) * self._dmotion + self.sign * uc[:nv])
        self.contact.set_solution(self._vx, self._w, pn, pt, gap, self._mine)

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        return self._tangential(uc)
