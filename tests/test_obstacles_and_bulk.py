"""Obstacles (gap, normal, motion, linearization) and bulk models beyond the block's linear elasticity."""
import numpy as np
import pytest
import ufl
from dolfinx import fem, mesh
from mpi4py import MPI

from fenics_contact.app.scenes import block
from fenics_contact.compat import function_space
from fenics_contact.contact import ContactSurface
from fenics_contact.laws import CrossConstraints, Penalty
from fenics_contact.materials import LinearElastic
from fenics_contact.obstacles import Cylinder, HalfPlane, Sphere
from fenics_contact.problem import ContactProblem, Dirichlet
from fenics_contact.solver import Solver


def _evaluate(obstacle, x, t):
    """Gap and normal of ``obstacle`` at the point ``x`` for load ``t`` (UFL, assembled on a unit cell)."""
    d = len(x)
    m = mesh.create_unit_square(MPI.COMM_SELF, 1, 1) if d == 2 else mesh.create_unit_cube(MPI.COMM_SELF, 1, 1, 1)
    load = fem.Constant(m, float(t))
    obstacle.bind(load)
    X = ufl.as_vector([float(c) for c in x])
    vals = [obstacle.gap(X)] + [obstacle.normal(X)[i] for i in range(d)]
    return np.array([fem.assemble_scalar(fem.form(v * ufl.dx(domain=m))) for v in vals])


@pytest.mark.parametrize("obstacle,x,t,gap,normal", [
    (HalfPlane([0, 0], [0, 1]), [0.3, -0.2], 0.0, 0.2, [0, 1]),
    (HalfPlane([1, 1], [1, 1], motion=[0.5, 0.5]), [1.0, 1.0], 1.0, 0.5 * np.sqrt(2), np.array([1, 1]) / np.sqrt(2)),
    (Cylinder([0, 0], 2.0), [0.0, 1.5], 0.0, 0.5, [0, 1]),
    (Cylinder([0, 0], 2.0, motion=[1.0, 0.0]), [3.5, 0.0], 1.0, -0.5, [1, 0]),
    (Cylinder([0, 0], 1.0, body_outside=False), [0.0, 1.25], 0.0, 0.25, [0, -1]),
    (Cylinder([0, 0, 0], 1.0, axis=[0, 0, 1]), [0.0, 0.8, 7.0], 0.0, 0.2, [0, 1, 0]),
    (Sphere([0, 0, 1], 1.0, motion=[0, 0, -0.5]), [0.0, 0.0, 0.0], 1.0, 0.5, [0, 0, -1]),
])
def test_gap_and_normal(obstacle, x, t, gap, normal):
    values = _evaluate(obstacle, x, t)
    assert np.isclose(values[0], gap, atol=1e-14)
    assert np.allclose(values[1:], normal, atol=1e-14)


@pytest.mark.parametrize("t,f", [(0.0, 0.0), (0.25, 0.25), (1.0, 1.0), (1.5, 1.0), (2.0, 1.0), (2.5, 0.5),
                                 (3.0, 0.0), (4.0, 0.0)])
def test_obstacle_load_path(t, f):
    """An obstacle with the path ``(t_k, f_k)`` has moved by ``f(t) motion`` (piecewise linear, constant beyond the
    ends): the UFL gap and the numeric ``factor`` agree with the interpolation."""
    plane = HalfPlane([0.0, 1.0], [0.0, -1.0], motion=[0.0, -0.4])
    plane.path = ([0.0, 1.0, 2.0, 3.0], [0.0, 1.0, 1.0, 0.0])
    assert plane.factor(t) == pytest.approx(f, abs=1e-15)
    gap = _evaluate(plane, [0.0, 0.5], t)[0]  # the plane at y = 1 - 0.4 f(t), the point at y = 0.5 below it
    assert gap == pytest.approx(0.5 - (1.0 - 0.4 * f), abs=1e-14)


def test_obstacle_path_refused():
    """A load path that is not ``(t_k, f_k)`` with increasing ``t_k``: one line naming it."""
    plane = HalfPlane([0.0, 0.0], [0.0, 1.0], motion=[0.0, 1.0])
    plane.path = ([1.0, 0.0], [0.0, 1.0])
    with pytest.raises(ValueError, match="obstacle path"):
        plane.factor(0.5)


