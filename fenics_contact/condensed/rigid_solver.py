"""Method ``coulomb`` against a flat rigid obstacle: the step solver of :class:`~.rigid_surface.CondensedContact`.

Formulation 1.6 (Renaud & Feng 2003): linear elasticity, small displacements, nodal (vertex) contact, 2D,
against a half-plane whose normal is a coordinate axis ``sign e_k`` (so the normal is the linearized, fixed one).
The contact dofs are the normal and tangential components of every contact vertex whose normal component is
free (not Dirichlet); a vertex with a prescribed tangential component has no tangential unknown (no friction
force). Per vertex the distance from the obstacle is ``d = d0 + t d_motion + sign u_n`` (>= 0 open), the normal
force ``R_n = sign R_k`` (> 0 compression), the slip increment ``s = u_t - u_t(previous converged step)``; the
rows are Alart-Curnier's (:mod:`.newton`).
"""
from __future__ import annotations

import numpy as np

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
        # the obstacle's geometry: normal component k (its sign), tangential component kt
        self.k, self.kt, self.sign = contact.plane.k, contact.kt, contact.plane.sign

    def _contact_dofs(self, problem, K: CondensedStiffness) -> np.ndarray:
        """Normal and tangential component of every contact vertex whose normal one is free (owned rows, gathered
        on every rank, sorted by position): normal components of all vertices, then the tangential ones."""
        comm, plane, parent_t = self.comm, self.contact.plane, self.contact.parent_t
        V = problem.u.function_space
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        r0 = K.A.getOwnershipRange()[0]
        dirichlet_local = set((K.dir_idx - r0).tolist())
        Xall = plane.Vk.tabulate_dof_coordinates()
        rows = []
        for j, dof in enumerate(plane.dofs):
            ln, lt = int(plane.parent[dof]), int(parent_t[dof])
            if ln >= n_owned or ln in dirichlet_local:
                continue
            gt = lt + r0 if (lt < n_owned and lt not in dirichlet_local) else -1
            rows.append((Xall[dof, 0], Xall[dof, 1], ln + r0, gt, plane.weight[j], comm.rank, int(dof)))
        rows = [r for part in comm.allgather(rows) for r in part]
        rows.sort(key=lambda r: (r[0], r[1]))
        self._vx = np.array([[r[0], r[1]] for r in rows]).reshape(-1, 2)
        self._gn = np.array([r[2] for r in rows], dtype=np.int64)
        self._gt = np.array([r[3] for r in rows], dtype=np.int64)
        self._w = np.array([r[4] for r in rows])
        self._mine = [(i, r[6]) for i, r in enumerate(rows) if r[5] == comm.rank]  # (vertex, local dof)
        nv = len(rows)
        self._has_t = self._gt >= 0
        self._it = np.flatnonzero(self._has_t)  # vertices with a tangential unknown
        self._tpos = nv + np.arange(len(self._it))
        obstacle = self.contact.obstacle
        self._d0 = self.sign * (self._vx[:, self.k] - obstacle.point[self.k])
        self._dmotion = -self.sign * obstacle.motion[self.k]  # d0(t) = d0 + f(t) * dmotion (the obstacle's path)
        self._ref = np.zeros(len(self._it))  # tangential displacement at the last converged step
        return np.concatenate([self._gn, self._gt[self._it]])

    def _residual(self, uc: np.ndarray, t: float, c: float):
        """Alart-Curnier residual, its generalized Jacobian, the per-vertex contact state (open, closed, slip or
        stick with the direction: for the cycle detection) and ``R``."""
        sgn, mu, nv, S = self.sign, self.mu, len(self._gn), self.S
        R = S @ uc + self._r
        Rn = sgn * R[:nv]
        d = self._d0 + self.contact.obstacle.factor(t) * self._dmotion + sgn * uc[:nv]
        Rt, s = R[self._tpos], uc[self._tpos] - self._ref
        F, J = np.zeros_like(uc), np.zeros((len(uc), len(uc)))
        lam = Rn - c * d
        active = lam > 0
        F[:nv] = np.where(active, c * d, Rn)
        J[:nv] = sgn * S[:nv]
        an = np.flatnonzero(active)
        J[an] = 0.0
        J[an, an] = c * sgn
        bound = mu * np.maximum(lam[self._it], 0.0)
        q = Rt - c * s
        stick = np.abs(q) <= bound
        direction = np.sign(q)
        F[self._tpos] = np.where(stick, c * s, Rt - bound * direction)
        for m, i in enumerate(self._it):
            row = self._tpos[m]
            if stick[m]:
                J[row] = 0.0
                J[row, row] = c
            else:
                J[row] = S[row]
                if active[i]:
                    J[row] -= mu * direction[m] * sgn * S[i]
                    J[row, i] += mu * direction[m] * c * sgn
        state = np.where(active, 1, 0)
        state[self._it] = np.where(active[self._it], np.where(stick, 2, 1) * np.where(direction < 0, -1, 1), 0)
        return F, J, state, R

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        """Nodal pressure ``sign R_k / w`` (> 0 compression), tangential traction ``R_t / w`` and gap (> 0
        penetration) of every condensed vertex to the surface."""
        nv = len(self._gn)
        R = self.S @ uc + self._r
        pn = self.sign * R[:nv] / self._w
        pt = np.zeros(nv)
        pt[self._it] = R[self._tpos] / self._w[self._it]
        gap = -(self._d0 + self.contact.obstacle.factor(t) * self._dmotion + self.sign * uc[:nv])
        self.contact.set_solution(self._vx, self._w, pn, pt, gap, self._mine)

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        return uc[self._tpos].copy()
