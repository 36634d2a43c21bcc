"""Exact Signorini-Coulomb contact on the stiffness condensed onto the contact dofs (method ``coulomb``).

Formulation 1.6 (Renaud & Feng 2003), for linear elasticity, small
displacements, nodal (vertex) contact, in 2D, against a flat rigid obstacle
(:class:`CondensedContact`: a half-plane with an axis-aligned normal, so the
normal is the linearized, fixed one) or between two deformable bodies in
small sliding (:class:`CondensedTwoBody`, below):

1. Condensation (once, at the first step). ``K`` is the stiffness (the
   problem's Jacobian, constant for linear elasticity). With the contact dofs
   ``c`` (rigid: normal and tangential component of every base vertex, minus
   Dirichlet ones) and the Dirichlet dofs prescribed, ``K_D`` (``K`` with those
   rows and columns replaced by the identity) is regular even when the body
   floats without its contact (the slab): the base is clamped. One MUMPS
   factorization of ``K_D``; one solve per contact dof gives the displacement
   mode ``phi_j`` (``u_c = e_j``, the rest in equilibrium, no load). Then the
   Schur complement ``S = K_cc - K_ci K_ii^-1 K_ic`` has columns ``(K phi_j)_c``.
   ``S`` is singular for a floating body; nothing here inverts it.
2. Each load step, the load as the problem has set it at ``t`` (tractions,
   body forces and Dirichlet values: any path, not only ``t`` times a load):
   one more solve gives the load mode ``u_0(t)`` (``u_c = 0``, the load
   ``f(t)``, the Dirichlet data at ``t``), and the force the contact dofs need
   (the contact force on the body) is ``R(u_c) = S u_c + r(t)``,
   ``r(t) = (K u_0(t) - f(t))_c``. Alart-Curnier's semismooth Newton on ``u_c``
   alone (``R`` is eliminated), per vertex with distance ``d >= 0``, normal
   force ``R_n`` and slip increment ``s = u_t - u_t(previous converged step)``:
   ``R_n - max(0, R_n - c d) = 0`` and ``R_t - proj_[-mu l, mu l](R_t - c s) = 0``
   with ``l = max(0, R_n - c d)``. ``c`` (the mean diagonal of ``S``)
   only steers the iteration: the solution does not depend on it (no penalty);
   a failed iteration is retried with ``c / 10`` and ``c / 100``.
   Converged when the residual is below ``tol`` times the largest entry of
   ``r(t)``; a repeated active set without progress (a cycle), a singular
   Jacobian or ``max_it`` iterations end the step with a message.
3. Recovery: one solve of ``K_D u = ...`` with ``u_c`` prescribed.

``K`` is re-assembled at every step and compared with the condensed one: a stiffness that changes with the load
(the vanishing spring of a force-controlled scene) is condensed again for that step (exact at every step).

Two bodies (:class:`CondensedTwoBody`, :class:`CondensedTwoBodyCoulomb`; 2D, P1, nodal, one pass, linear
elasticity). Small sliding: each slave vertex ``i`` is paired once, in the reference configuration, with its
closest point on the master surface (:func:`~fenics_contact.search.project`): master facet, shape-function
weights ``N_ik`` of its two vertices, the facet's outward normal ``n_i`` and tangent ``t_i = (n_{i,y},
-n_{i,x})``. Relative displacement ``w_i = u_s,i - sum_k N_ik u_m(i,k)``, distance ``d_i = d0_i + n_i . w_i``
(``d0_i``: the reference distance of the vertex from the facet's line; ``d >= 0`` open), slip increment ``s_i =
t_i . (w_i - w_i(previous converged step))``. Everything is linear in ``u``: pairing, normals and weights stay
those of the reference configuration, so the method is exact for the linearized (small-sliding) problem, not
for slips comparable with the facets. Condensed dofs: the free components of the paired slave vertices and of
the vertices of the master facets they are paired with (a prescribed component enters ``w`` as data). The
contact force of the master on slave vertex ``i`` is ``p_i n_i + q_i t_i``, its reaction ``-N_ik (p_i n_i + q_i
t_i)`` on master vertex ``k``; with ``R = S u_c + r(t)`` the force the contact dofs need, ``p_i = n_i . R_s,i``
and ``q_i = t_i . R_s,i`` are eliminated and the unknowns are ``u_c`` only: per paired slave vertex the two
Alart-Curnier rows above in ``(p_i, q_i, d_i, s_i)``, per free master component the linear row ``R_m + sum_i
N_im (p_i n_i + q_i t_i) = 0`` (action and reaction: the contact forces on the two bodies are equal and
opposite by construction). A paired slave vertex with one prescribed component (a symmetry plane across the
surface) carries no friction (``q_i = 0``; ``p_i`` from its free component); a prescribed normal motion is
refused. Unpaired slave vertices (farther than the search radius) are open: not condensed, no force. The same
Newton safeguards; as many rows as unknowns. Cost as below with ``n_c`` = both surfaces' contact dofs (the
mindlin scene: 568 for 14 200 dofs).

``S`` from one more MUMPS factorization, of ``K`` with the Dirichlet rows and columns the identity, that
eliminates all but the contact dofs (:func:`~fenics_contact.compat.schur_complement`, MUMPS's ICNTL(19)): about
the cost of one factorization. Parallel: ``K`` and its factorization for the solves are distributed (MUMPS);
PETSc does not hand out MUMPS's distributed Schur complement, so ``K`` is gathered on rank 0 for ``S`` (its
``nnz`` entries once) and ``S`` (``n_c x n_c``, a few hundred) is broadcast; every rank then runs the same small
Newton on the same data (identical on every rank; per step one allgather of ``r(t)``). Cost: two
factorizations, ``O(n_c^2)`` memory per rank (dense ``S``: 8 n_c^2 bytes); per step one more solve (the load
mode) and one for the recovery; per Newton iteration a dense ``n_c x n_c`` solve (``O(n_c^3)``). Two-body
Hertz, ``n_c`` = 390 / 768 at 2.9e4 / 1.0e5 dofs: ``S`` in 0.41 / 2.3 s; one solve per contact dof (blocks of
64 right-hand sides, before) took 2.96 / 18 s.
"""
from __future__ import annotations

