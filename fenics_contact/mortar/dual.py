"""Forward-mode dual numbers, vectorised: ``n`` values at once, each with derivatives with respect to ``nd``
inputs (:class:`Dual`). A law's ``force`` formula evaluated with :data:`DUAL_OPS` gives the force and its
derivatives, so the segment element's tangent is the exact derivative of its residual, without finite
differences.
"""
from __future__ import annotations

import types

import numpy as np

__all__ = ["Dual", "dual_max", "dual_min", "dual_exp", "dual_sqrt", "DUAL_OPS", "dot", "cross"]


class Dual:
    """``v + d . eps``: values ``v`` (n,) and derivatives ``d`` (n, nd) with respect to ``nd`` inputs."""

    __array_ufunc__ = None  # numpy arrays on the left defer to Dual's reflected operators

    def __init__(self, v, d):
        self.v, self.d = np.asarray(v, float), np.asarray(d, float)

    @staticmethod
    def seed(v: np.ndarray, k: int, nd: int) -> Dual:
        """The input number ``k`` of ``nd``: values ``v``, derivative 1 with respect to itself."""
        d = np.zeros((len(v), nd))
        d[:, k] = 1.0
        return Dual(v, d)

    def _parts(self, o):
        if isinstance(o, Dual):
            return o.v, o.d
        o = np.asarray(o, float)
        return o, np.zeros((1, self.d.shape[1]))

    def __add__(self, o):
        v, d = self._parts(o)
        return Dual(self.v + v, self.d + d)

    __radd__ = __add__

    def __sub__(self, o):
        v, d = self._parts(o)
        return Dual(self.v - v, self.d - d)

    def __rsub__(self, o):
        v, d = self._parts(o)
        return Dual(v - self.v, d - self.d)

    def __neg__(self):
        return Dual(-self.v, -self.d)

    def __mul__(self, o):
        v, d = self._parts(o)
        return Dual(self.v * v, self.d * _col(v) + _col(self.v) * d)

    __rmul__ = __mul__

    def __truediv__(self, o):
        v, d = self._parts(o)
        return Dual(self.v / v, (self.d * _col(v) - _col(self.v) * d) / _col(v * v))

    def __rtruediv__(self, o):
        v, d = self._parts(o)
        return Dual(v / self.v, (d * _col(self.v) - _col(v) * self.d) / _col(self.v * self.v))

    def __pow__(self, p: float):
        return Dual(self.v ** p, _col(p * self.v ** (p - 1.0)) * self.d)


def _col(a):
    a = np.asarray(a, float)
    return a[:, None] if a.ndim == 1 else a


def _value(a):
    return a.v if isinstance(a, Dual) else np.asarray(a, float)


def _select(mask, a, b, n: int, nd: int) -> Dual:
    """``a`` where ``mask`` else ``b`` (Dual or numbers)."""
    av, ad = (a.v, a.d) if isinstance(a, Dual) else (np.broadcast_to(np.asarray(a, float), (n,)), np.zeros((n, nd)))
    bv, bd = (b.v, b.d) if isinstance(b, Dual) else (np.broadcast_to(np.asarray(b, float), (n,)), np.zeros((n, nd)))
    mask = np.broadcast_to(mask, (n,))
    return Dual(np.where(mask, av, bv), np.where(mask[:, None], ad, bd))


def _shape(*xs) -> tuple[int, int]:
    for x in xs:
        if isinstance(x, Dual):
            return x.d.shape
    raise TypeError("dual ops need at least one Dual argument")


def dual_max(a, b):
    """Elementwise maximum (Duals or numbers); the derivative of the larger argument."""
    if not isinstance(a, Dual) and not isinstance(b, Dual):
        return np.maximum(a, b)
    return _select(_value(a) > _value(b), a, b, *_shape(a, b))


def dual_min(a, b):
    """Elementwise minimum (Duals or numbers); the derivative of the smaller argument."""
    if not isinstance(a, Dual) and not isinstance(b, Dual):
        return np.minimum(a, b)
    return _select(_value(a) < _value(b), a, b, *_shape(a, b))


def dual_exp(a):
    """``exp(a)`` (a Dual or numbers)."""
    if not isinstance(a, Dual):
        return np.exp(a)
    e = np.exp(a.v)
    return Dual(e, e[:, None] * a.d)


def dual_sqrt(a: Dual) -> Dual:
    """``sqrt(a)`` of a Dual with positive values."""
    s = np.sqrt(a.v)
    return Dual(s, a.d / (2.0 * s[:, None]))


#: The law operator namespace (:mod:`laws`) for dual numbers: a law's ``force`` gives force and tangent.
DUAL_OPS = types.SimpleNamespace(exp=dual_exp, max=dual_max, min=dual_min)


def dot(a, b):
    """``a . b`` of 3-vectors given as lists of components (numbers, arrays or Duals)."""
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def cross(a, b):
    """``a x b`` of 3-vectors given as lists of components (numbers, arrays or Duals)."""
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
