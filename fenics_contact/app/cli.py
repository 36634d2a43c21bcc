"""Command-line options shared by the demos (and the benchmarks): method, parameters, output; the demos' entry.

The command line is strict: an unknown ``--option`` is an error naming it
(with the closest known option), every number is range-checked while
parsing (before any work), and single-dash options go to PETSc's options
database (``-fc_snes_monitor``, ``-fc_snes_linesearch_type basic``: ``fc_``
is the solver's options prefix): a value PETSc rejects on its own
(``-fc_snes_max_it -5``) is an error naming it before any work
(:func:`check_petsc_values`), and once the solver is set up and has solved
(after the first converged load step of :func:`run.run`, and again at the
end of the demo) an option PETSc never read is an error naming it. Counts
(load steps, cells) are bounded by what the memory can hold
(:func:`count`). :func:`main` runs a demo's
``main(argv)`` and turns the expected errors (bad input, a refused
combination, a failed solve, a PETSc value PETSc rejects, a size the memory
cannot hold, running out of memory) into one line on rank 0 and a non-zero
exit, on every rank; a demo whose own check failed exits with
:data:`EXIT_CHECK`; ``sys.exit`` exits with its status, SIGINT with
:data:`EXIT_INTERRUPTED`; any other exception prints its traceback. Under
``mpirun``, a rank that leaves in any of these ways ends the whole job
within seconds (``MPI_Abort``) instead of leaving the other ranks waiting.

Exit status: 0 done and checked, :data:`EXIT_ERROR` (1) an error, :data:`EXIT_USAGE` (2) a bad command line,
:data:`EXIT_CHECK` (3) the demo ran and wrote its outputs but its check failed, :data:`EXIT_INTERRUPTED` (130)
SIGINT.
"""
from __future__ import annotations

import argparse
import difflib
import inspect
import logging
import math
import re
import signal
import sys
import threading
import time
import traceback
from typing import Callable, Sequence

import numpy as np
from mpi4py import MPI
from petsc4py import PETSc

from .. import methods
from ..condensed import operator as condensed_operator
from ..contact import QUADRATURES
from ..jitlog import quiet_compiler
from ..laws import ContactLaw, LagrangeMultiplier
from ..solver import DEFAULT_OPTIONS, INEXACT_NEWTON, LINEAR_SOLVERS, ConvergenceError, linear_solver_options
from ..solver.options import OWN_OPTIONS, option_used, petsc_complaint, value_problem
from .memory import BYTES_PER_DOF, available_memory

logger = logging.getLogger(__name__)

# PETSc options given on the command line (name without the dash, value), checked by check_petsc_options
_PETSC_OPTIONS: list[tuple[str, str]] = []
# PETSc options a user commonly gives (without the prefix): the candidates of "did you mean" for a misspelt one
_COMMON_PETSC = ("snes_monitor", "snes_converged_reason", "snes_view", "snes_linesearch_monitor",
                 "snes_convergence_test", "ksp_monitor", "ksp_converged_reason", "ksp_view", "condition_estimate",
                 "pc_factor_mat_solver_type", "mat_mumps_icntl_14", "ksp_gmres_restart", "pc_gamg_threshold")

__all__ = ["parser", "parse", "refuse_unsupported", "one_line_errors", "has_friction", "law_from_args",
           "method_parameters", "model_option", "model_degree",
           "method_options", "FRICTION_OPTIONS", "RANGE_TYPES",
           "solver_options", "StrictParser",
           "UsageError", "HelpFormatter", "GIVEN",
           "number", "POSITIVE", "NONNEGATIVE", "COUNT", "LEVEL", "EXPONENT", "output_options",
           "setup_logging", "recorded_options", "OUTPUT_ONLY", "say", "unused_petsc_options", "check_petsc_options",
           "check_petsc_values", "error_line",
           "main", "count",
           "EXIT_ERROR", "EXIT_USAGE", "EXIT_CHECK", "EXIT_INTERRUPTED"]

GIVEN = "given"  # StrictParser.requirements: the other option must be given (any value)
EXIT_ERROR, EXIT_USAGE, EXIT_CHECK = 1, 2, 3  # main's exit status: an error, a bad command line, a failed check
EXIT_INTERRUPTED = 130  # main's exit status after SIGINT (128 + the signal's number, as a shell says)
# Seconds a rank that failed waits for the others to reach the end of main (a rank still inside a collective of
# the demo never does: the job is then aborted)
AGREE_TIMEOUT = 5.0


class UsageError(ValueError):
    """A command line we refuse (unknown option, a value out of range); exit status 2 as argparse's."""


class HelpFormatter(argparse.ArgumentDefaultsHelpFormatter):
    """Each option's help followed by its default. An option whose default is unset (``None``) and whose help
    does not say what it defaults to gets ``(default: not used)``; a help saying ``default: <rule>`` whose option
    a demo gave a value (``set_defaults``) shows that value instead of the rule."""

    def _get_help_string(self, action):
        text = action.help or ""
        if action.default is argparse.SUPPRESS:  # --help
            return text
        if action.default is None:
            return text + " (default: not used)" if action.option_strings and "default:" not in text else text
        if "default:" in text:
            shown = f"{action.default:g}" if isinstance(action.default, float) else str(action.default)
            rule = re.search(r"default: [^;)]*", text).group(0)
            return text if shown in rule else text.replace(rule, "default: %(default)s", 1)
        return super()._get_help_string(action)


