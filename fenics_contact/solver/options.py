"""PETSc options of the solver: the defaults, the linear solvers, and the options in force under one prefix.

The options a solver wants (:func:`solver_options`: the defaults, what the contact formulations need, the
caller's own) are put in PETSc's database only for the duration of a set-up or a solve
(:meth:`ScopedOptions.active`) and only where absent, so anything given on the command line
(``-fc_snes_rtol 1e-12``) wins, and they do not leak into the next solver. The same options must be given on
every rank.

The caller's own options must be read by PETSc (:meth:`ScopedOptions.refuse_unused`): one that no PETSc object
of the set-up read (``snes_atoll``) is refused when the solver is made, one read inside a solve
(:func:`read_at_setup`: MUMPS, multigrid levels, a nested split) after the first converged load step.
"""
from __future__ import annotations

import ctypes
import difflib
import math
import re
from contextlib import contextmanager
from typing import Callable, Iterator, Mapping

from petsc4py import PETSc

from ..capabilities import UnsupportedCombination, check, of
from ..compat import petsc_library
from ..problem import ContactProblem

__all__ = ["ATOL_RELATIVE", "ROUNDOFF_FACTOR", "COMMON_OPTIONS", "DEFAULT_OPTIONS", "EW_RTOL_MAX", "INEXACT_NEWTON",
           "LINEAR_SOLVERS", "MULTIGRID", "linear_solver_options", "OWN_OPTIONS", "VI_ZERO_TOLERANCE", "ScopedOptions",
           "check_option_values",
           "option_used", "petsc_complaint", "probe_option", "read_at_setup", "rtol_max_problem", "solver_options",
           "value_problem"]

DEFAULT_OPTIONS = {
    "snes_type": "newtonls",
    "snes_linesearch_type": "l2",  # bt stalls on the exponential branch of cross-constraints
    "snes_rtol": 1e-11,
    # No snes_atol: the absolute floor is ATOL_RELATIVE times the run's force scale (newton.Newton.atol); a
    # snes_atol given by the caller or on the command line is used as it is.
    "snes_stol": 1e-14,
    "snes_max_it": 30,
    # Divergence (newton.Newton.convergence_test): the residual above this factor times the first
    # one AND grown in each of the last two iterations. PETSc's own test (above the factor at any iterate)
    # stops a penalty-like law's first iterate, which penetrates by the whole approach: its residual jumps
    # by ~K/E and then falls quadratically (hertz K = 1e14: 5.1 -> 5.0e7 -> 8.9e6 -> 3.7e-9); a diverging
    # Newton keeps growing (the sheet's three-point penalty at eps = 1e5: to 1e8 in 3 iterations, and each
    # iterate of an exploded geometry widens the two-body pattern). PETSc's test: -fc_snes_convergence_test
    # default. Real failures are named by failure.classify.
    "snes_divergence_tolerance": 1e4,
    "ksp_type": "preonly",
    "pc_type": "lu",
    "pc_factor_mat_solver_type": "mumps",
}

# The residual norm below which a solve has converged whatever its first residual, relative to the force scale of
# the run (the largest first residual of its solves, newton.Newton.force_scale): a step that changes little (a late
# augmentation) starts near it and stops there instead of at rtol of its own small first residual, at the
# round-off floor (~1e-16 x the internal forces x the conditioning of the assembly).
ATOL_RELATIVE = 1e-11
# SNES VI: an unknown within this distance of its bound is on it (an active constraint), relative to the size of
# the mesh (ContactProblem.mesh_size; PETSc's -snes_vi_zero_tolerance, absolute, 1e-8 by default: with R = 1e-6 every
# contact vertex would be on the plane). Above the round-off of a bound (~1e-16 of the coordinates).
VI_ZERO_TOLERANCE = 1e-8
# The round-off floor of a residual (finite strain, current gap) in units of machine epsilon x stiffness
# diagonal x cell size per row (newton.Newton.roundoff_floor): above the ~10 terms each entry of a stress sums.
ROUNDOFF_FACTOR = 100.0

