"""A linear bulk's residual as a product with its kept Jacobian (``kept.AffineResidual``): the same vector as the
assembled residual with its Dirichlet lifting, at any state, load and Dirichlet value."""
import dolfinx
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.compat import function_space, petsc_vec


def _plate(spring: float = 0.0):
    """A plate: bottom fixed, top pulled down with t, the left side on rollers, a traction on the right side that
    follows t and a body force on its own load path; with a ``spring``: the vanishing spring of
    :class:`fenics_contact.Stabilised` (its Jacobian changes with the load)."""
    comm = MPI.COMM_WORLD
    mesh = dolfinx.mesh.create_unit_square(comm, 12, 9)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    fdim = mesh.topology.dim - 1

    def side(test):
        return dolfinx.mesh.locate_entities_boundary(mesh, fdim, test)

    def fixed(component, facets, amplitude=0.0):
        Vi = V.sub(component)
        return fc.Dirichlet(Vi, fem.locate_dofs_topological(Vi, fdim, facets), amplitude)

    bottom, top = side(lambda x: np.isclose(x[1], 0.0)), side(lambda x: np.isclose(x[1], 1.0))
    left = side(lambda x: np.isclose(x[0], 0.0))
    dirichlet = [fixed(0, bottom), fixed(1, bottom), fixed(1, top, -0.02), fixed(0, left)]
    right = side(lambda x: np.isclose(x[0], 1.0))
    tags = dolfinx.mesh.meshtags(mesh, fdim, right, np.full(len(right), 1, np.int32))
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags)
    load = fem.Constant(mesh, 0.0)
    tractions = [(ufl.as_vector((30.0, 10.0)), ds(1)), (ufl.as_vector((0.0, -5.0)), ufl.dx, ([0.0, 1.0], [0.0, 3.0]))]
    if spring:
        return fc.Stabilised(u, fc.LinearElastic(1000.0, 0.3), load, dirichlet, [], tractions, spring, ufl.dx)
    return fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load, dirichlet, [], tractions)


def test_the_linear_bulk_residual_is_its_kept_jacobian_times_the_state():
    problem = _plate()
    affine = problem.bulk_residual
    assert not affine.ready()  # no Jacobian kept yet: the residual is assembled
    problem.J(problem.create_vector(), problem.create_matrix())
    assert affine.ready()  # a linear material: its Jacobian does not change, the residual is the product
    rng = np.random.default_rng(MPI.COMM_WORLD.rank)
    x = petsc_vec(problem.u).copy()
    b, assembled = problem.create_vector(), problem.create_vector()
    for t in (0.4, 1.0, 1.0):  # a new load (new loads and Dirichlet values), then the same load at a new state
        problem.set_load(t)
        x.array[:] = 1e-2 * rng.standard_normal(x.array.shape)
        assert affine.ready()
        problem.F(x, b)
        problem.bulk_jacobian.reuse = False  # assembled, as a fresh solve does
        assert not affine.ready()
        problem.F(x, assembled)
        problem.bulk_jacobian.reuse = True
        r0, lifting = affine._vectors[:2]
        assert r0.norm() > 0 and lifting.norm() > 0  # both parts of the product carry something
        assert assembled.norm() > 0
        b.axpy(-1.0, assembled)
        assert b.norm() <= 1e-12 * assembled.norm(), (t, b.norm() / assembled.norm())


def test_a_jacobian_that_changes_with_the_load_is_assembled_by_the_jacobian_alone():
    """A Jacobian with a load-scaled spring: at a new load the residual is assembled (not the product with the kept
    matrix of the last load, nor a matrix assembled for it: the tangent predictor evaluates three loads a step)."""
    problem = _plate(spring=50.0)
    A = problem.create_matrix()
    x = problem.create_vector()
    problem.set_load(0.5)
    problem.J(x, A)
    kept = problem.bulk_jacobian.matrix
    assert problem.bulk_residual.ready()
    problem.set_load(0.6)  # the spring k (1 - t) / t changes
    assert not problem.bulk_residual.ready()
    problem.F(x, problem.create_vector())
    assert problem.bulk_jacobian.matrix is kept and not problem.bulk_residual.ready()
    problem.J(x, A)
    assert problem.bulk_residual.ready()


def test_a_multipliers_jacobian_assembles_the_bulk_once():
    """A multiplier's Jacobian (its pattern explicit, widened by the contact's coupling at the first pairing): the
    kept bulk matrix is assembled once, added at every Jacobian (the first and the widened one included), and the
    Jacobian equals the one assembled from the forms."""
    import fenics_contact.kept as kept
    from fenics_contact.app.scenes import build, mindlin
    from fenics_contact.methods import make_law

    law = fc.Friction(make_law("lagrange"), mu=0.3, omega_t=mindlin.DEFAULT_OMEGA_T)
    problem = build("mindlin", law=law, sliding="small", ratios=(0.5,)).problem
    problem.set_load(0.5)
    x, b, A = petsc_vec(problem.u).copy(), problem.create_vector(), problem.create_matrix()
    bulk = []
    original = kept.assemble_matrix
    kept.assemble_matrix = lambda M, a, *args: (bulk.append(a), original(M, a, *args))
    try:
        for _ in range(2):  # the first Jacobian (the contact widens A's pattern) and one of the same pattern
            problem.F(x, b)
            problem.J(x, A)
    finally:
        kept.assemble_matrix = original
    assert len(bulk) == 1 and bulk[0] is problem.bulk_jacobian.form
    problem.bulk_jacobian.reuse = False  # assembled from the forms, as a fresh solve does
    fresh = A.duplicate()
    problem.J(x, fresh)
    problem.bulk_jacobian.reuse = True
    fresh.axpy(-1.0, A)
    assert A.norm() > 0 and fresh.norm() <= 1e-13 * A.norm()
