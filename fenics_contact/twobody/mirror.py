"""Mirror fields: the paired master facet seen from the slave points, so that the gap is UFL.

For every slave point ``x_s = X + u`` the mirror fields hold the reference positions ``X_k`` and the
displacements ``w_k`` of the nodes ``k`` of its paired master facet (:class:`MirrorFields`, Functions on the
slave side whose values at the slave points are these), and the gap is written against them
(:class:`MirrorObstacle`)::

    x_k = X_k + w_k,   n = outward unit normal of the flat facet (x_1, .., x_nv),
    g   = -(x_s - x_1) . n          (positive = penetration, see :mod:`laws`)

For a flat (P1) master facet the distance to its plane does not depend on the closest point, so this ``g``
is the exact closest-point gap as a function of the slave and master vertex positions while the projection
stays on the facet: its derivatives with respect to ``u`` and to ``w`` (taken by UFL) are the complete
consistent linearisation, including the rotation of the master normal; the motion of the projection point
drops out. A pairing change (large sliding) is a discrete event between Newton iterations.

Quadratic facets (2D, a degree-2 displacement): the master facet is the curve ``x(xi) = sum_k N_k(xi) x_k``
through its three nodes (end, middle, end; ``xi`` in [0, 1]); the slave points are the three nodes of each
slave facet (the mirror fields live in P2). We project on the curve, not on the two chords through the
middle node: the chords of two non-matching discretizations of one circle sag by different amounts
(``h^2/8R``, 4e-4 for the sheet's facets), so chords would make the two surfaces overlap by as much as an
exact method enforces; the quadratic curves agree to ``O(h^4)``. The closest point ``xi0`` is found in NumPy
(:mod:`~.pairing`) and written in UFL as one further Newton correction ``xi = xi0 - f/f'`` of the projection
equation ``f = (x_s - x(xi)) . x'(xi) = 0``: its value is ``xi0`` and its derivative the implicit-function
one, so UFL's second derivative of ``g = -(x_s - x(xi)) . n(xi)`` is the complete consistent tangent
(curvature and the moving projection point included; ``tests/test_sheet.py`` checks it against central
differences). Points that project on a facet's end (``xi`` clipped) keep ``xi`` fixed.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np
import ufl
from dolfinx import fem

from ..compat import function_space
from ..obstacles import Obstacle
from .facets import FacetData, SlavePoints

__all__ = ["MirrorFields", "MirrorObstacle", "barycentric", "ufl_normal"]


class MirrorFields:
    """The master facet paired with each slave point, as Functions on the slave side.

    The mirror space has one node per slave point: P1 at the vertices (``nodal``), DG1 whose trace has one
    value per Gauss point (``gauss``), P2 at the three nodes of a quadratic facet. ``space`` holds ``nv gdim``
    values per node (the paired facet's nodes, component by component), ``scalar_space`` one.

    Functions: ``reference`` (the paired facet's reference node coordinates ``X_k``; fixed during a Newton
    iteration), ``displacement`` (its nodes' displacements ``w_k``: the variable the coupling differentiates),
    ``active`` (1 where the point has a pair, else 0) and, for quadratic facets, ``local_coordinate`` (the
    closest point's ``xi0`` and ``free`` = 1 where it is inside the facet). ``node_dofs`` (nf, nq): the
    mirror nodes of the slave facets (in ``space``, block numbers; ``scalar_dofs`` in ``scalar_space``),
    ``global_nodes`` their global numbers.

    Raises:
        ValueError: Gauss points on a cell with two slave facets (their DG1 nodes would coincide).
    """

    def __init__(self, mesh, slave: FacetData, points: SlavePoints, quadrature: str, name: str):
        self.points, self.quadratic = points, slave.quadratic
        self.nv, self.gdim = slave.nv, mesh.geometry.dim
        family, degree = ("Lagrange", 2) if self.quadratic else ("Lagrange" if quadrature == "nodal" else "DG", 1)
        self.space = function_space(mesh, family, degree, (self.nv * self.gdim,))
        self.scalar_space = function_space(mesh, family, degree)
        self.reference = fem.Function(self.space, name="mirror_X")
        self.displacement = fem.Function(self.space, name="mirror_u")
        self.active = fem.Function(self.scalar_space, name="paired")
        self.local_coordinate = fem.Function(function_space(mesh, family, degree, (2,)), name="mirror_xi") \
            if self.quadratic else None
        nn = points.at_points.shape[1]  # mirror nodes per slave facet
        self.node_dofs = np.array([self.space.dofmap.cell_dofs(c)[loc] for c, loc in zip(slave.cells, slave.local)],
                                  dtype=np.int32).reshape(-1, nn)
        self.scalar_dofs = np.array([self.scalar_space.dofmap.cell_dofs(c)[loc]
                                     for c, loc in zip(slave.cells, slave.local)], dtype=np.int32).reshape(-1, nn)
        if quadrature == "gauss" and len(np.unique(self.node_dofs)) != self.node_dofs.size:
            raise ValueError(f"{name}: a cell has two slave facets; Gauss quadrature needs one per cell "
                             "(refine the mesh at the corner or use quadrature 'nodal')")
        Wmap = self.space.dofmap.index_map
        self.global_nodes = Wmap.local_to_global(self.node_dofs.ravel()).reshape(self.node_dofs.shape) \
            if len(slave.facets) else np.zeros((0, nn), np.int64)
        # Until the first pairing every point sees a unit facet: the UFL normal stays finite.
        self.reference.x.array[:] = np.tile(self.dummy_vertices().ravel(),
                                            len(self.reference.x.array) // (self.nv * self.gdim))

    def dummy_vertices(self) -> np.ndarray:
        """A unit facet (nv, gdim) for the unpaired points: keeps the UFL normal finite where ``active = 0``."""
        if self.quadratic:
            return np.array([[0.0, 0.0], [0.5, 0.0], [1.0, 0.0]])
        return np.vstack([np.zeros(self.gdim), np.eye(self.gdim)])[: self.nv]

    def nodal(self, facet: np.ndarray, per_facet: np.ndarray, unpaired: np.ndarray | None = None) -> np.ndarray:
        """Mirror node values (nf, nq, nv gdim) of values per master facet ``per_facet`` (n, nv, gdim) at the
        points paired with facet ``facet`` (nf, nq) (index into ``per_facet``, -1: unpaired; ``unpaired``
        (nv, gdim) there, default 0)."""
        # Values at the slave points, then the nodal values of the mirror space (B^-1).
        nf, nq = facet.shape
        bs = self.nv * self.gdim
        at_points = np.zeros((nf, nq, bs))
        ok = facet >= 0
        at_points[ok] = per_facet[facet[ok]].reshape(-1, bs)
        if unpaired is not None:
            at_points[~ok] = unpaired.ravel()
        return np.einsum("aq,fqb->fab", self.points.from_points, at_points)

    def set(self, f: fem.Function, nodal: np.ndarray) -> None:
        """Write mirror node values ``nodal`` (nf, nq, nv gdim) into ``f`` (a Function on ``space``)."""
        bs = self.nv * self.gdim
        f.x.array[self.node_dofs[..., None] * bs + np.arange(bs)] = nodal

    def fill(self, facet: np.ndarray, master: dict, local_coordinate: np.ndarray | None) -> None:
        """Set every mirror Function from a pairing: ``facet`` (nf, nq) index into the master facets ``master``
        (``X``, ``U``: reference coordinates and displacements, (n, nv, gdim)), -1 where unpaired;
        ``local_coordinate`` (nf, nq) the closest points' ``xi`` (quadratic facets)."""
        ok = facet >= 0
        self.set(self.reference, self.nodal(facet, master["X"], self.dummy_vertices()))
        self.set(self.displacement, self.nodal(facet, master["U"]))
        self.active.x.array[self.scalar_dofs] = np.einsum("aq,fq->fa", self.points.from_points, ok.astype(float))
        if self.quadratic:  # the mirror nodes are the slave points
            xi = local_coordinate
            free = ok & (xi > 1e-12) & (xi < 1 - 1e-12)
            idx = self.scalar_dofs[..., None] * 2 + np.arange(2)
            self.local_coordinate.x.array[idx] = np.stack([np.where(ok, xi, 0.5), free.astype(float)], axis=-1)


def ufl_normal(xs: Sequence[ufl.core.expr.Expr]) -> ufl.core.expr.Expr:
    """UFL unit normal of the flat facet with current vertices ``xs`` (same formula as :func:`search.facet_normals`)."""
    if len(xs) == 2:
        t = xs[1] - xs[0]
        n = ufl.as_vector((t[1], -t[0]))
    else:
        n = ufl.cross(xs[1] - xs[0], xs[2] - xs[0])
    return n / ufl.sqrt(ufl.dot(n, n))


def barycentric(x, xs: list) -> list:
    """UFL weights ``N_k`` of the closest point of the plane (line) of the flat facet with vertices ``xs`` (2 in
    2D, 3 in 3D) to ``x``: ``sum_k N_k = 1``, ``sum_k N_k x_k`` the projection of ``x``."""
    d = x - xs[0]
    if len(xs) == 2:
        t = xs[1] - xs[0]
        a = ufl.dot(d, t) / ufl.dot(t, t)
        return [1.0 - a, a]
    e1, e2 = xs[1] - xs[0], xs[2] - xs[0]
    g11, g12, g22 = ufl.dot(e1, e1), ufl.dot(e1, e2), ufl.dot(e2, e2)
    r1, r2 = ufl.dot(d, e1), ufl.dot(d, e2)
    det = g11 * g22 - g12 * g12
    a, b = (g22 * r1 - g12 * r2) / det, (g11 * r2 - g12 * r1) / det
    return [1.0 - a - b, a, b]


class MirrorObstacle(Obstacle):
    """The paired master facet seen from the slave points, as an obstacle of :class:`contact.ContactSurface`.

    Args:
        reference, displacement, active: the mirror Functions (:class:`MirrorFields`); the facet's nodes are
            ``X_k + w_k``.
        nv, gdim: nodes per facet, geometric dimension.
        open_gap: gap at unpaired points (negative: open; the search radius).
        local_coordinate: quadratic facets: ``(xi0, free)`` of :class:`MirrorFields` (the curve and one Newton
            correction of the closest point, see the module docstring); None for flat facets.
        sliding: ``finite`` (the current facet, see the module) or ``small`` (flat facets): the reference
            facet's normal ``n`` and the reference closest point's weights ``N_k`` (of the slave point's
            reference position), ``g = -(x_s - sum_k N_k x_k) . n``: linear in the slave and master
            displacements (the contact kinematics of small strains and small sliding).
    """

    def __init__(self, reference: fem.Function, displacement: fem.Function, active: fem.Function, nv: int,
                 gdim: int, open_gap: float, local_coordinate: fem.Function | None = None, sliding: str = "finite"):
        super().__init__(np.zeros(gdim))
        self.reference, self.displacement, self.active, self.nv, self.gdim = reference, displacement, active, nv, gdim
        self.open_gap = float(open_gap)
        self.local_coordinate = local_coordinate
        self.small = sliding == "small"
        if self.small and local_coordinate is not None:
            raise ValueError("sliding 'small' needs flat (degree-1) facets")

    def reference_vertices(self) -> list:
        """The paired facet's reference nodes ``X_k`` (UFL vectors)."""
        d = self.gdim
        return [ufl.as_vector([self.reference[k * d + i] for i in range(d)]) for k in range(self.nv)]

    def weights(self, x) -> list:
        """The weights ``N_k`` of the master point paired with the slave point ``x`` (UFL): of its closest point
        on the current facet, or with small sliding of the reference closest point to the slave point's
        reference position."""
        if self.small:
            X = ufl.SpatialCoordinate(self.reference.function_space.mesh)
            return barycentric(X, self.reference_vertices())
        return barycentric(x, self.vertices())

    def vertices(self) -> list:
        """The paired facet's current nodes ``X_k + w_k`` (UFL vectors)."""
        d = self.gdim
        return [ufl.as_vector([self.reference[k * d + i] + self.displacement[k * d + i] for i in range(d)])
                for k in range(self.nv)]

    def _curve(self, x):
        """Closest point ``x(xi)`` and tangent ``x'(xi)`` of the quadratic facet to ``x`` (UFL)."""
        xs = self.vertices()

        def at(xi):
            N = (2 * (xi - 0.5) * (xi - 1), -4 * xi * (xi - 1), 2 * xi * (xi - 0.5))
            dN = (4 * xi - 3, 4 - 8 * xi, 4 * xi - 1)
            return sum(a * b for a, b in zip(N, xs)), sum(a * b for a, b in zip(dN, xs))

        xi0, free = self.local_coordinate[0], self.local_coordinate[1]
        X0, dX0 = at(xi0)
        ddX = 4 * xs[0] - 8 * xs[1] + 4 * xs[2]
        f = ufl.dot(x - X0, dX0)
        fp = ufl.dot(x - X0, ddX) - ufl.dot(dX0, dX0)
        return at(xi0 - free * f / fp)

    def gap(self, x):
        """``-(x - x_1) . n`` (> 0 penetration) where paired; ``-open_gap`` where not, so that laws and
        augmentations see an open contact there."""
        if self.small:
            xm = sum(N * xk for N, xk in zip(self.weights(x), self.vertices()))
            g = -ufl.dot(x - xm, ufl_normal(self.reference_vertices()))
        elif self.local_coordinate is None:
            xs = self.vertices()
            g = -ufl.dot(x - xs[0], ufl_normal(xs))
        else:
            X, dX = self._curve(x)
            g = -ufl.dot(x - X, ufl_normal([X, X + dX]))
        return self.active * g - (1.0 - self.active) * self.open_gap

    def normal(self, x):
        """The paired master facet's outward unit normal at the closest point to ``x`` (UFL; small sliding: the
        reference facet's)."""
        if self.small:
            return ufl_normal(self.reference_vertices())
        if self.local_coordinate is None:
            return ufl_normal(self.vertices())
        X, dX = self._curve(x)
        return ufl_normal([X, X + dX])
