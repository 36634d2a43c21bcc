"""The load modes of earlier steps, reused when a step's load is a combination of theirs.

A load step's load mode ``u_0(t)`` (:mod:`.operator`) is linear in the load: the force vector ``f(t)`` and the
Dirichlet values ``g(t)``. Along a load path made of a few fixed patterns (a press by a Dirichlet value, then a
traction of growing amplitude), every step's ``(f, g)`` is a combination ``sum_k a_k (f_k, g_k)`` of those of
the steps solved before, and so are its load mode and contact force: ``u_0 = sum_k a_k u_0,k``, ``r = sum_k
a_k r_k``, without a solve. The coefficients are the least-squares ones; they are used only when they reproduce
``f`` and ``g`` each to ``RTOL`` (relative to its own size: forces and displacements are not compared).
"""
from __future__ import annotations

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

__all__ = ["LoadModes", "RTOL", "KEEP"]

RTOL = 1e-12  # a combination reproduces the load to round-off
KEEP = 4  # load modes kept (the oldest goes first)


class LoadModes:
    """Earlier steps' loads ``(f_k, g_k)`` (``f_k`` a distributed vector, ``g_k`` this rank's Dirichlet values),
    their load modes ``u_0,k`` and contact forces ``r_k`` (see the module)."""

    def __init__(self, comm):
        self.comm = comm
        self._modes: list[tuple[PETSc.Vec, np.ndarray, PETSc.Vec, np.ndarray]] = []
        self.reused = 0

    def clear(self) -> None:
        """Forget every mode (the stiffness changed)."""
        for f, _, x, _ in self._modes:
            f.destroy()
            x.destroy()
        self._modes = []

    def add(self, f: PETSc.Vec, g: np.ndarray, x: PETSc.Vec, r: np.ndarray) -> None:
        """Keep the step's load ``(f, g)``, load mode ``x`` and contact force ``r`` (copies)."""
        if len(self._modes) == KEEP:
            old = self._modes.pop(0)
            old[0].destroy()
            old[2].destroy()
        self._modes.append((f.copy(), g.copy(), x.copy(), r.copy()))

    def combine(self, f: PETSc.Vec, g: np.ndarray, x: PETSc.Vec) -> np.ndarray | None:
        """If ``(f, g)`` is a combination of the kept loads: its load mode into ``x`` and its contact force
        returned; else None (``x`` untouched). Collective."""
        if not self._modes:
            return None
        m = len(self._modes)
        F = [mode[0] for mode in self._modes]
        G = np.array([mode[1] for mode in self._modes]).reshape(m, -1)
        # Gram matrices and right-hand sides of both parts (the Dirichlet part summed over the ranks)
        gram_f = np.array([[F[i].dot(F[j]) for j in range(m)] for i in range(m)])
        rhs_f = np.array([F[i].dot(f) for i in range(m)])
        total = self.comm.allreduce(np.concatenate([(G @ G.T).ravel(), G @ g]), op=MPI.SUM)
        gram_g, rhs_g = total[:m * m].reshape(m, m), total[m * m:]
        # each part scaled to its own size so that neither dominates the least squares
        sf = 1.0 / max(float(np.max(np.diag(gram_f))), 1e-300)
        sg = 1.0 / max(float(np.max(np.diag(gram_g))), 1e-300)
        a = np.linalg.lstsq(sf * gram_f + sg * gram_g, sf * rhs_f + sg * rhs_g, rcond=None)[0]
        # the combination must reproduce both parts, each to round-off of its own size
        work = f.duplicate()
        f.copy(work)
        for ak, Fk in zip(a, F):
            work.axpy(-ak, Fk)
        gap_f = work.norm(PETSc.NormType.INFINITY)
        work.destroy()
        gap_g = self.comm.allreduce(float(np.max(np.abs(g - a @ G), initial=0.0)), op=MPI.MAX)
        big_f = max(f.norm(PETSc.NormType.INFINITY), max(abs(ak) * Fk.norm(PETSc.NormType.INFINITY)
                                                         for ak, Fk in zip(a, F)))
        big_g = self.comm.allreduce(max(float(np.max(np.abs(g), initial=0.0)),
                                        float(np.max(np.abs(a[:, None] * G), initial=0.0))), op=MPI.MAX)
        if gap_f > RTOL * big_f or gap_g > RTOL * big_g:
            return None
        x.set(0.0)
        r = np.zeros_like(self._modes[0][3])
        for ak, (_, _, xk, rk) in zip(a, self._modes):
            x.axpy(ak, xk)
            r += ak * rk
        self.reused += 1
        return r