class StrictParser(argparse.ArgumentParser):
    """``argparse.ArgumentParser`` without abbreviations (``--refinment`` never matches ``--refinement``) whose
    errors raise :class:`UsageError` (one line, naming the option) instead of printing the usage and exiting.
    ``requirements``: ``(dest, other, value)``, the option ``dest`` given only with the option ``other`` at
    ``value`` (:data:`GIVEN`: given at all); ``orders``: ``(dest, other)``, the value of ``dest`` below that of
    ``other`` (when both are set); ``checks``: functions of the parsed options raising :class:`UsageError` (the
    values together, e.g. a scene's lengths against each other); all checked when parsed."""

    def __init__(self, *args, **kwargs):
        kwargs.setdefault("allow_abbrev", False)
        kwargs.setdefault("formatter_class", HelpFormatter)
        kwargs.setdefault("epilog", "Other -options go to PETSc (prefix fc_); they must be used by PETSc.")
        super().__init__(*args, **kwargs)
        self.requirements: list[tuple[str, str, object]] = []
        self.orders: list[tuple[str, str]] = []
        self.checks: list[Callable[[argparse.Namespace], None]] = []  # of the parsed values together

    def error(self, message: str):
        # "argument --E: must be ..." -> "--E must be ..."; "argument --load: not allowed with argument
        # --approach" -> "--load contradicts --approach: give one of them"
        message = re.sub(r"^argument (\S+): must be", r"\1 must be", message)
        message = re.sub(r"^argument (\S+): not allowed with argument (\S+)",
                         r"\1 contradicts \2: give one of them", message)
        raise UsageError(message)

    def parse_known_args(self, args=None, namespace=None):
        ns, rest = super().parse_known_args(args, namespace)
        for dest, other, value in self.requirements:
            if getattr(ns, dest, None) is None or not hasattr(ns, other):
                continue
            have = getattr(ns, other)
            if (have is None) if value == GIVEN else (have != value):
                flag, needed = "--" + dest.replace("_", "-"), "--" + other.replace("_", "-")
                raise UsageError(f"{flag} is used only with {needed}" + ("" if value == GIVEN else f" {value}")
                                 + (f" (got {needed} {have})" if value != GIVEN else ""))
        for dest, other in self.orders:
            mine, theirs = getattr(ns, dest, None), getattr(ns, other, None)
            if mine is not None and theirs is not None and not mine < theirs:
                flag, bound = "--" + dest.replace("_", "-"), "--" + other.replace("_", "-")
                raise UsageError(f"{flag} must be < {bound} ({theirs:g}), got {mine:g}")
        for check in self.checks:
            check(ns)
        return ns, rest

    def parse_args(self, args=None, namespace=None):
        """All arguments must be ours (no PETSc options: :func:`parse` takes those): an unknown one is named, with
        the closest known option."""
        ns, rest = self.parse_known_args(args, namespace)
        if rest:
            name = rest[0].split("=", 1)[0]
            if name.startswith("-") and not _is_number(name):
                raise UsageError(f"unknown option {name}{_did_you_mean(name, self.long_options())}")
            raise UsageError(f"unexpected argument {rest[0]!r}")
        return ns

    def long_options(self) -> list[str]:
        return [s for a in self._actions for s in a.option_strings if s.startswith("--")]


def number(kind: type = float, low: float | None = None, high: float | None = None, low_open: bool = False,
           high_open: bool = False) -> Callable[[str], float]:
    """An argparse ``type``: ``kind`` (int or float), finite, in the range given (open ends with ``*_open``)."""
    lo = "" if low is None else f"{'>' if low_open else '>='} {low:g}"
    hi = "" if high is None else f"{'<' if high_open else '<='} {high:g}"
    what = ("an integer" if kind is int else "a finite number") + (
        f" in {'(' if low_open else '['}{low:g}, {high:g}{')' if high_open else ']'}" if lo and hi else
        f" {lo or hi}" if lo or hi else "")

    def convert(text: str):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text!r}") from None
        ok = math.isfinite(value)
        ok = ok and (low is None or (value > low if low_open else value >= low))
        ok = ok and (high is None or (value < high if high_open else value <= high))
        if not ok:
            raise argparse.ArgumentTypeError(f"must be {what}, got {text}")
        return value

    convert.__name__ = what  # argparse names the type in its messages
    convert.range = (kind, low, high, low_open, high_open)  # the accepted range, for tests and callers
    return convert


def count(low: int = 1) -> Callable[[str], int]:
    """An argparse ``type``: an integer ``>= low`` of load steps or cells, at most what the memory can hold
    (each takes at least 1 kB, :data:`~fenics_contact.app.memory.BYTES_PER_DOF`: a step's record, a cell's
    unknowns), checked when parsed."""
    at_least = number(int, low)

    def convert(text: str) -> int:
        nbytes, phrase = available_memory()
        most = int(float(f"{nbytes / BYTES_PER_DOF:.2g}"))
        try:
            value = int(text)
        except ValueError:
            value = None
        if value is None or value > most:
            raise argparse.ArgumentTypeError(f"must be an integer in [{low}, {most}] (a load step or a cell takes at "
                                             f"least 1 kB of {phrase}), got {text!r}")
        return at_least(text)

    convert.__name__ = at_least.__name__
    convert.range = at_least.range
    return convert


