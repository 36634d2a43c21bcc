"""The contact-balanced partition: every part gets its share of the cells and of the cells at the contact."""
from pathlib import Path

import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact import read_gmsh
from fenics_contact.app.meshes.mindlin3d import cap_on_block
from fenics_contact.partition import _bisect, balanced_owners


def _points(seed=0):
    """A box [0, 4] x [0, 1] x [-1, 0] of cells, and a contact patch: a disk of radius 0.1 on its top face, off
    centre at x = 3.85 (the planes across the box's longest axis at its quantiles leave the whole patch on one side)."""
    rng = np.random.default_rng(seed)
    X = rng.random((20000, 3)) * [4.0, 1.0, 1.0] - [0.0, 0.0, 1.0]
    r, a = 0.1 * np.sqrt(rng.random(3000)), 2 * np.pi * rng.random(3000)
    patch = np.column_stack([3.85 + r * np.cos(a), 0.5 + r * np.sin(a), -0.01 * rng.random(3000)])
    return np.vstack([X, patch]), np.r_[np.zeros(len(X), bool), np.ones(len(patch), bool)]


@pytest.mark.parametrize("parts", [2, 3, 4])
def test_every_part_gets_its_share_of_cells_and_contact_cells(parts):
    X, near = _points()
    owners = np.empty(len(X), np.int32)
    _bisect(X, near, np.arange(len(X)), 0, parts, owners)
    cells, contact = np.bincount(owners, minlength=parts), np.bincount(owners[near], minlength=parts)
    assert cells.max() - cells.min() <= 1, cells
    # one plane per cut: a share of the patch within 2 % of it (the plain bisection: the whole patch on one part)
    assert np.all(np.abs(contact - near.sum() / parts) <= 0.02 * near.sum()), contact
    plain = np.empty(len(X), np.int32)
    _bisect(X, np.zeros(len(X), bool), np.arange(len(X)), 0, parts, plain)
    assert np.bincount(plain[near], minlength=parts).max() > 0.9 * near.sum()  # what the direction's turn avoids


@pytest.mark.parametrize("parts", [2, 3])
def test_the_cap_on_a_block_splits_its_contact_surfaces(parts):
    """mindlin3d's mesh (graded to the contact point): the cells at the contact surfaces (the cap's and the block's
    top together) split over the parts like the cells, within 5 % (one plane per cut); in two halves, each
    surface's (the mesh is symmetric about the plane x = 0, which turning the plane finds)."""
    comm = MPI.COMM_SELF
    mesh, cells, facets = cap_on_block(comm, h_contact=0.02)
    owners = balanced_owners(mesh, facets.meshtags, [facets["cap_surface"], facets["block_top"]], nparts=parts)
    tdim = mesh.topology.dim
    mesh.topology.create_connectivity(tdim - 1, tdim)
    f_to_c = mesh.topology.connectivity(tdim - 1, tdim)
    original = np.asarray(mesh.topology.original_cell_index)
    counts = np.bincount(owners, minlength=parts)
    assert counts.max() - counts.min() <= 1
    at = {name: np.unique([f_to_c.links(f)[0] for f in facets.meshtags.find(facets[name])])
          for name in ("cap_surface", "block_top")}
    for name, cells_at in [("both", np.union1d(*at.values()))] + (list(at.items()) if parts == 2 else []):
        share = np.bincount(owners[original[cells_at]], minlength=parts)
        assert np.all(np.abs(share - len(cells_at) / parts) <= 0.05 * len(cells_at)), (name, share)


def test_distributed_with_the_contact_balanced_keeps_every_cell_and_facet():
    """The mesh distributed again with the balanced owners has the same cells and tagged facets (counted over
    the ranks), and each rank its share of the contact facets (on one rank: all)."""
    comm = MPI.COMM_WORLD
    plain = cap_on_block(comm, h_contact=0.02, balance=())
    balanced = cap_on_block(comm, h_contact=0.02)
    totals = []
    for mesh, _, facets in (plain, balanced):
        tdim = mesh.topology.dim
        owned_facets = mesh.topology.index_map(tdim - 1).size_local
        own = facets.meshtags.indices < owned_facets
        values = facets.meshtags.values[own]
        totals.append([comm.allreduce(mesh.topology.index_map(tdim).size_local)]
                      + [comm.allreduce(int(np.sum(values == v))) for v in sorted(facets.names.values())])
        if mesh is balanced[0]:
            for name in ("cap_surface", "block_top"):
                mine = int(np.sum(values == facets[name]))
                total = comm.allreduce(mine)
                assert abs(mine - total / comm.size) <= 0.05 * total, (name, mine, total)
    assert totals[0] == totals[1]


def test_a_region_to_balance_that_the_mesh_has_not_is_refused():
    geo = Path(__file__).parents[1] / "fenics_contact" / "app" / "geo" / "half_disk.geo"
    with pytest.raises(ValueError, match="balance: no facet region 'nowhere'; the mesh has "):
        read_gmsh(geo, gdim=2, balance=("nowhere",))
    mesh, _, facets = read_gmsh(geo, gdim=2, balance=("contact",))  # a half disk on its curved side
    comm = mesh.comm
    own = facets.meshtags.indices < mesh.topology.index_map(1).size_local
    mine = int(np.sum(facets.meshtags.values[own] == facets["contact"]))
    total = comm.allreduce(mine)
    assert total > 0 and abs(mine - total / comm.size) <= 0.05 * total
