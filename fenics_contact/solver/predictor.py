"""The state a load step starts from: the last converged state, the secant extrapolation of the last two, or the
tangent (Euler) predictor scaled back to the energy's stationary point along it."""
from __future__ import annotations

import time

import numpy as np

from ..compat import petsc_vec
from .newton import Newton

__all__ = ["PREDICTORS", "PREDICTOR_ETA", "PREDICTOR_FD", "PREDICTOR_RTOL", "PREDICTOR_WORSE", "Predictor"]

PREDICTORS = (False, True, "secant", "tangent")  # Solver(predictor=...)
PREDICTOR_FD = 1e-6  # forward-difference step of dR/dt in the tangent predictor, relative to the load step
# Line-search tolerance of the tangent predictor: |slope| <= PREDICTOR_ETA |slope at 0|. Near-exact (0.01 to 0.1
# give the same seal history); 0.5 accepts the full tangent where the seal's corner lands (16 iterations).
PREDICTOR_ETA = 0.05
# A tangent whose predicted state is out of balance by more than this times the last converged state's (at the new
# load) is dropped and the step starts from that state: a tangent through a contact without stiffness (points that
# touch with g = 0 under a penalty law: the seal at t = 0) is singular, and its state ~1e17 times out of balance.
PREDICTOR_WORSE = 1e6
# The Krylov tolerance of the tangent's solve (an iterative linear solver; a looser ksp_rtol stands): a start, not an
# answer. mindlin3d with friction at 72,461 dofs (2 ranks): 15 Krylov iterations instead of 27 at the solves' loosest
# 1e-4, the same Newton iterations (33) and figures.
PREDICTOR_RTOL = 1e-2