POSITIVE = number(float, 0.0, low_open=True)
NONNEGATIVE = number(float, 0.0)
COUNT = count(1)  # load steps, cells: >= 1, within the memory
LEVEL = number(int, 0)  # refinements, augmentations: >= 0
EXPONENT = number(float, 1.0)


def scene_scaled(value: float, builder: Callable, modulus: str | None = "E", length: str = "R",
                 E0: float | None = None) -> Callable[[argparse.Namespace], float]:
    """A stiffness per unit area (pressure per length: a penalty ``K``, a tangential ``omega_t``) chosen for a
    scene at its default modulus and size, as a function of the parsed options: ``value (E / E0) (L0 / L)``.

    Args:
        value: the stiffness at the builder's defaults.
        builder: the scene's builder; its keyword defaults give ``E0`` and ``L0``.
        modulus: the builder keyword (and option) of the modulus; None: the stiffness does not follow it.
        length: the builder keyword (and option) of the scene's size.
        E0: the default modulus where the builder's default is None (derived from other constants).

    Returns:
        A function of the parsed options giving the stiffness in the options' units.
    """
    defaults = {k: v.default for k, v in inspect.signature(builder).parameters.items()}
    E_ref = defaults.get(modulus) if E0 is None else E0
    L_ref = defaults[length]

    def derive(args: argparse.Namespace) -> float:
        E = getattr(args, modulus, None) if modulus is not None else None
        L = getattr(args, length, None)
        return value * (E / E_ref if E is not None and E_ref else 1.0) * (L_ref / L if L is not None else 1.0)
    return derive


def parser(description: str, default_K: float | Callable[[argparse.Namespace], float],
           quadratures: Sequence[str] = QUADRATURES,
           default_omega_t: float | Callable[[argparse.Namespace], float] | None = None) -> StrictParser:
    """The shared options; ``default_K``: a number, or a function of the parsed options (a K that scales with
    the scene's E and size, :func:`scene_scaled`); ``quadratures``: the accepted ``--quadrature`` values
    (two-body scenes add ``segment``); ``default_omega_t``: the tangential penalty's default, a number or such
    a function (None: ``--K``)."""
    p = StrictParser(description=description)
    p.set_defaults(derive_omega_t=default_omega_t if callable(default_omega_t) else None)
    p.add_argument("--method", choices=methods.names(), default="cross",
                   help="contact formulation: " + "; ".join(f"{m.name}: {m.summary}" for m in methods.methods()))
    derived = callable(default_K)
    p.set_defaults(derive_K=default_K if derived else None)
    for option, declared in method_options().items():
        param = declared[0][1]
        default = (None if derived else default_K) if param.default is None else \
            None if isinstance(param.default, str) else param.default
        helps = "; ".join(f"{', '.join(names)}: {text}" for text, names in _grouped_help(declared))
        if option == "K" and derived:
            helps += "; default: the scene's K, scaled with E / size"
        p.add_argument(f"--{option.replace('_', '-')}", dest=option, type=RANGE_TYPES[param.range], default=default,
                       help=helps)
    p.add_argument("--augment", type=LEVEL, default=None,
                   help="max augmentations per load step (default: the method's, " + ", ".join(
                       f"{m.name} {m.augment}" for m in methods.methods()) + ")")
    p.add_argument("--augment-tol", type=POSITIVE, default=1e-12,
                   help="stop augmenting when ||g_new - g_old|| <= this x the mesh's size (its bounding box's "
                   "diagonal; dimensionless)")
    p.add_argument("--mu", type=NONNEGATIVE, default=0.0,
                   help="Coulomb friction coefficient (>= 0; 0: frictionless; exact with method coulomb)")
    p.add_argument("--c-t", type=POSITIVE, default=None,
                   help="friction bound c_t <g>^m_t instead of mu F(g) (normal compliance friction)")
    p.add_argument("--m-t", type=EXPONENT, default=None, help="exponent m_t >= 1 of the bound (default: m_n)")
    p.add_argument("--tresca", type=NONNEGATIVE, default=None,
                   help="Tresca friction: the fixed bound (traction) on the closed points instead of mu F(g)")
    p.add_argument("--omega-t", type=POSITIVE, default=None if callable(default_omega_t) else default_omega_t,
                   help="tangential penalty of stick (pressure per length; default: " + (
                       "--K)" if default_omega_t is None else "the scene's, scaled with E / size)"))
    p.add_argument("--quadrature", choices=list(quadratures), default="nodal", help="contact quadrature")
    p.add_argument("--solver", choices=list(LINEAR_SOLVERS), default="direct",
                   help="linear solver: direct (MUMPS LU) or iterative (GMRES + GAMG, rigid-body modes; 3D; "
                        "multipliers: FGMRES + Schur complement field split)")
    p.add_argument("--inexact", action="store_true",
                   help="with --solver iterative: inexact Newton, the Krylov tolerance following the residual "
                        "(Eisenstat-Walker, at most 1e-2)")
    output_options(p)
    return p


