"""Load paths: how a load, a Dirichlet value or an obstacle's motion follows the load parameter ``t``.

A path is None (``f(t) = t``), a callable ``f(t)``, or piecewise linear ``(t_k, f_k)`` (increasing ``t_k``; constant
beyond its ends).
"""
from __future__ import annotations

from typing import Callable, Sequence, Union

import numpy as np

__all__ = ["LoadPath", "check_path", "load_factor"]

# a load path: None (f(t) = t), a callable f(t), or piecewise linear (t_k, f_k)
LoadPath = Union[tuple[Sequence[float], Sequence[float]], Callable[[float], float], None]


def check_path(path: LoadPath, name: str = "path") -> None:
    """``ValueError`` (one line, naming ``name``) unless ``path`` is None, a callable or ``(t_k, f_k)`` with
    increasing ``t_k`` and as many values."""
    if path is None or callable(path):
        return
    try:
        tk, fk = (np.asarray(a, dtype=float) for a in path)
    except (TypeError, ValueError):
        tk = fk = None
    if tk is None or tk.ndim != 1 or tk.shape != fk.shape or tk.size == 0 or np.any(np.diff(tk) <= 0):
        raise ValueError(f"{name} must be a callable f(t) or (t_k, f_k) with increasing t_k and as many values, "
                         f"got {path!r}")


def load_factor(path: LoadPath, t: float) -> float:
    """The factor ``f(t)`` of a load path at load parameter ``t``: ``t`` for ``None``; ``path(t)`` for a
    callable; the piecewise-linear interpolation of ``path = (t_k, f_k)`` (constant beyond its ends)."""
    if path is None:
        return float(t)
    if callable(path):
        return float(path(t))
    return float(np.interp(t, *path))
