"""What a compiled form depends on: its Constants and Functions, and their values (a form whose inputs keep their
values assembles to the same matrix)."""
from __future__ import annotations

import numpy as np
from dolfinx import fem

__all__ = ["form_inputs", "input_values"]


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