import time

import dolfinx.fem.petsc as fem_petsc
import numpy as np
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from .bounds import BoundContact
from .capabilities import check, of
from .compat import bc_dofs, function_space, petsc_vec, schur_complement
from .contact import check_facet_tag
from .laws import ContactLaw, Coulomb
from .obstacles import HalfPlane, Obstacle
from .search import facet_normals, project
from .surface import StepSolver, Surface
from .twobody import FacetData

__all__ = [
    "OPEN", "SLIP", "STICK", "P_TOL", "T_TOL", "classify", "StepFailure", "CondensedContact",
    "CondensedCoulomb", "CondensedTwoBody", "CondensedTwoBodyCoulomb", "step_solver_for"
]

OPEN, SLIP, STICK = 0, 1, 2
# State of a vertex from its values: open if p <= P_TOL * max p; at the Coulomb bound (slip) if
# |t| >= (1 - T_TOL) mu p; stick otherwise. mu = 0: every loaded vertex slips.
P_TOL, T_TOL = 1e-10, 1e-8


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


class _Condensation(StepSolver):
    """What both condensed solvers share: the stiffness ``K`` condensed onto the contact dofs ``self._cidx``
    (one MUMPS factorization of ``K_D``, the Schur complement ``S`` from blocked multi-right-hand-side solves),
    the contact force of the load at the step ``r(t)`` (one more solve per step), the semismooth Newton driver
    (retries with a smaller ``c``, cycle detection) and the recovery of the displacement. A subclass chooses the
    contact dofs (:meth:`_contact_dofs`), writes the Alart-Curnier residual (:meth:`_residual`), the output
    (:meth:`_set_output`) and the slip reference (:meth:`_slip_reference`)."""

    def __init__(self, comm, max_it: int, tol: float):
        if int(max_it) < 1 or not (np.isfinite(tol) and tol > 0):
            raise ValueError(f"max_it must be >= 1 and tol a finite number > 0, got {max_it!r}, {tol!r}")
        self.comm = comm
        self.max_it, self.tol = int(max_it), float(tol)
        # Alart-Curnier's c = c_scale * (mean diagonal of S); a failed iteration is retried with c / 10 and
        # c / 100 (a safeguard). Measured on the slab from the zero start (mu 0.4 - 5): c_scale from 1e-3 to
        # 1e2 gives the same iterations (6-8) and the same solution to 1e-14: active contacts get d = 0 and
        # sticking vertices s = 0 exactly after one step, so c hardly enters the active-set decisions.
        self.c_scale, self.retries = 1.0, 2
        self._ready = False
        self.timings = {"condense_s": 0.0, "load_s": 0.0, "contact_newton_s": 0.0, "recover_s": 0.0}

    # --- set-up: the condensed system ----------------------------------------
    def _condense(self, problem) -> None:
        if not problem.material.linear:
            raise ValueError("method 'coulomb' needs linear elasticity (a constant stiffness to condense), "
                             f"got material {type(problem.material).__name__}")
        start = time.perf_counter()
        comm = self.comm
        V = problem.u.function_space
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        # K (no boundary conditions; linear elasticity: constant unless a load-scaled term such as a vanishing
        # spring changes it, re-checked at every step by _stiffness_changed) and a vector for the load.
        self._A = fem_petsc.assemble_matrix(problem.a)
        self._A.assemble()
        self._f = fem_petsc.create_vector(problem.L)
        lo, hi = self._A.getOwnershipRange()
        # Dirichlet dofs (owned, global) and the Dirichlet condition each belongs to (its value at t, per step).
        self._dirichlet = []
        for d in problem.dirichlet:
            local = bc_dofs(d.bc)
            self._dirichlet.append((d, (local[local < n_owned] + lo).astype(PETSc.IntType)))
        self._dir_idx = np.concatenate([i for _, i in self._dirichlet] + [np.empty(0, PETSc.IntType)])
        self._dir_all = np.unique(np.concatenate(comm.allgather(self._dir_idx))).astype(np.int64)  # every rank's
        self._cidx = np.asarray(self._contact_dofs(problem), dtype=PETSc.IntType)
        self._cmine = np.flatnonzero((self._cidx >= lo) & (self._cidx < hi))
        fixed = np.unique(np.concatenate([self._dir_idx, self._cidx]))
        self._fixed = fixed[(fixed >= lo) & (fixed < hi)].astype(PETSc.IntType)
        self._x, self._b, self._y = self._f.duplicate(), self._f.duplicate(), self._f.duplicate()
        self._ksp = None
        self._factor()
        self._uc = np.zeros(len(self._cidx))  # last solution
        self._ready = True
        self.timings["condense_s"] += comm.allreduce(time.perf_counter() - start, op=MPI.MAX)

    def _factor(self) -> None:
        """Factor ``K_D`` (``K`` with the rows and columns of the contact and Dirichlet dofs replaced by the
        identity) and form the dense Schur complement ``S`` (every rank)."""
        nc = len(self._cidx)
        if self._ksp is not None:
            self._ksp.destroy()
            self._KD.destroy()
        KD = self._A.duplicate(copy=True)
        KD.zeroRowsColumns(self._fixed, diag=1.0)
        self._ksp = PETSc.KSP().create(self.comm)
        self._ksp.setOptionsPrefix("fc_condensed_")
        self._ksp.setType("preonly")
        self._ksp.getPC().setType("lu")
        self._ksp.getPC().setFactorSolverType("mumps")
        self._ksp.setFromOptions()
        self._ksp.setOperators(KD)
        self._KD = KD
        self._ksp.setUp()
        # S from MUMPS's partial factorization of K with the Dirichlet rows and columns the identity, which
        # eliminates all but the contact dofs (about one factorization: 0.41 s instead of 2.96 s for n_c = 390 at
        # 2.9e4 dofs, 2.3 s instead of 18 s for n_c = 768 at 1.0e5, by one solve per contact dof; the same S to
        # 3e-15). In parallel the matrix is gathered on rank 0 for it (compat.schur_complement).
        M = self._A.duplicate(copy=True)
        M.zeroRowsColumns(self._dir_idx, diag=1.0)
        S = schur_complement(M, self._cidx)
        M.destroy()
        self.S = 0.5 * (S + S.T)
        self._diag = float(np.mean(np.abs(np.diag(self.S)))) if nc else 1.0

    def _stiffness_changed(self, problem) -> bool:
        """Re-assemble ``K`` at the step; True (and ``K`` replaced) if it differs from the condensed one beyond
        round-off (a load-dependent stiffness, e.g. the vanishing spring of :class:`~fenics_contact.app.scenes.
        Stabilised`): the condensation is then redone for the step."""
        A = fem_petsc.assemble_matrix(problem.a)
        A.assemble()
        ref = self._A.norm(PETSc.NormType.FROBENIUS)
        A.axpy(-1.0, self._A, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
        changed = A.norm(PETSc.NormType.FROBENIUS) > 1e-13 * ref
        if changed:
            A.axpy(1.0, self._A, structure=PETSc.Mat.Structure.SAME_NONZERO_PATTERN)
            self._A.destroy()
            self._A = A
        else:
            A.destroy()
        return changed

    def _contact_dofs(self, problem) -> np.ndarray:
        """The global numbers of the condensed dofs (the same order on every rank); ``self._dir_all`` is known."""
        raise NotImplementedError

    def _loads(self, problem) -> np.ndarray:
        """The load of the step as the problem has set it (any path: tractions, body forces and Dirichlet values
        at ``problem.load``): ``f(t)`` (``-F`` at ``u = 0``) into ``self._f``, the Dirichlet values, the load mode
        ``u_0(t)`` (``u_c = 0``) into ``self._x``, and ``r(t) = (K u_0(t) - f(t))_c`` (the same on every rank)."""
        start = time.perf_counter()
        u = problem.u
        saved = u.x.array.copy()
        u.x.array[:] = 0.0
        with self._f.localForm() as fl:
            fl.set(0.0)
        fem_petsc.assemble_vector(self._f, problem.L)
        self._f.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        self._f.scale(-1.0)
        u.x.array[:] = saved
        self._dir_val = np.concatenate([np.full(len(i), float(d.value.value)) for d, i in self._dirichlet]
                                       + [np.empty(0)])
        self._displacement(np.zeros(len(self._cidx)), self._x)
        self._A.mult(self._x, self._y)
        self._y.axpy(-1.0, self._f)
        lo = self._A.getOwnershipRange()[0]
        r = np.zeros(len(self._cidx))
        for idx, v in self.comm.allgather((self._cmine, self._y.array[self._cidx[self._cmine] - lo])):
            r[idx] = v
        self.timings["load_s"] += time.perf_counter() - start
        return r

    def _displacement(self, uc: np.ndarray, x: PETSc.Vec) -> None:
        """``x``: the displacement with contact dofs ``uc``, the step's Dirichlet data and load (:meth:`_loads`),
        in equilibrium elsewhere (one solve with the factorization of ``K_D``)."""
        lo, hi = self._A.getOwnershipRange()
        g = self._y
        g.set(0.0)
        idx = np.concatenate([self._dir_idx, self._cidx]).astype(PETSc.IntType)
        val = np.concatenate([self._dir_val, uc])
        keep = (idx >= lo) & (idx < hi)
        g.array[idx[keep] - lo] = val[keep]
        self._A.mult(g, self._b)
        self._b.scale(-1.0)
        self._b.axpy(1.0, self._f)
        self._b.array[idx[keep] - lo] = val[keep]
        self._ksp.solve(self._b, x)

    # --- the semismooth Newton on the condensed system ------------------------
    def _residual(self, uc: np.ndarray, t: float):
        """Alart-Curnier residual ``F``, its generalized Jacobian ``J``, the contact state (for the cycle
        detection) and the contact force ``R = S u_c + r(t)``."""
        raise NotImplementedError

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
        scale = max(float(np.max(np.abs(self._r))) if len(self._r) else 0.0, 1e-300)
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
        elif self._stiffness_changed(problem):
            start = time.perf_counter()
            self._factor()
            self.timings["condense_s"] += self.comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
        t = float(problem.load.value)
        self._r = self._loads(problem)
        self._step_data()
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
        self._displacement(uc, self._x)
        self._x.copy(petsc_vec(problem.u))
        problem.u.x.scatter_forward()
        self.timings["recover_s"] += time.perf_counter() - start
        return int(PETSc.SNES.ConvergedReason.CONVERGED_FNORM_ABS), history, ""

    def _step_data(self) -> None:
        """What else the step needs from the load mode ``self._x`` (after :meth:`_loads`)."""
        return None

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        raise NotImplementedError

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        """The tangential quantity whose change over a step is the slip increment, at ``uc``."""
        raise NotImplementedError

    # --- step-solver hooks ------------------------------------------------------
    def commit(self) -> None:
        """The converged step becomes the reference of the next step's slip increments."""
        if self._ready:
            self._ref = self._slip_reference(self._uc)

    def state(self) -> dict:
        if not self._ready:
            return {}
        return {"uc": self._uc.copy(), "ref": self._ref.copy()}

    def restore(self, state: dict) -> None:
        if state:
            self._uc, self._ref = state["uc"].copy(), state["ref"].copy()


class CondensedCoulomb(_Condensation):
    """Signorini contact with Coulomb friction of ``contact`` against a flat rigid obstacle, solved exactly on the
    condensed system (see the module): the problem's step solver (``ContactProblem(...,
    step_solver=CondensedCoulomb(contact))``). ``max_it`` semismooth Newton iterations at most per try, converged
    at the relative residual ``tol``."""

    def __init__(self, contact: CondensedContact, max_it: int = 50, tol: float = 1e-11):
        if not isinstance(contact, CondensedContact):
            raise ValueError(f"contact must be the CondensedContact of method 'coulomb', got {type(contact).__name__}")
        super().__init__(contact.comm, max_it, tol)
        self.contact = contact
        c = contact  # its geometry: normal component k (sign), tangential kt, vertex dofs and weights
        self.k, self.kt, self.sign, self.obstacle = c.k, c.kt, c.sign, c.obstacle
        self._Vk, self._dofs, self._parent, self._parent_t, self._weight = (c._Vk, c._dofs, c._parent, c._parent_t,
                                                                             c._weight)
        self.mu = contact.mu

    def _contact_dofs(self, problem) -> np.ndarray:
        """Normal and tangential component of every base vertex whose normal one is free (owned rows, gathered on
        every rank, sorted by position): normal components of all vertices, then the tangential ones."""
        comm = self.comm
        V = problem.u.function_space
        n_owned = V.dofmap.index_map.size_local * V.dofmap.index_map_bs
        r0 = self._A.getOwnershipRange()[0]
        dirichlet_local = set((self._dir_idx - r0).tolist())
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
        self._tpos = nv + np.arange(len(self._it))
        self._d0 = self.sign * (self._vx[:, self.k] - self.obstacle.point[self.k])
        self._dmotion = -self.sign * self.obstacle.motion[self.k]  # d0(t) = d0 + t * dmotion
        self._ref = np.zeros(len(self._it))  # tangential displacement at the last converged step
        return np.concatenate([self._gn, self._gt[self._it]])

    def _residual(self, uc: np.ndarray, t: float):
        """Alart-Curnier residual, its generalized Jacobian and the per-vertex active set."""
        sgn, c, mu, nv = self.sign, self.c, self.mu, len(self._gn)
        R = self.S @ uc + self._r
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

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        nv = len(self._gn)
        R = self.S @ uc + self._r
        pn = self.sign * R[:nv] / self._w
        pt = np.zeros(nv)
        pt[self._it] = R[self._tpos] / self._w[self._it]
        gap = -(self._d0 + t * self._dmotion + self.sign * uc[:nv])
        self.contact.set_solution(self._vx, self._w, pn, pt, gap, self._mine)

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        return uc[self._tpos].copy()


class CondensedTwoBody(Surface):
    """The two-body contact surface of method ``coulomb`` (2D, P1, nodal; small sliding): the slave vertices of
    ``slave_tag`` paired once, in the reference configuration, with their closest point on the master facets of
    ``master_tag`` (:func:`~fenics_contact.search.project` within ``radius``, default twice the longest master
    facet): master facet, shape-function weights ``N``, its outward normal ``n`` and tangent ``t = (n_y, -n_x)``
    (+x on a master facing +y), the reference distance ``d0`` of the vertex from the facet's line (> 0 open).
    No residual term and no bounds: its load steps are solved by a :class:`CondensedTwoBodyCoulomb` (see the
    module), which writes the nodal contact forces back here (:meth:`set_solution`). Figures as the penalty
    two-body friction surface's: ``log`` (per committed step), :meth:`friction_profile`, :meth:`total_force`,
    :meth:`tangential_force`; output Functions ``gap_out``, ``pressure_out``, ``traction_out``, ``state_out``."""

    requires_step_solver = True

    def __init__(self, u: fem.Function, facet_tags, slave_tag, master_tag, law: ContactLaw, load: fem.Constant,
                 radius: float | None = None, name: str = "twobody"):
        if not isinstance(law, Coulomb):
            raise ValueError(f"CondensedTwoBody needs the Coulomb law of method 'coulomb', got {law!r}")
        check(**of(law, u), kind="two-body", quadrature="nodal", passes="one")  # before any assembly
        V = u.function_space
        mesh = V.mesh
        if mesh.geometry.dim != 2 or V.num_sub_spaces != 2 or V.sub(0).num_sub_spaces != 0:
            raise ValueError("method 'coulomb' between two bodies is implemented in 2D for a displacement unknown "
                             "(one tangential direction)")
        if len(V.dofmap.dof_layout.entity_dofs(1, 0)):
            raise ValueError("method 'coulomb' between two bodies needs degree-1 (P1) displacements")
        if slave_tag == master_tag:
            raise ValueError(f"slave_tag and master_tag must differ, both are {slave_tag}")
        if radius is not None and not (np.isfinite(radius) and radius > 0):
            raise ValueError(f"search radius must be a finite number > 0, got {radius!r}")
        slave = check_facet_tag(mesh, facet_tags, slave_tag, f"{name} slave_tag")
        master = check_facet_tag(mesh, facet_tags, master_tag, f"{name} master_tag")
        self.u, self.law, self.load, self.name, self.comm = u, law, load, name, mesh.comm
        self.mu = float(law.mu)
        comm = self.comm
        sd, md = FacetData(V, slave), FacetData(V, master)
        # This rank's (owned and ghost) vertex block dofs of the slave and of the master surface.
        self.local_dofs = (np.unique(sd.dofs), np.unique(md.dofs))

        # Slave vertices (every rank's, on every rank): global block dof, reference position, weight int phi ds.
        own = sd.owned
        length = np.linalg.norm(sd.X[own, 1] - sd.X[own, 0], axis=1)
        parts = comm.allgather((sd.global_dofs[own].ravel(), sd.X[own].reshape(-1, 2), np.repeat(0.5 * length, 2)))
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
            radius = 2.0 * float(np.max(np.linalg.norm(np.diff(self.master_X, axis=1), axis=2)))
        self.radius = float(radius)
        if np.intersect1d(self.slave_dofs, self.master_facets).size:
            raise ValueError(f"{name}: the slave and master surfaces share vertices (two bodies do not)")

        # The pairing, fixed (small sliding): closest master facet, weights N, normal, tangent, distance d0.
        facet, bary, _ = project(self.X, self.master_X, self.radius)
        self.facet, self.N = facet, bary
        self.paired = facet >= 0
        self.normal = np.zeros((len(facet), 2))
        self.normal[self.paired] = facet_normals(self.master_X[facet[self.paired]])
        self.tangent = np.stack([self.normal[:, 1], -self.normal[:, 0]], axis=1)
        self.d0 = np.full(len(facet), np.inf)
        self.d0[self.paired] = np.einsum("ij,ij->i", self.X[self.paired] - self.master_X[facet[self.paired], 0],
                                         self.normal[self.paired])

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

    def residual(self, v):
        """None: the step solver enforces the contact."""
        return None

    def set_solution(self, fn: np.ndarray, ft: np.ndarray, gap: np.ndarray, state: np.ndarray,
                     slip: np.ndarray) -> None:
        """A solved step, per slave vertex (the same on every rank): nodal normal force ``fn`` (> 0 compression)
        and tangential force ``ft`` (along the tangent) of the master on the slave, ``gap`` (> 0 penetration;
        ``-radius`` unpaired), ``state`` (0 open, 1 slip, 2 stick) and slip increment of the step."""
        self._solution = (fn, ft, gap, state, slip)
        a, b, i = self._out.T
        for f, v in ((self.gap_out, gap), (self.pressure_out, fn / self.weight), (self.state_out, state)):
            f.x.array[:] = 0.0
            f.x.array[a] = v[i]
            f.x.scatter_forward()
        q = (ft / self.weight)[:, None] * self.tangent
        self.traction_out.x.array[:] = 0.0
        for k in range(2):
            self.traction_out.x.array[2 * b + k] = q[i, k]
        self.traction_out.x.scatter_forward()

    def _need(self) -> tuple:
        if self._solution is None:
            raise RuntimeError(f"{self.name}: no step has been solved yet")
        return self._solution

    # --- figures ----------------------------------------------------------------
    def friction_profile(self) -> dict:
        """Slave vertices sorted by reference position (identical on every rank): ``x`` (n, 2), ``gap`` (> 0
        penetration), ``pressure`` (> 0 compression), ``traction`` (of the master on the slave along the
        tangent ``(n_y, -n_x)`` of the master normal: +x on a master facing +y), ``state`` (0 open, 1 slip,
        2 stick)."""
        fn, ft, gap, state, _ = self._need()
        return {"x": self.X.copy(), "gap": gap.copy(), "pressure": fn / self.weight, "traction": ft / self.weight,
                "state": state.astype(int)}

    def displacement(self) -> np.ndarray:
        """The displacement of every slave vertex (n, 2), in the order of :attr:`X`, the same on every rank."""
        _, b, i = self._out.T
        ua = self.u.x.array
        out = np.zeros((len(self.X), 2))
        for idx, v in self.comm.allgather((i, np.stack([ua[2 * b], ua[2 * b + 1]], axis=1))):
            out[idx] = v
        return out

    def point_values(self, reference: bool = False, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray,
                                                                                     np.ndarray]:
        """Current position (``reference=True``: reference position), gap (> 0 penetration) and pressure of the
        slave vertices, sorted by reference position (as the penalty two-body surfaces'; small strain: the
        nominal and Cauchy pressures are the same)."""
        if kind not in ("nominal", "cauchy"):
            raise ValueError(f"kind must be 'nominal' or 'cauchy', got {kind!r}")
        fn, _, gap, _, _ = self._need()
        return (self.X.copy() if reference else self.X + self.displacement()), gap.copy(), fn / self.weight

    def total_force(self) -> np.ndarray:
        """Normal contact force of the master on the slave body, ``sum_i f_n,i n_i`` (per unit thickness)."""
        fn = self._need()[0]
        return np.sum(fn[:, None] * self.normal, axis=0)

    def tangential_force(self) -> np.ndarray:
        """Tangential (friction) force of the master on the slave body, ``sum_i f_t,i t_i``."""
        ft = self._need()[1]
        return np.sum(ft[:, None] * self.tangent, axis=0)

    def capacity(self) -> float:
        """``mu sum_i f_n,i``: the largest tangential force the surface can carry at the current contact forces."""
        return self.mu * float(np.sum(self._need()[0]))

    def state_areas(self) -> dict[str, float]:
        """Length of the slave surface in each state by the vertex rule (sum of the vertex weights)."""
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
        self.log.append({"load": float(self.load.value), "normal_force": self.total_force().tolist(),
                         "tangential_force": self.tangential_force().tolist(), "capacity": self.capacity(),
                         "dissipated": self.dissipated, **self.state_areas()})

    def state(self) -> dict:
        return {"solution": self._solution, "dissipated": self.dissipated}

    def restore(self, state: dict) -> None:
        if self._solution is not state["solution"] and state["solution"] is not None:
            self.set_solution(*state["solution"])
        self._solution, self.dissipated = state["solution"], state["dissipated"]


class CondensedTwoBodyCoulomb(_Condensation):
    """Signorini contact with Coulomb friction between two linear-elastic bodies (small sliding), solved exactly on
    the system condensed onto both surfaces' contact dofs (see the module): the problem's step solver
    (``ContactProblem(..., step_solver=CondensedTwoBodyCoulomb(contact))``). ``max_it`` semismooth Newton
    iterations at most per try, converged at the relative residual ``tol``."""

    def __init__(self, contact: CondensedTwoBody, max_it: int = 50, tol: float = 1e-11):
        if not isinstance(contact, CondensedTwoBody):
            raise ValueError(f"contact must be the CondensedTwoBody of method 'coulomb', got {type(contact).__name__}")
        super().__init__(contact.comm, max_it, tol)
        self.contact, self.mu = contact, contact.mu

    def _contact_dofs(self, problem) -> np.ndarray:
        """The free components of every paired slave vertex, then those of the vertices of the master facets they
        are paired with (each sorted by position). A prescribed component (Dirichlet) is not condensed: its
        value enters the relative displacement as data. A paired slave vertex with one prescribed component
        (a symmetry plane across the contact surface) carries no friction force (``q = 0``: its support takes
        the tangential force), ``p`` from its free component; two prescribed components are refused."""
        c = self.contact
        ps = np.flatnonzero(c.paired)
        if not len(ps):
            raise ValueError(f"{c.name}: no slave vertex is within the search radius {c.radius:g} of the master "
                             "surface (nothing to condense)")
        ns = len(ps)
        n, t, N = c.normal[ps], c.tangent[ps], c.N[ps]
        sdofs = (2 * c.slave_dofs[ps][:, None] + np.arange(2)).astype(np.int64)  # (ns, 2) global components
        sfree = ~np.isin(sdofs, self._dir_all)
        roller = sfree.sum(axis=1) == 1
        bad = ~sfree.all(axis=1) & ~(roller & (np.abs(np.where(sfree, n, 0.0)).sum(axis=1) > 0.1))
        if bad.any():
            i = ps[np.flatnonzero(bad)[0]]
            raise ValueError(f"{c.name}: slave vertex at {tuple(np.round(c.X[i], 12))} is within the search radius "
                             "of the master and its normal motion is prescribed (Dirichlet): method 'coulomb' needs "
                             "a free normal component at every paired slave vertex (or pass a smaller radius)")
        mverts, minv = np.unique(c.master_facets[c.facet[ps]], return_inverse=True)  # global block dofs
        minv = minv.reshape(-1, 2)
        pos = np.zeros((len(mverts), 2))  # master vertex positions, for a partition-independent order
        pos[minv.ravel()] = c.master_X[c.facet[ps]].reshape(-1, 2)
        morder = np.lexsort(np.round(pos, 12).T[::-1])
        rank = np.empty(len(mverts), np.int64)
        rank[morder] = np.arange(len(mverts))
        mverts, minv = mverts[morder], rank[minv]
        mdofs = (2 * mverts[:, None] + np.arange(2)).astype(np.int64)  # (nm, 2)
        mfree = ~np.isin(mdofs, self._dir_all)
        # Positions in u_c (-1: prescribed) and in the list of prescribed components (-1: free).
        nsf = int(sfree.sum())
        scol, mcol = np.full(sdofs.shape, -1, np.int64), np.full(mdofs.shape, -1, np.int64)
        scol[sfree], mcol[mfree] = np.arange(nsf), nsf + np.arange(int(mfree.sum()))
        nc = nsf + int(mfree.sum())
        self._presc = np.concatenate([sdofs[~sfree], mdofs[~mfree]])  # values from the load mode u_0(t)
        spc, mpc = np.full(sdofs.shape, -1, np.int64), np.full(mdofs.shape, -1, np.int64)
        spc[~sfree] = np.arange(int((~sfree).sum()))
        mpc[~mfree] = int((~sfree).sum()) + np.arange(int((~mfree).sum()))
        self._ps, self._ns, self._nc, self._fric = ps, ns, nc, np.flatnonzero(~roller)
        # w_i = u_s,i - sum_k N_ik u_m(i,k) = Gw u_c + Pw u_presc: (ns, 2, nc) and (ns, 2, n_presc)
        Gw, Pw = np.zeros((ns, 2, nc)), np.zeros((ns, 2, len(self._presc)))
        rows = np.arange(ns)
        for j in range(2):
            f = sfree[:, j]
            Gw[rows[f], j, scol[f, j]] = 1.0
            Pw[rows[~f], j, spc[~f, j]] = 1.0
            for k in range(2):
                m = minv[:, k]
                f = mfree[m, j]
                np.add.at(Gw, (rows[f], j, mcol[m[f], j]), -N[f, k])
                np.add.at(Pw, (rows[~f], j, mpc[m[~f], j]), -N[~f, k])
        self._Gn, self._Gt = np.einsum("ij,ijc->ic", n, Gw), np.einsum("ij,ijc->ic", t, Gw)
        self._Pn, self._Pt = np.einsum("ij,ijc->ic", n, Pw), np.einsum("ij,ijc->ic", t, Pw)
        # Contact forces from R: p_i = n_i . R_s,i, q_i = t_i . R_s,i; a roller: p_i = R_s,i[free] / n_i[free],
        # q_i = 0. Rows of the maps (ns, nc).
        self._Nn, self._Nt = np.zeros((ns, nc)), np.zeros((ns, nc))
        for j in range(2):
            f = sfree[:, j] & ~roller
            self._Nn[rows[f], scol[f, j]] = n[f, j]
            self._Nt[rows[f], scol[f, j]] = t[f, j]
            f = sfree[:, j] & roller
            self._Nn[rows[f], scol[f, j]] = 1.0 / n[f, j]
        # Master rows: R_m + sum_i N_im (p_i n_i + q_i t_i) = 0 for each free master component (action and
        # reaction); for a slave vertex without a prescribed component p_i n_i + q_i t_i = R_s,i.
        self._M = np.zeros((int(mfree.sum()), nc))
        self._M[np.arange(self._M.shape[0]), mcol[mfree]] = 1.0
        for k in range(2):
            m = minv[:, k]
            for j in range(2):
                f = np.flatnonzero(mfree[m, j])
                np.add.at(self._M, mcol[m[f], j] - nsf,
                          N[f, k, None] * (n[f, j, None] * self._Nn[f] + t[f, j, None] * self._Nt[f]))
        self._d0 = c.d0[ps]
        self._ref = np.zeros(ns)  # t . w at the last converged step
        self._w0n, self._w0t = np.zeros(ns), np.zeros(ns)
        return np.concatenate([sdofs[sfree], mdofs[mfree]])

    def _step_data(self) -> None:
        """The prescribed components' values at the step (read from the load mode ``u_0(t)``), the Jacobian's
        fixed blocks."""
        lo, hi = self._A.getOwnershipRange()
        vals = np.zeros(len(self._presc))
        here = np.flatnonzero((self._presc >= lo) & (self._presc < hi))
        for idx, v in self.comm.allgather((here, self._x.array[self._presc[here] - lo])):
            vals[idx] = v
        self._w0n, self._w0t = self._Pn @ vals, self._Pt @ vals
        # The Jacobian's fixed blocks (S may have been condensed again for this step).
        self._PnS, self._PtS, self._MS = self._Nn @ self.S, self._Nt @ self.S, self._M @ self.S

    def _kinematics(self, uc: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Distance ``d`` (> 0 open) and ``t . w`` of every paired slave vertex at ``uc``."""
        return self._d0 + self._Gn @ uc + self._w0n, self._Gt @ uc + self._w0t

    def _residual(self, uc: np.ndarray, t: float):
        """Alart-Curnier rows of the slave vertices (normal, tangential) and the master rows; generalized
        Jacobian; state per slave vertex (0 open, +-1 slip and its direction, 2 stick)."""
        c, mu = self.c, self.mu
        R = self.S @ uc + self._r
        p, q = self._Nn @ R, self._Nt @ R
        d, tw = self._kinematics(uc)
        s = tw - self._ref
        PnS, PtS = self._PnS, self._PtS
        lam = p - c * d
        active = lam > 0
        bound = mu * np.maximum(lam, 0.0)
        qtr = q - c * s
        stick = active & (np.abs(qtr) <= bound)
        direction = np.sign(qtr)
        Fn = np.where(active, c * d, p)
        Jn = np.where(active[:, None], c * self._Gn, PnS)
        Ft = np.where(stick, c * s, q - bound * direction)
        slip_J = PtS - (mu * direction * active)[:, None] * (PnS - c * self._Gn)
        Jt = np.where(stick[:, None], c * self._Gt, slip_J)
        fr = self._fric  # the vertices with a tangential row (not the rollers: q = 0 there)
        F = np.concatenate([Fn, Ft[fr], self._M @ R])
        J = np.vstack([Jn, Jt[fr], self._MS])
        state = active.astype(np.int64)
        state[fr] = np.where(active[fr], np.where(stick[fr], 2, np.where(direction[fr] < 0, -1, 1)), 0)
        return F, J, state, R

    def _set_output(self, uc: np.ndarray, t: float) -> None:
        c = self.contact
        R = self.S @ uc + self._r
        p, q = self._Nn @ R, self._Nt @ R
        d, tw = self._kinematics(uc)
        nv = len(c.X)
        fn, ft, gap, slip = np.zeros(nv), np.zeros(nv), np.full(nv, -c.radius), np.zeros(nv)
        ps = self._ps
        fn[ps], ft[ps], gap[ps], slip[ps] = p, q, -d, tw - self._ref
        state = np.full(nv, OPEN)
        state[ps] = classify(p, q, self.mu)
        c.set_solution(fn, ft, gap, state, slip)

    def _slip_reference(self, uc: np.ndarray) -> np.ndarray:
        return self._kinematics(uc)[1]


def step_solver_for(contacts) -> _Condensation | None:
    """The step solver ``contacts`` need: a :class:`CondensedCoulomb` (rigid obstacle) or a
    :class:`CondensedTwoBodyCoulomb` (two bodies) for the one that requires it (method ``coulomb``), or None when
    none does."""
    need = [c for c in contacts if c.requires_step_solver]
    if len(need) > 1:
        raise ValueError(f"method 'coulomb' condenses one contact surface, got {len(need)}: "
                         f"{', '.join(c.name for c in need)}")
    if not need:
        return None
    return CondensedTwoBodyCoulomb(need[0]) if isinstance(need[0], CondensedTwoBody) else CondensedCoulomb(need[0])
