"""Method ``coulomb`` in 3D: the Coulomb disk (two tangential directions) on the condensed system.

A box (``nu = 0``: pressing causes no lateral strain, so the pressed base carries no tangential traction) rests on
the rigid plane ``z = 0``, its top pressed down then dragged along a direction 30 degrees off ``x``:

- dragged a little with much friction: every base vertex sticks: no tangential displacement at the base, every
  traction inside its disk;
- dragged far with little friction: every base vertex slides and, once the sliding is steady, the friction
  force is ``mu P`` (1e-10) opposite the drag (1e-6 in angle): a disk, not a square (a box law would
  put it at 45 degrees or beyond ``mu P``); each vertex's traction on its disk's rim, opposite its slip.

The same box between two bodies (a box on a box, both ``nu = 0``, non-matching meshes): the same steady sliding.
"""
import numpy as np
import pytest
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app.meshes import stacked_blocks
from fenics_contact.compat import cell_partitioner
from fenics_contact.condensed import SLIP, STICK
from fenics_contact.domain import NamedTags

E, PRESS = 1000.0, 5e-3
THETA = np.radians(30.0)
DIRECTION = np.array([np.cos(THETA), np.sin(THETA), 0.0])


def _box(comm, n=(4, 4, 2)):
    """The box [0, 1] x [0, 1] x [0, 0.5] (tetrahedra) and its facets ``base`` (z = 0), ``top``."""
    msh = dmesh.create_box(comm, [np.zeros(3), np.array([1.0, 1.0, 0.5])], list(n), dmesh.CellType.tetrahedron,
                           partitioner=cell_partitioner())
    found = [(t, dmesh.locate_entities_boundary(msh, 2, lambda x, c=c: np.isclose(x[2], c)))
             for t, c in ((1, 0.0), (2, 0.5))]
    idx = np.concatenate([f for _, f in found]).astype(np.int32)
    val = np.concatenate([np.full(len(f), t, dtype=np.int32) for t, f in found])
    order = np.argsort(idx)
    return msh, NamedTags(dmesh.meshtags(msh, 2, idx[order], val[order]), {"base": 1, "top": 2})


def _top_motion(V, facets, tag, drag):
    """The top pressed down by PRESS over t in [0, 1], then moved by ``drag`` along DIRECTION over [1, 2]."""
    out = []
    for k in range(3):
        dofs = fem.locate_dofs_topological(V.sub(k), 2, facets.find(tag))
        if k == 2:
            out.append(fc.Dirichlet(V.sub(2), dofs, -PRESS, ([0.0, 1.0, 2.0], [0.0, 1.0, 1.0])))
        else:
            out.append(fc.Dirichlet(V.sub(k), dofs, drag * DIRECTION[k], ([0.0, 1.0, 2.0], [0.0, 0.0, 1.0])))
    return out


def _on_plane(mu, drag, comm=MPI.COMM_WORLD):
    msh, facets = _box(comm)
    law = fc.make_law("coulomb", mu=mu)
    V = fc.function_space(msh, "Lagrange", 1, (3,))
    u = fem.Function(V)
    load = fem.Constant(msh, 0.0)
    c = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(E, 0.0), load, _top_motion(V, facets, "top", drag), [c],
                                step_solver=fc.step_solver_for([c]))
    return problem, c


def _check_steady_sliding(prof, N, T, mu, closed):
    """Every closed vertex slides on its disk's rim; the friction force is mu |N| opposite DIRECTION."""
    p, q = prof["pressure"], prof["traction"]
    assert np.count_nonzero(closed) >= 9 and np.all(prof["state"][closed] == SLIP)
    assert np.allclose(np.linalg.norm(q[closed], axis=1), mu * p[closed], rtol=1e-10, atol=0)
    assert abs(np.linalg.norm(T) - mu * np.linalg.norm(N)) <= 1e-10 * np.linalg.norm(N), (T, N)
    # The slip directions approach the drag's from step to step (the elastic part of the slip shrinks against the
    # step's rigid motion): within 1e-6 after four steps; a box (square) law would be 15 degrees off.
    assert np.linalg.norm(np.cross(T / np.linalg.norm(T), -DIRECTION)) < 1e-6 and T @ DIRECTION < 0, T


