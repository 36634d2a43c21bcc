"""One results API on every contact surface (:class:`~fenics_contact.surface.Surface`): ``total_force()``,
``point_values(reference, kind)``, ``surface_values(kind)`` (``point_values(reference=True, kind)``) and
``friction_profile()`` (``ValueError`` naming the surface on a frictionless one), with the same signatures and
meaning: positions (n, gdim), reference ones at the surface's points, current ones the reference plus the
displacement there; gap > 0 penetration, pressure > 0 compression. Every surface sets ``law``."""
import inspect

import numpy as np
import pytest
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app.meshes import stacked_blocks
from fenics_contact.app.scenes import build
from fenics_contact.collocation import CollocatedSurface
from fenics_contact.compat import collapse
from fenics_contact.contact import is_mixed

RESULTS = ("total_force", "point_values", "surface_values", "friction_profile")
SURFACES = (fc.ContactSurface, fc.FrictionalContact, fc.BoundContact, fc.NitscheContact, fc.MultiplierContact,
            fc.TwoBodyMultiplier, fc.CondensedContact, fc.CondensedTwoBody, CollocatedSurface)
E, NU, H, D = 1000.0, 0.3, 2.0, 0.32


def _parameters(f) -> list[tuple]:
    return [(p.name, p.kind, p.default) for p in inspect.signature(f).parameters.values()]


@pytest.mark.parametrize("cls", SURFACES, ids=lambda c: c.__name__)
def test_results_have_the_declared_signatures(cls):
    """The four results with :class:`Surface`'s parameters; ``surface_values`` is Surface's own (the reference
    ``point_values``)."""
    for name in RESULTS:
        assert _parameters(getattr(cls, name)) == _parameters(getattr(fc.Surface, name)), (cls.__name__, name)
    assert cls.surface_values is fc.Surface.surface_values, cls.__name__


