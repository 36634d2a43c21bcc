"""The slave and master facets of a two-body contact and the contact points on the slave facets.

:class:`FacetData` orders the nodes of each facet so that its normal points out of its body and records
their dofs; :func:`facet_pair` makes the slave and the master ones from two facet tags of one mesh;
:class:`SlavePoints` places the contact points on the slave facets (the vertices, the Gauss points, or the
three nodes of a quadratic facet).
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem

from ..compat import collapse
from ..contact import check_facet_tag, is_mixed
from ..search import facet_normals

__all__ = ["POINT_RULES", "FacetData", "facet_pair", "SlavePoints"]

# Barycentric coordinates of the slave points on a flat facet (rows: points, columns: facet vertices), by
# (quadrature, vertices per facet).
_S = 0.5 / np.sqrt(3.0)
POINT_RULES = {
    ("nodal", 2): np.eye(2),
    ("gauss", 2): np.array([[0.5 + _S, 0.5 - _S], [0.5 - _S, 0.5 + _S]]),
    ("nodal", 3): np.eye(3),
    ("gauss", 3): np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]]),
}


class FacetData:
    """The local facets ``facets`` of the displacement space ``V``, their nodes and dofs.

    Flat facets have the ``nv = tdim`` vertices of a simplex cell; quadratic facets (2D, one dof per edge)
    the ``nv = 3`` nodes (end, middle, end). Per facet (first axis ``nf``): ``dofs`` (nf, nv) block dofs of
    the nodes, ordered so that the normal of :func:`search.facet_normals` points out of the body; ``X``
    (nf, nv, gdim) their reference coordinates; ``cells`` the cell of the facet, ``local`` the cell-local
    dof numbers of its nodes and ``vertex_local`` those of its vertices (the ends); ``owned`` whether this
    rank owns it; ``global_facets`` its global facet number. ``comp`` (nf, nv, gdim): local indices of the
    displacement components in the unknown's array, ``global_comp`` their global numbers. For a mixed
    unknown (:mod:`multipliers`) ``V`` is the collapsed displacement space and ``parent = (collapsed-to-parent
    map, parent space)``.

    Raises:
        ValueError: a facet is not on the boundary, or a degree-1 space is not on simplex cells.
    """

    def __init__(self, V: fem.FunctionSpace, facets: np.ndarray, parent=None):
        mesh = V.mesh
        tdim, gdim = mesh.topology.dim, mesh.geometry.dim
        mesh.topology.create_connectivity(tdim - 1, tdim)
        mesh.topology.create_connectivity(tdim - 1, 0)
        mesh.topology.create_connectivity(tdim, 0)
        mesh.topology.create_connectivity(tdim, tdim - 1)
        f2c, f2v, c2v, c2f = (mesh.topology.connectivity(tdim - 1, tdim), mesh.topology.connectivity(tdim - 1, 0),
                              mesh.topology.connectivity(tdim, 0), mesh.topology.connectivity(tdim, tdim - 1))
        # Quadratic facets: a 2D space with one dof per edge (P2); other spaces use the facets' vertices.
        self.quadratic = tdim == 2 and len(V.dofmap.dof_layout.entity_dofs(1, 0)) == 1
        self.nv = nv = 3 if self.quadratic else tdim  # nodes of a facet: (end, middle, end) or the simplex vertices
        nf = len(facets)
        self.cells = np.zeros(nf, np.int32)
        self.local = np.zeros((nf, nv), np.int32)
        self.vertex_local = np.zeros((nf, tdim), np.int32)  # cell-local vertex numbers (= P1 dofs) of the ends
        coords = V.tabulate_dof_coordinates()
        layout = V.dofmap.dof_layout
        dofs = np.zeros((nf, nv), np.int32)
        for i, f in enumerate(facets):
            cells = f2c.links(f)
            if len(cells) != 1:
                raise ValueError(f"facet {f} of a contact surface is not on the boundary (it has {len(cells)} cells)")
            c = cells[0]
            cv = list(c2v.links(c))
            if not self.quadratic and len(cv) != tdim + 1:
                raise ValueError("two-body contact with degree-1 facets needs simplex cells (flat facets): "
                                 "triangles or tetrahedra")
            vloc = [cv.index(v) for v in f2v.links(f)]
            cdofs = V.dofmap.cell_dofs(c)
            if self.quadratic:
                mid = layout.entity_dofs(1, list(c2f.links(c)).index(f))[0]
                ends = [layout.entity_dofs(0, v)[0] for v in vloc]
                loc = [ends[0], mid, ends[1]]
                fd = cdofs[loc]
                # Outward: the normal of the ordered ends must point away from the cell's centre.
                n = facet_normals(coords[fd[[0, 2]]][None, :, :gdim])[0]
                inside = coords[cdofs, :gdim].mean(axis=0)
                if np.dot(n, coords[fd[1], :gdim] - inside) < 0:
                    loc, vloc, fd = loc[::-1], vloc[::-1], fd[::-1]
            else:
                loc = vloc
                fd = cdofs[loc]
                # Orientation: the normal of the ordered vertices must point away from the opposite vertex.
                other = cdofs[[j for j in range(tdim + 1) if j not in loc][0]]
                n = facet_normals(coords[fd][None, :, :gdim])[0]
                if np.dot(n, coords[fd[0], :gdim] - coords[other, :gdim]) < 0:
                    loc, vloc, fd = loc[::-1], vloc[::-1], fd[::-1]
            self.cells[i], self.local[i], self.vertex_local[i], dofs[i] = c, loc, vloc, fd
        self.dofs = dofs
        self.facets = np.asarray(facets, dtype=np.int32)
        self.X = coords[dofs][..., :gdim] if nf else np.zeros((0, nv, gdim))
        imap = mesh.topology.index_map(tdim - 1)
        self.owned = np.asarray(facets) < imap.size_local
        self.global_facets = imap.local_to_global(self.facets) if nf else np.zeros(0, np.int64)
        Vmap = V.dofmap.index_map
        self.global_dofs = Vmap.local_to_global(dofs.ravel()).reshape(dofs.shape) if nf else dofs.astype(np.int64)
        comp = dofs[..., None] * gdim + np.arange(gdim)
        if parent is None:
            self.comp, self.global_comp = comp, self.global_dofs[..., None] * gdim + np.arange(gdim)
        else:
            to_parent, W = np.asarray(parent[0]), parent[1]
            self.comp = to_parent[comp].astype(np.int32)
            Wmap = W.dofmap.index_map  # a mixed space has block size 1
            self.global_comp = (Wmap.local_to_global(self.comp.ravel()).reshape(self.comp.shape) if nf
                                else self.comp.astype(np.int64))

    def current(self, u: np.ndarray) -> np.ndarray:
        """Current node positions ``X + u`` (nf, nv, gdim), ``u`` the unknown's local array (owned and ghosts)."""
        return self.X + u[self.comp]


