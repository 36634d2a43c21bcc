"""A C-shaped (horseshoe) block extruded in z, tetrahedra, mirror-symmetric about its mid-plane ``y = height / 2``:
two arms joined by a spine, a slot between the arms (3D self-contact); or its half ``y <= height / 2``."""
from __future__ import annotations

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...domain import NamedTags
from .structured import exterior_facets, facet_tags, kuhn_tetrahedra

__all__ = ["FACETS", "horseshoe"]

FACETS = {"outer_low": 1, "outer_high": 2, "inner_low": 3, "inner_high": 4, "back": 5, "bottom": 6, "cut": 7}


def horseshoe(comm: MPI.Comm, length: float, height: float, depth: float, spine: float, arm: float,
              n: tuple[int, int, int], half: bool = False) -> tuple[dmesh.Mesh, None, NamedTags]:
    """The block ``[0, length] x [0, height] x [0, depth]`` without the slot ``x > spine``, ``arm < y < height -
    arm`` (``half``: its half ``y <= height / 2``). ``n = (nx, ny, nz)``: cells along x, across one arm, along z
    (the slot's half-width is one cell; nx rounded so that x = spine is a grid line). The half mesh is the lower
    half of the full one node for node (the full mesh is the half and its mirror image).

    Facets: ``outer_low`` (y = 0), ``outer_high`` (y = height), ``inner_low``, ``inner_high`` (the arms' faces
    across the slot), ``back`` (x = 0), ``bottom`` (z = 0), ``cut`` (the half's faces on y = height / 2). Collective.

    Returns:
        ``(mesh, None, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    from ...compat import create_mesh

    if not (0 < spine < length and 0 < arm < height / 2 and depth > 0):
        raise ValueError(f"horseshoe needs 0 < spine < length, 0 < arm < height / 2, depth > 0, got length={length!r},"
                         f" height={height!r}, depth={depth!r}, spine={spine!r}, arm={arm!r}")
    if len(n) != 3 or min(n) < 1:
        raise ValueError(f"n must be 3 cell counts >= 1, got {n!r}")
    nx, ny, nz = (int(v) for v in n)
    n_spine = max(1, round(nx * spine / length))
    xs = np.concatenate([np.linspace(0, spine, n_spine + 1), np.linspace(spine, length, nx - n_spine + 1)[1:]])
    ys = np.concatenate([np.linspace(0, arm, ny + 1), [height / 2]])
    zs = np.linspace(0, depth, nz + 1)
    grid = np.meshgrid(xs, ys, zs, indexing="ij")
    x = np.stack([g.ravel() for g in grid], axis=1)
    idx = np.arange(x.shape[0]).reshape(grid[0].shape)
    tets = kuhn_tetrahedra(idx)
    keep = np.ones(tets.shape[:3], bool)
    keep[n_spine:, ny:, :] = False  # the slot
    cells = tets[keep].reshape(-1, 4)
    if not half:  # the mirror image, sharing the nodes on the mid-plane
        on_plane = np.abs(x[:, 1] - height / 2) < 1e-12 * height
        mirror = np.where(on_plane, np.arange(len(x)), len(x) + np.cumsum(~on_plane) - 1)
        x = np.concatenate([x, x[~on_plane] * [1, -1, 1] + [0, height, 0]])
        cells = np.concatenate([cells, mirror[cells]])
    used = np.unique(cells)
    renumber = np.full(len(x), -1)
    renumber[used] = np.arange(len(used))
    x, cells = x[used], renumber[cells]
    if comm.rank != 0:
        x, cells = np.zeros((0, 3)), np.zeros((0, 4), np.int64)
    msh = create_mesh(comm, cells, x, "tetrahedron")
    msh.name = "horseshoe_half" if half else "horseshoe"
    facets, mid = exterior_facets(msh)
    tol = 1e-9 * max(length, height)
    values = np.zeros(len(facets), np.int32)
    slot = mid[:, 0] > spine + tol
    for name, where in (("outer_low", np.abs(mid[:, 1]) < tol), ("outer_high", np.abs(mid[:, 1] - height) < tol),
                        ("inner_low", slot & (np.abs(mid[:, 1] - arm) < tol)),
                        ("inner_high", slot & (np.abs(mid[:, 1] - (height - arm)) < tol)),
                        ("back", np.abs(mid[:, 0]) < tol), ("bottom", np.abs(mid[:, 2]) < tol),
                        ("cut", ~slot & (np.abs(mid[:, 1] - height / 2) < tol))):
        values[where & (values == 0)] = FACETS[name]
    return msh, None, facet_tags(msh, facets, values, FACETS)