def model_option(p: argparse.ArgumentParser, default: str = "linear", mixed: bool = False,
                 help: str = "bulk material") -> None:
    """``--model``: the bulk models of :data:`~fenics_contact.materials.MODELS`, the displacement ones and, with
    ``mixed`` (a scene whose builder takes them), the mixed displacement-pressure ones."""
    from ..models import MODELS

    choices = [name for name, cls in MODELS.items() if mixed or not cls.mixed]
    p.add_argument("--model", choices=choices, default=default,
                   help=help + ("; the -mixed models: nearly incompressible, Taylor-Hood P2-P1 (u, p), contact "
                                "quadrature gauss or simpson" if mixed else ""))


def model_degree(model: str, degree: int = 1) -> int:
    """The displacement degree a scene of displacement ``degree`` runs ``model`` with: 2 (Taylor-Hood) for a
    mixed model."""
    from ..models import MODELS

    return 2 if MODELS[model].mixed else degree


FRICTION_OPTIONS = ("mu", "c_t", "m_t", "tresca", "omega_t")  # options of the friction on top of a law
RANGE_TYPES = {"positive": POSITIVE, "nonnegative": NONNEGATIVE, "exponent": EXPONENT,
               "unit": number(float, 0.0, 1.0, high_open=True), "sign": number(float, -1.0, 1.0)}


def method_options() -> dict[str, list]:
    """Every registered method's parameter options: option -> [(method name, Parameter), ...] in registry
    order (an option several methods share, e.g. ``K``, once), the friction options left out."""
    out: dict[str, list] = {}
    for m in methods.methods():
        for param in m.parameters:
            if param.option not in FRICTION_OPTIONS:
                out.setdefault(param.option, []).append((m.name, param))
    return out


def _grouped_help(declared: list) -> list[tuple[str, list[str]]]:
    """The help texts of one option, each with the methods that give it."""
    groups: dict[str, list[str]] = {}
    for name, param in declared:
        groups.setdefault(param.help, []).append(name)
    return list(groups.items())


def output_options(p: argparse.ArgumentParser, out: str | None = None) -> None:
    """``--out``, ``--restart``, ``--overwrite``, ``--no-pictures``, ``--no-xdmf``, ``--quiet``, ``--verbose``
    (every demo has them)."""
    p.add_argument("--out", default=out, help="output directory (default: results/<scene>)")
    p.add_argument("--restart", action="store_true",
                   help="go on with the run stopped in --out from its last completed step (same options and ranks)")
    p.add_argument("--overwrite", action="store_true",
                   help="empty --out first if it holds another run's files (refused otherwise)")
    p.add_argument("--no-pictures", action="store_true", help="skip the PNG pictures")
    p.add_argument("--no-xdmf", action="store_true", help="no XDMF field output (benchmarks: solver time alone)")
    p.add_argument("--quiet", action="store_true", help="no progress lines (warnings and errors only)")
    p.add_argument("--verbose", action="store_true", help="debug log, with the form compiler's (FFCx, cffi) output")


def parse(p: argparse.ArgumentParser, argv: Sequence[str] | None = None) -> argparse.Namespace:
    """Parse our options (an unknown ``--option`` is an error naming it, with the closest known one); insert the
    single-dash ones with their values into PETSc's options (checked after the run: :func:`check_petsc_options`);
    set up logging (``--quiet``, ``--verbose``)."""
    one_line_errors()  # for scripts not run through main()
    argv = list(sys.argv[1:] if argv is None else argv)
    args, rest = p.parse_known_args(argv)
    known = p.long_options() if isinstance(p, StrictParser) else [
        s for a in p._actions for s in a.option_strings if s.startswith("--")]
    petsc: list[tuple[str, str]] = []
    for token in rest:
        if token.startswith("--"):
            name = token.split("=", 1)[0]
            raise UsageError(f"unknown option {name}{_did_you_mean(name, known)}")
        if token.startswith("-") and not _is_number(token):
            petsc.append((token[1:], ""))
        elif petsc and not petsc[-1][1]:
            petsc[-1] = (petsc[-1][0], token)
        else:
            raise UsageError(f"unexpected argument {token!r} (not the value of an option)")
    if petsc:
        PETSc.Options().insertString(" ".join(f"-{k} {v}" for k, v in petsc))
        _PETSC_OPTIONS.extend(petsc)
        check_petsc_values(petsc)
    setup_logging(verbose=getattr(args, "verbose", False), quiet=getattr(args, "quiet", False))
    if getattr(args, "inexact", False) and getattr(args, "solver", None) != "iterative":
        raise UsageError(f"--inexact needs --solver iterative, got --solver {getattr(args, 'solver', None)}")
    if hasattr(args, "method"):
        # Method lagrange with friction and no --K: Alart-Curnier's c from the problem (run.run), not the penalty's
        # K (a penalty ~ 20 E / h made its Newton cycle between stick and slip: c ~ E / h steers it best).
        args.scaled_c = (methods.get(args.method).law is LagrangeMultiplier and has_friction(args)
                         and not any(t == "--K" or t.startswith("--K=") for t in argv))
        if getattr(args, "K", 0) is None and getattr(args, "derive_K", None) is not None:
            args.K = float(args.derive_K(args))
        if getattr(args, "augment", 0) is None:
            args.augment = methods.get(args.method).augment
        for option, declared in method_options().items():  # a default that is another option's value
            other = declared[0][1].default
            if isinstance(other, str) and getattr(args, option, 0) is None:
                setattr(args, option, getattr(args, other))
        if getattr(args, "omega_t", 0) is None and getattr(args, "derive_omega_t", None) is not None:
            args.omega_t = float(args.derive_omega_t(args))
        if getattr(args, "omega_t", 0) is None:
            args.omega_t = args.K
    return args


