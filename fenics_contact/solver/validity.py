"""What a converged state may not be: cells turned inside out (a failure of the solve), a small-strain model past
its range, or a contact surface's model past its (small sliding off its facets): warnings of the run. Checked once
per converged solve or accepted step; their seconds go to ``timings["validity_s"]``."""
from __future__ import annotations

import logging
import time

import numpy as np
from mpi4py import MPI

from ..materials import SMALL_STRAIN
from ..models import locking_warning
from ..problem import ContactProblem

__all__ = ["inverted_failure", "max_strain", "range_warnings", "strain_warning"]

logger = logging.getLogger(__package__)


def max_strain(problem: ContactProblem) -> float:
    """Largest absolute principal value of the small strain ``sym(grad u)`` of ``problem`` at its current
    displacement over every cell's vertices (:meth:`ContactProblem.vertex_kinematics`), over all ranks: how far a
    small-strain model is from its premise (strains, and rotations, much below 1). Collective."""
    values = problem.vertex_kinematics()[1]
    n = values.shape[-1]
    d = int(round((np.sqrt(8 * n + 1) - 1) / 2))  # n = d (d + 1) / 2 components
    pairs = [(i, j) for i in range(d) for j in range(i, d)]
    values = values.reshape(-1, n)
    if not len(values):
        return problem.comm.allreduce(0.0, op=MPI.MAX)
    if d == 2:  # closed form: the principal values are the mean of the diagonal plus or minus Mohr's radius
        a, b, c = values.T
        local = float(np.max(np.abs(a + c) / 2 + np.hypot((a - c) / 2, b)))
        return problem.comm.allreduce(local, op=MPI.MAX)
    # The spectral norm is at least the Frobenius norm / sqrt(d) and at most the Frobenius norm: only the points
    # whose Frobenius norm reaches the largest one / sqrt(d) can hold the largest principal value.
    weights = np.array([1.0 if i == j else 2.0 for i, j in pairs])
    frobenius = np.sqrt((values * values) @ weights)
    candidates = values[frobenius >= frobenius.max() / np.sqrt(d)]
    tensor = np.zeros((len(candidates), d, d))
    for k, (i, j) in enumerate(pairs):
        tensor[:, i, j] = tensor[:, j, i] = candidates[:, k]
    return problem.comm.allreduce(float(np.abs(np.linalg.eigvalsh(tensor)).max()), op=MPI.MAX)


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
    strain = max_strain(problem)
    timings["validity_s"] += time.perf_counter() - start
    if strain > SMALL_STRAIN:
        # nearly incompressible: the displacement-only neohookean locks as the linear model does
        model = "neohookean-mixed" if locking_warning(problem.material, 1) else "neohookean"
        text = (f"small-strain model past its range: strain {strain:.3g} (largest principal value of sym(grad u)) "
                f"> {SMALL_STRAIN:g} at step {step} (t = {load:.6g}); a finite-strain model ({model}) holds there")
        warnings.append(text)
        if problem.comm.rank == 0:
            logger.warning(text)


def range_warnings(problem: ContactProblem, step: int, load: float, warnings: list[str], timings: dict) -> None:
    """Each contact surface's model past its range at the accepted step ``step`` (load ``load``)
    (:meth:`~fenics_contact.surface.Surface.range_warning`): a line appended to ``warnings`` and logged (WARNING,
    rank 0), once per surface and kind per run. Not a failure. Collective."""
    start = time.perf_counter()
    found = [(c.name, c.range_warning()) for c in problem.contacts]
    timings["validity_s"] += time.perf_counter() - start
    for name, text in found:
        if text is None:
            continue
        kind = f"{name}: {text.split(':')[0]}"
        if any(w.startswith(kind) for w in warnings):
            continue
        line = f"{name}: {text} at step {step} (t = {load:.6g})"
        warnings.append(line)
        if problem.comm.rank == 0:
            logger.warning(line)
