"""Nitsche's method between two bodies integrated segment to segment (:class:`NitscheSegmentSurface`, 2D, P1).

:class:`~.surface.SegmentSurface`'s pairs and assembly with the element of :mod:`~.nitsche_element`: each owned
slave facet's cell (its three vertices: the stress) against the master facets its sub-segments project on. The
master part ``int p v_m(Pi x) ds`` is integrated exactly on each sub-segment, so the uniform state of the
contact patch test is the discrete solution on non-matching meshes (the pointwise rules of
:class:`~fenics_contact.twobody.nitsche.NitscheTwoBody` integrate it across the kinks of the master shape
functions).
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem

from ..compat import space_degree
from ..search import facet_normals
from ..twobody.nitsche import NitscheTwoBody
from .cell_stress import CellStress
from .element import reference_measure
from .nitsche_element import segment_element, uncovered_element
from .surface import SegmentSurface, _same

__all__ = ["NitscheSegmentSurface"]


class NitscheSegmentSurface(SegmentSurface):
    """:class:`~.surface.SegmentSurface` with Nitsche's pressure ``<gamma g + p_s(u)>`` (nominal, > 0 compression,
    ``gamma = gamma0 E_s / h_s`` of the slave cell) and stress terms (``theta``). Arguments as
    :class:`~.surface.SegmentSurface`, and ``material``: the bulk material (a
    :class:`~fenics_contact.materials.Materials` for two: the slave cell's).

    Raises:
        ValueError: no material; a displacement that is not 2D degree 1 (triangles: :class:`FacetData`).
    """

    def __init__(self, u: fem.Function, facet_tags, slave_tag, master_tag, law, load, weight: float = 1.0,
                 radius: float | None = None, name: str = "twobody", material=None):
        if material is None:
            raise ValueError("method 'nitsche' needs the bulk material (material=...) for the surface stress")
        V = u.function_space
        if V.mesh.geometry.dim != 2 or space_degree(V) != 1:
            raise ValueError(f"{name}: segment-to-segment Nitsche needs a 2D degree-1 displacement, got "
                             f"dimension {V.mesh.geometry.dim}, degree {space_degree(V)}")
        self.material = material
        super().__init__(u, facet_tags, slave_tag, master_tag, law, load, weight, radius, name)
        sd = self.slave_data
        self.stress = CellStress(material, u)
        # Per slave facet: its cell's vertices ordered (facet s0, facet s1, opposite), their reference
        # gradients, the local and global displacement dofs.
        order = np.zeros((len(sd.facets), 3), np.int32)
        for f, loc in enumerate(sd.local):
            order[f] = list(loc) + [k for k in range(3) if k not in loc]
        cell_dofs = np.array([V.dofmap.cell_dofs(c) for c in sd.cells], np.int32).reshape(-1, 3)
        self._cell_dofs = np.take_along_axis(cell_dofs, order, axis=1) if len(order) else cell_dofs
        self._X_cells = X = V.tabulate_dof_coordinates()[self._cell_dofs][..., :2]
        E = np.stack([X[:, 1] - X[:, 0], X[:, 2] - X[:, 0]], axis=1)  # rows: edges from s0
        Gb = np.linalg.inv(E) if len(E) else np.zeros((0, 2, 2))  # columns: gradients of the 2nd, 3rd shape function
        G1, G2 = Gb[:, :, 0], Gb[:, :, 1]
        self._grad = np.stack([-G1 - G2, G1, G2], axis=1)  # (nf, 3 vertices, 2)
        comp = self._cell_dofs[..., None] * 2 + np.arange(2)
        self._comp = comp.reshape(-1, 6)
        Vmap = V.dofmap.index_map
        g = Vmap.local_to_global(self._cell_dofs.ravel()).reshape(self._cell_dofs.shape) if len(order) else \
            self._cell_dofs.astype(np.int64)
        self._cell_global = (g[..., None] * 2 + np.arange(2)).reshape(-1, 6)
        self._N = facet_normals(sd.X) if len(sd.X) else np.zeros((0, 2))
        self._Jf = reference_measure(sd.X)

    _pressure = NitscheTwoBody._pressure  # the nodal state's pressure (outputs at the vertices)

    def _traction(self, facets: np.ndarray):
        """``t = P N`` (n, 2), ``dt/du`` (n, 2, 6) and ``d^2t/du^2`` (n, 2, 6, 6) of the slave facets' cells
        (columns: the ordered cell vertices' (x, y)), and ``gamma`` (n,)."""
        P, D, D2, Eh = self.stress.eval(self.slave_data.cells[facets])
        N, G = self._N[facets], self._grad[facets]
        t = np.einsum("nkm,nm->nk", P, N)
        # dt_k/du_(a,i) = G_al D[i, l, k, m] N_m
        T = np.einsum("nal,nilkm,nm->nkai", G, D, N, optimize=True).reshape(-1, 2, 6)
        # d^2t_k/du_(a,i)du_(b,p) = G_al G_br D2[i, l, p, r, k, m] N_m
        T2 = np.einsum("nal,nbr,nilprkm,nm->nkaibp", G, G, D2, N, optimize=True).reshape(-1, 2, 6, 6)
        return t, T, T2, float(self.constants["gamma0"].value) * Eh

    def _elements(self, points: bool = False):
        """Element residuals, tangents and global dof indices (n, 10): the pairs', then the owned slave facets'
        traction-free terms."""
        sd, seg = self.slave_data, self.segments
        f, m = seg.pairs[:, 0], seg.pairs[:, 1]
        ua = self.u.x.array
        xc = self._X_cells + ua[self._comp].reshape(-1, 3, 2)
        x = np.concatenate([xc[f], seg.master_x[m]], axis=1)
        theta = float(self.constants["theta"].value)
        weight = float(self.weight.value)
        owned = np.flatnonzero(sd.owned)
        dofs = np.concatenate([np.concatenate([self._cell_global[f], seg.master_dofs[m].reshape(-1, 4)], axis=1),
                               np.concatenate([self._cell_global[owned], np.full((len(owned), 4), -1)], axis=1)])
        inputs = (np.concatenate([xc.ravel(), x.ravel()]), {"gamma0": float(self.constants["gamma0"].value),
                                                           "theta": theta}, {}, weight, dofs)
        if not points and self._element_cache is not None and _same(self._element_cache[0], inputs):
            return self._element_cache[1], dofs
        t, T, T2, gamma = self._traction(np.arange(len(sd.facets)))
        out = segment_element(x, self._N[f], t[f], T[f], T2[f], gamma[f], theta, self._Jf[f], weight, points=points)
        r0, K0 = uncovered_element(self._N[owned], t[owned], T[owned], T2[owned], gamma[owned], theta,
                                   self._Jf[owned], weight)
        r, K = np.concatenate([out[0], r0]), np.concatenate([out[1], K0])
        if points:
            return (r, K, out[2]), dofs
        self._element_cache = (inputs, (r, K))
        return (r, K), dofs