# Linear solvers of ``--solver``. direct: sparse LU (MUMPS), robust for every method, the default for
# the 2D scenes (up to ~1e5 dofs). iterative: GMRES with smoothed-aggregation AMG (GAMG) and the
# rigid-body modes as near-nullspace, for 3D meshes where LU's fill-in and time grow too fast.
# (CG would do for these symmetric Jacobians, but GAMG's Chebyshev smoothers, with eigenvalue
# estimates from the first contact iterations, reported an indefinite preconditioner on the sphere.)
# Multipliers (a saddle point): "iterative" becomes their own FGMRES + Schur complement field split
# (multipliers.PressureUnknown.iterative_solver_options; options of the caller's own still win).
# Inexact Newton (Eisenstat-Walker, PETSc's -snes_ksp_ew; demos' --inexact): each Krylov tolerance follows the
# nonlinear residual's decrease, at most EW_RTOL_MAX (ksp_rtol is then unused). An early two-body iterate pushes
# the undeformed bodies through each other: its Jacobian (large pressures times the master normal's variation)
# took GAMG-GMRES 53 / 145 / over 1000 iterations to 1e-8 at 5e3 / 1e4 / 2e4 dofs (sphere on block), a failed
# solve and a cutback each time; to 1e-2 it takes 9-89, and the Newton iterations fall too (23 -> 15 at 2e4
# dofs). EW's default cap 0.9 doubles the Newton iterations. Not the default: the path of the Newton iterates
# then depends on the partition (GAMG), and with it the pairing that the search's hysteresis keeps (a nodal
# pressure 1e-3 / 7e-3 apart between 1 and 2 ranks at 1.2e5 / 4e5 dofs); with ksp_rtol 1e-8 they agree closely.
EW_RTOL_MAX = 1e-2
INEXACT_NEWTON = {"snes_ksp_ew": True, "snes_ksp_ew_rtol0": EW_RTOL_MAX, "snes_ksp_ew_rtolmax": EW_RTOL_MAX}
# Preconditioners whose set-up builds a hierarchy of level solvers (renewed, not reset, on a new pattern).
MULTIGRID = ("gamg", "ml", "hypre", "mg")

LINEAR_SOLVERS = {
    "direct": {"ksp_type": "preonly", "pc_type": "lu", "pc_factor_mat_solver_type": "mumps"},
    "iterative": {"ksp_type": "gmres", "pc_type": "gamg", "ksp_rtol": 1e-8, "ksp_max_it": 500},
}


def linear_solver_options(solver: str) -> dict:
    """The PETSc options of the capability grid's ``solver`` value: ``direct`` and ``iterative``
    (:data:`LINEAR_SOLVERS`), ``inexact`` (the iterative one with :data:`INEXACT_NEWTON`)."""
    if solver == "inexact":
        return {**LINEAR_SOLVERS["iterative"], **INEXACT_NEWTON}
    if solver not in LINEAR_SOLVERS:
        raise ValueError(f"solver must be one of {(*LINEAR_SOLVERS, 'inexact')}, got {solver!r}")
    return dict(LINEAR_SOLVERS[solver])


# Options the solver reads itself, not PETSc's objects (Solver.summary: the condition estimate of the last Jacobian;
# ksp_rtol_max: the Krylov tolerance of each Newton iteration follows the residual, newton.Newton.forcing).
OWN_OPTIONS = ("condition_estimate", "distributed_lu", "ksp_rtol_max")
# PETSc options often given (without prefix), besides the library's own: the candidates of "did you mean" for a
# misspelt one.
COMMON_OPTIONS = ("snes_atol", "snes_monitor", "snes_converged_reason", "snes_view", "snes_linesearch_monitor",
                  "snes_linesearch_damping", "snes_convergence_test", "snes_max_funcs", "snes_lag_jacobian",
                  "ksp_monitor", "ksp_converged_reason", "ksp_view", "ksp_atol", "ksp_gmres_restart",
                  "pc_factor_mat_ordering_type", "pc_gamg_threshold", "pc_gamg_type", "mat_mumps_icntl_14",
                  "mat_mumps_icntl_23", "mat_mumps_icntl_24", "mg_levels_ksp_type", "mg_levels_pc_type",
                  "mg_levels_ksp_max_it")


