"""The solver driver: PETSc SNES, load stepping with cutback, augmentation loop, record.

Every Newton iterate logs its residual and the active set of the contact
points (closed, ``g > 0``); a failed solve is classified by
:func:`fenics_contact.failure.classify` (cycling, stagnation, divergence,
linear-solve failure / ill-conditioning) and recorded in the step's
``failure`` (and in ``summary.json``) instead of a bare "did not converge".

PETSc options: the defaults below are set under the options prefix only when
absent, so anything given on the command line (``-fc_snes_rtol 1e-12``) or
in ``options`` wins. The same options must be given on every rank.

Modules, one job each:

- :mod:`.options`: the PETSc defaults, the linear solvers, and the options in force under the prefix;
- :mod:`.linear`: the linear solver (field split, Schur complement, near-nullspace, preconditioner renewal,
  MUMPS workspace growth, time of one linear solve);
- :mod:`.newton`: the SNES, its callbacks and convergence test, the per-iterate log, the diagnosis of a failure;
- :mod:`.predictor`: the secant and tangent predictors;
- :mod:`.stepping`: :class:`Solver`, load stepping with cutback and rollback, and the augmentation loop;
- :mod:`.record`: :class:`StepRecord`, :class:`ConvergenceError`, the summary of a run;
- :mod:`.validity`: a converged state with inverted cells (a failure), a small-strain model past its range (a
  warning).
"""
import logging

from .linear import MUMPS_WORKSPACE_DEFAULT, MUMPS_WORKSPACE_MAX
from .newton import FORCING_MARGIN
from .options import DEFAULT_OPTIONS, EW_RTOL_MAX, INEXACT_NEWTON, LINEAR_SOLVERS, MULTIGRID, linear_solver_options
from .predictor import PREDICTOR_ETA, PREDICTOR_FD, PREDICTOR_RTOL, PREDICTOR_WORSE, PREDICTORS
from .record import ConvergenceError, StepRecord
from .stepping import Solver

__all__ = [
    "DEFAULT_OPTIONS", "PREDICTORS", "PREDICTOR_FD", "PREDICTOR_ETA", "PREDICTOR_RTOL", "PREDICTOR_WORSE",
    "LINEAR_SOLVERS", "INEXACT_NEWTON", "FORCING_MARGIN", "linear_solver_options",
    "ConvergenceError", "StepRecord", "Solver", "EW_RTOL_MAX", "MULTIGRID", "MUMPS_WORKSPACE_DEFAULT",
    "MUMPS_WORKSPACE_MAX"
]

logger = logging.getLogger(__name__)  # the solver's progress lines and warnings, from every module of the package