def test_3d_box_on_a_plane_gauss_and_augmentation():
    """Unit cube pressed 0.01 onto z = 0, free lateral faces (symmetry on x = 0, y = 0):
    uniaxial stress, p = E (0.01 - d) with d = p / K for penalty; exact with augmentation."""
    comm = MPI.COMM_WORLD
    msh = mesh.create_unit_cube(comm, 3, 3, 3)
    fdim = 2
    marks = {1: lambda x: np.isclose(x[2], 0), 2: lambda x: np.isclose(x[2], 1),
             3: lambda x: np.isclose(x[0], 0), 4: lambda x: np.isclose(x[1], 0)}
    facets = [(t, mesh.locate_entities_boundary(msh, fdim, f)) for t, f in marks.items()]
    idx = np.concatenate([f for _, f in facets])
    vals = np.concatenate([np.full(len(f), t, dtype=np.int32) for t, f in facets])
    order = np.argsort(idx)
    tags = mesh.meshtags(msh, fdim, idx[order], vals[order])
    E, nu, d = 1000.0, 0.3, 0.01
    results = {}
    for name, law, aug in [("penalty", Penalty(1e5), 0), ("cross", CrossConstraints(1e5, 5.0), 10)]:
        V = function_space(msh, "Lagrange", 1, (3,))
        u = fem.Function(V)
        load = fem.Constant(msh, 0.0)
        bcs = [Dirichlet(V.sub(i), fem.locate_dofs_topological(V.sub(i), fdim, tags.find(t)), a)
               for i, t, a in [(2, 2, -d), (0, 3, 0.0), (1, 4, 0.0)]]
        c = ContactSurface(u, tags, 1, HalfPlane([0, 0, 0], [0, 0, 1]), law, load, quadrature="gauss")
        s = Solver(ContactProblem(u, LinearElastic(E, nu), load, bcs, [c]), augment_max=aug, quiet=True)
        s.run([1.0])
        results[name] = (c.mean_pressure(), c.max_penetration(), c.total_force()[2])
    p, pen, force = results["penalty"]
    assert np.isclose(pen, p / 1e5, rtol=1e-6) and np.isclose(p, E * (d - pen), rtol=1e-6)
    assert np.isclose(force, p, rtol=1e-10)  # unit area
    assert np.isclose(results["cross"][0], E * d, rtol=1e-8)


def test_neohookean_block_tends_to_linear_at_small_strain():
    """Neo-Hookean and linear elastic blocks agree to O(strain) at small load, differ at the paper's 16 %."""
    law = lambda: CrossConstraints(1e5, 0.0)  # noqa: E731
    rel = {}
    for t in (1e-3, 1.0):
        setups = {m: block.build(law(), model=m) for m in ("linear", "neohookean")}
        p = {}
        for m, s in setups.items():
            Solver(s.problem, augment_max=10, quiet=True).run([t])
            p[m] = s.figures()["contact_pressure"]
        rel[t] = abs(p["neohookean"] - p["linear"]) / p["linear"]
    assert rel[1e-3] < 1e-3 and rel[1.0] > 10 * rel[1e-3]


@pytest.mark.parametrize("law", [Penalty(1e5), CrossConstraints(1e5, 0.0)], ids=["penalty", "cross"])
def test_moving_rigid_cylinder_indents_a_block(law):
    """A rigid disk (R = 1) moved 0.02 into an elastic block: curved gap of x + u, equilibrium, Newton rate."""
    from fenics_contact.app.meshes import rectangle

    comm = MPI.COMM_WORLD
    msh, _, tags = rectangle(comm, 1.0, 1.0, 20, 20)
    V = function_space(msh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    load = fem.Constant(msh, 0.0)
    dofs = lambda i, t: fem.locate_dofs_topological(V.sub(i), 1, tags.find(t))  # noqa: E731
    bcs = [Dirichlet(V.sub(1), dofs(1, "bottom")), Dirichlet(V.sub(0), dofs(0, "left"))]
    disk = Cylinder([0.0, 2.0], 1.0, motion=[0.0, -0.02])
    c = ContactSurface(u, tags, "top", disk, law, load)
    problem = ContactProblem(u, LinearElastic(1000.0, 0.3), load, bcs, [c])
    solver = Solver(problem, quiet=True)
    solver.run([0.5, 1.0])
    force = c.total_force()
    reaction = problem.reaction(dofs(1, "bottom"))
    assert force[1] < 0 and np.isclose(-force[1], reaction, rtol=1e-8)  # obstacle pushes down, base pushes up
    x, g, p = c.surface_values()
    assert p[0] == p.max() and p[-1] == 0.0  # loaded under the disk's axis, free at the far edge
    # quadratic convergence once the contact set has settled (consistent tangent of the curved
    # gap): measured from the first residual, the last step about doubles the digits gained
    r = np.array(solver.records[-1].residuals[-1])
    assert r[-1] < 1e-10 * r[0] and len(r) <= 8
    assert np.log(r[-1] / r[0]) / np.log(r[-2] / r[0]) > 1.8
