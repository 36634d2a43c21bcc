"""Why a Newton solve failed: cycling of the active set, stagnation, divergence, linear-solve failure.

The solver driver (:mod:`fenics_contact.solver`) logs, for every Newton
iterate of a solve, the residual norm and the *active set*: which contact
points are closed (``g > 0``), as one global fingerprint (a digest per
rank). When SNES gives up, :func:`classify` names the cause from that log,
in this order of precedence:

``linear_solve`` / ``ill_conditioning``
    the linear solve failed (SNES ``DIVERGED_LINEAR_SOLVE``); a failed
    factorization or a NaN/Inf in the Krylov solve (KSP ``DIVERGED_PC_FAILED``,
    ``DIVERGED_NANORINF``, ``DIVERGED_BREAKDOWN``) is ``ill_conditioning``
    (singular or near-singular Jacobian), any other KSP failure ``linear_solve``.
    Also ``ill_conditioning``: a condition estimate of the last Jacobian
    (:func:`condition_estimate`, direct solvers only) above ``ILL_CONDITIONED``.
    A failed MUMPS factorization is named by MUMPS's ``INFOG(1)`` (``mumps_infog`` in the record): a work
    array too small for the pivots delayed at factorization (:data:`MUMPS_WORKSPACE`, e.g. ``-9``) is
    ``linear_solve`` (the Jacobian is fine; the solver grows ``ICNTL(14)`` and retries the step), ``-10``
    (numerically singular) ``ill_conditioning``.
``out_of_memory``
    MUMPS could not allocate its arrays (:data:`MUMPS_MEMORY`, e.g. ``-13``; or its memory cap ``ICNTL(23)``
    is too small): the record's ``message`` says how much it asked for. Not cut back (:func:`cutback_helps`):
    a smaller load step has the same matrix pattern, so the same factorization size.
``divergence``
    a non-finite residual, SNES ``DIVERGED_DTOL``/``DIVERGED_FNORM_NAN``, or a
    final residual above ``1e4`` times the first.
``cycling``
    the active set repeats: the tail of the fingerprints is periodic with a
    period ``p >= 2`` over at least two full periods and not constant (the same
    points switch open/closed again and again); or, inexactly, in the last
    ``8`` iterates the set changed at least 4 times and every set had been seen
    earlier in the solve.
``stagnation``
    the residual no longer decreases: the smallest residual of the second half
    of the iterations is above ``0.1`` times the smallest of the first half
    (at least 6 iterations).
``max_iterations``
    none of the above: still converging, too slowly for the iteration limit.
``inverted_elements``
    (set by the solver, not by :func:`classify`) Newton converged, but to a state with ``det F <= 0``
    (``F = I + grad u``) somewhere (:meth:`ContactProblem.min_jacobian`), for any material (a small-strain
    model converges to such a state without complaint): not an answer; the step is cut back.
``exploded_geometry``
    (set by the solver from :meth:`Surface.take_failure`) an iterate stretched a two-body facet past
    :data:`~fenics_contact.search.STRETCH_LIMIT` times its reference size: the surface rejected it (a
    non-finite residual) instead of searching it; the step is cut back.

PETSc's own divergence test (``DIVERGED_DTOL`` when the residual exceeds 1e4 x the first) is replaced
in the solver by one that also asks for growth in the last two iterations: a penalty-like law's first
iterate overshoots by ~K/E and Newton then converges. A solve that SNES *accepts* on the step
length alone with its residual above tolerance is :func:`stalled` (the round-off floor of the linear
solves); the solver then estimates the condition of the Jacobian and fails the solve as
``ill_conditioning`` above ``ILL_CONDITIONED`` (e.g. a free rigid mode), else accepts it and records
it as stalled.
"""
from __future__ import annotations

import hashlib
from typing import Hashable, Sequence

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from .compat import redundant_ksp

__all__ = [
    "ILL_CONDITIONED", "KINDS", "MUMPS_MEMORY", "MUMPS_WORKSPACE", "NO_CUTBACK", "mumps_factors", "mumps_error",
    "mumps_message", "fingerprint", "find_cycle", "condition_estimate", "classify", "cutback_helps", "stalled",
    "reason_name"
]

# MUMPS INFOG(1) values meaning a work array sized at analysis (plus ICNTL(14) percent) was too small: pivots
# delayed by the numerical pivoting of the factorization need more room than the analysis estimated (Jacobians
# of unsymmetric friction tangents with penalty entries ~1e6 x the elastic ones). Cure: a larger ICNTL(14).
MUMPS_WORKSPACE = (-8, -9, -11, -12, -14, -15, -17, -20)
# MUMPS INFOG(1) values meaning an allocation failed (-5, -7: at analysis; -13: at factorization or solve) or the
# memory cap ICNTL(23) is below what the factorization needs (-19). INFOG(2): the size asked for (< 0: millions).
MUMPS_MEMORY = (-5, -7, -13, -19)
ILL_CONDITIONED = 1e12  # condition estimate above which a failed solve is blamed on the Jacobian
KINDS = ("linear_solve", "ill_conditioning", "out_of_memory", "divergence", "cycling", "stagnation",
         "max_iterations", "inverted_elements", "exploded_geometry")
