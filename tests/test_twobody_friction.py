"""Friction between two deformable bodies: consistent tangent with the master dofs (stick, slip, mixed; one and
two pass), history on accepted steps only, equilibrium of the two bodies, bad input."""
import dolfinx.fem.petsc as fem_petsc
import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

import fenics_contact as fc
from fenics_contact.app.meshes import stacked_blocks
from fenics_contact.app.scenes import build
from fenics_contact.compat import bc_dofs, petsc_vec
from fenics_contact.friction import SLIP, STICK
from fenics_contact.methods import make_law
from fenics_contact.solver import Solver

OMEGA_T = 30.0
N_STEPS = 80  # the closed cycle: backward Euler is first order (40 steps: work - D = 3.5 % of D; 80: 1.9 %)


def _friction(mu=0.3, **kw):
    return lambda: fc.Friction(make_law("penalty", K=1e3), omega_t=OMEGA_T, **({"mu": mu} | kw))


def _sliding_state(setup, dim):
    """Upper block shifted along the interface by an amount growing with x (so that the slip varies), pressed, every
    node perturbed (master facets rotate); a direction ``d`` with the Dirichlet dofs left fixed."""
    problem = setup.problem
    u = problem.u
    V = u.function_space
    rng = np.random.default_rng(0)
    x = petsc_vec(u).copy()
    X = V.tabulate_dof_coordinates()[: len(x.array) // dim]
    z = X[:, dim - 1]
    upper = (z > 1.0 + 1e-9) | np.isclose(z, 1.0 - 1e-6, rtol=0, atol=1e-9)
    x.array[:] = 1e-3 * rng.standard_normal(x.array.shape)
    x.array[0::dim][upper] += 0.02 + 0.03 * X[upper, 0]
    if dim == 3:
        x.array[1::dim][upper] += 0.013
    x.array[dim - 1::dim][upper] -= 0.002
    d = x.duplicate()
    d.array[:] = rng.standard_normal(d.array.shape)
    for bc in problem.bcs:
        d.array[bc_dofs(bc)] = 0.0
        x.array[bc_dofs(bc)] = 0.0
    return x, d, upper


def _set(u, x):
    """``u`` (owned and ghost values) from the PETSc vector ``x`` (owned values)."""
    x.copy(petsc_vec(u))
    u.x.scatter_forward()


def _states(c, x, u):
    """Slip states (at the slave points, nodal) of contact ``c`` at ``u = x``, of every rank."""
    _set(u, x)
    c.update()
    s = fem.Function(c.S)
    c.projector.project(c.projector.compile(c.slip_state_expr), s)
    return set().union(*MPI.COMM_WORLD.allgather(set(np.rint(s.x.array[c.projector.surface_dofs]).astype(int)
                                                     .tolist())))


def _ratios(c, x, u):
    """|q_trial| / (F(g)) at the closed slave points: the mu that separates stick from slip there."""
    _set(u, x)
    c.update()
    law = c.law
    qtr = ufl.sqrt(ufl.dot(c.traction, c.traction))  # at mu huge: the trial traction itself (stick)
    F = law.normal.force(c.gap, c.params, fc.laws.ufl_ops())
    out = []
    for e in (qtr, F):
        f = fem.Function(c.S)
        c.projector.project(c.projector.compile(e), f)
        out.append(f.x.array[c.projector.surface_dofs])
    q, F = out
    closed = F > 1e-9
    return np.concatenate(MPI.COMM_WORLD.allgather(q[closed] / F[closed]))  # the same on every rank


@pytest.mark.parametrize("passes,dim,quadrature", [("one", 2, "nodal"), ("two", 2, "nodal"), ("one", 2, "gauss"),
                                                   ("one", 3, "nodal")])
def test_consistent_tangent_with_master_dofs(passes, dim, quadrature, contact_tangent_error):
    """Central differences of the residual (slave and master rows) against the assembled tangent (bulk subtracted)
    at a stick, a slip and a mixed state, to 1e-6 relative."""
    sizes = {} if dim == 2 else {"n_lower": (2, 2, 1), "n_upper": (3, 3, 1)}
    setup = build("patch", law_factory=_friction(), quadrature=quadrature, passes=passes, **sizes)
    problem = setup.problem
    contacts = problem.contacts
    assert all(isinstance(c, fc.FrictionalTwoBodySurface) for c in contacts)
    solver = Solver(problem, quiet=True)
    problem.set_load(1.0)
    u = problem.u
    V = u.function_space
    x, d, upper = _sliding_state(setup, dim)
    for c in contacts:
        c.constants["mu"].value = 1e6
    ratios = np.concatenate([_ratios(c, x, u) for c in contacts])
    du, v = ufl.TrialFunction(V), ufl.TestFunction(V)
    Ab = fem_petsc.assemble_matrix(fem.form(ufl.derivative(
        ufl.derivative(problem.material.energy(u) * ufl.dx, u, v), u, du)), bcs=problem.bcs)
    Ab.assemble()
    # Mixed: mu in the widest gap between two ratios of the middle half (no point at |q_tr| = b, where the return
    # mapping has a kink); slip: below every ratio (Gauss: DG1 dofs can dip below 0).
    r = np.unique(ratios)
    lo, hi = len(r) // 4, max(len(r) // 4 + 1, 3 * len(r) // 4)
    i = lo + int(np.argmax(np.diff(r[lo:hi + 1])))
    mixed, slip = 0.5 * (r[i] + r[i + 1]), max(0.01 * ratios.min(), 0.0)
    for mu, expected in ((100.0 * ratios.max(), {STICK}), (mixed, {STICK, SLIP}), (slip, {SLIP})):
        for c in contacts:
            c.constants["mu"].value = mu
        if quadrature == "nodal":
            found = set().union(*[_states(c, x, u) for c in contacts]) - {0}
            assert found == expected, (mu, found)
        err, master = contact_tangent_error(solver, x, d, lambda c: c.pairing(), Ab, np.repeat(~upper, dim))
        assert master > 0.1  # master rows are nonzero: the coupling acts on both bodies
        print(f"FD check friction {passes}-pass {dim}D {quadrature} mu={mu:.3g}: relative error {err:.2e}")
        assert err <= 1e-6, (mu, err)


def _sheared_blocks(law_factory, T, P=10.0, comm=MPI.COMM_WORLD):
    """A unit block (2D) on the middle of a block twice as wide, clamped at its base; on the top of the upper one
    the pressure ``P`` over the load 0..1, then the tangential traction ``T`` over 1..2 (its horizontal rigid mode
    is held only by friction; under the soft tangential penalty it slides by about half a lower facet, which stays
    within the lower block's top)."""
    mesh, _, ft = stacked_blocks(comm, 2.0, 1.0, 1.0, (8, 2), (3, 2), 1e-6,  # touching: stick at once
                                 upper_span=(0.5, 1.5))
    u, V = fc.unknown(mesh, 1, law_factory())
    load = fem.Constant(mesh, 0.0)
    bcs = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 0), fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1)]
    contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", law_factory, load)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft.meshtags, subdomain_id=ft["upper_top"])
    # The problem scales tractions by the load t: this vector times t is the path above.
    path = ufl.as_vector((T * ufl.max_value(load - 1.0, 0.0) / load, -P * ufl.min_value(load, 1.0) / load))
    problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load, bcs, contacts, [(path, ds)])
    return problem, contacts


