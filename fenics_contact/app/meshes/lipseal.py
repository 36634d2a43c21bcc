"""Cross-section of a lip seal with two lips (a U-cup; the ``lipseal`` scene): a structured triangle mesh of the
heel and the two flared lips with the V-shaped slot between them, or of its half ``x >= 0``, symmetric about
``x = 0``."""
from __future__ import annotations

import numpy as np
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...domain import NamedTags
from .structured import exterior_facets, facet_tags

__all__ = ["FACETS", "lipseal_section"]

FACETS = {"outer": 1, "slot": 2, "bottom": 3, "cut": 4}


def _block(corners: np.ndarray, nx: int, ny: int) -> np.ndarray:
    """Nodes ((ny + 1) rows of nx + 1) of the bilinear map of the unit square on the quadrilateral ``corners``
    (bottom left, bottom right, top right, top left)."""
    s = np.linspace(0.0, 1.0, nx + 1)[None, :, None]
    e = np.linspace(0.0, 1.0, ny + 1)[:, None, None]
    p00, p10, p11, p01 = corners
    return (1 - s) * (1 - e) * p00 + s * (1 - e) * p10 + s * e * p11 + (1 - s) * e * p01


def lipseal_section(comm: MPI.Comm, width: float, heel: float, lip: float, flare: float, slot: float, nx: int,
                    ny_heel: int, ny_lip: int, half: bool = False) -> tuple[dmesh.Mesh, None, NamedTags]:
    """The seal's section in the plane (``x`` across the seal, ``y`` along its lips), or its half ``x >= 0``.

    The heel ``[-width/2, width/2] x [0, heel]``; on it two lips of length ``lip``, each the quadrilateral from the
    heel's top (``0 <= |x| <= width/2`` at ``y = heel``) to its tip (``slot/2 <= |x| <= width/2 + flare`` at ``y =
    heel + lip``): the slot between the lips is a V from the root ``(0, heel)`` to the width ``slot`` at the tips,
    and the lips' outer faces flare out by ``flare`` past the heel's. ``nx`` cells across each half, ``ny_heel``
    along the heel, ``ny_lip`` along a lip; each quadrilateral split into two triangles, the full mesh the half
    and its mirror image (exactly symmetric). Facets: ``outer`` (the heel's sides, the lips' outer faces and tips),
    ``slot`` (the lips' inner faces), ``bottom`` (``y = 0``), ``cut`` (the half's face on ``x = 0``). Collective.

    Returns:
        ``(mesh, None, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    """
    from ...compat import create_mesh

    for name, value in (("nx", nx), ("ny_heel", ny_heel), ("ny_lip", ny_lip)):
        if int(value) != value or value < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {value!r}")
    for name, value in (("width", width), ("heel", heel), ("lip", lip), ("slot", slot)):
        if not (np.isfinite(value) and value > 0):
            raise ValueError(f"{name} must be a length > 0, got {value!r}")
    if not (np.isfinite(flare) and flare >= 0):
        raise ValueError(f"flare must be a length >= 0, got {flare!r}")
    if not slot / 2 < width / 2 + flare:
        raise ValueError(f"slot must be narrower than the lips' span at the tips (width + 2 flare = "
                         f"{width + 2 * flare:g}), got {slot!r}")
    nx, ny_heel, ny_lip = int(nx), int(ny_heel), int(ny_lip)
    w, H, L = 0.5 * width, heel, lip
    low = _block(np.array([[0.0, 0.0], [w, 0.0], [w, H], [0.0, H]]), nx, ny_heel)
    up = _block(np.array([[0.0, H], [w, H], [w + flare, H + L], [0.5 * slot, H + L]]), nx, ny_lip)
    x = np.concatenate([low, up[1:]]).reshape(-1, 2)  # the lip's first row is the heel's last
    rows, cols = ny_heel + ny_lip, nx
    idx = np.arange(x.shape[0]).reshape(rows + 1, cols + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel(), idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    cells = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    if not half:  # the mirror image x -> -x, sharing the nodes on x = 0 (the heel's column 0, the slot's root)
        on_axis = np.flatnonzero(x[:, 0] == 0.0)
        other = np.arange(x.shape[0]) + x.shape[0]
        other[on_axis] = on_axis
        keep = np.setdiff1d(np.arange(x.shape[0]), on_axis)
        renumber = np.arange(2 * x.shape[0])
        renumber[x.shape[0] + keep] = x.shape[0] + np.arange(len(keep))
        mirrored = renumber[other[cells]][:, ::-1]  # reversed: the same orientation
        x = np.concatenate([x, x[keep] * [-1.0, 1.0]])
        cells = np.concatenate([cells, mirrored])
    cells = np.asarray(cells, np.int64)
    if comm.rank != 0:
        x, cells = np.zeros((0, 2)), np.zeros((0, 3), np.int64)
    msh = create_mesh(comm, cells, x, "triangle")
    msh.name = "lipseal_half" if half else "lipseal"
    facets, mid = exterior_facets(msh)
    tol = 1e-9 * (H + L)
    inner = np.abs(np.abs(mid[:, 0]) - 0.5 * slot * (mid[:, 1] - H) / L) < tol
    values = np.full(len(facets), FACETS["outer"], np.int32)
    values[(mid[:, 1] > H) & inner] = FACETS["slot"]
    values[np.abs(mid[:, 1]) < tol] = FACETS["bottom"]
    values[(np.abs(mid[:, 0]) < tol) & (mid[:, 1] < H)] = FACETS["cut"]
    return msh, None, facet_tags(msh, facets, values, FACETS)
