"""Mesh of the ``ironing`` scene: a punch with a flat, round-cornered face on a long block, one dolfinx mesh, no
shared node, structured triangles. Regions by name (:class:`NamedTags`)."""
from __future__ import annotations

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...domain import NamedTags
from .structured import facet_tags, grid, layer_fractions, two_bodies

__all__ = ["CELLS", "FACETS", "punch_profile", "punch_on_block"]

CELLS = {"block": 1, "punch": 2}
FACETS = {"block_bottom": 1, "block_top": 2, "punch_face": 3, "punch_top": 4}


def punch_profile(a: float, r: float, theta: float, h_flat: float, h_arc: float) -> np.ndarray:
    """Points ``(x, y)`` of the punch's face, left to right: the flat ``|x| <= a`` at ``y = 0`` (intervals of about
    ``h_flat``), then on each side a circular fillet of radius ``r`` (centre ``(+-a, r)``) turning up to the angle
    ``theta`` (radians from the vertical; intervals of about ``h_arc`` along the arc)."""
    n_flat = max(2, int(round(2 * a / h_flat)))
    n_arc = max(2, int(round(r * theta / h_arc)))
    flat = np.linspace(-a, a, n_flat + 1)
    phi = np.linspace(0.0, theta, n_arc + 1)[1:]
    xr, yr = a + r * np.sin(phi), r * (1 - np.cos(phi))
    x = np.concatenate([-xr[::-1], flat, xr])
    y = np.concatenate([yr[::-1], np.zeros_like(flat), yr])
    return np.stack([x, y], axis=1)


def punch_on_block(comm: MPI.Comm, x0: float, x1: float, H: float, h: float, ny: int, a: float, r: float,
                   theta: float, height: float, h_flat: float, h_arc: float, ny_punch: int, centre: float = 0.0,
                   overlap: float = 0.0) -> tuple[dmesh.Mesh, NamedTags, NamedTags]:
    """Block ``[x0, x1] x [-H, 0]`` (``h`` wide columns, ``ny`` layers graded so that the top one is about ``h``
    thick); punch of :func:`punch_profile` (``a``, ``r``, ``theta``, ``h_flat``, ``h_arc``) centred at ``x =
    centre``, its flat face at ``y = -overlap``, its top at ``y = height`` (``ny_punch`` layers graded toward the
    face). Cells ``block``, ``punch``; facets ``block_bottom``, ``block_top``, ``punch_face`` (the flat and the two
    fillets), ``punch_top``. Collective (made on rank 0 and distributed)."""
    if not (x0 < centre - a - r < centre + a + r < x1 and H > 0 and 0 < theta <= np.pi / 2
            and height > r * (1 - np.cos(theta)) and min(h, h_flat, h_arc) > 0 and ny >= 1 and ny_punch >= 1):
        raise ValueError(f"punch_on_block needs the punch within the block, H > 0, 0 < theta <= pi/2, the top above "
                         f"the fillets and sizes > 0, got x0={x0}, x1={x1}, centre={centre}, a={a}, r={r}, H={H}, "
                         f"theta={theta}, height={height}")
    nx = max(2, int(round((x1 - x0) / h)))
    xb = np.linspace(x0, x1, nx + 1)
    s = layer_fractions(H, h, ny)  # 0 at the block's top
    xs_block, cells_block = grid(np.stack([xb, np.zeros_like(xb)], 1), np.stack([xb, np.full_like(xb, -H)], 1), s, 0)
    face = punch_profile(a, r, theta, h_flat, h_arc) + np.array([centre, -overlap])
    top = np.stack([face[:, 0], np.full(len(face), height - overlap)], 1)
    xs_punch, cells_punch = grid(face, top, layer_fractions(height, min(h_flat, h_arc), ny_punch), len(xs_block))
    # the punch lies above its face (y >= -overlap), the block below 0
    msh, cell_tags, facets, fmid, pf = two_bodies(comm, np.concatenate([xs_block, xs_punch]),
                                                  np.concatenate([cells_block, cells_punch]), "punch_on_block",
                                                  lambda mid: mid[:, 1] > -overlap, ("block", "punch"), CELLS)
    tol = 1e-9 * H
    wall = np.abs(np.abs(fmid[:, 0] - centre) - (a + r * np.sin(theta))) < tol
    ends = (np.abs(fmid[:, 0] - x0) < tol) | (np.abs(fmid[:, 0] - x1) < tol)
    values = np.zeros(len(facets), np.int32)
    values[(np.abs(fmid[:, 1] + H) < tol) & ~pf] = FACETS["block_bottom"]
    values[(np.abs(fmid[:, 1]) < tol) & ~pf & ~ends] = FACETS["block_top"]
    on_top = np.abs(fmid[:, 1] - (height - overlap)) < tol
    values[pf & on_top] = FACETS["punch_top"]
    values[pf & ~on_top & ~wall] = FACETS["punch_face"]
    return msh, cell_tags, facet_tags(msh, facets, values, FACETS)
