"""Quarter ring (structured polar mesh) for the ring scene."""
from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from mpi4py import MPI

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

    from ...domain import NamedTags

from .rectangle import rectangle, tag_boundary

__all__ = ["ring_quarter"]


def ring_quarter(comm: MPI.Comm, R_out: float, R_in: float, n_theta: int, n_r: int,
                 quadrilateral: bool = True) -> tuple[Mesh, None, NamedTags]:
    """Lower-right quarter (x >= 0, y <= R_out) of the ring R_in <= r <= R_out centred at (0, R_out).

    Structured polar mesh: ``n_theta`` cells along the quarter circle (equal angles), ``n_r``
    through the thickness; quadrilaterals (default) or triangles. The ring touches y = 0 at (0, 0).
    Facets: ``outer``, ``inner`` (arcs), ``axis`` (x = 0), ``mid`` (y = R_out).

    Returns:
        ``(mesh, None, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    for name, value in (("n_theta", n_theta), ("n_r", n_r)):
        if int(value) != value or value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    if not (0 < R_in < R_out):
        raise ValueError(f"ring radii need 0 < R_in < R_out, got R_in={R_in!r}, R_out={R_out!r}")
    msh, _, _ = rectangle(comm, 1.0, 1.0, n_theta, n_r, quadrilateral)
    x = msh.geometry.x
    theta, r = -0.5 * np.pi * (1.0 - x[:, 0]), R_in + (R_out - R_in) * x[:, 1]
    x[:, 0], x[:, 1] = r * np.cos(theta), R_out + r * np.sin(theta)
    x[np.abs(x[:, 0]) < 1e-12 * R_out, 0] = 0.0  # exact zeros on the axis
    tol = 1e-8 * R_out
    radius = lambda p: np.hypot(p[0], p[1] - R_out)  # noqa: E731
    facet_tags = tag_boundary(msh, (("outer", lambda p: np.abs(radius(p) - R_out) < tol),
                                    ("inner", lambda p: np.abs(radius(p) - R_in) < tol),
                                    ("axis", lambda p: np.abs(p[0]) < tol),
                                    ("mid", lambda p: np.abs(p[1] - R_out) < tol)))
    msh.name = "ring_quarter"
    return msh, None, facet_tags