def option_used(name: str) -> bool:
    """Whether PETSc read option ``name`` (with prefix, no dash) from its database: ``PetscOptionsUsed``, which
    petsc4py 3.18 does not wrap, called in the PETSc library petsc4py has loaded (the same database)."""
    used = ctypes.c_int(0)  # PetscBool is a C enum
    if petsc_library().PetscOptionsUsed(None, name.encode(), ctypes.byref(used)) != 0:
        raise RuntimeError(f"PetscOptionsUsed failed for -{name}")
    return bool(used.value)


# Prefix of the probe that checks one option alone (probe_option)
_PROBE = "fc_probe_option_"
# Options that take a value (a flag without one, ``None``, is ignored by PETSc without a word): by their name's end
_VALUED = ("_type", "tol", "_max_it", "_max_funcs", "_damping", "_restart", "_threshold", "_levels", "_maxstep")
# The PETSc object whose types a ``<kind>_type`` option names (for the accepted values of a type it does not know)
# Tolerances and iteration limits: a negative value is an error on PETSc 3.18 but "the default" on later releases
# (PETSC_DETERMINE): refused on every release, as the user meant a number, not the default.
_NON_NEGATIVE = ("_rtol", "_atol", "_stol", "_max_it", "_max_funcs")
_TYPES = {"snes_type": lambda: PETSc.SNES.Type, "ksp_type": lambda: PETSc.KSP.Type, "pc_type": lambda: PETSc.PC.Type,
          "pc_factor_mat_solver_type": lambda: PETSc.Mat.SolverType}


def petsc_complaint(exc: PETSc.Error) -> str:
    """PETSc's own complaint: the last line of its error stack, without the rank."""
    lines = [s.split("] ", 1)[-1].strip() for s in str(exc).splitlines() if s.strip()]
    return lines[-1] if lines else f"error code {exc.ierr}"


def probe_option(name: str, value: object) -> str | None:
    """PETSc's complaint about option ``name`` (without prefix) ``= value`` alone, or None: a SNES of a probe prefix
    with only this option reads it with its KSP and line search, then hands its tolerances back to PETSc's checking
    setters (``SNESSetFromOptions`` stores ``snes_max_it -5`` unchecked; the solve then fails without a word on
    it). Not collective (a SNES of this process)."""
    key = _PROBE + name
    opts = PETSc.Options()
    opts[key] = value
    snes = PETSc.SNES().create(PETSc.COMM_SELF)
    try:
        snes.setOptionsPrefix(_PROBE)
        snes.setFromOptions()
        ksp = snes.getKSP()
        ksp.setFromOptions()
        snes.setTolerances(*snes.getTolerances())
        ksp.setTolerances(*ksp.getTolerances())
        return None
    except PETSc.Error as exc:
        return petsc_complaint(exc)
    finally:
        snes.destroy()
        opts.delValue(key)


def _is_number(value: object) -> bool:
    try:
        float(value)
        return True
    except (TypeError, ValueError):
        return False


def check_option_values(options: object) -> None:
    """``ValueError`` naming the first of a caller's PETSc ``options`` (name without dash or prefix -> value) that
    PETSc could not use, with the values it accepts: ``options`` not a dict; a name that is not a string of letters,
    digits and underscores; a value :func:`value_problem` finds wrong."""
    if options is None:
        return
    if not isinstance(options, Mapping):
        raise ValueError(f"Solver options must be a dict of PETSc option names (without dash or prefix) to values, got "
                         f"{type(options).__name__} {options!r}")
    for name, value in options.items():
        if not (isinstance(name, str) and re.fullmatch(r"[A-Za-z][A-Za-z0-9_]*", name)):
            raise ValueError(f"Solver option name {name!r}: accepted: a PETSc option name without dash or prefix, "
                             "letters, digits and underscores (e.g. 'snes_rtol')")
        if name in OWN_OPTIONS and name != "ksp_rtol_max":  # flags the solver reads itself
            continue
        complaint = value_problem(name, value)
        if complaint is not None:
            raise ValueError(f"Solver option {name} = {value!r}: {complaint}")


