"""What a compiled form depends on: its Constants and Functions, and their values (a form whose inputs keep their
values assembles to the same matrix)."""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from mpi4py import MPI

__all__ = ["form_inputs", "input_values", "same_everywhere"]


def form_inputs(form) -> tuple[list, list]:
    """The Constants and the Functions of ``form`` after expanding its derivatives."""
    from ufl.algorithms import expand_derivatives
    from ufl.algorithms.analysis import extract_coefficients, extract_constants

    form = expand_derivatives(form)
    return extract_constants(form), extract_coefficients(form)


def input_values(inputs: tuple[list, list], u: fem.Function) -> list[np.ndarray] | None:
    """Copies of the values of a form's ``inputs`` (:func:`form_inputs`: Constants, Functions); None if they include
    the displacement ``u`` itself (a form that changes with every iterate)."""
    constants, functions = inputs
    if any(f is u for f in functions):
        return None
    return [np.array(c.value, copy=True) for c in constants] + [f.x.array.copy() for f in functions]


def same_everywhere(comm: MPI.Comm, now: list | None, kept: list | None) -> bool:
    """True when the values ``now`` (:func:`input_values`) equal ``kept`` on every rank (a Function's values may
    differ on one rank only); False where either is None. Collective."""
    same = now is not None and kept is not None and all(np.array_equal(a, b) for a, b in zip(now, kept))
    return bool(comm.allreduce(int(same), op=MPI.MIN))
