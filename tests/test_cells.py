"""A mesh with inverted (tangled) or degenerate cells is refused before any work, in one line naming how many and
where: through read_gmsh, and through ContactProblem for any dolfinx mesh."""
import re

import gmsh
import numpy as np
import pytest
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.cells import MeshError, check_cells


def _signed_areas(x: np.ndarray, tri: np.ndarray) -> np.ndarray:
    a, b, c = x[tri[:, 0]], x[tri[:, 1]], x[tri[:, 2]]
    return (b[:, 0] - a[:, 0]) * (c[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (c[:, 0] - a[:, 0])


def _gmsh_square(move):
    """A gmsh unit square (triangles, named regions) whose interior node nearest the centre is moved by
    ``move(P, Q, R)`` (``Q``, ``R``: the other nodes of the one of its triangles for which the move turns over
    the fewest) on rank 0; returns the count of triangles whose signed area the move changed in sign (turned
    over, or to zero), and the centroid of that triangle after the move."""
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    flipped, centroid = 0, None
    if MPI.COMM_WORLD.rank == 0:
        gmsh.model.add("square")
        s = gmsh.model.occ.addRectangle(0, 0, 0, 1, 1)
        gmsh.model.occ.synchronize()
        gmsh.model.addPhysicalGroup(2, [s], 1)
        gmsh.model.setPhysicalName(2, 1, "body")
        curves = [c for _, c in gmsh.model.getBoundary([(2, s)])]
        gmsh.model.addPhysicalGroup(1, curves, 2)
        gmsh.model.setPhysicalName(1, 2, "boundary")
        gmsh.option.setNumber("Mesh.MeshSizeMax", 0.1)
        gmsh.model.mesh.generate(2)
        tags, coords, _ = gmsh.model.mesh.getNodes(2, s)  # the interior nodes
        x = coords.reshape(-1, 3)
        p = int(np.argmin(np.linalg.norm(x[:, :2] - 0.5, axis=1)))
        _, elements, nodes = gmsh.model.mesh.getElements(2, s)
        tri = nodes[0].reshape(-1, 3).astype(np.int64)
        all_tags, all_coords, _ = gmsh.model.mesh.getNodes()
        index = {int(t): i for i, t in enumerate(all_tags)}
        X = all_coords.reshape(-1, 3)
        local = np.vectorize(index.get)(tri)
        before = _signed_areas(X, local)
        mine = index[int(tags[p])]
        best = None
        for one in local[np.any(tri == tags[p], axis=1)]:  # the triangle whose move turns over the fewest
            q, r = [X[i] for i in one if i != mine]
            moved = X.copy()
            moved[mine] = move(x[p], q, r)
            after = _signed_areas(moved, local)
            count = int(np.count_nonzero((np.sign(after) != np.sign(before)) | (np.abs(after) < 1e-12)))
            if best is None or count < best[0]:
                best = (count, moved[mine], (moved[mine] + q + r)[:2] / 3)
        flipped, new, centroid = best
        gmsh.model.mesh.setNode(int(tags[p]), list(new), [])
    return MPI.COMM_WORLD.bcast((flipped, centroid), root=0)


def test_a_tangled_gmsh_mesh_is_refused_naming_its_inverted_cells():
    """The centre node pushed through the far edge of one of its triangles (to its mirror image, past the
    edge by 30 % of the edge's distance): the cells it turns over overlap their neighbours; read_gmsh names as
    many inverted cells as turned over, in one line, with their place."""
    try:
        flipped, _ = _gmsh_square(lambda p, q, r: (q + r) / 2 + 0.3 * ((q + r) / 2 - p))
        with pytest.raises(MeshError) as err:
            fc.read_gmsh(None, MPI.COMM_WORLD, gdim=2)
    finally:
        gmsh.finalize()
    message = str(err.value)
    assert "\n" not in message and "degenerate" not in message
    assert flipped >= 1
    assert re.search(rf"has {flipped} inverted \(tangled\) cells? of \d+ (at|in the box) \(", message), message


def test_a_zero_area_cell_is_refused_at_its_place():
    """The centre node moved onto the middle of the far edge of one of its triangles (the one for which no other
    turns over): that triangle has zero area; read_gmsh names one degenerate cell at its centroid, the edge's
    midpoint."""
    try:
        flipped, centroid = _gmsh_square(lambda p, q, r: (q + r) / 2)
        with pytest.raises(MeshError) as err:
            fc.read_gmsh(None, MPI.COMM_WORLD, gdim=2)
    finally:
        gmsh.finalize()
    message = str(err.value)
    assert flipped == 1
    assert "\n" not in message and "inverted" not in message, message
    found = re.search(r"has 1 degenerate \(zero area or volume\) cell of \d+ at \(([^,]+), ([^)]+)\)", message)
    assert found, message
    assert np.allclose([float(found[1]), float(found[2])], centroid, atol=1e-3)


@pytest.mark.parametrize("cell", ["triangle", "quadrilateral", "tetrahedron"])
def test_contact_problem_refuses_a_mesh_with_an_inverted_cell(cell):
    """Built-in meshes (their cells of either orientation) pass; a vertex moved through its neighbours' facets
    (beyond the next vertex along x) makes ContactProblem refuse the mesh before any form is compiled."""
    comm = MPI.COMM_WORLD
    if cell == "tetrahedron":
        msh = dmesh.create_unit_cube(comm, 3, 3, 3)
    else:
        msh = dmesh.create_unit_square(comm, 4, 4, getattr(dmesh.CellType, cell))
    check_cells(msh)  # either orientation is fine
    x = msh.geometry.x
    h = 1.0 / (3 if cell == "tetrahedron" else 4)
    centre = np.full(msh.geometry.dim, 0.5 if cell != "tetrahedron" else 1 / 3)
    inner = np.flatnonzero(np.all(np.isclose(x[:, :msh.geometry.dim], centre), axis=1))
    x[inner, 0] += 1.5 * h  # past the next vertex: its cells fold over their neighbours
    u = fem.Function(fc.function_space(msh, "Lagrange", 1, (msh.geometry.dim,)))
    with pytest.raises(MeshError, match=r"^the mesh has \d+ inverted \(tangled\) cells? of \d+ "):
        fc.ContactProblem(u, fc.LinearElastic(1.0, 0.3), fem.Constant(msh, 0.0))


def test_a_program_reading_a_tangled_mesh_file_ends_in_one_line(tmp_path_factory, capsys):
    """A tangled mesh written to a .msh file and read by a program run through the demos' entry (cli.main): exit
    status 1 and one line naming the file and the inverted cells, no traceback."""
    from fenics_contact.app import cli

    comm = MPI.COMM_WORLD
    path = comm.bcast(str(tmp_path_factory.mktemp("mesh") / "tangled.msh") if comm.rank == 0 else None)
    try:
        flipped, _ = _gmsh_square(lambda p, q, r: (q + r) / 2 + 0.3 * ((q + r) / 2 - p))
        if comm.rank == 0:
            gmsh.write(path)
    finally:
        gmsh.finalize()
    comm.barrier()
    with pytest.raises(SystemExit) as ended:
        cli.main(lambda argv: fc.read_gmsh(path, comm, gdim=2), [])
    assert ended.value.code == cli.EXIT_ERROR
    err = capsys.readouterr().err.strip().splitlines()
    if comm.rank == 0:
        assert len(err) == 1 and "Traceback" not in err[0], err
        assert f"error: read_gmsh: {path!r} has {flipped} inverted (tangled) cell" in err[0], err


@pytest.mark.parametrize("scale, said", [(1e200, r"has coordinates up to 1e\+200: its cells' areas \(size\^2, up to "
                                                 r"[0-9.e+]+\^2\) overflow floating point: scale it to other units$"),
                                         (1e-300, r"has cells of size [0-9.e-]+: their areas \(size\^2\) underflow "
                                                  r"floating point: scale it to other units$"),
                                         (np.inf, r"has \d+ nodes? with a coordinate that is not finite")])
def test_coordinates_out_of_floating_point_range_are_said_as_such(scale, said):
    """A unit square scaled by 1e200 (areas overflow) or 1e-300 (areas underflow), or with infinite coordinates: one
    line saying so, not "degenerate cells"; scaled by 1e100 or 1e-100 it is a mesh like any other."""
    comm = MPI.COMM_WORLD
    for ok in (1e100, 1e-100):
        msh = dmesh.create_unit_square(comm, 4, 4)
        msh.geometry.x[:] *= ok
        check_cells(msh)
    msh = dmesh.create_unit_square(comm, 4, 4)
    with np.errstate(invalid="ignore"):  # inf x 0: a NaN, not finite either
        msh.geometry.x[:, :2] *= scale
    with pytest.raises(MeshError, match="^the mesh " + said):
        check_cells(msh)