def rtol_max_problem(value: object) -> str | None:
    """What is wrong with a value of the solver's own option ``ksp_rtol_max`` (the largest Krylov tolerance of a
    Newton iteration, :meth:`~.newton.Newton.forcing`), or None."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = math.nan
    if not 0.0 <= number < 1.0:
        return "accepted: a number in [0, 1) (at or below ksp_rtol: the Krylov tolerance fixed at ksp_rtol)"
    return None


def value_problem(name: str, value: object) -> str | None:
    """What is wrong with PETSc option ``name`` (without dash or prefix) ``= value`` (None: a flag without a value),
    with the values accepted, or None: a value other than a string, number, bool or None; a number that is not
    finite; None for an option that takes a value; a value PETSc rejects on its own (:func:`probe_option`); a
    negative tolerance or iteration limit (which later PETSc releases take as "the default"). The solver's own
    ``ksp_rtol_max``: :func:`rtol_max_problem`."""
    if name == "ksp_rtol_max":
        return rtol_max_problem(value)
    if value is not None and not isinstance(value, (str, bool, int, float)):
        return f"accepted: a string, a number, a bool or None (a flag), got {type(value).__name__}"
    if not isinstance(value, bool) and _is_number(value) and not math.isfinite(float(value)):
        return "accepted: a finite number"
    if value is None and (name.endswith(_VALUED) or (name in DEFAULT_OPTIONS and not isinstance(
            DEFAULT_OPTIONS[name], bool))):
        return "this option takes a value, none was given"
    complaint = probe_option(name, value)
    if (complaint is None and name.endswith(_NON_NEGATIVE) and not isinstance(value, bool) and _is_number(value)
            and float(value) < 0):
        complaint = f"{name} {value} must be non-negative; accepted: a finite number >= 0"
    if complaint is not None and name in _TYPES and "Unable to find" in complaint:
        kind = _TYPES[name]()
        known = sorted(str(getattr(kind, k)) for k in dir(kind) if not k.startswith("_"))
        complaint += f"; accepted: {', '.join(known)}"
    return complaint


def _library_option(name: str) -> bool:
    """An option the library itself sets (a default, a linear solver's): never misspelt, even where the formulation
    replaces the solver it belongs to (a field split instead of LU)."""
    return name in DEFAULT_OPTIONS or name in INEXACT_NEWTON or any(name in s for s in LINEAR_SOLVERS.values())


def read_at_setup(name: str) -> bool:
    """Options read when the linear solver is set up inside a solve, not by ``setFromOptions``: a nested split's
    blocks (the Schur complement's KSP) and a multigrid's level smoothers and coarse solver are made then, and
    MUMPS reads its ``mat_mumps_*`` options at each symbolic factorization (a new factor on every new sparsity
    pattern)."""
    # A split's own MUMPS or multigrid options start with fieldsplit_.
    return name.startswith(("fieldsplit_", "mat_mumps_", "mg_levels_", "mg_coarse_"))


def solver_options(problem: ContactProblem, options: dict | None = None) -> dict:
    """The PETSc options (without prefix) a solver of ``problem`` wants: :data:`DEFAULT_OPTIONS` (SNES VI if a
    contact is bounded), then what the contact formulations need, then ``options``; a direct solve takes the
    formulations' ``direct_solver_options``, a multigrid one their ``iterative_solver_options`` (the caller's
    own options still win). Raises ``UnsupportedCombination`` for a law the iterative solver cannot do."""
    bounded = any(c.bounded for c in problem.contacts)
    vi = {"snes_type": "vinewtonrsls", "snes_vi_zero_tolerance": VI_ZERO_TOLERANCE * problem.mesh_size()}
    defaults = {**DEFAULT_OPTIONS, **(vi if bounded else {})}
    for c in problem.contacts:  # what a formulation needs (multipliers: full semismooth Newton steps)
        defaults.update(c.solver_options)
    wanted = {**defaults, **(options or {})}
    if wanted.get("snes_ksp_ew") not in (None, False, 0, "0", "false", "no"):  # inexact Newton: the grid's solver
        for c in problem.contacts:
            try:
                check(**of(c.law, u=problem.u), solver="inexact")
            except UnsupportedCombination as exc:  # named by the option that chose it
                raise UnsupportedCombination(f"snes_ksp_ew = {wanted['snes_ksp_ew']!r} (inexact Newton, the demos' "
                                             f"--inexact): {exc}") from None
    if wanted.get("pc_type") == "lu":  # a direct solve: a formulation may split off trivial blocks
        for c in problem.contacts:
            wanted.update(c.direct_solver_options)
    elif wanted.get("pc_type") in MULTIGRID:  # the iterative solve: a formulation may need its own (Schur)
        for c in problem.contacts:  # the capability matrix, before any assembly
            check(**of(c.law, u=problem.u), solver="iterative")
        for c in problem.contacts:
            if c.iterative_solver_options:  # the caller's own options (not those of the generic GAMG) win
                generic = LINEAR_SOLVERS["iterative"]
                own = {k: v for k, v in (options or {}).items() if k not in generic or generic[k] != v}
                kept = c.constant_bulk_solver_options if problem.bulk_jacobian.constant else {}
                wanted.update({**c.iterative_solver_options, **kept, **own})
                break
    return wanted


class ScopedOptions:
    """The options a solver wants (``wanted``, names without prefix) under its options ``prefix``, put in PETSc's
    database only inside :meth:`active`; ``given``: the caller's own, which PETSc must read
    (:meth:`refuse_unused`)."""

    def __init__(self, prefix: str, wanted: dict, given: dict | None = None):
        self.prefix = prefix
        self.wanted = wanted
        self.given = dict(given or {})
        self.used: set[str] = set()  # names of ours that PETSc read while they were in its database
        self._checked_later = False

    def refuse_unused(self, later: bool = False) -> None:
        """``ValueError`` naming the options of ``given`` that PETSc did not read (with the closest known option):
        those read at set-up (call after it), or with ``later`` those read inside a solve (:func:`read_at_setup`;
        call after a load step whose Newton solved a linear system). Options the solver reads itself
        (:data:`OWN_OPTIONS`) and the library's own names are not checked."""
        unused = [k for k in self.given if read_at_setup(k) == later and k not in OWN_OPTIONS
                  and not _library_option(k) and k not in self.used and not option_used(self.prefix + k)]
        if not unused:
            return
        known = list(dict.fromkeys([*DEFAULT_OPTIONS, *INEXACT_NEWTON, *(k for s in LINEAR_SOLVERS.values()
                                                                           for k in s), *COMMON_OPTIONS, *self.used]))
        named = []
        for k in unused:
            close = difflib.get_close_matches(k, [c for c in known if c != k], n=1, cutoff=0.6)
            named.append(f"{k}{f' (did you mean {close[0]}?)' if close and k not in known else ''}")
        where = "in the first load step's solves" if later else "when the solver was set up"
        raise ValueError(f"Solver option{'s' * (len(unused) > 1)} not read by PETSc {where} (misspelt, or not an "
                         f"option of this solver's objects): {', '.join(named)}")

    def refuse_unused_later(self, solved: bool) -> None:
        """:meth:`refuse_unused` of the options read inside a solve, once: the first time ``solved`` (a converged
        load step whose Newton solved a linear system, so that MUMPS, the multigrid levels and a nested split have
        been set up)."""
        if solved and not self._checked_later:
            self._checked_later = True
            self.refuse_unused(later=True)

    def has(self, name: str) -> bool:
        """True if ``prefix + name`` is in PETSc's database (the command line's; inside :meth:`active`, ours
        too)."""
        return PETSc.Options().hasName(self.prefix + name)

    def get_real(self, name: str, default: float) -> float:
        """The real value of ``prefix + name`` in PETSc's database, else ``default``."""
        return PETSc.Options().getReal(self.prefix + name, default)

    def get_bool(self, name: str, default: bool) -> bool:
        """The boolean value of ``prefix + name`` in PETSc's database, else ``default``."""
        return PETSc.Options().getBool(self.prefix + name, default)

    @contextmanager
    def active(self, keep: Callable[[str], bool] = lambda name: True) -> Iterator[None]:
        """Our options (those of ``wanted`` that ``keep`` accepts) in PETSc's database for the ``with`` block,
        under our prefix; options already there (the command line's) win and stay. Removed afterwards, so that
        they do not leak into the next solver."""
        opts = PETSc.Options()
        present = opts.getAll()  # not hasName: that marks an option as used, hiding a misspelt one
        ours = [k for k in self.wanted if keep(k) and self.prefix + k not in present]
        for k in ours:
            opts[self.prefix + k] = self.wanted[k]
        try:
            yield
        finally:
            self.used.update(k for k in ours if option_used(self.prefix + k))
            for k in ours:
                opts.delValue(self.prefix + k)