class Predictor:
    """The predictor ``kind`` (one of :data:`PREDICTORS`; ``True`` is ``"secant"``) of the Newton solves of
    ``newton``; seconds go to ``timings["predictor_s"]``. Owns its work vectors (:meth:`destroy`)."""

    def __init__(self, kind: bool | str, newton: Newton, timings: dict[str, float]):
        self.kind = "secant" if kind is True else kind  # False, "secant" or "tangent"
        self.newton, self.problem, self.timings = newton, newton.problem, timings
        self.converged: list[tuple[float, np.ndarray]] = []  # the last two converged (t, u.x.array)
        self._work: list | None = None

    def destroy(self) -> None:
        """Destroy the work vectors. Collective."""
        for v in self._work or []:
            v.destroy()
        self._work = None

    def start(self, t: float) -> None:
        """A run starts from the state at load ``t``: the first converged state unless there is one."""
        if self.kind and not self.converged:
            self.converged = [(t, self.problem.u.x.array.copy())]

    def accept(self, t: float) -> None:
        """``problem.u`` converged at load ``t``."""
        if self.kind:
            self.converged = [*self.converged[-1:], (t, self.problem.u.x.array.copy())]

    def predict(self, t: float, t_n: float) -> tuple[float | None, float | None]:
        """Move ``problem.u``, converged at ``t_n``, to the predicted state at ``t`` (the load already set to
        ``t``). Returns ``(reference, scale)``: the residual norm of the converged state at ``t`` (the rtol
        reference of :meth:`Newton.convergence_test`) if a prediction was made, and the tangent's scale ``s`` (0:
        the tangent dropped, :data:`PREDICTOR_WORSE`); None each otherwise."""
        tangent = self.kind == "tangent" and not self.newton.bounded and t != t_n
        secant = self.kind == "secant" and len(self.converged) == 2
        reference = scale = None
        if tangent or secant:  # the relative tolerance refers to the out-of-balance of u_n at t
            newton = self.newton
            x = petsc_vec(self.problem.u).copy()
            newton.residual(newton.snes, x, newton.b)
            reference = newton.b.norm()
            x.destroy()
        if tangent:
            before = petsc_vec(self.problem.u).copy()
            scale, predicted = self.tangent(t, t_n)
            newton = self.newton
            if predicted is None:  # the tangent dropped: the residual at u_n
                x = petsc_vec(self.problem.u).copy()
                newton.residual(newton.snes, x, newton.b)
                predicted = newton.b.norm()
                x.destroy()
            if not np.isfinite(predicted) or predicted > PREDICTOR_WORSE * reference:  # a singular tangent: u_n
                newton.set_u(before)
                scale = 0.0
            before.destroy()
        elif secant:
            (t0, u0), (t1, u1) = self.converged
            self.problem.u.x.array[:] = u1 + (t - t1) / (t1 - t0) * (u1 - u0)
        return reference, scale

    def tangent(self, t: float, t0: float) -> tuple[float, float | None]:
        """Start the step to load ``t`` from ``u_n + s du``: ``u_n`` converged at ``t_n = t0``, ``du = -J^-1
        dR/dt (t - t_n)`` the tangent of the load path there (``J`` at ``(u_n, t_n)``, so with the contact set of
        ``u_n``; ``dR/dt`` by a forward difference of the residual in ``t``, which also moves Dirichlet values along
        their paths). ``s = 1`` unless the energy rises before the end of ``du``, i.e. the slope ``R(u_n + s du, t) .
        du`` (the derivative of the energy along ``du``) at ``s = 1`` is positive and above ``PREDICTOR_ETA`` times
        its value at 0: then ``s`` in (0, 1) is its root (regula falsi, Illinois), to ``PREDICTOR_ETA`` too.

        Why: the tangent holds until the next contact event. A contact that closes within the step (the seal's
        outer corner) is driven far into the obstacle by the tangent of the open state (0.44 at h = 0.5, a force
        of ~1e4 against plate forces ~1), and Newton rocks from there.

        The residual at ``(u_n, t)`` is in ``newton.b`` on entry (:meth:`predict`'s reference). Returns ``(s,
        norm)``: ``norm`` the residual's at the predicted state, the last one evaluated (None where there is no
        tangent: the state is ``u_n``)."""
        newton, p = self.newton, self.problem
        start, assembly = time.perf_counter(), self.timings["assembly_s"]
        if self._work is None:
            self._work = [newton.b.duplicate() for _ in range(5)]
        x, r0, r1, du, at_t = self._work
        newton.b.copy(at_t)  # R(u_n, t): the slope at s = 0
        petsc_vec(p.u).copy(x)
        eps = PREDICTOR_FD * abs(t - t0)
        p.set_load(t0 + eps)
        newton.residual(newton.snes, x, r1)
        p.set_load(t0)  # last: the Jacobian's state (a two-body pairing) is that of the last residual
        newton.residual(newton.snes, x, r0)
        r1.axpy(-1.0, r0)
        r1.scale(-(t - t0) / eps)
        reason = -1  # no Jacobian, no solve where dR/dt is not finite (a load undefined at t_n): no tangent
        if np.isfinite(r1.norm()):
            newton.jacobian(newton.snes, x, newton.A, newton.A)
            ksp = newton.snes.getKSP()
            tolerances = ksp.getTolerances()
            ksp.setTolerances(rtol=max(tolerances[0], PREDICTOR_RTOL))
            reason = newton.linear.solve(newton.A, r1, du)
            ksp.setTolerances(*tolerances)  # the Newton solves' own (the forcing sets its own at every Jacobian)
        p.set_load(t)
        if reason < 0 or not np.isfinite(du.norm()):  # no tangent (e.g. a singular J): u_n
            newton.set_u(x)
            self.timings["assembly_s"] = assembly
            self.timings["predictor_s"] += time.perf_counter() - start
            return 0.0, None

        def slope(s: float) -> float:
            """The energy's derivative along ``du`` at ``u_n + s du``; +inf where it has none (a non-finite
            residual: an exploded two-body geometry), i.e. beyond the stationary point."""
            x.copy(r0)
            r0.axpy(s, du)
            newton.residual(newton.snes, r0, r1)
            f = r1.dot(du)
            return f if np.isfinite(f) else np.inf

        s, f0, f1 = 1.0, at_t.dot(du), slope(1.0)
        f0 = f0 if np.isfinite(f0) else np.inf
        tol = PREDICTOR_ETA * abs(f0)
        if f0 < 0 < f1 and f1 > tol:  # the energy has a minimum inside: find it (bracket [a, b])
            a, fa, b, fb, side = 0.0, f0, 1.0, f1, 0
            for _ in range(30):
                # an end beyond the geometry (an exploded two-body state: no slope) is halved towards
                s = (a * fb - b * fa) / (fb - fa) if np.isfinite(fb) else (a + b) / 2
                f = slope(s)
                if abs(f) <= tol:
                    break
                if f < 0:
                    a, fa = s, f
                    fb, side = (fb / 2, -1) if side == -1 else (fb, -1)  # Illinois: halve the stale end
                else:
                    b, fb = s, f
                    fa, side = (fa / 2, 1) if side == 1 else (fa, 1)
        x.axpy(s, du)
        newton.set_u(x)
        self.timings["assembly_s"] = assembly  # counted here, not as the Newton iterations' assembly
        self.timings["predictor_s"] += time.perf_counter() - start
        return s, r1.norm()  # r1: the residual at the last slope's s, the state predicted
