"""The traction ``t = P N`` of P1 triangles and its first two derivatives with respect to the cell's vertex
displacements, from the material's own UFL stress (:class:`CellStress`).

On an affine P1 triangle ``F = I + grad u`` is constant, so ``P``, ``A = dP/dF`` and ``dA/dF`` are the cell's
values: one :class:`dolfinx.fem.Expression` evaluates them (the derivatives along the fields ``z_ij = X_j e_i``,
whose gradient is ``e_i (x) e_j``) with ``E / h`` (Nitsche's parameter without ``gamma0``; ``h`` the cell
diameter, :func:`ufl.CellDiameter`) at each cell's centroid. With the reference gradients ``G_a`` of the cell's
shape functions, ``dt/du_(a,i) = sum_l G_al (dP/dF_il) N`` and likewise for the second derivative.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem

from ..compat import evaluate_expression

__all__ = ["CellStress"]


class CellStress:
    """``P``, ``dP/dF``, ``d^2P/dF^2`` and ``E / h`` of the material on the cells of ``u``'s (2D, P1) mesh.

    Args:
        material: the bulk :class:`~fenics_contact.materials.Material` (or ``Materials``).
        u: the displacement (vector P1 on triangles).
    """

    def __init__(self, material, u: fem.Function):
        V = u.function_space
        d = V.mesh.geometry.dim
        z = {}
        for i in range(d):
            for j in range(d):
                f = fem.Function(V)
                f.interpolate(lambda x, i=i, j=j: np.stack([x[j] if k == i else 0.0 * x[0] for k in range(d)]))
                z[i, j] = f
        P = material.piola(u)
        dP = {ij: ufl.derivative(P, u, z[ij]) for ij in z}
        entries = [P[k, m] for k in range(d) for m in range(d)]
        entries += [dP[ij][k, m] for ij in z for k in range(d) for m in range(d)]
        entries += [ufl.derivative(dP[ij], u, z[kl])[k, m] for ij in z for kl in z for k in range(d) for m in range(d)]
        entries.append(material.E / ufl.CellDiameter(V.mesh))
        self.d, self.mesh = d, V.mesh
        self.expression = fem.Expression(ufl.as_vector(entries), np.full((1, d), 1.0 / (d + 1)))

    def eval(self, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """``P`` (n, d, d), ``D[i, l] = dP/dF_il`` (n, d, d, d, d), ``D2[i, l, m, r] = d^2P/dF_il dF_mr``
        (n, d, d, d, d, d, d) and ``E / h`` (n,) on the local cells ``cells`` (``u``'s ghosts current)."""
        d = self.d
        if len(cells) == 0:
            v = np.zeros((0, d * d + d ** 4 + d ** 6 + 1))
        else:
            cells = np.asarray(cells, dtype=np.int32)
            v = evaluate_expression(self.expression, self.mesh, cells).reshape(len(cells), -1)
        n = len(v)
        a, b = d * d, d * d + d ** 4
        return (v[:, :a].reshape(n, d, d), v[:, a:b].reshape((n,) + (d,) * 4),
                v[:, b:-1].reshape((n,) + (d,) * 6), v[:, -1])
