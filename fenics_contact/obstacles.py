"""Rigid analytic obstacles as UFL of the current position ``x = X + u``.

An obstacle gives the normal gap ``g(x)`` (positive = penetration, see
:mod:`fenics_contact.laws`) and the unit normal ``n(x)`` pointing from the
obstacle into the body's admissible side. It may move rigidly with the load
parameter ``t``: its reference point is ``point + f(t) * motion``, ``f(t) = t`` or the piecewise-linear load
path ``path = (t_k, f_k)`` set on it (as :attr:`~fenics_contact.problem.Dirichlet.path`; constant beyond its ends).
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import ufl

from .paths import check_path

__all__ = ["Obstacle", "HalfPlane", "Ball", "Cylinder", "Sphere"]


class Obstacle:
    """Base class. ``bind(load)`` must be called before ``gap``/``normal``. ``shape``: the obstacle's value on
    the capability grid's ``obstacle`` axis (``aligned``: a half-plane with an axis-aligned normal,
    ``plane``: another half-plane, ``curved``).

    Args:
        point: a reference point of the obstacle (length).
        motion: the obstacle's displacement at ``t = 1`` (length; it moves by ``t * motion``); None: fixed.

    ``path``: None (it moves by ``t * motion``) or ``(t_k, f_k)``, increasing ``t_k``: it moves by
    ``f(t) * motion``, ``f`` interpolated linearly and constant beyond the ends (e.g. ``([0, 1, 2], [0, 1, 1])``:
    moves up to ``t = 1``, then holds). Set it before the obstacle's surface is built.
    """

    shape = "curved"
    path = None

    def __init__(self, point: Sequence[float], motion: Sequence[float] | None = None):
        self.point = np.asarray(point, dtype=float)
        self.motion = np.zeros_like(self.point) if motion is None else np.asarray(motion, dtype=float)
        if self.motion.shape != self.point.shape:
            raise ValueError(f"obstacle motion {self.motion} must have the dimension of its point {self.point}")
        self._load = None

    def bind(self, load: ufl.core.expr.Expr) -> None:
        """Attach the load parameter (a scalar ``Constant``) that moves the obstacle."""
        self._load = load

    def factor(self, t: float) -> float:
        """``f(t)``: the fraction of ``motion`` the obstacle has moved at load ``t``."""
        return float(t) if self.path is None else float(np.interp(t, *self._path()))

    def _path(self) -> tuple[np.ndarray, np.ndarray]:
        if callable(self.path):  # the gap is UFL of t: a piecewise-linear path is, a callable is not
            raise ValueError(f"obstacle path must be (t_k, f_k) with increasing t_k, got the callable {self.path!r}")
        check_path(self.path, "obstacle path")
        return tuple(np.asarray(a, dtype=float) for a in self.path)

    def _factor(self) -> ufl.core.expr.Expr:
        """``f(t)`` of the bound load parameter (UFL: the piecewise-linear path as nested conditionals)."""
        t = self._load
        if self.path is None:
            return t
        tk, fk = self._path()
        f = ufl.as_ufl(fk[0])
        for i in range(len(tk) - 1):
            segment = fk[i] + (fk[i + 1] - fk[i]) * (t - tk[i]) / (tk[i + 1] - tk[i])
            f = ufl.conditional(ufl.gt(t, tk[i]), segment, f)
        return ufl.conditional(ufl.gt(t, tk[-1]), fk[-1], f)

    def origin(self) -> ufl.core.expr.Expr:
        """Current reference point of the obstacle, ``point + f(t) * motion`` (UFL)."""
        if self._load is None:
            raise RuntimeError("obstacle is not bound to a load parameter: call bind(load) first")
        return ufl.as_vector(list(self.point)) + self._factor() * ufl.as_vector(list(self.motion))

    def gap(self, x: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        raise NotImplementedError

    def normal(self, x: ufl.core.expr.Expr) -> ufl.core.expr.Expr:
        raise NotImplementedError

    def describe(self) -> dict:
        out = {"type": type(self).__name__, "point": self.point.tolist(), "motion": self.motion.tolist()}
        return out if self.path is None else {**out, "path": [list(map(float, a)) for a in self.path]}


class HalfPlane(Obstacle):
    """Rigid half-space ``(x - p) . n < 0``; ``n`` (any orientation) points into the body.

    Args:
        point: a point on the boundary plane (length).
        normal: the plane's normal, pointing into the body (normalized here).
        motion: the obstacle's displacement at ``t = 1`` (length; it moves by ``t * motion``); None: fixed.
    """

    def __init__(self, point, normal, motion=None):
        super().__init__(point, motion)
        n = np.asarray(normal, dtype=float)
        if n.shape != self.point.shape or not np.linalg.norm(n) > 0:
            raise ValueError(f"half-plane normal {normal} must be a nonzero vector of dimension {self.point.size}")
        self.n = n / np.linalg.norm(n)

    def gap(self, x):
        return -ufl.dot(x - self.origin(), ufl.as_vector(list(self.n)))

    def normal(self, x):
        return ufl.as_vector(list(self.n))

    @property
    def shape(self) -> str:
        """``"aligned"`` when the normal is a coordinate axis, else ``"plane"``."""
        return "aligned" if np.count_nonzero(self.n) == 1 else "plane"

    def describe(self):
        return {**super().describe(), "normal": self.n.tolist()}


class Ball(Obstacle):
    """Rigid disk (2D), cylinder with an axis (3D) or sphere (3D) of radius ``radius``; on an axisymmetric body
    (the meridian section ``(r, z)``) the 2D disk with its center on the axis ``(0, z)`` is a sphere.

    ``body_outside=True``: the body lies outside the obstacle (a pin, a
    punch); ``False``: the body lies inside a rigid cavity.

    Args:
        center: the centre (a point on the axis for a cylinder), length.
        radius: the radius (length), > 0.
        motion: the obstacle's displacement at ``t = 1`` (length; it moves by ``t * motion``); None: fixed.
        axis: the cylinder's axis (3D cylinder only; None: a disk or a sphere).
        body_outside: True if the body lies outside the obstacle (a pin, a punch), False inside a rigid cavity.
    """

    def __init__(self, center, radius: float, motion=None, axis=None, body_outside: bool = True):
        super().__init__(center, motion)
        if not float(radius) > 0:
            raise ValueError(f"obstacle radius must be > 0, got {radius!r}")
        self.radius = float(radius)
        self.axis = None if axis is None else np.asarray(axis, float) / np.linalg.norm(axis)
        self.sign = 1.0 if body_outside else -1.0

    def _radial(self, x):
        d = x - self.origin()
        if self.axis is not None:
            a = ufl.as_vector(list(self.axis))
            d = d - ufl.dot(d, a) * a
        return d

    def gap(self, x):
        return self.sign * (self.radius - ufl.sqrt(ufl.dot(self._radial(x), self._radial(x))))

    def normal(self, x):
        d = self._radial(x)
        return self.sign * d / ufl.sqrt(ufl.dot(d, d))

    def describe(self):
        return {**super().describe(), "radius": self.radius, "body_outside": self.sign > 0,
                "axis": None if self.axis is None else self.axis.tolist()}


class Cylinder(Ball):
    """A rigid disk (2D) or, in 3D, a cylinder about ``axis`` (required), of radius ``radius``.

    Args:
        center: the centre (a point on the axis for a cylinder), length.
        radius: the radius (length), > 0.
        motion: the obstacle's displacement at ``t = 1`` (length; it moves by ``t * motion``); None: fixed.
        axis: the axis (3D, required; 2D: None).
        body_outside: True if the body lies outside the obstacle (a pin, a punch), False inside a rigid cavity.
    """

    def __init__(self, center, radius: float, motion=None, axis=None, body_outside: bool = True):
        if len(center) == 3 and axis is None:
            raise ValueError("a 3D cylinder obstacle needs its axis")
        super().__init__(center, radius, motion, axis, body_outside)


class Sphere(Ball):
    """A rigid sphere (3D) of radius ``radius``. In an axisymmetric model (the meridian section ``(r, z)``) a sphere
    is a :class:`Ball` with its center on the axis, ``(0, z)``.

    Args:
        center: the centre (a point on the axis for a cylinder), length.
        radius: the radius (length), > 0.
        motion: the obstacle's displacement at ``t = 1`` (length; it moves by ``t * motion``); None: fixed.
        body_outside: True if the body lies outside the obstacle (a pin, a punch), False inside a rigid cavity.
    """

    def __init__(self, center, radius: float, motion=None, body_outside: bool = True):
        if len(center) != 3:
            raise ValueError(f"a sphere obstacle is 3D: its center needs 3 coordinates, got {len(center)}; in 2D use "
                             "fc.Ball(center, radius): a disk in plane strain, and a sphere in an axisymmetric "
                             "model (material plane='axisymmetric', the center on the axis, (0, z))")
        super().__init__(center, radius, motion, None, body_outside)
