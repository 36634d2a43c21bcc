"""What a converged state may not be: cells turned inside out (a failure of the solve), or a small-strain model
past its range (a warning of the run). Both are checked on the displacement alone, once per converged solve or
accepted step; their seconds go to ``timings["validity_s"]``."""
from __future__ import annotations

import logging
import time

from ..materials import SMALL_STRAIN
from ..problem import ContactProblem

__all__ = ["inverted_failure", "strain_warning"]

logger = logging.getLogger(__package__)


def inverted_failure(problem: ContactProblem, timings: dict) -> dict | None:
    """``{"kind": "inverted_elements", "min_jacobian", "inverted_cells", "message"}`` if the current displacement
    has ``det(I + grad u) <= 0`` in some cell (:meth:`ContactProblem.min_jacobian`), for any material (a
    small-strain solve converges to such a state without complaint), else None. Collective."""
    start = time.perf_counter()
    try:
        J = problem.min_jacobian()
        if J > 0.0:
            return None
        bad, cells = problem.inverted_cells()
        return {"kind": "inverted_elements", "min_jacobian": J, "inverted_cells": bad,
                "message": f"converged to a state with {bad} of {cells} cells inverted (det F <= 0, min {J:.3g}): "
                           "the displacement overlaps itself"}
    finally:
        timings["validity_s"] += time.perf_counter() - start


def strain_warning(problem: ContactProblem, step: int, load: float, warnings: list[str], timings: dict) -> None:
    """A small-strain model (``problem.material.linear``) past :data:`~fenics_contact.materials.SMALL_STRAIN` at
    the accepted step ``step`` (load ``load``): a line appended to ``warnings`` and logged (WARNING, rank 0),
    once per run (none if ``warnings`` has one already). Not a failure. Collective."""
    if not problem.material.linear or any(w.startswith("small-strain") for w in warnings):
        return
    start = time.perf_counter()
    strain = problem.max_strain()
    timings["validity_s"] += time.perf_counter() - start
    if strain > SMALL_STRAIN:
        text = (f"small-strain model past its range: strain {strain:.3g} (largest principal value of sym(grad u)) "
                f"> {SMALL_STRAIN:g} at step {step} (t = {load:.6g}); a finite-strain model (neohookean) holds there")
        warnings.append(text)
        if problem.comm.rank == 0:
            logger.warning(text)
