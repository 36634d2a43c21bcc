"""Exact Signorini-Coulomb contact on the stiffness condensed onto the contact dofs (method ``coulomb``).

Formulation 1.6 (Renaud & Feng 2003), for linear elasticity, small
displacements, nodal (vertex) contact against a flat rigid obstacle (a
half-plane with an axis-aligned normal, so the normal is the linearized,
fixed one), in 2D:

1. Condensation (once, at the first step). ``K`` is the stiffness (the
   problem's Jacobian, constant for linear elasticity) and ``f`` the external
   load at ``t = 1``. With the contact dofs ``c`` (normal and tangential
   component of every base vertex, minus Dirichlet ones) and the Dirichlet dofs
   prescribed, ``K_D`` (``K`` with those rows and columns replaced by the
   identity) is regular even when the body floats without its contact (the
   slab): the base is clamped. One MUMPS factorization of ``K_D``; one solve per
   contact dof gives the displacement mode ``phi_j`` (``u_c = e_j``, the rest in
   equilibrium, no load), and one more the load mode ``u_0`` (``u_c = 0``, load
   ``f``, Dirichlet data). Then the Schur complement ``S = K_cc - K_ci K_ii^-1
   K_ic`` has columns ``(K phi_j)_c`` and the contact force (obstacle on body)
   is ``R(u_c) = S u_c + t r_0``, ``r_0 = (K u_0 - f)_c``. ``S`` is singular for
   a floating body; nothing here inverts it.
2. Each load step: Alart-Curnier's semismooth Newton on ``u_c`` alone
   (``R`` is eliminated), per vertex with distance ``d >= 0``, normal force
   ``R_n`` and slip increment ``s = u_t - u_t(previous converged step)``:
   ``R_n - max(0, R_n - c d) = 0`` and ``R_t - proj_[-mu l, mu l](R_t - c s) = 0``
   with ``l = max(0, R_n - c d)``. ``c`` (the mean diagonal of ``S``)
   only steers the iteration: the solution does not depend on it (no penalty);
   a failed iteration is retried with ``c / 10`` and ``c / 100``.
   Converged when the residual is below ``tol`` times the load's contact
   force; a repeated active set without progress (a cycle), a singular
   Jacobian or ``max_it`` iterations end the step with a message.
3. Recovery: one solve of ``K_D u = ...`` with ``u_c`` prescribed.

Parallel: ``K`` and its factorization are distributed (MUMPS). The modes are
solved by blocks of 64 right-hand sides (a dense matrix, ``MatMatSolve``),
collectively; every rank keeps its owned rows of ``(K phi_j)_c``, and one
``allgather`` gives the dense ``S`` (``n_c x n_c``, a few hundred) to every
rank, which then runs the same small Newton on the same data (identical on
every rank, no further communication). Cost: one factorization, ``n_c + 2``
triangular solves (``n_c`` of them blocked) and mat-vecs, ``O(n_c^2)`` memory per rank; per Newton
iteration a dense ``n_c x n_c`` solve.
"""
from __future__ import annotations

import time

import dolfinx.fem.petsc as fem_petsc
import numpy as np
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .bounds import BoundContact
from .compat import bc_dofs, petsc_vec
from .laws import ContactLaw
from .obstacles import HalfPlane, Obstacle
from .surface import StepSolver

__all__ = [
    "OPEN", "SLIP", "STICK", "P_TOL", "T_TOL", "CHUNK", "classify", "StepFailure", "CondensedContact",
    "CondensedCoulomb", "step_solver_for"
]

OPEN, SLIP, STICK = 0, 1, 2
# State of a vertex from its values: open if p <= P_TOL * max p; at the Coulomb bound (slip) if
# |t| >= (1 - T_TOL) mu p; stick otherwise. mu = 0: every loaded vertex slips.
P_TOL, T_TOL = 1e-10, 1e-8
CHUNK = 64  # contact dofs per multi-right-hand-side solve of the condensation (memory: CHUNK dense vectors)


def classify(pressure: np.ndarray, traction: np.ndarray, mu: float) -> np.ndarray:
    """Vertex states (0 open, 1 slip, 2 stick) from pressure (> 0 compression) and tangential traction."""
    pressure, traction = np.asarray(pressure, float), np.asarray(traction, float)
    pmax = float(np.max(pressure)) if pressure.size else 0.0
    loaded = pressure > P_TOL * pmax
    at_bound = np.abs(traction) >= (1.0 - T_TOL) * mu * pressure
    return np.where(loaded, np.where(at_bound, SLIP, STICK), OPEN)


class StepFailure(RuntimeError):
    """The condensed semismooth Newton did not converge (the message says why)."""


