"""A user's mesh with named regions: gmsh physical names instead of integer tags.

``read_gmsh("part.msh" | "part.geo" | None, comm, gdim)`` reads a mesh file
(``.geo`` is meshed first, ``None`` takes the gmsh model already built in
this process) on rank 0, distributes it with the deterministic partitioner
and returns ``(mesh, cells, facets)``: :class:`NamedTags` that give each
physical group by its name (``facets["contact"]``) and work wherever the
library takes facet or cell tags. A name that the mesh does not have is an
error naming the names it has; so is a ``gdim`` other than the mesh's
dimension (raised on every rank). A cell given twice and two bodies covering the same region are refused
(:mod:`~fenics_contact.gmshmodel`); so is a mesh with a coordinate that is not finite, or with inverted or
degenerate cells (:class:`~fenics_contact.cells.MeshError`, :func:`~fenics_contact.cells.check_cells`).

Everything here is collective on ``comm``; gmsh is imported only when a
mesh is read.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable, Mapping, Sequence

import numpy as np
from mpi4py import MPI

__all__ = ["NamedTags", "read_gmsh", "distribute", "tag_value", "check_tags", "tag_boundary"]


class NamedTags:
    """Mesh tags (dolfinx ``MeshTags``) with a name for each value: ``tags["contact"]`` is the value of the
    physical group named ``contact``; ``indices``, ``values``, ``dim`` as on ``MeshTags``; ``meshtags`` is the
    dolfinx object (for ``ufl.Measure(subdomain_data=...)``).

    Args:
        meshtags: the dolfinx ``MeshTags``.
        names: region name -> tag value.
    """

    def __init__(self, meshtags, names: Mapping[str, int]):
        self.meshtags = meshtags
        self.names = dict(names)

    @property
    def indices(self) -> np.ndarray:
        return self.meshtags.indices

    @property
    def values(self) -> np.ndarray:
        return self.meshtags.values

    @property
    def dim(self) -> int:
        return self.meshtags.dim

    def __getitem__(self, name: str) -> int:
        if name not in self.names:
            raise ValueError(f"no region named {name!r}; the mesh has {sorted(self.names)}")
        return self.names[name]

    def find(self, name: str) -> np.ndarray:
        """Local entities of the region ``name``."""
        return self.indices[self.values == self[name]]

    def __repr__(self) -> str:
        return f"NamedTags(dim={self.dim}, {self.names})"


def merge_regions(mesh, tags: NamedTags, name: str, regions: Sequence[str]) -> NamedTags:
    """``tags`` with one more region ``name``: the entities of ``regions``, which keep their own names too; e.g.
    the union of two surfaces that may touch each other, for self-contact.

    Args:
        mesh: the mesh of ``tags``.
        tags: facet or cell tags with names (:class:`NamedTags`).
        name: the new region's name.
        regions: names of ``tags`` whose entities make the new region.

    Returns:
        The tags with the new region (a new :class:`NamedTags`; ``tags`` is not changed).

    Raises:
        ValueError: ``name`` is already a region, or a region of ``regions`` is not one.
    """
    from dolfinx import mesh as dmesh

    if name in tags.names:
        raise ValueError(f"region {name!r} exists already; the mesh has {sorted(tags.names)}")
    value = max(tags.names.values(), default=0) + 1
    extra = np.unique(np.concatenate([tags.find(r) for r in regions])).astype(np.int32)
    index = np.concatenate([tags.indices, extra]).astype(np.int32)
    values = np.concatenate([tags.values, np.full(len(extra), value, np.int32)]).astype(np.int32)
    order = np.argsort(index, kind="stable")
    merged = dmesh.meshtags(mesh, tags.dim, index[order], values[order])
    merged.name = tags.meshtags.name
    return NamedTags(merged, {**tags.names, name: value})


def tag_value(tags, tag: int | str) -> tuple[object, int]:
    """``(dolfinx MeshTags, integer value)`` of ``tag`` (a name of :class:`NamedTags`, or an integer value of
    plain ``MeshTags``)."""
    if isinstance(tags, NamedTags):
        return tags.meshtags, tags[tag] if isinstance(tag, str) else int(tag)
    if isinstance(tag, str):
        raise ValueError(f"region {tag!r} given by name, but the tags have no names (use read_gmsh's NamedTags)")
    return tags, int(tag)


def physical_names(gmsh) -> dict[int, dict[str, int]]:
    """``{dim: {name: value}}`` of the physical groups of the current gmsh model, for its top dimension and the
    one below (an unnamed group is named by its value). Raises ``ValueError`` if the model has none."""
    groups = gmsh.model.getPhysicalGroups()
    tdim = max((d for d, _ in groups), default=-1)
    if tdim < 1:
        raise ValueError("the gmsh model has no physical groups (name the regions to read)")
    names: dict[int, dict[str, int]] = {}
    for d, t in groups:
        if d in (tdim, tdim - 1):
            names.setdefault(d, {})[gmsh.model.getPhysicalName(d, t) or str(t)] = t
    return names


def distribute(model, comm: MPI.Comm, gdim: int, names: Mapping[int, Mapping[str, int]],
               balance: Sequence[str] = ()):
    """The dolfinx mesh and tags of rank 0's gmsh ``model`` (``names``: its physical names by dimension,
    :func:`physical_names`), distributed by the deterministic partitioner; with ``balance`` (facet region names:
    the contact surfaces) on several ranks, distributed again so that the cells at those facets are split evenly
    too (:func:`~fenics_contact.partition.balanced_owners`): the contact's assembly and search then run on every
    rank, not on the one rank a graph partition gives a small contact patch to. Returns ``(mesh, cell_tags,
    facet_tags)`` (dolfinx ``MeshTags``). Collective."""
    from .compat import model_to_mesh
    from .partition import balanced_owners

    facet_names = names.get(gdim - 1, {})  # the model's dimension is gdim
    unknown = [n for n in balance if n not in facet_names]
    if unknown:  # on any number of ranks (the same names on every rank), before the mesh is made
        raise ValueError(f"balance: no facet region {unknown[0]!r}; the mesh has {', '.join(sorted(facet_names))}")
    mesh, cell_tags, facet_tags = model_to_mesh(model, comm, 0, gdim)
    if not balance or comm.size == 1:
        return mesh, cell_tags, facet_tags
    owners = balanced_owners(mesh, facet_tags, [facet_names[n] for n in balance])
    if not comm.bcast(owners is not None, root=0):
        return mesh, cell_tags, facet_tags
    del mesh, cell_tags, facet_tags
    return model_to_mesh(model, comm, 0, gdim, owners)


def read_gmsh(source: str | Path | None, comm: MPI.Comm = MPI.COMM_WORLD, gdim: int = 3,
              balance: Sequence[str] = ()):
    """Mesh and named cell and facet tags from a gmsh ``.msh``/``.geo`` file or (``source=None``) the gmsh model
    of this process (rank 0's). Returns ``(mesh, cells, facets)`` (:class:`NamedTags`). ``gdim``: the geometric
    dimension, the model's own (2 for a planar mesh in the plane z = 0, 3 for a solid); another is a
    ``ValueError`` naming both. Inverted (tangled) or degenerate cells: :class:`~fenics_contact.cells.MeshError`
    naming how many and where.

    Args:
        source: a ``.msh`` or ``.geo`` file, or None for the gmsh model of this process (rank 0's).
        comm: the communicator of the mesh.
        gdim: the geometric dimension, 2 or 3 (the model's own).
        balance: facet region names (the contact surfaces) whose cells are split evenly over the ranks too
            (:func:`distribute`); none by default.

    Returns:
        ``(mesh, cells, facets)``: the mesh and its named cell and facet tags (:class:`NamedTags`).
    """
    import gmsh

    from .cells import check_cells
    from .gmshmodel import prepare

    if gdim not in (2, 3):
        raise ValueError(f"gdim must be 2 or 3, got {gdim!r}")
    path = None if source is None else Path(source)
    error = ""
    if comm.rank == 0 and path is not None and (not path.is_file() or path.suffix not in (".msh", ".geo")):
        error = f"read_gmsh: {str(path)!r} is not a .msh or .geo file"
    error = comm.bcast(error, root=0)
    if error:
        raise ValueError(error)
    # source None: the caller's model; gmsh before 4.9 (Debian 12: 4.8) has no isInitialized, and a model built
    # with its API means the caller initialized it
    own = path is not None or not getattr(gmsh, "isInitialized", lambda: True)()
    if own:
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NoPopup", 1)  # gmsh's questions (a very large mesh?) answered, never asked
    try:
        names, error = {}, ""
        if comm.rank == 0:
            try:
                if path is not None:
                    gmsh.model.add(path.stem)
                    gmsh.merge(str(path))
                    if path.suffix == ".geo":
                        gmsh.model.geo.synchronize()
                dim = gmsh.model.getDimension()  # of the model's entities: a .geo's before it is meshed
                if dim != gdim:
                    what = "the gmsh model" if path is None else repr(str(path))
                    raise ValueError(f"gdim={gdim}, but {what} is {dim}D: give gdim={dim}")
                if path is not None and path.suffix == ".geo":
                    gmsh.model.mesh.generate(gdim)
                names = physical_names(gmsh)
                prepare(gmsh, "the gmsh model" if path is None else repr(str(path)))
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"read_gmsh: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise ValueError(error)
        names = comm.bcast(names, root=0)
        mesh, cell_tags, facet_tags = distribute(gmsh.model, comm, gdim, names, balance)
    finally:
        if own:
            gmsh.finalize()
    check_cells(mesh, "read_gmsh: " + ("the gmsh model" if path is None else repr(str(path))))
    tdim = mesh.topology.dim
    return mesh, NamedTags(cell_tags, names.get(tdim, {})), NamedTags(facet_tags, names.get(tdim - 1, {}))


def check_tags(facet_tags, tags: Mapping[str, int] | None,
               comm: MPI.Comm) -> None:
    """Raise ValueError if a tag of ``tags`` (name -> value; default: every name of :class:`NamedTags`) marks
    no facet on any rank."""
    if tags is None:
        tags = facet_tags.names
    local = np.asarray(facet_tags.values)
    present = sorted(set().union(*comm.allgather(set(np.unique(local).tolist()))))
    for name, value in tags.items():
        if comm.allreduce(int(np.count_nonzero(local == value)), op=MPI.SUM) == 0:
            raise ValueError(f"facet tag {name!r}={value} is absent from the mesh; "
                             f"tags present: {present}")


def tag_boundary(msh, sides: Sequence[tuple[str, Callable[[np.ndarray], np.ndarray]]]) -> NamedTags:
    """Named tags of the boundary facets of a mesh without physical names (e.g. dolfinx's built-in meshes).

    Args:
        msh: the mesh.
        sides: ``(name, where)`` pairs; ``where(x)`` is true on the vertices of the facets to tag (``x`` of shape
            (3, n)). A facet matched by several pairs is tagged once per pair.

    Returns:
        :class:`NamedTags`: the facet tags, numbered 1, 2, ... in the order of ``sides``, by name.
    """
    from dolfinx import mesh as dmesh

    fdim = msh.topology.dim - 1
    indices, values = [], []
    names = {name: i + 1 for i, (name, _) in enumerate(sides)}
    for name, where in sides:
        tag = names[name]
        facets = dmesh.locate_entities_boundary(msh, fdim, where)
        indices.append(facets)
        values.append(np.full(len(facets), tag, dtype=np.int32))
    index = np.concatenate(indices).astype(np.int32)
    order = np.argsort(index)
    facet_tags = dmesh.meshtags(msh, fdim, index[order], np.concatenate(values)[order])
    facet_tags.name = "facet_tags"
    return NamedTags(facet_tags, names)