def test_equilibrium_and_history_on_accepted_steps():
    """Pressed then sheared below the Coulomb limit: the tangential contact force carries the whole applied shear
    (equilibrium of the upper body), the forces on the two bodies are equal and opposite (the contact residual on
    both bodies sums to zero per component), and the history moves only on commit and is rolled back by
    restore."""
    problem, (c,) = _sheared_blocks(_friction(mu=0.5), 3.0)  # Q / (mu P) = 0.6
    solver = Solver(problem, quiet=True)
    solver.run([1.0])
    before = c.state()
    solver.run([1.5, 2.0])
    assert all(r.converged for r in solver.records)
    force = c.total_force() + c.tangential_force()  # of the lower body on the upper one: normal + friction
    assert force == pytest.approx([-3.0, 10.0], rel=1e-8)  # equilibrium of the upper body
    # The contact residual on both bodies (slave rows + I^T master rows) sums to zero in each direction.
    b = fem_petsc.assemble_vector(fem.form(c.residual(ufl.TestFunction(problem.u.function_space))))
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    c.add_residual(b)
    total = [MPI.COMM_WORLD.allreduce(float(np.sum(b.array[i::2]))) for i in (0, 1)]
    assert abs(total[0]) <= 1e-8 * 3.0 and abs(total[1]) <= 1e-8 * 10.0, total
    assert MPI.COMM_WORLD.allreduce(int(any(np.any(q.x.array != 0) for q in c.q_old))) > 0
    c.restore(before)
    assert all(np.array_equal(f.x.array, a) for f, a in zip(c.history, before["history"]))
    assert np.array_equal(c.u_old.x.array, before["u_old"])


