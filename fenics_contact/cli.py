"""Command-line options shared by the demos (and the benchmarks): method, parameters, output.

Arguments that argparse does not know are handed to PETSc's options
database, so ``-fc_snes_monitor`` or ``-fc_snes_linesearch_type basic``
work on any demo (``fc_`` is the solver's options prefix).
"""
from __future__ import annotations

import argparse
import logging
import sys
from typing import Sequence

from petsc4py import PETSc

from .contact import QUADRATURES
from .laws import METHODS, ContactLaw, make_law
from .solver import LINEAR_SOLVERS

__all__ = ["parser", "parse", "check", "one_line_errors", "has_friction", "law_from_args", "method_parameters",
           "solver_options"]


def parser(description: str, default_K: float, quadratures: Sequence[str] = QUADRATURES) -> argparse.ArgumentParser:
    """The shared options; ``quadratures``: the accepted ``--quadrature`` values (two-body scenes add ``segment``)."""
    p = argparse.ArgumentParser(description=description, epilog="Other -options go to PETSc (prefix fc_).",
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--method", choices=list(METHODS), default="cross", help="contact formulation")
    p.add_argument("--K", type=float, default=default_K,
                   help="penalty K (penalty, auglag), stiffness K_hat at g = 0 (cross) or complementarity c (lagrange)")
    p.add_argument("--F-hat", type=float, default=0.0, help="cross: target pressure at g = 0")
    p.add_argument("--a", type=float, default=0.0, help="cross: shape parameter in [0, 1)")
    p.add_argument("--tau", type=float, default=1.0, help="cross: K_hat <- tau K_hat per augmentation")
    p.add_argument("--augment", type=int, default=None,
                   help="max augmentations per load step (default: 0 for penalty, 10 otherwise)")
    p.add_argument("--augment-tol", type=float, default=1e-12, help="stop when ||g_new - g_old|| <= this")
    p.add_argument("--c-n", type=float, default=None, help="compliance: c_n in F = c_n <g>^m_n (default: --K)")
    p.add_argument("--m-n", type=float, default=1.0, help="compliance: exponent m_n >= 1")
    p.add_argument("--mu", type=float, default=0.0,
                   help="Coulomb friction coefficient (>= 0; 0: frictionless; exact with method coulomb)")
    p.add_argument("--c-t", type=float, default=None,
                   help="friction bound c_t <g>^m_t instead of mu F(g) (normal compliance friction)")
    p.add_argument("--m-t", type=float, default=None, help="exponent m_t >= 1 of the bound (default: m_n)")
    p.add_argument("--omega-t", type=float, default=None, help="tangential penalty of stick (default: --K)")
    p.add_argument("--quadrature", choices=list(quadratures), default="nodal", help="contact quadrature")
    p.add_argument("--gamma0", type=float, default=10.0, help="nitsche: gamma = gamma0 E / h (dimensionless)")
    p.add_argument("--solver", choices=list(LINEAR_SOLVERS), default="direct",
                   help="linear solver: direct (MUMPS LU) or iterative (GMRES + GAMG, rigid-body modes; 3D)")
    p.add_argument("--out", default=None, help="output directory (default: results/<scene>)")
    p.add_argument("--no-pictures", action="store_true", help="skip the PNG pictures")
    p.add_argument("--no-xdmf", action="store_true", help="no XDMF field output (benchmarks: solver time alone)")
    p.add_argument("--quiet", action="store_true", help="no progress lines")
    return p


def parse(p: argparse.ArgumentParser, argv: Sequence[str] | None = None) -> argparse.Namespace:
    """Parse our options; insert the rest (which must start with '-') into PETSc's options."""
    # UFL warns about every custom quadrature rule; the nodal rule is one on purpose.
    # (The compiler lines on a form's first JIT come from cffi, hard-coded verbose.)
    logging.getLogger("UFL").setLevel(logging.ERROR)
    one_line_errors()
    args, rest = p.parse_known_args(sys.argv[1:] if argv is None else argv)
    stray = [r for r in rest if not r.startswith("-") and not _is_value(r)]
    if stray:
        p.error(f"unrecognised arguments: {' '.join(stray)}")
    if rest:
        PETSc.Options().insertString(" ".join(rest))
    if args.augment is None:
        args.augment = 0 if args.method in ("penalty", "vi", "compliance", "coulomb", "lagrange",
                                                "penalty_multiplier", "nitsche") else 10
    if args.c_n is None:
        args.c_n = args.K
    if args.omega_t is None:
        args.omega_t = args.K
    return args


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


def check(args: argparse.Namespace, **axes) -> None:
    """Check the demo's options against the capability matrix before any work: method, quadrature, linear
    solver, friction and passes from ``args``, the scene's own axes (``kind``, ``dim``, ``degree``, ``model``)
    as keywords. Raises :class:`~fenics_contact.capabilities.UnsupportedCombination`."""
    from .capabilities import check as check_combination

    combo = {"method": args.method, "quadrature": args.quadrature, "solver": getattr(args, "solver", None),
             "friction": has_friction(args) or (args.method == "coulomb" and args.mu > 0),
             "passes": getattr(args, "passes", None)}
    check_combination(**{**combo, **axes})


def has_friction(args: argparse.Namespace) -> bool:
    """Friction is on when ``--mu`` is not 0 or ``--c-t`` is given (a negative mu is an error, not off)."""
    return args.mu != 0.0 or args.c_t is not None


def _is_value(s: str) -> bool:
    try:
        float(s)
        return True
    except ValueError:
        return s.isidentifier()


def law_from_args(args: argparse.Namespace) -> ContactLaw:
    """The contact law named by ``--method`` with its parameters, with friction if asked for."""
    if args.method == "cross":
        law = make_law("cross", K_hat=args.K, F_hat=args.F_hat, a=args.a, tau=args.tau)
    elif args.method == "vi":
        law = make_law("vi")
    elif args.method == "compliance":
        law = make_law("compliance", c_n=args.c_n, m_n=args.m_n)
    elif args.method == "coulomb":
        return make_law("coulomb", mu=args.mu)  # exact Coulomb: mu is the law's own parameter
    elif args.method == "lagrange":
        law = make_law("lagrange", c=args.K)
    elif args.method == "nitsche":
        law = make_law("nitsche", gamma0=args.gamma0)
    else:
        law = make_law(args.method, K=args.K)
    if not has_friction(args):
        return law
    if args.method in ("vi", "lagrange", "penalty_multiplier", "nitsche"):
        raise ValueError(f"method {args.method!r} has no friction: use --mu 0 (or another method)")
    if args.c_t is not None and args.mu != 0.0:
        raise ValueError(f"give either --mu ({args.mu}) or --c-t ({args.c_t}), not both")
    from .friction import Friction

    if args.c_t is not None:
        return Friction(law, c_t=args.c_t, m_t=args.m_t, omega_t=args.omega_t)
    return Friction(law, mu=args.mu, omega_t=args.omega_t)


def method_parameters(args: argparse.Namespace) -> dict:
    keys = {"penalty": ["K"], "auglag": ["K"], "cross": ["K", "F_hat", "a", "tau"], "vi": [],
            "compliance": ["c_n", "m_n"], "coulomb": ["mu"], "lagrange": ["K"],
            "penalty_multiplier": ["K"], "nitsche": ["gamma0"]}[args.method]
    if has_friction(args) and args.method != "coulomb":
        keys = keys + (["c_t", "m_t"] if args.c_t is not None else ["mu"]) + ["omega_t"]
    return {**{k: getattr(args, k) for k in keys}, "augment": args.augment, "augment_tol": args.augment_tol,
            "quadrature": args.quadrature, "solver": getattr(args, "solver", "direct")}


def solver_options(args: argparse.Namespace) -> dict:
    """PETSc options (prefix ``fc_``) of ``--solver``; options on the command line still win."""
    return dict(LINEAR_SOLVERS[getattr(args, "solver", "direct")])