def facet_pair(u: fem.Function, facet_tags, slave_tag: int | str, master_tag: int | str,
              name: str, self_contact: bool = False) -> tuple[FacetData, FacetData]:
    """Slave and master :class:`FacetData` of the facets tagged ``slave_tag`` and ``master_tag`` (values, or
    names of :class:`domain.NamedTags`) on the mesh of the unknown ``u`` (a displacement, or a mixed
    (displacement, pressure) Function: the displacement's components then). ``self_contact``: the tags must be
    equal (a surface against itself). Collective.

    Raises:
        ValueError: the tags are equal (differ, for ``self_contact``), or no rank has a facet with one of them
            (named after ``name``).
    """
    if self_contact and slave_tag != master_tag:
        raise ValueError(f"self-contact pairs one surface with itself: slave_tag {slave_tag} and master_tag "
                         f"{master_tag} must be equal")
    if slave_tag == master_tag and not self_contact:
        raise ValueError(f"slave_tag and master_tag must differ, both are {slave_tag}")
    V = u.function_space
    slave = check_facet_tag(V.mesh, facet_tags, slave_tag, f"{name} slave_tag")
    master = check_facet_tag(V.mesh, facet_tags, master_tag, f"{name} master_tag")
    if is_mixed(V):  # the displacement is the first field of a mixed unknown (method lagrange)
        Vd, to_parent = collapse(V.sub(0))
        return FacetData(Vd, slave, (to_parent, V)), FacetData(Vd, master, (to_parent, V))
    return FacetData(V, slave), FacetData(V, master)


class SlavePoints:
    """The contact points on the slave facets ``slave``, ``nq`` per facet.

    ``at_points`` (nq, nv): the value at each point of values at the facet's nodes (barycentric coordinates
    of :data:`POINT_RULES`; quadratic facets: the identity, the points are the three nodes); ``from_points``
    (nv, nq) its inverse. ``excluded`` (nf, nq): points left without a pair, those within ``1e-9 max |X|``
    of a reference position in ``exclude`` (k, gdim) (node on node with the other pass of a quadratic pair).
    """

    def __init__(self, slave: FacetData, quadrature: str, exclude: np.ndarray | None = None):
        self.facets = slave
        self.at_points = np.eye(3) if slave.quadratic else POINT_RULES[(quadrature, slave.nv)]
        self.from_points = np.linalg.inv(self.at_points)
        X = self.reference()
        self.excluded = np.zeros(X.shape[:2], bool)
        if exclude is not None and len(exclude) and len(X):
            dmin = np.min(np.linalg.norm(X[:, :, None, :] - np.asarray(exclude)[None, None], axis=3), axis=2)
            self.excluded = dmin <= 1e-9 * float(np.abs(X).max())

    @property
    def per_facet(self) -> int:
        """Points per facet, ``nq``."""
        return self.at_points.shape[0]

    def reference(self) -> np.ndarray:
        """Reference positions of the local slave points (nf, nq, gdim)."""
        return np.einsum("qk,fkj->fqj", self.at_points, self.facets.X)

    def current(self, u: np.ndarray) -> np.ndarray:
        """Current positions of the local slave points (nf, nq, gdim) from the unknown's local array ``u``."""
        return np.einsum("qk,fkj->fqj", self.at_points, self.facets.current(u))

    def values(self, nodal: np.ndarray) -> np.ndarray:
        """Values at the points (nf, nq) of nodal values (nf, nv) of a field on the facets."""
        return np.einsum("qk,fk->fq", self.at_points, nodal)
