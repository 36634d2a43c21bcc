"""A user's gmsh mesh with named regions: names from the physical groups, errors naming what exists, the same
mesh on any number of ranks (the deterministic partitioner); a gdim other than the mesh's is one error on every
rank."""
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact.domain import read_gmsh

GEO = Path(__file__).parents[1] / "fenics_contact" / "app" / "geo" / "half_disk.geo"
SPHERE = GEO.with_name("sphere.geo")  # a solid (3D) geometry


def test_names_from_physical_groups():
    comm = MPI.COMM_WORLD
    mesh, cells, facets = read_gmsh(GEO, comm, gdim=2)
    assert cells.names == {"disk": 1} and facets.names == {"contact": 2, "top": 3}
    # The contact arc (half a circle of radius 1) and the diameter (length 2), summed over ranks, owned facets only.
    x = mesh.geometry.x
    nown = mesh.topology.index_map(1).size_local
    from fenics_contact.compat import entities_to_geometry

    def length(name):
        f = facets.find(name)
        f = f[f < nown]
        g = entities_to_geometry(mesh, 1, f)
        return comm.allreduce(float(np.sum(np.linalg.norm(x[g[:, 1]] - x[g[:, 0]], axis=1))))

    assert abs(length("top") - 2.0) < 1e-12
    # Chords of the unit arc: each is shorter than its arc by h^3/24 (to leading order), h <= 0.1 (the .geo's h).
    assert 0 < np.pi - length("contact") < np.pi * 0.1**2 / 24
    with pytest.raises(ValueError, match=r"no region named 'bottom'; the mesh has \['contact', 'top'\]"):
        facets.find("bottom")


def test_bad_source():
    with pytest.raises(ValueError, match="is not a .msh or .geo file"):
        read_gmsh("no_such_mesh.msh", MPI.COMM_WORLD, gdim=2)
    with pytest.raises(ValueError, match="gdim must be 2 or 3"):
        read_gmsh(GEO, MPI.COMM_WORLD, gdim=4)


@pytest.mark.parametrize("has_is_initialized", [True, False])
def test_current_gmsh_model(has_is_initialized, monkeypatch):
    """``read_gmsh(None)`` reads the model built with the gmsh API, also with a gmsh without ``isInitialized``
    (4.8, Debian 12), and leaves the caller's gmsh session open."""
    gmsh = pytest.importorskip("gmsh")
    if not has_is_initialized:
        monkeypatch.delattr(gmsh, "isInitialized", raising=False)
    elif not hasattr(gmsh, "isInitialized"):
        pytest.skip("this gmsh has no isInitialized")
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("square")
        if MPI.COMM_WORLD.rank == 0:
            square = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
            gmsh.model.occ.synchronize()
            bottom = [t for d, t in gmsh.model.getBoundary([(2, square)], oriented=False)
                      if np.isclose(gmsh.model.occ.getCenterOfMass(1, t)[1], 0.0)]
            gmsh.model.addPhysicalGroup(2, [square], 1)
            gmsh.model.setPhysicalName(2, 1, "body")
            gmsh.model.addPhysicalGroup(1, bottom, 2)
            gmsh.model.setPhysicalName(1, 2, "bottom")
            gmsh.option.setNumber("Mesh.CharacteristicLengthMax", 0.25)
            gmsh.model.mesh.generate(2)
        mesh, cells, facets = read_gmsh(None, MPI.COMM_WORLD, gdim=2)
        assert gmsh.model.getCurrent() == "square"  # the caller's session is still open
    finally:
        gmsh.finalize()
    assert cells.names == {"body": 1} and facets.names == {"bottom": 2}
    assert MPI.COMM_WORLD.allreduce(len(facets.find("bottom")), op=MPI.SUM) >= 4


@pytest.mark.parametrize("source,gdim,dim", [(SPHERE, 2, 3), (GEO, 3, 2)])
def test_gdim_other_than_the_mesh_dimension(source, gdim, dim):
    """A 3D geometry read with gdim=2, a planar one with gdim=3: one ValueError naming gdim and the model's
    dimension, before meshing, raised on every rank (none waits for the others)."""
    with pytest.raises(ValueError, match=rf"^read_gmsh: gdim={gdim}, but '.*{source.name}' is {dim}D: "
                                         rf"give gdim={dim}$"):
        read_gmsh(source, MPI.COMM_WORLD, gdim=gdim)


def _two_squares(shift: float, same_group: bool = False, nan: bool = False, gap_tag: bool = False) -> None:
    """A gmsh model on rank 0 (initialised; finalise after): the unit square ``a`` and the unit square ``b`` moved
    up by ``shift``, without shared nodes (no fragment); ``same_group``: the one square in both groups instead;
    ``nan``: a node of ``a`` at NaN; ``gap_tag``: an extra node of tag 10**6 (node tags not 1..n)."""
    import gmsh

    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    if MPI.COMM_WORLD.rank == 0:
        gmsh.model.add("squares")
        a = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
        b = a if same_group else gmsh.model.occ.addRectangle(0, shift, 0, 1, 1)
        gmsh.model.occ.synchronize()
        for tag, (name, s) in enumerate((("a", a), ("b", b)), start=1):
            gmsh.model.addPhysicalGroup(2, [s], tag)
            gmsh.model.setPhysicalName(2, tag, name)
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(2)
        if nan:
            tags, coords, _ = gmsh.model.mesh.getNodes(2, a)
            gmsh.model.mesh.setNode(int(tags[0]), [float("nan"), 0.5, 0.0], [])
        if gap_tag:
            gmsh.model.mesh.addNodes(0, 1, [10**6], [0.0, 0.0, 0.0])


@pytest.mark.parametrize("case, said", [
    (dict(shift=0.0), r"the bodies 'a' and 'b' cover the same region \(100% of one lies inside the other"),
    (dict(shift=0.5), r"the bodies 'a' and 'b' cover the same region \((4[5-9]|5[0-5])% of one"),
    (dict(shift=0.0, same_group=True), r"cells given twice \(the same nodes\), the first at \(.*\) in 'a' and 'b'"),
    (dict(shift=1.0, nan=True), r"has 1 node with a coordinate that is not finite \(NaN or inf\): fix the mesh$"),
])
def test_a_mesh_that_is_not_one_region_once_is_refused(case, said):
    """Two bodies without shared nodes covering the same region (or half of it), a cell in two groups, a node at
    NaN: one error naming it, before any form (not twice the force, dolfinx's "Duplicate mesh entity", or a
    diverged Newton)."""
    import gmsh

    from fenics_contact.cells import MeshError

    try:
        _two_squares(**case)
        with pytest.raises((ValueError, MeshError), match=said):
            read_gmsh(None, MPI.COMM_WORLD, gdim=2)
    finally:
        gmsh.finalize()


@pytest.mark.parametrize("case", [dict(shift=1.0), dict(shift=0.99), dict(shift=1.0, gap_tag=True)])
def test_touching_or_slightly_overlapping_bodies_and_gaps_in_node_tags_are_read(case):
    """Bodies that touch, or overlap by 1 % of their height (an initial penetration contact resolves), are read;
    so is a model whose node tags are not 1..n (dolfinx's reader asserts they are: they are renumbered)."""
    import gmsh

    try:
        _two_squares(**case)
        mesh, cells, _ = read_gmsh(None, MPI.COMM_WORLD, gdim=2)
    finally:
        gmsh.finalize()
    area = MPI.COMM_WORLD.allreduce(float(np.sum(cells.find("a") < mesh.topology.index_map(2).size_local)))
    assert area > 0 and cells.names == {"a": 1, "b": 2}
