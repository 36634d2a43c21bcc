"""Mesh of the ``mindlin`` scene: a body with a circular bottom of radius ``R`` resting on a block, one dolfinx mesh,
no shared node, structured triangles graded toward the contact point. Regions by name (:class:`NamedTags`)."""
from __future__ import annotations

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI
from scipy.optimize import brentq

from ...domain import NamedTags
from .structured import facet_tags, grid_triangles, layer_fractions, two_bodies

__all__ = ["CELLS", "FACETS", "graded_axis", "disk_on_block", "WEDGE_CELLS", "WEDGE_FACETS", "block_on_incline"]

CELLS = {"lower": 1, "upper": 2}
FACETS = {"lower_bottom": 1, "lower_top": 2, "upper_bottom": 3, "upper_top": 4}


def graded_axis(L: float, w: float, h: float, n_coarse: int) -> np.ndarray:
    """Node coordinates on ``[-L, L]``: uniform of size about ``h`` on ``[-w, w]`` (an even number of intervals:
    0 is a node), then ``n_coarse`` intervals on each side growing geometrically from about ``h`` to ``L``."""
    for name, v in (("L", L), ("w", w), ("h", h)):
        if not (np.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")
    if not (w < L and h < w):
        raise ValueError(f"graded axis needs h < w < L, got h={h}, w={w}, L={L}")
    n_fine = 2 * max(1, int(round(w / h)))
    fine = np.linspace(-w, w, n_fine + 1)
    h = 2 * w / n_fine
    rest = L - w
    if rest <= n_coarse * h:  # no room to grow: uniform
        out = w + rest * np.arange(1, n_coarse + 1) / n_coarse
    else:
        k = brentq(lambda k: rest * np.expm1(k / n_coarse) / np.expm1(k) - h, 1e-9, 30.0)
        out = w + rest * np.expm1(k * np.arange(1, n_coarse + 1) / n_coarse) / np.expm1(k)
    return np.concatenate([-out[::-1], fine, out])


def disk_on_block(comm: MPI.Comm, R: float, L: float, H: float, D: float, h: float, w: float,
                  n_coarse: int = 20, ny: int = 24, lower_coarsening: float = 1.15,
                  overlap: float = 0.0) -> tuple[dmesh.Mesh, NamedTags, NamedTags]:
    """Lower block ``[-L, L] x [-D, 0]``; upper body over ``[-L, L]`` between the circle ``y = R - sqrt(R^2 - x^2)
    - overlap`` (the bottom of a disk of radius ``R`` centred at ``(0, R - overlap)``) and ``y = H``. Contact mesh
    size ``h`` on ``|x| <= w`` (the lower block's ``lower_coarsening`` times coarser: non-matching interfaces),
    graded beyond; ``ny`` layers per body, graded so that the first one at the interface is about ``h`` thick.
    Cells ``lower``, ``upper``; facets ``lower_bottom``, ``lower_top``, ``upper_bottom`` (the arc),
    ``upper_top``. Collective (the mesh is made on rank 0 and distributed)."""
    if not (0 < L < R and H > R - np.sqrt(R**2 - L**2) and D > 0):
        raise ValueError(f"disk_on_block needs 0 < L < R, H above the arc's ends and D > 0, got R={R}, L={L}, H={H}, "
                         f"D={D}")
    xs, cs = [], []
    offset = 0
    for b, hb in ((0, h * lower_coarsening), (1, h)):
        xa = graded_axis(L, w, hb, n_coarse)
        s = layer_fractions(D if b == 0 else H, hb, ny)  # 0 at the interface
        X, S = np.meshgrid(xa, s, indexing="ij")
        if b == 0:
            Y = -D * S
        else:
            f = R - np.sqrt(R**2 - X**2) - overlap
            Y = f + (H - f) * S
        xs.append(np.stack([X.ravel(), Y.ravel()], axis=1))
        cs.append(grid_triangles(np.arange(X.size).reshape(X.shape) + offset))
        offset += X.size
    # the upper body lies above its arc (>= -overlap), the block below 0
    msh, cell_tags, facets, fmid, ub = two_bodies(comm, np.concatenate(xs), np.concatenate(cs), "disk_on_block",
                                                  lambda mid: mid[:, 1] > 0.0, ("lower", "upper"), CELLS)
    tol = 1e-9 * R
    sides = np.abs(np.abs(fmid[:, 0]) - L) < tol
    values = np.zeros(len(facets), np.int32)
    values[(np.abs(fmid[:, 1] + D) < tol) & ~ub] = FACETS["lower_bottom"]
    values[(np.abs(fmid[:, 1]) < tol) & ~ub & ~sides] = FACETS["lower_top"]
    values[(fmid[:, 1] < 0.5 * H) & ub & ~sides] = FACETS["upper_bottom"]
    values[(np.abs(fmid[:, 1] - H) < tol) & ub] = FACETS["upper_top"]
    return msh, cell_tags, facet_tags(msh, facets, values, FACETS)


WEDGE_CELLS = {"wedge": 1, "block": 2}
WEDGE_FACETS = {"wedge_bottom": 1, "wedge_top": 2, "block_bottom": 3, "block_top": 4, "block_left": 5}


def block_on_incline(comm: MPI.Comm, alpha: float, L: float, D: float, b: float, h: float, n_wedge: tuple[int, int],
                     n_block: tuple[int, int], overlap: float = 0.0) -> tuple[dmesh.Mesh, NamedTags, NamedTags]:
    """The rectangle ``[-L, L] x [-D, 0]`` (the wedge's incline is its top) and the block ``[-b, b] x [-overlap,
    h - overlap]`` on it, both turned by ``alpha`` (radians) about the origin: the incline rises toward +x at the
    angle ``alpha``. Structured triangles ``n_wedge``, ``n_block`` = (nx, ny); no shared node. Cells ``wedge``,
    ``block``; facets ``wedge_bottom``, ``wedge_top``, ``block_bottom``, ``block_top``, ``block_left`` (named, in
    the turned frame). Collective."""
    if not (0 <= alpha < np.pi / 2 and 0 < b < L and D > 0 and h > 0):
        raise ValueError(f"block_on_incline needs 0 <= alpha < pi/2, 0 < b < L, D > 0, h > 0, got alpha={alpha}, "
                         f"L={L}, b={b}, D={D}, h={h}")
    xs, cs, offset = [], [], 0
    for (x0, x1, y0, y1), (nx, ny) in (((-L, L, -D, 0.0), n_wedge), ((-b, b, -overlap, h - overlap), n_block)):
        X, Y = np.meshgrid(np.linspace(x0, x1, nx + 1), np.linspace(y0, y1, ny + 1), indexing="ij")
        xs.append(np.stack([X.ravel(), Y.ravel()], axis=1))
        cs.append(grid_triangles(np.arange(X.size).reshape(X.shape) + offset))
        offset += X.size
    rot = np.array([[np.cos(alpha), -np.sin(alpha)], [np.sin(alpha), np.cos(alpha)]])
    # the block lies above the incline in the unturned frame
    msh, cell_tags, facets, fmid, fb = two_bodies(comm, np.concatenate(xs) @ rot.T, np.concatenate(cs),
                                                  "block_on_incline", lambda mid: (mid[:, :2] @ rot)[:, 1] > 0.0,
                                                  ("wedge", "block"), WEDGE_CELLS)
    fl = fmid[:, :2] @ rot
    tol = 1e-9 * L
    values = np.zeros(len(facets), np.int32)
    values[(np.abs(fl[:, 1] + D) < tol) & ~fb] = WEDGE_FACETS["wedge_bottom"]
    values[(np.abs(fl[:, 1]) < tol) & ~fb] = WEDGE_FACETS["wedge_top"]
    values[(np.abs(fl[:, 1] + overlap) < tol) & fb] = WEDGE_FACETS["block_bottom"]
    values[(np.abs(fl[:, 1] - h + overlap) < tol) & fb] = WEDGE_FACETS["block_top"]
    values[(np.abs(fl[:, 0] + b) < tol) & fb] = WEDGE_FACETS["block_left"]
    return msh, cell_tags, facet_tags(msh, facets, values, WEDGE_FACETS)
