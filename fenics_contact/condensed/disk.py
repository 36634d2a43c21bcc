"""Alart-Curnier's tangential rows: the projection onto the Coulomb disk and its generalized Jacobian.

Per contact vertex, with the tangential force ``R_t`` and the slip increment ``s`` (``m`` components along an
orthonormal tangent basis: ``m = 1`` in 2D, 2 in 3D), ``lam = R_n - c d`` the augmented normal force and the disk
radius ``b = mu max(0, lam)``::

    F_t = R_t - proj_b(R_t - c s),   proj_b(q) = q                  |q| <= b   (stick: F_t = c s)
                                               = b q / |q|          |q| >  b   (slip)

In 2D the disk is the interval ``[-b, b]``. The generalized Jacobian of a slipping row,
``dF_t = A dR_t + B ds + g dlam``, has ``A = I - (b / |q|) P``, ``B = c (b / |q|) P``, ``g = -mu q / |q|`` (when
``lam > 0``) with ``P = I - e e^T``, ``e = q / |q|`` (``P = 0`` in 2D); a sticking row ``A = 0``, ``B = c I``,
``g = 0``. A vertex may lack a direction (a prescribed tangential component, a symmetry plane): ``has`` masks it
out (its ``R_t``, ``s`` and rows are zero).
"""
from __future__ import annotations

import numpy as np

__all__ = ["disk_rows", "tangent_basis"]


def disk_rows(Rt: np.ndarray, s: np.ndarray, lam: np.ndarray, mu: float, c: float,
              has: np.ndarray) -> tuple[np.ndarray, ...]:
    """The tangential rows of ``n`` vertices (see the module).

    Args:
        Rt: tangential forces (n, m).
        s: slip increments (n, m).
        lam: augmented normal forces ``R_n - c d`` (n,).
        mu: the friction coefficient.
        c: Alart-Curnier's parameter.
        has: the directions each vertex has (n, m), bool.

    Returns:
        ``F`` (n, m), ``A`` (n, m, m), ``B`` (n, m, m), ``g`` (n, m), ``stick`` (n,) and the slip direction ``e``
        (n, m) (zero where the vertex sticks or ``q = 0``).
    """
    n, m = Rt.shape
    mask = has.astype(float)
    Rt, s = Rt * mask, s * mask
    active = lam > 0
    bound = mu * np.maximum(lam, 0.0)
    q = Rt - c * s
    size = np.linalg.norm(q, axis=1)
    stick = active & (size <= bound)
    slip = ~stick
    e = np.where((slip & (size > 0))[:, None], q / np.where(size > 0, size, 1.0)[:, None], 0.0)
    F = np.where(stick[:, None], c * s, Rt - bound[:, None] * e)
    eye = mask[:, :, None] * np.eye(m)[None]
    ratio = np.where(slip & (size > 0), bound / np.where(size > 0, size, 1.0), 0.0)  # b / |q| (< 1 slipping)
    P = eye - e[:, :, None] * e[:, None, :]
    A = np.where(stick[:, None, None], 0.0, eye - ratio[:, None, None] * P)
    B = np.where(stick[:, None, None], c * eye, c * ratio[:, None, None] * P)
    g = np.where((slip & active)[:, None], -mu * e, 0.0)
    return F * mask, A, B, g * mask, stick, e


def tangent_basis(normal: np.ndarray) -> np.ndarray:
    """An orthonormal tangent basis (n, dim - 1, dim) of unit normals ``normal`` (n, dim), a function of the normal
    alone (the same on every rank): 2D ``t = (n_y, -n_x)`` (+x on a surface facing +y); 3D ``t_1`` the
    coordinate axis least aligned with ``n`` (the first of a tie) made orthogonal to it, ``t_2 = n x t_1`` (+x and
    +y on a surface facing +z)."""
    normal = np.asarray(normal, float)
    if normal.shape[1] == 2:
        return np.stack([normal[:, 1], -normal[:, 0]], axis=1)[:, None, :]
    axis = np.eye(3)[np.argmin(np.abs(normal), axis=1)]
    t1 = axis - np.einsum("ij,ij->i", axis, normal)[:, None] * normal
    t1 /= np.linalg.norm(t1, axis=1)[:, None]
    return np.stack([t1, np.cross(normal, t1)], axis=1)
