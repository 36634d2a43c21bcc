"""Cross-section of a thick-walled tube (the ``tube`` scene): a structured polar triangle mesh of the annulus, or of
its half ``y >= 0``, symmetric about both axes."""
from __future__ import annotations

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...domain import NamedTags
from .structured import exterior_facets, facet_tags

__all__ = ["tube_section"]

FACETS = {"outer": 1, "inner": 2, "cut": 3}


def tube_section(comm: MPI.Comm, r_in: float, thickness: float, n_theta: int, n_r: int,
                 half: bool = False) -> tuple[dmesh.Mesh, None, NamedTags]:
    """The annulus ``r_in <= r <= r_in + thickness`` centred at the origin (``half``: its half ``y >= 0``).

    ``n_theta`` cells around the whole circle (a multiple of 4: nodes on both axes; the half has ``n_theta / 2``),
    ``n_r`` through the wall; each polar quadrilateral split into two triangles along the diagonal that makes the
    mesh symmetric about both axes (so that the half is exactly the full mesh's upper half). Facets: ``outer``,
    ``inner`` (the arcs), ``cut`` (the half's faces on ``y = 0``). Collective.

    Returns:
        ``(mesh, None, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    from ...compat import create_mesh

    for name, value, low in (("n_theta", n_theta, 4), ("n_r", n_r, 1)):
        if int(value) != value or value < low or (name == "n_theta" and value % 4):
            raise ValueError(f"{name} must be an integer >= {low}{' and a multiple of 4' if low == 4 else ''}, "
                             f"got {value!r}")
    if not (r_in > 0 and thickness > 0):
        raise ValueError(f"tube needs r_in > 0 and thickness > 0, got r_in={r_in!r}, thickness={thickness!r}")
    n_theta, n_r = int(n_theta), int(n_r)
    m = n_theta // 2 + 1 if half else n_theta  # angular node columns (the full circle closes on itself)
    theta = np.pi * np.arange(m) / (n_theta // 2) if half else -np.pi + 2 * np.pi * np.arange(m) / n_theta
    r = r_in + thickness * np.arange(n_r + 1) / n_r
    x = np.stack([np.outer(np.cos(theta), r).ravel(), np.outer(np.sin(theta), r).ravel()], axis=1)
    x[np.abs(x) < 1e-14 * (r_in + thickness)] = 0.0  # exact zeros on the axes
    idx = np.arange(m * (n_r + 1)).reshape(m, n_r + 1)
    cells = []
    for j in range(n_theta // 2 if half else n_theta):
        j1 = (j + 1) % m
        mid = theta[j] + np.pi / n_theta
        flip = np.sin(mid) * np.cos(mid) < 0  # mirrored diagonal in the quadrants of the other sign
        for i in range(n_r):
            a, b, c, d = idx[j, i], idx[j1, i], idx[j1, i + 1], idx[j, i + 1]
            cells += [[a, b, d], [b, c, d]] if flip else [[a, b, c], [a, c, d]]
    cells = np.asarray(cells, np.int64)
    if comm.rank != 0:
        x, cells = np.zeros((0, 2)), np.zeros((0, 3), np.int64)
    msh = create_mesh(comm, cells, x, "triangle")
    msh.name = "tube_half" if half else "tube"
    facets, mid = exterior_facets(msh)
    radius = np.hypot(mid[:, 0], mid[:, 1])
    on_cut = np.abs(mid[:, 1]) < 1e-9 * (r_in + thickness)  # the half's faces (the full mesh has none outside)
    values = np.where(on_cut, FACETS["cut"], np.where(radius > r_in + 0.5 * thickness, FACETS["outer"],
                                                      FACETS["inner"])).astype(np.int32)
    return msh, None, facet_tags(msh, facets, values, FACETS)