def test_tresca_bound_and_slip():
    """Tresca (fixed bound s on the closed points): the capacity is s times the contact length whatever the
    pressure (here 10 / length); shears below it are carried whole, with a part of the surface sticking."""
    s = 1.5
    problem, (c,) = _sheared_blocks(_friction(mu=None, tresca=s), 1.0)
    solver = Solver(problem, quiet=True)
    solver.run([1.0, 2.0])
    assert c.capacity() == pytest.approx(s * 1.0, rel=1e-12)
    assert (c.total_force() + c.tangential_force()) == pytest.approx([-1.0, 10.0], rel=1e-8)
    problem, (c,) = _sheared_blocks(_friction(mu=None, tresca=s), 2.0 * s)
    solver = Solver(problem, quiet=True)
    solver.run([1.0, 1.375])  # shear 0.75 s: carried
    assert (c.total_force() + c.tangential_force()) == pytest.approx([-0.75 * s, 10.0], rel=1e-8)
    assert c.state_areas()["stick"] > 0.0


@pytest.mark.parametrize("kwargs,match", [
    ({"quadrature": "segment"}, "friction"),
])
def test_bad_two_body_friction_input(kwargs, match):
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (2, 2), 1e-6)
    u, _ = fc.unknown(mesh, 1, _friction()())
    with pytest.raises(fc.UnsupportedCombination, match=match):
        fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", _friction(), fem.Constant(mesh, 0.0), **kwargs)
    u2, _ = fc.unknown(mesh, 2, _friction()())
    with pytest.raises(fc.UnsupportedCombination, match="P2"):
        fc.two_body_surfaces(u2, ft, "upper_bottom", "lower_top", _friction(), fem.Constant(mesh, 0.0), "simpson")
    with pytest.raises(ValueError, match="mu must be"):
        fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", _friction(mu=-0.1), fem.Constant(mesh, 0.0))
    with pytest.raises(ValueError, match="tresca must be"):
        fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", _friction(mu=None, tresca=-1.0),
                             fem.Constant(mesh, 0.0))


def test_dissipation_over_a_closed_cycle():
    """Two blocks: the upper one's top glued to a platen that presses, drags right (sliding), drags back and lifts
    off. Every step dissipates >= 0, the total is positive, and it equals the net work of the platen over the
    cycle (the bodies end stress-free and apart) to the time-discretization error."""
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 0.5, 0.5, (6, 3), (5, 3), 1e-6)
    law = lambda: fc.Friction(make_law("penalty", K=1e5), mu=0.5, omega_t=1e4)  # noqa: E731
    u, V = fc.unknown(mesh, 1, law())
    load = fem.Constant(mesh, 0.0)
    top = ft.find("upper_top")
    dofs = [fem.locate_dofs_topological(V.sub(i), 1, top) for i in (0, 1)]
    ts = [0, 1, 2, 3, 4]
    bcs = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 0), fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1),
           fc.Dirichlet(V.sub(0), dofs[0], 1.0, (ts, [0, 0, 0.02, 0.0, 0.0])),
           fc.Dirichlet(V.sub(1), dofs[1], 1.0, (ts, [0, -0.005, -0.005, -0.005, 0.001]))]
    (c,) = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(1000, 0.3), load, bcs, [c])
    solver = Solver(problem, quiet=True)
    work, R_prev, u_prev, slid = 0.0, np.zeros(2), np.zeros(2), False
    for t in np.linspace(0, 4, N_STEPS + 1)[1:]:
        solver.run([t])
        R = np.array([problem.reaction(d) for d in dofs])  # platen on the body
        u_top = np.array([b.at(t) for b in bcs[2:]])
        work += 0.5 * (R + R_prev) @ (u_top - u_prev)
        R_prev, u_prev = R, u_top
        slid |= c.state_areas()["slip"] > 0.5
    D = c.dissipated
    steps = np.diff([0.0] + [s["dissipated"] for s in c.log])
    print(f"two-body friction cycle: dissipated {D:.6g}, platen work {work:.6g}")
    assert slid and D > 0 and np.all(steps >= -1e-15 * D)
    assert np.allclose(c.tangential_force(), 0, atol=1e-12) and np.allclose(c.total_force(), 0, atol=1e-12)
    assert work > 0 and abs(work - D) < 0.03 * D, (work, D)


def test_tresca_from_the_command_line():
    """``--tresca s`` gives the Tresca law; a negative bound, or two bounds at once, are one-line errors."""
    from fenics_contact.app import cli

    def law(argv):
        return cli.law_from_args(cli.parse(cli.parser("x", 1e5), argv))

    f = law(["--method", "penalty", "--tresca", "1.5"])
    assert isinstance(f, fc.Friction) and f.scalars["tresca"] == 1.5 and "mu" not in f.scalars
    with pytest.raises(ValueError, match="--tresca must be"):
        law(["--method", "penalty", "--tresca", "-1"])
    with pytest.raises(ValueError, match="give one of --mu"):
        law(["--method", "penalty", "--tresca", "1", "--mu", "0.3"])
    with pytest.raises(ValueError, match="--tresca: method 'coulomb'"):
        law(["--method", "coulomb", "--tresca", "1"])
