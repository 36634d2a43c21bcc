"""The scenes' gmsh geometry sources (top-level meshes/*.geo): each builder meshes its .geo with the builder's
parameters; a missing source is a one-line error naming it."""
import math

import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI

from fenics_contact.app import meshes
from fenics_contact.app.meshes.gmshutil import geo_path

comm = MPI.COMM_WORLD
SOURCES = ("hertz", "pin", "sheet", "rings", "two_disks", "sphere", "seal", "half_disk", "mindlin3d")


def _length(mesh, facets, name):
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags)
    return comm.allreduce(fem.assemble_scalar(fem.form(fem.Constant(mesh, 1.0) * ds(facets[name]))), op=MPI.SUM)


@pytest.mark.parametrize("name", SOURCES)
def test_every_source_is_in_meshes(name):
    assert geo_path(name).name == f"{name}.geo"


def test_missing_source_is_a_clear_error(monkeypatch, tmp_path):
    monkeypatch.setenv("FENICS_CONTACT_MESHES", str(tmp_path))
    with pytest.raises(FileNotFoundError, match=r"gmsh geometry '.*pin\.geo' not found"):
        meshes.pin_plate(comm)


def test_parameters_reach_the_geometry():
    """Non-default parameters (the plate's size, the radius) are those of the mesh: named boundary lengths."""
    mesh, cells, facets = meshes.pin_plate(comm, R=0.5, half_width=3.0, below=2.0, above=4.0, h_contact=0.05)
    assert abs(_length(mesh, facets, "top") - 3.0) < 1e-12
    assert abs(_length(mesh, facets, "free") - (3.0 + 6.0)) < 1e-12
    assert abs(_length(mesh, facets, "contact") - math.pi * 0.5) < 1e-3
    mesh, cells, facets = meshes.sheet_over_cylinder(comm, 2.0, 0.5, 1.5, 8, 2, 3, order=2, cylinder=(0.7, 6, 2))
    assert sorted(cells.names) == ["cylinder", "sheet"]
    assert abs(_length(mesh, facets, "end") - 0.5) < 1e-12
    assert abs(_length(mesh, facets, "cylinder_fixed") - math.pi * 0.7) < 1e-3
