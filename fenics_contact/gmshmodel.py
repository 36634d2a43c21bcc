"""A gmsh model checked before dolfinx reads it: node tags made 1..n, repeated cells and bodies covering the same
region twice refused.

dolfinx reads a gmsh model's nodes assuming their tags are ``1..n`` (``gmshio.extract_geometry`` asserts it; a model
read back from a file, or meshed with some options, may have gaps): they are renumbered when they are not. It
reads the cells of every physical group of the top dimension: a cell given twice (the same nodes in two groups, or
twice in a file) stops dolfinx with "Duplicate mesh entity detected"; it is refused here naming how many and where.
Two bodies (physical groups of cells) that do not share nodes but cover the same region of space would both be
solved (twice the stiffness, twice the force): the centroids of each body's simplices are located in the other
body's, and an overlap of more than :data:`OVERLAP` of the smaller body's volume is refused (a slight initial
penetration, which contact resolves, is far below it).
"""
from __future__ import annotations

import numpy as np

__all__ = ["OVERLAP", "prepare"]

# Fraction of the smaller body's volume inside the other above which two bodies are refused as overlapping
OVERLAP = 0.1
# gmsh element types of the simplices (3-node triangle, 4-node tetrahedron, and their higher-order forms)
_SIMPLEX = {2: (2, 9, 21, 23, 25), 3: (4, 11, 29, 30, 31)}


def _fmt(p: np.ndarray) -> str:
    return "(" + ", ".join(f"{v:.4g}" for v in p) + ")"


def _cells(gmsh, dim: int) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """``{group name: (element types, node tags of the corners)}`` of the physical groups of dimension ``dim``, as
    dolfinx reads them (each entity of a group, once per group)."""
    out = {}
    for _, tag in gmsh.model.getPhysicalGroups(dim):
        name = gmsh.model.getPhysicalName(dim, tag) or str(tag)
        types, rows = [], []
        for entity in gmsh.model.getEntitiesForPhysicalGroup(dim, tag):
            kinds, _, nodes = gmsh.model.mesh.getElements(dim, entity)
            for kind, tags in zip(kinds, nodes):
                properties = gmsh.model.mesh.getElementProperties(kind)  # (..., nodes, coordinates, corners)
                block = np.asarray(tags, dtype=np.int64).reshape(-1, properties[3])[:, :properties[5]]
                rows.append(block)
                types.append(np.full(len(block), kind))
        if rows:
            width = max(r.shape[1] for r in rows)
            padded = [np.pad(r, ((0, 0), (0, width - r.shape[1])), constant_values=-1) for r in rows]
            out[name] = (np.concatenate(types), np.concatenate(padded))
    return out


def _overlap(x: np.ndarray, a: np.ndarray, b: np.ndarray) -> float:
    """Volume of the simplices ``a`` (corner rows of ``x``) whose centroids lie inside a simplex of ``b``, found
    among the 16 of ``b`` with the nearest centroids."""
    from scipy.spatial import cKDTree

    ca, cb = x[a].mean(axis=1), x[b].mean(axis=1)
    k = min(16, len(b))
    _, near = cKDTree(cb).query(ca, k=k)
    near = near.reshape(len(a), k)
    inside = np.zeros(len(a), dtype=bool)
    for j in range(k):
        corners = x[b[near[:, j]]]  # (cells, dim + 1, dim)
        T = np.transpose(corners[:, 1:] - corners[:, :1], (0, 2, 1))
        with np.errstate(all="ignore"):
            lam = np.linalg.solve(T, (ca - corners[:, 0])[..., None])[..., 0]
        lam = np.concatenate([1 - lam.sum(axis=1, keepdims=True), lam], axis=1)
        inside |= np.all(lam > 1e-9, axis=1)
    corners = x[a]
    volumes = np.abs(np.linalg.det(np.transpose(corners[:, 1:] - corners[:, :1], (0, 2, 1))))
    return float(volumes[inside].sum()) / float(volumes.sum()) if volumes.sum() > 0 else 0.0


def prepare(gmsh, what: str, check: bool = True) -> None:
    """Make the current gmsh model's node tags ``1..n`` (renumbered only if they are not) and, with ``check`` (a
    user's model), raise ``ValueError`` (one line, naming ``what``) if a cell of the top dimension is given twice
    or two bodies overlap (module docstring). Call on the rank that holds the model, before dolfinx reads it."""
    tags, coords, _ = gmsh.model.mesh.getNodes()
    if len(tags) and not np.array_equal(np.sort(np.asarray(tags)), np.arange(1, len(tags) + 1)):
        gmsh.model.mesh.renumberNodes()
        tags, coords, _ = gmsh.model.mesh.getNodes()
    if not check:
        return
    groups = gmsh.model.getPhysicalGroups()
    dim = max((d for d, _ in groups), default=0)
    if dim < 1 or len(tags) == 0:
        return
    x = np.zeros((len(tags) + 1, 3))
    x[np.asarray(tags, dtype=np.int64)] = np.asarray(coords).reshape(-1, 3)
    bodies = _cells(gmsh, dim)
    if not bodies:
        return
    names = list(bodies)
    rows = np.concatenate([bodies[n][1] for n in names])
    owner = np.concatenate([np.full(len(bodies[n][1]), i) for i, n in enumerate(names)])
    key = np.sort(rows, axis=1)
    _, first, counts = np.unique(key, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        repeated = int(np.sum(counts[counts > 1] - 1))
        dup = np.flatnonzero(np.all(key == key[first[np.argmax(counts > 1)]], axis=1))
        where = x[rows[dup[0]][rows[dup[0]] > 0]].mean(axis=0)
        groups_of = sorted({names[owner[i]] for i in dup})
        raise ValueError(f"{what}: {repeated} cell{'s' * (repeated > 1)} given twice (the same nodes), the first at "
                         f"{_fmt(where)} in {' and '.join(repr(g) for g in groups_of)}: give each cell once")
    if not np.all(np.isfinite(x)):
        return  # no place to test: the mesh's check of its coordinates refuses it (cells.check_cells)
    simplices = {n: r[:, :dim + 1] for n, (t, r) in bodies.items() if np.all(np.isin(t, _SIMPLEX.get(dim, ())))}
    for i, a in enumerate(names):
        for b in names[i + 1:]:
            if a not in simplices or b not in simplices:
                continue
            shared = np.intersect1d(simplices[a], simplices[b]).size
            if shared:
                continue  # bodies joined by nodes are one body in two groups (materials), not an overlap
            xs = x[:, :dim]
            fraction = max(_overlap(xs, simplices[a], simplices[b]), _overlap(xs, simplices[b], simplices[a]))
            if fraction > OVERLAP:
                raise ValueError(f"{what}: the bodies {a!r} and {b!r} cover the same region ({fraction:.0%} of one "
                                 f"lies inside the other, more than {OVERLAP:.0%}): give the region once")