def _surface_displacement(u: fem.Function, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Coordinates (n, gdim) and displacement (n, gdim) of the displacement dofs on the local ``facets``, from
    every rank (read from the unknown's dofs: independent of the surfaces' own output)."""
    V = u.function_space
    mesh = V.mesh
    gdim = mesh.geometry.dim
    if is_mixed(V):
        Vd, to_w = collapse(V.sub(0))
        values = u.x.array[np.asarray(to_w)]
    else:
        Vd, values = V, u.x.array
    mesh.topology.create_connectivity(mesh.topology.dim - 1, 0)
    dofs = fem.locate_dofs_topological(Vd, mesh.topology.dim - 1, facets)
    local = (Vd.tabulate_dof_coordinates()[dofs, :gdim], values.reshape(-1, gdim)[dofs])
    return tuple(np.concatenate(a) for a in zip(*mesh.comm.allgather(local)))


def _at(points: np.ndarray, where: np.ndarray, values: np.ndarray) -> np.ndarray:
    """``values`` at ``points``: those of the nearest of ``where`` (which must coincide)."""
    d = np.linalg.norm(points[:, None] - where[None], axis=2)
    nearest = np.argmin(d, axis=1)
    assert np.all(d[np.arange(len(points)), nearest] <= 1e-12), "a point of the surface has no displacement dof"
    return values[nearest]


def _check_points(c, facets: np.ndarray) -> None:
    """Reference and current positions of ``c``'s points against the unknown's dofs on ``facets``; gap and
    pressure the same for both; ``surface_values`` the reference ``point_values``."""
    gdim = c.u.function_space.mesh.geometry.dim
    X, g, p = c.point_values(reference=True)
    x, g2, p2 = c.point_values()
    assert X.shape == x.shape == (len(g), gdim) and p.shape == g.shape
    assert np.array_equal(g, g2) and np.array_equal(p, p2)
    assert np.all(np.diff(X[:, 0]) >= 0)  # sorted by reference position
    where, u = _surface_displacement(c.u, facets)
    assert np.allclose(X, _at(X, where, where), rtol=0, atol=1e-12)  # the surface's points
    assert np.allclose(x, X + _at(X, where, u), rtol=0, atol=1e-12)
    assert np.max(np.abs(x - X)) > 1e-3  # the displacement is not trivial
    for a, b in zip(c.surface_values(), (X, g, p)):
        assert np.array_equal(a, b)


def _block(method: str):
    """A block [0, 1] x [0, H] on the rigid plane y = 0 (its top moved down by D, u_x = 0 on x = 0), contact
    surface named ``base plate``; solved. Returns the surface, its law and the base facets."""
    mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([1.0, H])], [3, 6])
    fdim = mesh.topology.dim - 1
    sides = {1: lambda x: np.isclose(x[1], 0.0), 2: lambda x: np.isclose(x[1], H), 3: lambda x: np.isclose(x[0], 0)}
    found = [(tag, dmesh.locate_entities_boundary(mesh, fdim, where)) for tag, where in sides.items()]
    indices = np.concatenate([f for _, f in found]).astype(np.int32)
    values = np.concatenate([np.full(len(f), tag, np.int32) for tag, f in found])
    order = np.argsort(indices)
    tags = dmesh.meshtags(mesh, fdim, indices[order], values[order])
    law = {"penalty": lambda: fc.make_law("penalty", K=1e5), "vi": lambda: fc.make_law("vi"),
           "nitsche": lambda: fc.make_law("nitsche"), "lagrange": lambda: fc.make_law("lagrange"),
           "friction": lambda: fc.Friction(fc.Penalty(1e5), mu=0.3, omega_t=1e5),
           "coulomb": lambda: fc.make_law("coulomb", mu=0.3)}[method]()
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    material = fc.LinearElastic(E, NU)
    contact = fc.contact_surface(u, tags, 1, fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, name="base plate",
                                 material=material if method == "nitsche" else None)
    bcs = [fc.Dirichlet.on_facets(V, tags, 2, 1, -D), fc.Dirichlet.on_facets(V, tags, 3, 0)]
    problem = fc.ContactProblem(u, material, load, bcs, [contact], step_solver=fc.step_solver_for([contact]))
    solver = fc.Solver(problem, quiet=True)
    solver.run([1.0])
    assert solver.records[-1].converged
    return contact, law, tags.indices[tags.values == 1], -problem.reaction(bcs[0].dofs)


RIGID = {"penalty": fc.ContactSurface, "vi": fc.BoundContact, "nitsche": fc.NitscheContact,
         "lagrange": fc.MultiplierContact, "friction": fc.FrictionalContact, "coulomb": fc.CondensedContact}


@pytest.mark.parametrize("method", list(RIGID))
def test_rigid_surfaces(method):
    """A block pressed on a rigid plane: the surface's law, its points (reference: the base vertices; current:
    plus the displacement), the normal force (the plate pushes up as hard as the top is pushed down), the
    friction profile (the same vertices) or a ValueError naming the surface."""
    c, law, facets, pushed = _block(method)
    assert type(c) is RIGID[method] and c.law is law
    _check_points(c, facets)
    X, g, p = c.point_values(reference=True)
    assert np.allclose(X[:, 1], 0.0, atol=1e-12) and len(X) == 4  # the base's vertices
    force = c.total_force()
    assert force.shape == (2,) and force[1] == pytest.approx(pushed, rel=1e-8) and pushed > 0
    assert np.all(p > 0) and np.all(g > -1e-12)
    if method in ("friction", "coulomb"):
        prof = c.friction_profile()
        assert set(prof) == {"x", "gap", "pressure", "traction", "state"}
        assert np.allclose(prof["x"], X, rtol=0, atol=1e-12) and np.allclose(prof["pressure"], p, rtol=1e-10)
        if method == "coulomb":  # the normal and the friction force make up the sum of the nodal forces
            assert np.allclose(c.total_force() + c.tangential_force(), c.contact_force(), rtol=1e-12)
    else:
        with pytest.raises(ValueError, match="base plate"):
            c.friction_profile()


def _blocks(law, delta=5e-3):
    """Two stacked blocks (non-matching meshes, touching), the lower one clamped at its base, the top of the
    upper one moved down by ``delta``; one-pass surfaces (slave: the upper block's bottom); solved."""
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 0.5, 0.5, (4, 2), (3, 2), 0.0)
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 0), fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1),
                 fc.Dirichlet.on_facets(V, ft, "upper_top", 0), fc.Dirichlet.on_facets(V, ft, "upper_top", 1, -delta)]
    contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load,
                                    cls=fc.TwoBodyMultiplier if isinstance(law, fc.LagrangeMultiplier) else None)
    problem = fc.ContactProblem(u, fc.LinearElastic(E, NU), load, dirichlet, contacts,
                                step_solver=fc.step_solver_for(contacts))
    solver = fc.Solver(problem, quiet=True)
    solver.run([1.0])
    assert solver.records[-1].converged
    return contacts[0], ft.find("upper_bottom")