# options of the output and of the log: a restart may change them (the others shape the problem or its load path)
OUTPUT_ONLY = ("out", "restart", "overwrite", "no_pictures", "quiet", "verbose")


def recorded_options(args: argparse.Namespace) -> dict:
    """The options of the parsed command line ``args`` that shape the problem or its load path (all but
    :data:`OUTPUT_ONLY`), by flag (``--steps``), as parsed (defaults and derived values included), in the
    parser's order: what ``summary.json`` records and a restart must give again."""
    def plain(v: object) -> bool:
        return v is None or isinstance(v, (bool, int, float, str)) or (
            isinstance(v, (list, tuple)) and all(plain(x) for x in v))

    return {"--" + k.replace("_", "-"): list(v) if isinstance(v, tuple) else v for k, v in vars(args).items()
            if k not in OUTPUT_ONLY and plain(v)}


def setup_logging(verbose: bool = False, quiet: bool = False) -> None:
    """The package's log (``fenics_contact.*``) on rank 0's stdout: progress at INFO (``quiet``: warnings only),
    DEBUG with ``verbose``, which also shows the form compiler's log and UFL's warnings (hidden otherwise)."""
    root = logging.getLogger("fenics_contact")
    if not any(getattr(h, "_fenics_contact", False) for h in root.handlers):
        handler = logging.StreamHandler(sys.stdout)
        handler.setFormatter(logging.Formatter("%(message)s"))
        handler._fenics_contact = True
        root.addHandler(handler)
        root.propagate = False
    level = logging.DEBUG if verbose else logging.WARNING if quiet else logging.INFO
    root.setLevel(level if MPI.COMM_WORLD.rank == 0 else max(level, logging.ERROR))
    # UFL warns about every custom quadrature rule (the nodal rule is one on purpose); FFCx logs its JIT
    logging.getLogger("UFL").setLevel(logging.DEBUG if verbose else logging.ERROR)
    logging.getLogger("ffcx").setLevel(logging.DEBUG if verbose else logging.WARNING)
    quiet_compiler(not verbose)  # the compiler's commands of a form's first JIT, shown with verbose


def _abort_on_uncaught() -> None:
    """An exception that ends the program outside :func:`main` (an import, a script that does not use it), on one
    rank of an ``mpirun`` job: after its traceback, ``MPI_Abort`` ends the whole job (a rank that exited normally
    would wait in ``MPI_Finalize`` for the others, and they for it)."""
    previous = sys.excepthook

    def hook(kind, value, tb):
        previous(kind, value, tb)
        if MPI.Is_initialized() and not MPI.Is_finalized() and MPI.COMM_WORLD.size > 1:
            sys.stderr.flush()
            MPI.COMM_WORLD.Abort(EXIT_INTERRUPTED if issubclass(kind, KeyboardInterrupt) else EXIT_ERROR)

    sys.excepthook = hook


_abort_on_uncaught()


def one_line_errors() -> None:
    """Make a ``ValueError`` that ends a demo (a refused combination, a bad option value) one line on stderr
    (``error: ...``, from rank 0) and exit status 1, without a traceback; other exceptions keep theirs."""
    previous = sys.excepthook

    def hook(kind, value, tb):
        if not issubclass(kind, ValueError):
            return previous(kind, value, tb)
        from mpi4py import MPI

        if MPI.COMM_WORLD.rank == 0:
            sys.stderr.write(f"error: {str(value).splitlines()[0] if str(value) else kind.__name__}\n")
        sys.stderr.flush()  # the interpreter then exits with status 1 (every rank raised the same error)

    sys.excepthook = hook


def refuse_unsupported(args: argparse.Namespace, **axes) -> None:
    """Check the demo's options against the capability matrix before any work: method, quadrature, linear
    solver, friction, passes and sliding from ``args``, the scene's own axes (``kind``, ``dim``, ``degree``, ``model``)
    as keywords. Raises :class:`~fenics_contact.capabilities.UnsupportedCombination`."""
    from ..capabilities import check as check_combination

    solver = "inexact" if getattr(args, "inexact", False) else getattr(args, "solver", None)
    combo = {"method": args.method, "quadrature": args.quadrature, "solver": solver,
             "friction": has_friction(args),
             "passes": getattr(args, "passes", None), "sliding": getattr(args, "sliding", None)}
    if combo["method"] == "coulomb" and combo["solver"] == "iterative":
        combo["solver"] = None  # the sparse method's, if the size switches to it: refuse_condensed_solver, once built
    check_combination(**{**combo, **axes})