# Kinds a smaller load step cannot cure: the solver gives up at once instead of cutting the step back.
NO_CUTBACK = ("out_of_memory",)

# KSP reasons that mean a singular or numerically unusable operator (PETSc KSPConvergedReason).
_ILL_CONDITIONED_KSP = {"DIVERGED_PC_FAILED", "DIVERGED_PCSETUP_FAILED", "DIVERGED_NANORINF", "DIVERGED_BREAKDOWN",
                        "DIVERGED_INDEFINITE_MAT", "DIVERGED_INDEFINITE_PC"}


def fingerprint(closed: np.ndarray, comm: MPI.Comm) -> tuple[Hashable, int]:
    """Global fingerprint of an active set given by this rank's closed flags, and the number of closed points."""
    flags = np.asarray(closed, dtype=bool)
    local = hashlib.blake2b(np.packbits(flags).tobytes() + flags.size.to_bytes(8, "little"), digest_size=8).hexdigest()
    return tuple(comm.allgather(local)), comm.allreduce(int(np.count_nonzero(flags)), op=MPI.SUM)


def find_cycle(sets: Sequence[Hashable]) -> dict | None:
    """The shortest period ``p >= 2`` with which the tail of ``sets`` repeats over two full periods or more,
    the set not being constant over a period: ``{"period", "start", "repeats"}`` (``start``: index of the
    first iterate of the periodic tail), or None."""
    n = len(sets)
    for p in range(2, n // 2 + 1):
        i = n - 1
        while i - p >= 0 and sets[i] == sets[i - p]:
            i -= 1
        start = i - p + 1  # sets[j] == sets[j + p] for every j >= start
        length = n - max(start, 0)
        if length >= 2 * p and len(set(sets[n - p:])) >= 2:
            return {"period": p, "start": max(start, 0), "repeats": length / p}
    return None


def _revisiting(sets: Sequence[Hashable], window: int = 8) -> bool:
    if len(sets) < window + 1:
        return False
    tail = sets[-window:]
    changes = sum(a != b for a, b in zip(tail[:-1], tail[1:]))
    seen_before = all(s in sets[: len(sets) - window + k] for k, s in enumerate(tail))
    return changes >= window // 2 and seen_before


def condition_estimate(A, ksp, iterations: int = 15) -> float | None:
    """Estimate of the 2-norm condition number of ``A`` (a PETSc Mat): power iteration for ``||A||``
    times inverse iteration (with ``ksp``'s factorization of ``A``) for ``||A^-1||``. None unless ``ksp``
    is a direct solve (LU or Cholesky) already set up with ``A`` (not with a part of it: SNES VI factors the rows of
    the inactive set). Collective; a lower bound in general."""
    if ksp.getPC().getType() not in ("lu", "cholesky", "redundant") or not A.assembled:  # no Jacobian yet
        return None
    if ksp.getOperators()[0].getSize() != A.getSize():  # SNES VI: the factorization is of the reduced system
        return None
    x, y = A.createVecs()
    norms = []
    for apply in (lambda a, b: A.mult(a, b), lambda a, b: ksp.solve(a, b)):
        x.setRandom()
        x.normalize()
        growth = 0.0
        for _ in range(iterations):
            apply(x, y)
            growth = y.norm()
            if not np.isfinite(growth) or growth == 0.0:
                break
            y.copy(x)
            x.scale(1.0 / growth)
        norms.append(growth)
    x.destroy()
    y.destroy()
    cond = norms[0] * norms[1]
    return float(cond) if np.isfinite(cond) else float("inf")


def mumps_factors(ksp) -> list:
    """The MUMPS factor matrices of ``ksp``'s preconditioner: its own (LU or Cholesky) or those of its field
    split's blocks, if set up (none before the first solve). Collective over the KSP's communicator."""
    pc = ksp.getPC()
    if pc.getType() == "fieldsplit":
        try:
            subs = pc.getFieldSplitSubKSP()
        except PETSc.Error:  # not set up yet
            return []
        return [F for sub in subs for F in mumps_factors(sub)]
    if pc.getType() == "redundant":  # every rank's sequential factorization (solver.linear.repeatable_lu)
        return mumps_factors(redundant_ksp(pc))
    if pc.getType() not in ("lu", "cholesky") or pc.getFactorSolverType() != "mumps":
        return []
    try:
        return [pc.getFactorMatrix()]
    except PETSc.Error:  # no factorization yet
        return []


def mumps_error(ksp) -> tuple[int, int] | None:
    """``(INFOG(1), INFOG(2))`` of the first MUMPS factorization of ``ksp`` that failed (INFOG(1) < 0; the
    same on every rank), else None."""
    # Only after a failed preconditioner: a solve that stopped before any linear solve leaves a factor matrix never
    # factored, and PETSc 3.25 hands it out, whose INFOG is then a segmentation fault.
    if ksp.getConvergedReason() != PETSc.KSP.ConvergedReason.DIVERGED_PCSETUP_FAILED:
        return None
    for F in mumps_factors(ksp):
        info = F.getMumpsInfog(1)
        if info < 0:
            return int(info), int(F.getMumpsInfog(2))
    return None


def mumps_message(info: int, size: int) -> str:
    """One line on a MUMPS failure of :data:`MUMPS_MEMORY` or :data:`MUMPS_WORKSPACE` (``INFOG(1)``, ``INFOG(2)``)."""
    entries = -size * 1e6 if size < 0 else size  # MUMPS gives a size above 2^31 in millions, negated
    if info == -19:
        return (f"MUMPS INFOG(1) = -19: out of memory, its cap ICNTL(23) is {entries:.3g} entries short of what "
                "the factorization needs")
    if info in MUMPS_MEMORY:
        what = "integer" if info == -7 else "real"
        phase = "analysis" if info in (-5, -7) else "factorization"
        return (f"MUMPS INFOG(1) = {info}: out of memory, the {phase} could not allocate {entries:.3g} {what} "
                f"entries (~{entries * 8 / 1e9:.3g} GB)")
    return f"MUMPS INFOG(1) = {info}: a work array is too small (INFOG(2) = {size})"


def cutback_helps(failure: dict | None) -> bool:
    """False for a failure a smaller load step cannot cure (kind in ``NO_CUTBACK``: out of memory)."""
    return (failure or {}).get("kind") not in NO_CUTBACK


def classify(snes_reason: str, ksp_reason: str, residuals: Sequence[float], sets: Sequence[Hashable],
             closed: Sequence[int], condition: float | None = None, mumps: tuple[int, int] | None = None) -> dict:
    """Name the failure of one Newton solve (see the module docstring).

    ``snes_reason``/``ksp_reason``: PETSc reason names; ``residuals``: residual norm per iterate (iterate 0
    first); ``sets``: active-set fingerprints per iterate (may be empty: no law-based contact);
    ``closed``: closed points per iterate; ``condition``: condition estimate of the last Jacobian (or None);
    ``mumps``: ``(INFOG(1), INFOG(2))`` of a failed MUMPS factorization (:func:`mumps_error`), or None.
    Returns ``{"kind", "iterations", ...}`` with the reasons, the first and last residual and the estimate.
    """
    r = np.asarray(residuals, dtype=float)
    its = max(len(r) - 1, 0)
    out = {"iterations": its, "snes_reason": snes_reason, "ksp_reason": ksp_reason,
           "residual_first": float(r[0]) if len(r) else None, "residual_last": float(r[-1]) if len(r) else None,
           "condition_estimate": condition}
    if mumps is not None:
        out["mumps_infog"] = list(mumps)
        if mumps[0] in MUMPS_MEMORY:
            return {"kind": "out_of_memory", **out, "message": mumps_message(*mumps)}
        if mumps[0] in MUMPS_WORKSPACE:
            return {"kind": "linear_solve", **out, "message": mumps_message(*mumps)}
    if snes_reason == "DIVERGED_LINEAR_SOLVE" and ksp_reason not in _ILL_CONDITIONED_KSP and not (
            condition is not None and condition > ILL_CONDITIONED):
        return {"kind": "linear_solve", **out}
    if ksp_reason in _ILL_CONDITIONED_KSP or (condition is not None and condition > ILL_CONDITIONED):
        return {"kind": "ill_conditioning", **out}
    if (len(r) and not np.all(np.isfinite(r))) or snes_reason in ("DIVERGED_DTOL", "DIVERGED_FNORM_NAN") or (
            len(r) > 1 and r[-1] > 1e4 * r[0]):
        return {"kind": "divergence", **out}
    cycle = find_cycle(list(sets))
    if cycle is not None or _revisiting(list(sets)):
        detail = cycle or {"period": None, "start": None, "repeats": None}
        tail = list(closed[detail["start"]:]) if detail["start"] is not None else list(closed[-8:])
        return {"kind": "cycling", **out, **detail, "closed_points_in_cycle": tail[: detail["period"] or len(tail)]}
    if its >= 6:
        half = len(r) // 2
        if np.min(r[half:]) > 0.1 * np.min(r[:half]):
            return {"kind": "stagnation", **out}
    return {"kind": "max_iterations", **out}


def stalled(snes_reason: str, residuals: Sequence[float], rtol: float, atol: float) -> bool:
    """True if SNES accepted a solve on the step length alone (``CONVERGED_SNORM_RELATIVE``) while its last
    residual is above both ``atol`` and ``rtol`` times the first: Newton stopped moving at the round-off
    floor of the linear solves (``~ eps x cond x |r|``), i.e. an ill-conditioned Jacobian, not a solution
    to the asked tolerance."""
    r = np.asarray(residuals, dtype=float)
    return snes_reason == "CONVERGED_SNORM_RELATIVE" and len(r) > 1 and bool(r[-1] > max(atol, rtol * r[0]))


def reason_name(enum: type, code: int) -> str:
    """Name of a PETSc reason code (``PETSc.SNES.ConvergedReason``, ``PETSc.KSP.ConvergedReason``)."""
    names = {v: k for k, v in vars(enum).items() if isinstance(v, int) and not k.startswith("_")}
    return names.get(code, str(code))