@pytest.mark.parametrize("method", ["lagrange", "coulomb"])
def test_two_body_surfaces(method):
    """A block pressed on a block: the slave surface's law, its points (the upper block's bottom vertices, then
    displaced), the normal force of the lower block on the upper one (upward), the friction profile or a
    ValueError naming the surface."""
    law = fc.make_law(method, **({"mu": 0.3} if method == "coulomb" else {}))
    c, facets = _blocks(law)
    assert type(c) is {"lagrange": fc.TwoBodyMultiplier, "coulomb": fc.CondensedTwoBody}[method] and c.law is law
    X, g, p = c.point_values(reference=True)
    assert np.allclose(X[:, 1], 0.5, atol=1e-12) and len(X) == 4 and np.all(p > 0)
    x, _, _ = c.point_values()
    assert np.all(x[:, 1] < 0.5)  # pressed down
    if method == "lagrange":
        _check_points(c, facets)
    else:  # a Surface of its own: no facets attribute, the same check from the mesh's tags
        where, u = _surface_displacement(c.u, facets)
        assert np.allclose(x, X + _at(X, where, u), rtol=0, atol=1e-12)
        assert np.allclose(c.friction_profile()["x"], X, rtol=0, atol=1e-12)
        for a, b in zip(c.surface_values(), c.point_values(reference=True)):
            assert np.array_equal(a, b)
    force = c.total_force()
    assert force.shape == (2,) and force[1] > 0
    if method == "lagrange":
        with pytest.raises(ValueError, match=c.name):
            c.friction_profile()


def test_collocated_surfaces():
    """The collocated element on the concentric rings (P2): each surface's points are its nodes (vertices and
    middle nodes) and their displaced positions; its total force is the element's own (the interface pressure
    on the quarter arc of radius b: ``p b`` per component, opposite on the two bodies); no friction."""
    setup = build("rings", law=fc.LagrangeMultiplier(1e3), degree=2, quadrature="collocated", n=8)
    fc.Solver(setup.problem, quiet=True).run(setup.loads)
    a, b = setup.contacts
    for c in (a, b):
        assert isinstance(c, CollocatedSurface) and isinstance(c.law, fc.LagrangeMultiplier)
        _check_points(c, c.facets)
        with pytest.raises(ValueError, match=c.name):
            c.friction_profile()
    f = setup.figures()
    pb = f["p_reaction"] * setup.parameters["b"]
    assert np.allclose(-a.total_force(), pb, rtol=1e-3) and np.allclose(b.total_force(), pb, rtol=3e-3)


TWO_BODY = [m for m in fc.methods.names() if fc.capabilities.supported(
    method=m, kind="two-body", dim=2, degree=1, quadrature="nodal", passes="one", model="linear", obstacle="none")]


@pytest.mark.parametrize("method", TWO_BODY)
def test_one_call_builds_every_two_body_method_of_the_grid(method):
    """``fc.two_body_surfaces`` with nothing but the law (and the bulk material) builds the contact of every
    method the capability grid lists for two bodies (no surface class to choose): the stacked blocks solve, and the
    contact force of the lower block on the upper one balances the reaction at the upper block's top (equilibrium,
    1e-8)."""
    assert {"penalty", "lagrange", "coulomb"} <= set(TWO_BODY)
    stiff = 1e3 * E  # pressure per length: a penalty of about E / h on these blocks (h ~ 0.2)
    params = {p.name: (0.0 if p.name == "mu" else stiff) for p in fc.methods.get(method).parameters
              if p.name in ("K", "K_hat", "c_n", "c", "mu")}
    law = fc.make_law(method, **params)
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 0.5, 0.5, (4, 2), (3, 2), 0.0)
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    top = fc.Dirichlet.on_facets(V, ft, "upper_top", 1, -5e-3)
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 0), fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1),
                 fc.Dirichlet.on_facets(V, ft, "upper_top", 0), top]
    material = fc.LinearElastic(E, NU)  # method nitsche's stress term needs it; the others do not use it
    contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load, material=material)
    problem = fc.ContactProblem(u, material, load, dirichlet, contacts,
                                step_solver=fc.step_solver_for(contacts))
    fc.Solver(problem, quiet=True, augment_max=20, augment_tol=1e-10).run([1.0])
    force = contacts[0].total_force()[1]
    support = -problem.reaction(top.dofs)  # the force of the support on the upper block: downward
    assert force > 0 and force == pytest.approx(support, rel=1e-8)