def refuse_condensed_solver(args: argparse.Namespace, setup) -> None:
    """:class:`UsageError` for ``--solver iterative`` with method coulomb where the built scene is solved by the
    condensed system (it factors the stiffness itself); the solver serves the sparse exact method the run takes
    where the condensed system is too large (its size is known once the contact is paired)."""
    if getattr(args, "method", None) == "coulomb" and getattr(args, "solver", None) == "iterative" and \
            setup.problem.step_solver is not None:
        raise UsageError(f"--solver iterative: method coulomb solves this scene on its condensed system (at most "
                         f"{condensed_operator.MAX_CONDENSED} contact dofs), which factors the stiffness itself "
                         "(MUMPS); accepted: --solver direct (iterative serves method coulomb only above that size, "
                         "where the run takes the sparse exact method)")


def say(*parts: object) -> None:
    """A demo's report line (tables, comparisons) through the log (``fenics_contact.demo``, INFO): shown unless
    ``--quiet``; call on rank 0."""
    logging.getLogger("fenics_contact.demo").info(" ".join(str(p) for p in parts))


def has_friction(args: argparse.Namespace) -> bool:
    """Friction is on when ``--mu`` is not 0 or ``--c-t`` or ``--tresca`` is given (a negative mu is an error, not
    off)."""
    return args.mu != 0.0 or args.c_t is not None or getattr(args, "tresca", None) is not None