class CondensedContact(BoundContact):
    """The contact surface of method ``coulomb``: contact vertices, their weights ``int phi_i ds``, the output
    fields (pressure, tangential traction) and figures. It has no residual term and no bounds: its load steps
    are solved by a :class:`CondensedCoulomb` given to the problem (``requires_step_solver``), which writes
    the nodal contact forces over the vertex weights back here (:meth:`set_solution`)."""

    bounded = False
    requires_step_solver = True

    def __init__(self, u: fem.Function, facet_tags, tag: int, obstacle: Obstacle, law: ContactLaw,
                 load: fem.Constant, quadrature: str = "nodal", name: str = "contact"):
        if not isinstance(obstacle, HalfPlane) or np.count_nonzero(obstacle.n) != 1:
            raise ValueError("method 'coulomb' needs a flat rigid obstacle (a half-plane with an axis-aligned "
                             f"normal): it uses the linearized normal; got {type(obstacle).__name__}")
        if quadrature != "nodal":
            raise ValueError("method 'coulomb' enforces the contact at the vertices: use quadrature 'nodal'")
        if u.function_space.mesh.geometry.dim != 2:
            raise ValueError("method 'coulomb' is implemented in 2D only (one tangential direction)")
        super().__init__(u, facet_tags, tag, obstacle, law, load, quadrature, name)
        self.mu = float(law.mu)
        self.kt = 1 - self.k  # the tangential component
        _, parent_t = u.function_space.sub(self.kt).collapse()
        self._parent_t = np.asarray(parent_t, dtype=np.int32)
        self.traction_out = fem.Function(self._Vk, name="tangential_traction")
        self._solution = None  # (vx, w, pn, pt, gap) of the last step, from set_solution

    def after_solve(self, problem) -> None:
        """Nothing: the pressure is the step solver's (:meth:`set_solution`), not the nodal reaction."""

    def set_solution(self, vx: np.ndarray, w: np.ndarray, pn: np.ndarray, pt: np.ndarray, gap: np.ndarray,
                     mine: list[tuple[int, int]]) -> None:
        """The contact vertices' positions ``vx``, weights ``w``, pressure ``pn``, tangential traction ``pt`` and gap
        (all vertices, the same on every rank) of a solved step; ``mine``: (vertex, local dof) of this rank's."""
        self._solution = (vx, w, pn, pt, gap)
        self._p.x.array[:] = 0.0
        self.traction_out.x.array[:] = 0.0
        for i, dof in mine:
            self._p.x.array[dof] = pn[i]
            self.traction_out.x.array[dof] = pt[i]
        self._p.x.scatter_forward()
        self.traction_out.x.scatter_forward()

    # --- figures --------------------------------------------------------------
    def friction_profile(self) -> dict:
        """Base vertices sorted by position (identical on every rank): ``x`` (n, 2), ``gap`` (> 0
        penetration), ``pressure`` (> 0 compression), ``traction`` (tangential, along +x), ``state``
        (0 open, 1 slip, 2 stick, by :func:`classify`)."""
        if self._solution is None:
            raise RuntimeError("no step has been solved yet")
        vx, _, pn, pt, gap = self._solution
        return {"x": vx.copy(), "gap": gap.copy(), "pressure": pn.copy(), "traction": pt.copy(),
                "state": classify(pn, pt, self.mu)}

    def contact_force(self) -> np.ndarray:
        """Total force of the obstacle on the body (sum of the nodal contact forces), by component."""
        _, w, pn, pt, _ = self._solution
        f = np.zeros(2)
        f[self.k] = self.sign * float(np.sum(pn * w))
        f[self.kt] = float(np.sum(pt * w))
        return f


