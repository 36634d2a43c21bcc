"""Tests of fenics_contact.app.meshes (serial and under mpirun)."""
from __future__ import annotations

import math

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx.mesh import compute_midpoints
from mpi4py import MPI

from fenics_contact.app import meshes
from fenics_contact.compat import cell_sizes

comm = MPI.COMM_WORLD


@pytest.fixture(scope="module")
def hertz():
    return meshes.hertz_quarter_disk(comm)


def _total(value: float) -> float:
    return comm.allreduce(value, op=MPI.SUM)


def _integral(mesh, measure) -> float:
    return _total(fem.assemble_scalar(fem.form(fem.Constant(mesh, 1.0) * measure)))


def test_hertz_tags_and_measures(hertz):
    mesh, cell_tags, facet_tags = hertz
    assert sorted(facet_tags.names) == ["contact", "symmetry", "top"] and list(cell_tags.names) == ["disk"]
    for name in ("contact", "symmetry", "top"):
        assert _total(len(facet_tags.find(name))) > 0
    assert _total(len(cell_tags.find("disk"))) > 0
    meshes.check_tags(facet_tags, None, comm)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags)
    assert abs(_integral(mesh, ds(facet_tags["contact"])) - math.pi / 2) < 1e-3
    assert abs(_integral(mesh, ds(facet_tags["symmetry"])) - 1.0) < 1e-12
    assert abs(_integral(mesh, ds(facet_tags["top"])) - 1.0) < 1e-12
    assert abs(_integral(mesh, ufl.dx(domain=mesh)) - math.pi / 4) < 1e-3


def test_hertz_graded(hertz):
    mesh = hertz[0]
    tdim = mesh.topology.dim
    cells = np.arange(mesh.topology.index_map(tdim).size_local, dtype=np.int32)
    h = cell_sizes(mesh, tdim, cells)
    r = np.linalg.norm(compute_midpoints(mesh, tdim, cells)[:, :2], axis=1)
    near = comm.allreduce(h[r < 0.05].max(initial=0.0), op=MPI.MAX)
    far = comm.allreduce(h[r > 0.8].min(initial=np.inf), op=MPI.MIN)
    assert near < 2.0 / 400  # about h_contact = R/400
    assert far > 0.05  # about h_far = R/10
    num_cells = _total(len(cells))
    assert 5_000 < num_cells < 50_000


def test_rectangle_tags():
    for quadrilateral in (False, True):
        mesh, cell_tags, facet_tags = meshes.rectangle(comm, 2.0, 0.5, 8, 4, quadrilateral)
        assert cell_tags is None
        meshes.check_tags(facet_tags, None, comm)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags)
        lengths = {"bottom": 2.0, "right": 0.5, "top": 2.0, "left": 0.5}
        assert sorted(facet_tags.names) == sorted(lengths)
        for name, length in lengths.items():
            assert abs(_integral(mesh, ds(facet_tags[name])) - length) < 1e-12


def test_check_tags_names_missing_tag():
    _, _, facet_tags = meshes.rectangle(comm, 1.0, 1.0, 2, 2)
    with pytest.raises(ValueError, match=r"facet tag 'contact'=7 is absent .*\[1, 2, 3, 4\]"):
        meshes.check_tags(facet_tags, {"bottom": facet_tags["bottom"], "contact": 7}, comm)
    with pytest.raises(ValueError, match=r"no region named 'contact'; the mesh has \['bottom', 'left', "):
        facet_tags["contact"]


@pytest.mark.parametrize("isolate", [False, True])
def test_a_gmsh_model_whose_node_tags_are_not_1_to_n_gives_a_mesh(isolate):
    """dolfinx reads a gmsh model's nodes assuming tags 1..n (``gmshio.extract_geometry`` asserts it): a scene's model
    with a gap in its node tags (here an extra node of tag 10**6; the mindlin3d cap on a block at refinement 2 has
    one) is renumbered and gives its mesh, meshed here or in a child process."""
    import gmsh
    from mpi4py import MPI

    from fenics_contact.app.meshes.gmshutil import _from_gmsh

    def build():
        gmsh.model.add("square")
        s = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [s], 1)
        gmsh.model.setPhysicalName(2, 1, "body")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.25)
        gmsh.model.mesh.generate(2)
        gmsh.model.mesh.addNodes(0, 1, [10**6], [0.0, 0.0, 0.0])

    mesh, cells, _ = _from_gmsh(MPI.COMM_WORLD, build, "a square", isolate=isolate)
    area = MPI.COMM_WORLD.allreduce(mesh.topology.index_map(2).size_local)
    assert area > 0 and cells.names == {"body": 1}