def _is_number(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return False


def _did_you_mean(name: str, candidates: Sequence[str]) -> str:
    lower = {c.lower(): c for c in candidates}
    close = difflib.get_close_matches(name.lower(), list(lower), n=1, cutoff=0.6)
    return f" (did you mean {lower[close[0]]}?)" if close else ""


def law_from_args(args: argparse.Namespace) -> ContactLaw:
    """The contact law named by ``--method`` with its parameters (the method's declaration), with friction if
    asked for."""
    method = methods.get(args.method)
    tresca, c_t = getattr(args, "tresca", None), getattr(args, "c_t", None)
    if method.friction == "own":
        for option, value in (("--tresca", tresca), ("--c-t", c_t)):
            if value is not None:
                raise ValueError(f"{option}: method {args.method!r} has Coulomb friction only (use --mu, or another "
                                 "method)")
    law = method.make_law(**{p.name: getattr(args, p.option) for p in method.parameters})
    if method.friction == "own" or not has_friction(args):
        return _augmented(law, args)
    if method.friction == "none":
        raise ValueError(f"method {args.method!r} has no friction: use --mu 0 (or another method)")
    if sum((args.mu != 0.0, c_t is not None, tresca is not None)) > 1:
        raise ValueError(f"give one of --mu ({args.mu}), --c-t ({c_t}) and --tresca ({tresca}), not several")
    from ..friction import Friction

    if tresca is not None:
        return _augmented(Friction(law, tresca=tresca, omega_t=args.omega_t), args)
    if c_t is not None:
        return _augmented(Friction(law, c_t=c_t, m_t=args.m_t, omega_t=args.omega_t), args)
    return _augmented(Friction(law, mu=args.mu, omega_t=args.omega_t), args)


def _augmented(law: ContactLaw, args: argparse.Namespace) -> ContactLaw:
    """``law``, if it reads the augmentations ``--augment`` asks for; :class:`UsageError` if it has nothing to
    augment (the run would record augmentations that never happen)."""
    augment = getattr(args, "augment", 0) or 0
    if augment and not law.augmentable:
        takers = ", ".join(m.name for m in methods.methods() if m.augment)
        raise UsageError(f"--augment {augment}: method {args.method} has nothing to augment; accepted: --augment 0 "
                         f"(augmented: methods {takers}, or any method with friction)")
    return law


def method_parameters(args: argparse.Namespace) -> dict:
    """The run's method parameters by option (for the summary): the method's own, the friction's if on, the
    augmentation, quadrature and linear solver."""
    method = methods.get(args.method)
    keys = [p.option for p in method.parameters]
    if has_friction(args) and method.friction == "law":
        keys = keys + (["c_t", "m_t"] if args.c_t is not None else ["tresca"] if getattr(args, "tresca", None)
                       is not None else ["mu"]) + ["omega_t"]
    return {**{k: getattr(args, k) for k in keys}, "augment": args.augment, "augment_tol": args.augment_tol,
            "quadrature": args.quadrature, "solver": getattr(args, "solver", "direct")}


def solver_options(args: argparse.Namespace) -> dict:
    """PETSc options (prefix ``fc_``) of ``--solver`` (and ``--inexact``); options on the command line still win."""
    return linear_solver_options("inexact" if getattr(args, "inexact", False) else getattr(args, "solver", "direct"))


# --- PETSc options and the demos' entry ------------------------------------------------------------------

def unused_petsc_options(later: Sequence[str] = ()) -> list[str]:
    """The command line's PETSc options that PETSc never read, each with the closest known option if any; those
    ending in one of ``later`` (read after the point of the check) are not reported."""
    known = [f"-fc_{k}" for k in dict.fromkeys([*DEFAULT_OPTIONS, *(k for s in LINEAR_SOLVERS.values() for k in s),
                                                *INEXACT_NEWTON, *_COMMON_PETSC])]
    return [f"-{name}{_did_you_mean('-' + name, known)}" for name, _ in dict.fromkeys(_PETSC_OPTIONS)
            if not name.endswith(tuple(later)) and not option_used(name)]


def check_petsc_options(later: Sequence[str] = ()) -> None:
    """Raise ``UsageError`` naming every PETSc option of the command line that PETSc did not use (misspelt, or
    without the ``fc_`` prefix); call after the solvers have been set up and run (:func:`run.run` after its
    first converged step, ``later``: options read only afterwards; :func:`main` at the end of a demo).
    Collective in effect: every rank has the same options and raises alike."""
    unused = unused_petsc_options(later)
    if unused:
        raise UsageError(f"PETSc option{'s' * (len(unused) > 1)} not used by any solver (misspelt, or without "
                         f"the fc_ prefix?): {', '.join(unused)}")


# Options prefix of the solvers (Solver's default)
_PREFIX = "fc_"


def check_petsc_values(options: Sequence[tuple[str, str]]) -> None:
    """Raise ``UsageError`` naming the first command-line PETSc option of the solvers' prefix (name without dash,
    value; ``""`` a flag) whose value cannot be used (:func:`~fenics_contact.solver.options.value_problem`: PETSc
    rejects it on its own, a number that is not finite, no value for an option that takes one), with the reason:
    before any work."""
    for name, value in options:
        if not name.startswith(_PREFIX):
            continue
        complaint = value_problem(name[len(_PREFIX):], value if value != "" else None)
        if complaint is not None:
            who = "" if name[len(_PREFIX):] in OWN_OPTIONS else "PETSc rejected "  # the solver's own: not PETSc's
            raise UsageError(f"{who}-{name} {value}".rstrip() + f": {complaint}")


def _petsc_message(exc: PETSc.Error) -> str:
    """One line for a PETSc error: the command-line options it names (by value or name) with PETSc's complaint;
    when it names none, every PETSc option of the command line, so that the one at fault is among them."""
    last = petsc_complaint(exc)
    words = " ".join(str(exc).splitlines()).split()
    bad = [f"-{k} {v}".rstrip() for k, v in _PETSC_OPTIONS if (v and v in words) or f"-{k}" in words]
    if bad:
        return f"PETSc rejected {', '.join(bad)}: {last}"
    given = ", ".join(f"-{k} {v}".rstrip() for k, v in _PETSC_OPTIONS)
    return f"PETSc error {exc.ierr}: {last}" + (f" (PETSc options given: {given})" if given else "")


def _where(exc: BaseException) -> str:
    """`` (in file:line, function)`` of the deepest frame of ``exc``'s traceback outside installed libraries
    (numpy's allocation is not news: the line of the package or of the script that asked for it is)."""
    frames = traceback.extract_tb(exc.__traceback__)
    ours = [f for f in frames if "fenics_contact" in f.filename
            or not any(p in f.filename for p in ("site-packages", "dist-packages", "/lib/python"))]
    ours = ours or frames
    if not ours:
        return ""
    f = ours[-1]
    start = f.filename.rfind("fenics_contact/")
    return f" (in {f.filename[max(start, 0):]}:{f.lineno}, {f.name})"


def error_line(exc: BaseException) -> str | None:
    """One line for the errors a user can cause (bad input, refused combination, failed solve, rejected PETSc
    value, a size the memory cannot hold, running out of memory); None for anything else (a bug: its traceback
    is shown)."""
    if isinstance(exc, PETSc.Error):
        return _petsc_message(exc)
    names = {c.__name__ for c in type(exc).__mro__}
    if isinstance(exc, ConvergenceError):
        spent = "" if exc.newton_iterations is None else f" ({exc.newton_iterations} Newton iterations spent)"
        if (exc.failure or {}).get("kind") == "out_of_memory":
            return f"out of memory: {exc}{spent}"
        return f"did not converge: {exc}{spent}"
    if isinstance(exc, MemoryError):
        _, phrase = available_memory()
        text = str(exc).splitlines()[0] if str(exc) else "Python could not allocate memory"
        return f"out of memory: {text}{_where(exc)}; {phrase}"
    if "SizeError" in names:  # a scene's size: its builder argument is the option --<argument>
        option = f"--{exc.parameter.replace('_', '-')}"
        return f"{option} {exc.value:g}: {exc.reason}; accepted: {option} {exc.accepted}"
    if isinstance(exc, ValueError) or {"UnsupportedCombination", "MeshingError"} & names:
        return str(exc).splitlines()[0] if str(exc) else type(exc).__name__
    return None


def _failed_check(result: object) -> str | None:
    """One line on a demo's own check (``result["check"]``, :func:`~fenics_contact.app.checks.reference_check`)
    that did not pass; None if it passed or the demo has none."""
    c = result.get("check") if isinstance(result, dict) else None
    if not isinstance(c, dict) or c.get("passed", True):
        return None
    if c.get("value") is None or c.get("rel_error") is None:
        return f"check failed: {c.get('figure')} has no value (the run gave none)"
    source = f" ({c['source']})" if c.get("source") else ""
    flag = f"; reference out of its range: {c['flag']}" if c.get("flag") else ""
    return (f"check failed: {c['figure']} = {c['value']:.6g}, reference {c['reference']:.6g}{source}, "
            f"rel. error {c['rel_error']:.2e} > tolerance {c['tolerance']:.0e}{flag}")


def _agree(comm: MPI.Comm, status: int, line: str | None, prog: str) -> int:
    """Every rank's status, agreed at the end of :func:`main` (the highest; its line printed once, by the lowest
    rank that has it). A rank that failed waits at most :data:`AGREE_TIMEOUT` s for the others: one still inside
    a collective of the demo never comes, and the job is aborted with this rank's line."""
    size = comm.size
    mine = status * size + (size - 1 - comm.rank) if status else 0
    send, got = np.array([mine], dtype=np.int64), np.zeros(1, dtype=np.int64)
    request = comm.Iallreduce(send, got, op=MPI.MAX)
    deadline = time.monotonic() + AGREE_TIMEOUT
    while not request.Test():
        if status and time.monotonic() > deadline:
            sys.stdout.flush()
            said = line or f"exit status {status}"
            print(f"{prog}: rank {comm.rank}: {said} (the other ranks did not finish: aborting)", file=sys.stderr,
                  flush=True)
            MPI.COMM_WORLD.Abort(status)
        time.sleep(0.005)
    agreed = int(got[0])
    status, first = agreed // size, size - 1 - agreed % size
    if status and comm.rank == first and line:
        sys.stdout.flush()
        print(f"{prog}: {line}", file=sys.stderr, flush=True)
    return status


def main(demo: Callable[[Sequence[str] | None], object], argv: Sequence[str] | None = None) -> None:
    """Run ``demo(argv)`` as a program, on every rank. Bad input, a refused combination, a failed solve, a PETSc
    value PETSc rejects, a size the memory cannot hold or running out of memory end in one line on rank 0
    (``<program>: error: ...``) and exit status :data:`EXIT_ERROR` (:data:`EXIT_USAGE` for a bad command line),
    without a Python traceback; so does a PETSc option PETSc never used (checked at the end). A demo that returns
    a ``check`` that did not pass (its outputs written) exits with :data:`EXIT_CHECK`, one line saying so.
    ``sys.exit(code)`` in the demo exits with ``code``, and SIGINT (``KeyboardInterrupt``) with
    :data:`EXIT_INTERRUPTED`, one line saying so. Any other exception is a bug: its traceback. Under ``mpirun``,
    every way a rank leaves ends the whole job within seconds (:func:`_agree`, ``MPI_Abort``) rather than leave
    the other ranks waiting in a collective."""
    prog = sys.argv[0].rsplit("/", 1)[-1] if sys.argv and sys.argv[0] else "demo"
    world = MPI.COMM_WORLD
    comm, interrupted = _duplicate(world)  # the agreement at the end must not match a collective a stuck rank is in
    status, line, left = 0, None, False
    try:
        if interrupted:
            raise KeyboardInterrupt
        result = demo(argv)
        check_petsc_options()
        failed = _failed_check(result)
        if failed is not None:
            status, line = EXIT_CHECK, failed
    except (SystemExit, KeyboardInterrupt) as exc:
        (status, line), left = _leaving(exc, prog), True
    except Exception as exc:  # noqa: BLE001 - only the kinds error_line knows are turned into one line
        line = error_line(exc)
        if line is None:
            if world.size == 1:
                raise
            sys.stdout.flush()
            traceback.print_exc()
            print(f"{prog}: rank {world.rank}: unexpected {type(exc).__name__}: aborting every rank", file=sys.stderr,
                  flush=True)
            world.Abort(EXIT_ERROR)
        try:  # a failed run may also have been given an option PETSc never read: say so too
            unused = unused_petsc_options() if not isinstance(exc, UsageError) else []
        except Exception:  # noqa: BLE001
            unused = []
        if unused:
            line += f"; PETSc options not used: {', '.join(unused)}"
        line = f"error: {line}"
        status = EXIT_USAGE if isinstance(exc, UsageError) else EXIT_ERROR
    try:
        status = _agree(comm, status, line, prog)
    except KeyboardInterrupt:  # a second SIGINT while waiting for the other ranks: leave at once
        if world.size > 1:
            world.Abort(EXIT_INTERRUPTED)
        status = EXIT_INTERRUPTED
    comm.Free()
    if status or left:  # sys.exit(0) in the demo (its --help) still leaves
        sys.exit(status)


def _duplicate(world: MPI.Comm) -> tuple[MPI.Comm, bool]:
    """``world.Dup()``, and whether SIGINT came meanwhile: held back until the duplicate is made on every rank (a
    ``KeyboardInterrupt`` raised as the collective returns would leave this rank without it). Collective."""
    if threading.current_thread() is not threading.main_thread():
        return world.Dup(), False
    came: list[int] = []
    before = signal.signal(signal.SIGINT, lambda signum, frame: came.append(signum))
    try:
        comm = world.Dup()
    finally:
        signal.signal(signal.SIGINT, before if before is not None else signal.SIG_DFL)
    return comm, bool(came)


def _leaving(exc: SystemExit | KeyboardInterrupt, prog: str) -> tuple[int, str | None]:
    """The exit status and line of a demo that called ``sys.exit`` or was interrupted (SIGINT)."""
    if isinstance(exc, KeyboardInterrupt):
        return EXIT_INTERRUPTED, "interrupted by SIGINT"
    code = exc.code
    if code is None or isinstance(code, bool) and not code:
        return 0, None
    if isinstance(code, int):
        return code, None  # the demo has said why
    text = str(code)  # sys.exit("message"): the message, status 1
    return EXIT_ERROR, text[len(prog) + 2:] if text.startswith(f"{prog}: ") else text