def test_box_on_plane_sticks_under_a_small_drag():
    """mu = 2, a drag of PRESS / 20: every base vertex sticks (no tangential displacement at the base, every
    traction strictly inside its disk)."""
    mu = 2.0
    problem, c = _on_plane(mu, PRESS / 20)
    solver = fc.Solver(problem, quiet=True)
    solver.run([1.0, 2.0])
    assert all(r.converged for r in solver.records)
    prof = c.friction_profile()
    p, q = prof["pressure"], prof["traction"]
    closed = p > 0
    assert np.count_nonzero(closed) == len(p) == 25 and np.all(prof["state"] == STICK)
    assert np.all(np.linalg.norm(q, axis=1) < mu * p)
    assert np.linalg.norm(q[:, :2], axis=1).max() > 1e-3 * p.max()  # the drag does load the base
    # the base displacement in its plane: zero where it sticks (from the pressed state, which slid nowhere)
    V = problem.u.function_space
    X = V.tabulate_dof_coordinates()
    n = V.dofmap.index_map.size_local
    base = np.flatnonzero(np.isclose(X[:n, 2], 0.0))
    ut = np.concatenate(problem.comm.allgather(problem.u.x.array[(3 * base[:, None] + np.arange(2)).ravel()]))
    assert np.abs(ut).max() <= 1e-12 * PRESS


def test_box_on_plane_slides_on_the_disk():
    """mu = 0.3, a drag of 40 PRESS in four steps (a rigid motion: small strain): steady sliding on the rim of
    the Coulomb disk, the friction force mu P opposite the drag, 30 degrees off x."""
    mu = 0.3
    problem, c = _on_plane(mu, 40 * PRESS)
    solver = fc.Solver(problem, quiet=True)
    solver.run([1.0, 1.25, 1.5, 1.75, 2.0])
    assert all(r.converged for r in solver.records)
    prof = c.friction_profile()
    F = c.contact_force()
    N, T = np.array([0.0, 0.0, F[2]]), np.array([F[0], F[1], 0.0])
    _check_steady_sliding(prof, N, T, mu, prof["pressure"] > 0)
    assert all(r.newton_iterations <= 12 for r in solver.records), [r.newton_iterations for r in solver.records]


def _blocks3d(mu, comm=MPI.COMM_WORLD, drag=40 * PRESS):
    """A box on a box (non-matching meshes, nu = 0), the lower one clamped at its base, the upper one's top pressed
    then dragged along DIRECTION."""
    msh, _, ft = stacked_blocks(comm, 1.0, 0.5, 0.5, (3, 3, 2), (2, 2, 1), 0.0)
    law = fc.make_law("coulomb", mu=mu)
    V = fc.function_space(msh, "Lagrange", 1, (3,))
    u = fem.Function(V)
    load = fem.Constant(msh, 0.0)
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", k) for k in range(3)]
    dirichlet += _top_motion(V, ft, "upper_top", drag)
    contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(E, 0.0), load, dirichlet, contacts,
                                step_solver=fc.step_solver_for(contacts))
    return problem, contacts[0]


def test_box_on_box_slides_on_the_disk():
    """Two bodies: the upper box dragged far on the lower one slides steadily, the friction force mu P exactly
    opposite the drag."""
    mu = 0.3
    problem, c = _blocks3d(mu)
    assert isinstance(c, fc.CondensedTwoBody)
    solver = fc.Solver(problem, quiet=True)
    solver.run([1.0, 1.25, 1.5, 1.75, 2.0])
    assert all(r.converged for r in solver.records)
    prof = c.friction_profile()
    _check_steady_sliding(prof, c.total_force(), c.tangential_force(), mu, prof["pressure"] > 0)


def test_condensed_size_is_bounded(monkeypatch):
    """A condensed system above the dense bound is refused when the surface is made, in one line naming the
    surface and its vertices."""
    from fenics_contact.condensed import operator

    monkeypatch.setattr(operator, "MAX_CONDENSED", 50)
    with pytest.raises(ValueError, match=r"^method 'coulomb': contact: 25 contact vertices .* gives 75 contact dofs, "
                       r"more than the 50"):
        _on_plane(0.3, PRESS)
    with pytest.raises(ValueError, match=r"^method 'coulomb': twobody: \d+ slave vertices within the search radius"):
        _blocks3d(0.3)


@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="compares a parallel run with the serial one")
def test_parallel_equals_serial():
    """Under mpirun -n 2: the box dragged on the plane (partial slip after one drag step) and on the box give the
    serial contact forces and friction profile to 1e-8."""
    out = []
    for comm in (MPI.COMM_WORLD, MPI.COMM_SELF):
        problem, c = _on_plane(0.3, 2 * PRESS, comm)
        fc.Solver(problem, quiet=True).run([1.0, 1.5])
        prof = c.friction_profile()
        problem2, c2 = _blocks3d(0.3, comm)
        fc.Solver(problem2, quiet=True).run([1.0, 1.5])
        out.append(np.concatenate([c.contact_force(), prof["pressure"], prof["traction"].ravel(), c2.total_force(),
                                   c2.tangential_force(), c2.friction_profile()["traction"].ravel()]))
    assert np.allclose(out[0], out[1], rtol=0, atol=1e-8 * np.abs(out[1]).max())