class CondensedCoulomb(StepSolver):
    """Signorini contact with Coulomb friction of ``contact``, solved exactly on the condensed system (see the
    module): the problem's step solver (``ContactProblem(..., step_solver=CondensedCoulomb(contact))``).
    ``max_it`` semismooth Newton iterations at most per try, converged at the relative residual ``tol``."""

    def __init__(self, contact: CondensedContact, max_it: int = 50, tol: float = 1e-11):
        if not isinstance(contact, CondensedContact):
            raise ValueError(f"contact must be the CondensedContact of method 'coulomb', got {type(contact).__name__}")
        if int(max_it) < 1 or not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"max_it must be >= 1 and tol a finite number > 0, got {max_it!r}, {tol!r}")
        self.contact = contact
        c = contact  # its geometry: normal component k (sign), tangential kt, vertex dofs and weights
        self.k, self.kt, self.sign, self.obstacle, self.comm = c.k, c.kt, c.sign, c.obstacle, c.comm
        self._Vk, self._dofs, self._parent, self._parent_t, self._weight = (c._Vk, c._dofs, c._parent, c._parent_t,
                                                                             c._weight)
        self.mu = contact.mu
        self.max_it, self.tol = int(max_it), float(tol)
        # Alart-Curnier's c = c_scale * (mean diagonal of S); a failed iteration is retried with c / 10 and
        # c / 100 (a safeguard). Measured on the slab from the zero start (mu 0.4 - 5): c_scale from 1e-3 to
        # 1e2 gives the same iterations (6-8) and the same solution to 1e-14: active contacts get d = 0 and
        # sticking vertices s = 0 exactly after one step, so c hardly enters the active-set decisions.
        self.c_scale, self.retries = 1.0, 2
        self._ready = False
        self.timings = {"condense_s": 0.0, "contact_newton_s": 0.0, "recover_s": 0.0}

    # --- set-up: the condensed system ----------------------------------------
    def _condense(self, problem) -> None:
        if not problem.material.linear:
            raise ValueError("method 'coulomb' needs linear elasticity (a constant stiffness to condense), "
                             f"got material {type(problem.material).__name__}")
        start = time.perf_counter()
        comm = self.comm
        V = problem.u.function_space
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        u_save, t_save = problem.u.x.array.copy(), float(problem.load.value)

        # K (no boundary conditions) and the external load f at t = 1 (-F at u = 0).
        problem.u.x.array[:] = 0.0
        problem.load.value = 1.0
        self._A = fem_petsc.assemble_matrix(problem.a)
        self._A.assemble()
        self._f = fem_petsc.create_vector(problem.L)
        with self._f.localForm() as fl:
            fl.set(0.0)
        fem_petsc.assemble_vector(self._f, problem.L)
        self._f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self._f.scale(-1.0)
        problem.u.x.array[:] = u_save
        problem.load.value = t_save
        r0 = self._A.getOwnershipRange()[0]

        # Dirichlet dofs (owned, global) with their amplitudes at t = 1.
        dir_idx, dir_amp = [], []
        for d in problem.dirichlet:
            local = bc_dofs(d.bc)
            local = local[local < n_owned]
            dir_idx.append(local + r0)
            dir_amp.append(np.full(len(local), float(d.amplitude)))
        self._dir_idx = np.concatenate(dir_idx + [np.empty(0, np.int64)]).astype(PETSc.IntType)
        self._dir_amp = np.concatenate(dir_amp + [np.empty(0)])
        dirichlet_local = set((self._dir_idx - r0).tolist())

        # Contact vertices: owned normal dofs; gather (coordinates, global dofs, weight) on every rank.
        Xall = self._Vk.tabulate_dof_coordinates()
        rows = []
        for j, dof in enumerate(self._dofs):
            ln, lt = int(self._parent[dof]), int(self._parent_t[dof])
            if ln >= n_owned or ln in dirichlet_local:
                continue
            gt = lt + r0 if (lt < n_owned and lt not in dirichlet_local) else -1
            rows.append((Xall[dof, 0], Xall[dof, 1], ln + r0, gt, self._weight[j], comm.rank, int(dof)))
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
        # Unknown ordering: normal components of all vertices, then tangential ones.
        self._cidx = np.concatenate([self._gn, self._gt[self._it]]).astype(PETSc.IntType)
        self._tpos = nv + np.arange(len(self._it))
        nc = len(self._cidx)
        self._d0 = self.sign * (self._vx[:, self.k] - self.obstacle.point[self.k])
        self._dmotion = -self.sign * self.obstacle.motion[self.k]  # d0(t) = d0 + t * dmotion

        # K_D: K with the rows and columns of the contact and Dirichlet dofs replaced by the identity.
        fixed = np.unique(np.concatenate([self._dir_idx, self._cidx]))
        lo, hi = self._A.getOwnershipRange()
        self._fixed = fixed[(fixed >= lo) & (fixed < hi)].astype(PETSc.IntType)
        KD = self._A.duplicate(copy=True)
        KD.zeroRowsColumns(self._fixed, diag=1.0)
        self._ksp = PETSc.KSP().create(comm)
        self._ksp.setOptionsPrefix("fc_condensed_")
        self._ksp.setType("preonly")
        self._ksp.getPC().setType("lu")
        self._ksp.getPC().setFactorSolverType("mumps")
        self._ksp.setFromOptions()
        self._ksp.setOperators(KD)
        self._KD = KD
        self._x, self._b, self._y = self._f.duplicate(), self._f.duplicate(), self._f.duplicate()

        # Columns of S from multi-right-hand-side solves (blocks of CHUNK dofs), r_0 from one more solve;
        # each rank keeps its owned contact rows.
        self._ksp.setUp()
        mine = np.flatnonzero((self._cidx >= lo) & (self._cidx < hi))
        cols = np.zeros((len(mine), nc))
        for first in range(0, nc, CHUNK):
            block = np.arange(first, min(first + CHUNK, nc))
            cols[:, block] = self._modes(block, mine)
        self._displacement(np.zeros(nc), 1.0, self._x)
        self._A.mult(self._x, self._y)
        self._y.axpy(-1.0, self._f)
        r0_mine = self._y.array[self._cidx[mine] - lo]
        S, r0v = np.zeros((nc, nc)), np.zeros(nc)
        for idx, c, r in comm.allgather((mine, cols, r0_mine)):
            S[idx], r0v[idx] = c, r
        self.S, self.r0 = 0.5 * (S + S.T), r0v
        self._diag = float(np.mean(np.abs(np.diag(self.S)))) if nc else 1.0
        self._uc = np.zeros(nc)  # last solution
        self._ref = np.zeros(len(self._it))  # tangential displacement at the last converged step
        self._ready = True
        self.timings["condense_s"] += comm.allreduce(time.perf_counter() - start, op=MPI.MAX)

    def _modes(self, block: np.ndarray, mine: np.ndarray) -> np.ndarray:
        """``(K phi_j)_c`` on this rank's contact rows ``mine`` for the contact dofs ``block``: ``phi_j`` has
        ``u_c = e_j``, zero Dirichlet data and no load (one MUMPS solve with a dense block of right-hand sides)."""
        A, comm = self._A, self.comm
        lo, hi = A.getOwnershipRange()
        E = PETSc.Mat().createDense(((hi - lo, A.getSize()[0]), (PETSc.DECIDE, len(block))), comm=comm)
        E.setUp()
        e = E.getDenseArray()
        e[:] = 0.0
        here = np.flatnonzero((self._cidx[block] >= lo) & (self._cidx[block] < hi))
        e[self._cidx[block[here]] - lo, here] = 1.0
        E.assemble()
        B = A.matMult(E)  # right-hand sides: -K e_j on the free rows, e_j on the held ones
        b = B.getDenseArray()
        b *= -1.0
        b[self._fixed - lo, :] = 0.0
        b[self._cidx[block[here]] - lo, here] = 1.0
        X = B.duplicate()
        self._ksp.getPC().getFactorMatrix().matSolve(B, X)
        Y = A.matMult(X)
        out = Y.getDenseArray()[self._cidx[mine] - lo, :].copy()
        for m in (E, B, X, Y):
            m.destroy()
        return out

    def _displacement(self, uc: np.ndarray, t: float, x: PETSc.Vec) -> None:
        """``x``: the displacement with contact dofs ``uc``, Dirichlet data and load at ``t``, in equilibrium
        elsewhere (one solve with the factorization of ``K_D``)."""
        lo, hi = self._A.getOwnershipRange()
        g = self._y
        g.set(0.0)
        idx = np.concatenate([self._dir_idx, self._cidx]).astype(PETSc.IntType)
        val = np.concatenate([t * self._dir_amp, uc])
        keep = (idx >= lo) & (idx < hi)
        g.array[idx[keep] - lo] = val[keep]
        self._A.mult(g, self._b)
        self._b.scale(-1.0)
        self._b.axpy(t, self._f)
        self._b.array[idx[keep] - lo] = val[keep]
        self._ksp.solve(self._b, x)

    # --- the semismooth Newton on the condensed system ------------------------
    def _residual(self, uc: np.ndarray, t: float):
        """Alart-Curnier residual, its generalized Jacobian and the per-vertex active set."""
        sgn, c, mu, nv = self.sign, self.c, self.mu, len(self._gn)
        R = self.S @ uc + t * self.r0
        Rn = sgn * R[:nv]
        d = self._d0 + t * self._dmotion + sgn * uc[:nv]
        Rt, s = R[self._tpos], uc[self._tpos] - self._ref
        F, J = np.zeros_like(uc), np.zeros((len(uc), len(uc)))
        lam = Rn - c * d
        active = lam > 0
        F[:nv] = np.where(active, c * d, Rn)
        J[:nv] = sgn * self.S[:nv]
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
                J[row] = self.S[row]
                if active[i]:
                    J[row] -= mu * direction[m] * sgn * self.S[i]
                    J[row, i] += mu * direction[m] * c * sgn
        state = np.where(active, 1, 0)
        state[self._it] = np.where(active[self._it], np.where(stick, 2, 1) * np.where(direction < 0, -1, 1), 0)
        return F, J, state, R

    def _newton(self, t: float) -> tuple[np.ndarray, list[float]]:
        """Semismooth Newton from the last solution with ``c = c_scale * mean diag S``; if it fails, again
        with ``c`` divided by 10, ``retries`` times. Returns ``u_c`` and the residual history of all tries."""
        history, reasons = [], []
        for k in range(self.retries + 1):
            self.c = self.c_scale * self._diag / 10**k
            try:
                uc, h = self._newton_c(t)
                return uc, history + h
            except StepFailure as exc:
                history += exc.args[1]
                reasons.append(f"c = {self.c:.3g}: {exc.args[0]}")
        raise StepFailure("; ".join(reasons), history)

    def _newton_c(self, t: float) -> tuple[np.ndarray, list[float]]:
        scale = max(float(np.max(np.abs(t * self.r0))) if len(self.r0) else 0.0, 1e-300)
        uc = self._uc.copy()
        history, seen = [], {}
        for it in range(self.max_it + 1):
            F, J, state, _ = self._residual(uc, t)
            norm = float(np.max(np.abs(F))) if len(F) else 0.0
            history.append(norm / scale)
            if norm <= self.tol * scale:
                return uc, history
            if it == self.max_it:
                raise StepFailure(f"no convergence in {self.max_it} iterations (relative residual {norm / scale:.2e})",
                                  history)
            key = state.tobytes()
            if key in seen and history[seen[key]] <= norm / scale:
                raise StepFailure(f"the semismooth Newton cycles (the contact state of iteration {it} repeats that "
                                  f"of iteration {seen[key]} without progress, relative residual {norm / scale:.2e})",
                                  history)
            seen[key] = it
            try:
                uc = uc - np.linalg.solve(J, F)
            except np.linalg.LinAlgError:
                raise StepFailure(f"singular semismooth Newton matrix at iteration {it} (no vertex in contact "
                                  "holds the body)", history) from None
        raise AssertionError("unreachable")

    def solve_step(self, problem) -> tuple[int, list[float], str]:
        """Solve the step at the problem's current load: ``(reason, residual history, message)``.

        ``reason`` > 0 converged (SNES's CONVERGED_FNORM_ABS), < 0 failed (DIVERGED_MAX_IT)."""
        if not self._ready:
            self._condense(problem)
        t = float(problem.load.value)
        start = time.perf_counter()
        try:
            uc, history = self._newton(t)
        except StepFailure as exc:
            self.timings["contact_newton_s"] += time.perf_counter() - start
            return int(PETSc.SNES.ConvergedReason.DIVERGED_MAX_IT), list(exc.args[1]), \
                f"method 'coulomb', mu = {self.mu:g}: {exc.args[0]}"
        self.timings["contact_newton_s"] += time.perf_counter() - start
        start = time.perf_counter()
        self._uc = uc
        self._set_output(uc, t)
        self._displacement(uc, t, self._x)
        self._x.copy(petsc_vec(problem.u))
        problem.u.x.scatter_forward()
        self.timings["recover_s"] += time.perf_counter() - start
        return int(PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS), history, ""

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        nv = len(self._gn)
        R = self.S @ uc + t * self.r0
        pn = self.sign * R[:nv] / self._w
        pt = np.zeros(nv)
        pt[self._it] = R[self._tpos] / self._w[self._it]
        gap = -(self._d0 + t * self._dmotion + self.sign * uc[:nv])
        self.contact.set_solution(self._vx, self._w, pn, pt, gap, self._mine)

    # --- step-solver hooks ------------------------------------------------------
    def commit(self) -> None:
        """The converged step becomes the reference of the next step's slip increments."""
        if self._ready:
            self._ref = self._uc[self._tpos].copy()

    def state(self) -> dict:
        if not self._ready:
            return {}
        return {"uc": self._uc.copy(), "ref": self._ref.copy()}

    def restore(self, state: dict) -> None:
        if state:
            self._uc, self._ref = state["uc"].copy(), state["ref"].copy()


def step_solver_for(contacts) -> CondensedCoulomb | None:
    """The step solver ``contacts`` need: a :class:`CondensedCoulomb` for the one that requires it (method
    ``coulomb``), or None when none does."""
    need = [c for c in contacts if c.requires_step_solver]
    if len(need) > 1:
        raise ValueError(f"method 'coulomb' condenses one contact surface, got {len(need)}: "
                         f"{', '.join(c.name for c in need)}")
    return CondensedCoulomb(need[0]) if need else None
