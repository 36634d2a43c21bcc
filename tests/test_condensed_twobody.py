"""Method ``coulomb`` between two linear-elastic bodies (:class:`~fenics_contact.condensed.CondensedTwoBody`):
exact Signorini-Coulomb on the stiffness condensed onto both surfaces' contact dofs, small sliding.

Cattaneo-Mindlin partial slip (the ``mindlin`` scene: a non-proportional load path, pressed by a Dirichlet
approach, then sheared by a force-controlled traction), equilibrium of both bodies from the recovered
displacement, the exact contact conditions, a block sheared on a block past the Coulomb limit (tangential force
``mu`` times the normal one) and the refusals."""
import numpy as np
import pytest
from dolfinx import fem
from mpi4py import MPI

import fenics_contact as fc
import fenics_contact.app as app
from fenics_contact.app.meshes import stacked_blocks
from fenics_contact.app.scenes import mindlin
from fenics_contact.condensed import OPEN, SLIP, STICK

from solved import solved

MU = 0.3


def _build(comm):
    setup = app.build("mindlin", law=fc.make_law("coulomb", mu=MU), comm=comm)
    assert isinstance(setup.contacts[0], fc.CondensedTwoBody)
    assert isinstance(setup.problem.step_solver, fc.CondensedTwoBodyCoulomb)
    return setup


def _run(comm=MPI.COMM_WORLD):
    """The default mindlin scene solved exactly (once per communicator size): setup, figures, solver."""
    setup, solver, figures = solved("mindlin coulomb", _build, comm)
    return setup, figures, solver


def test_stick_zone_against_cattaneo_mindlin():
    """At Q / (mu P) = 0.2, 0.5, 0.8 the stick half-width is within one contact element and within 5 % of
    c = a sqrt(1 - Q / (mu P)) (a: Hertz for the measured P, two identical bodies); the contact half-width is
    Hertz's; the semismooth Newton needs a handful of iterations per step; the stiffness is factored once."""
    setup, f, solver = _run()
    h = f["h_contact"]
    for r in mindlin.RATIOS:
        c, ref = f[f"c_{r:g}"], f[f"c_ref_{r:g}"]
        print(f"exact mindlin Q/(mu P) = {r}: c = {c:.6g}, Cattaneo-Mindlin {ref:.6g}, error {abs(c - ref) / ref:.2%} "
              f"= {abs(c - ref) / h:.2f} elements")
        assert abs(c - ref) <= h and abs(c - ref) <= 0.05 * ref, (r, c, ref)
    assert f["a_error"] < 0.02
    assert max(len(h) for rec in solver.records for h in rec.residuals) <= 15
    # linear bodies: K assembled and condensed once for the whole load path (pressing and shear); the shear
    # steps after the first are combinations of the earlier loads (no solve for their load modes); the
    # semismooth Newton's systems are row updates of one or two dense inverses
    step_solver = setup.problem.step_solver
    K = step_solver.K
    assert len(solver.records) == mindlin.PRESS_STEPS_EXACT + len(mindlin.RATIOS)
    assert (K.assemblies, K.factorizations) == (1, 1)
    assert K.modes.reused == len(mindlin.RATIOS) - 1
    assert step_solver.linear.factorizations <= 2 < step_solver.linear.updates


def test_equilibrium_of_both_bodies():
    """From the recovered displacement (internal forces ``dW[phi_i]`` at the contact vertices, where no other
    load acts): the contact force on the slave body is minus the one on the master (1e-10 of P), it is the
    surface's own total (1e-8), and at every shear step the friction force carries the applied Q = r mu P
    exactly (the traction's amplitude is fixed after t = 1: the load path is not proportional)."""
    setup, f, _ = _run()
    c, problem = setup.contacts[0], setup.problem
    P = f["P"]
    r = problem.internal_force()
    n_owned = problem.u.function_space.dofmap.index_map.size_local

    def force(dofs):
        own = dofs[dofs < n_owned]
        return np.array([problem.comm.allreduce(float(np.sum(r[2 * own + k]))) for k in range(2)])

    slave, master = (force(d) for d in c.local_dofs)
    assert np.max(np.abs(slave + master)) <= 1e-10 * P, (slave, master)
    own = c.total_force() + c.tangential_force()
    assert np.allclose(slave, own, rtol=0, atol=1e-8 * P), (slave, own)
    for ratio in mindlin.RATIOS:
        assert f[f"Q_{ratio:g}"] == pytest.approx(ratio * MU * P, rel=1e-8)
    assert -slave[0] == pytest.approx(mindlin.RATIOS[-1] * MU * P, rel=1e-8)  # the last step's friction force


def test_exact_contact_conditions():
    """At the last step: no penetration and no gap where there is pressure (Signorini exactly: 1e-9 of the
    approach), no pressure where open; |q| = mu p at the sliding vertices (1e-8), |q| < mu p at the sticking ones,
    both present; the friction work dissipated over the steps is not negative."""
    setup, _, _ = _run()
    c = setup.contacts[0]
    prof = c.friction_profile()
    p, q, g, s = prof["pressure"], prof["traction"], prof["gap"], prof["state"]
    approach = setup.parameters["approach"]
    assert np.all(p >= -1e-10 * p.max())
    assert np.all(g <= 1e-9 * approach)  # gap > 0: penetration
    assert np.all(np.abs(g[s != OPEN]) <= 1e-9 * approach)
    assert np.all(np.abs(p[s == OPEN]) <= 1e-10 * p.max())
    assert np.any(s == SLIP) and np.any(s == STICK)
    assert np.allclose(np.abs(q[s == SLIP]), MU * p[s == SLIP], rtol=1e-8, atol=1e-12 * MU * p.max())
    assert np.all(np.abs(q[s == STICK]) < MU * p[s == STICK])
    pressed = c.log[mindlin.PRESS_STEPS_EXACT - 1]["dissipated"]
    assert c.log[-1]["dissipated"] >= 0.0 and c.log[-1]["dissipated"] > pressed


def _blocks(law, comm=MPI.COMM_WORLD, delta=5e-3, slide=2e-2):
    """Two stacked blocks (non-matching meshes, touching), the lower one clamped at its base; the top of the upper
    one is pressed down by ``delta`` over t in [0, 1], then moved sideways by ``slide`` over t in [1, 2]."""
    mesh, _, ft = stacked_blocks(comm, 1.0, 0.5, 0.5, (4, 2), (3, 2), 0.0)
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    top = [fem.locate_dofs_topological(V.sub(k), 1, ft.find("upper_top")) for k in range(2)]
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 0), fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1),
                 fc.Dirichlet(V.sub(1), top[1], -delta, ([0.0, 1.0, 2.0], [0.0, 1.0, 1.0])),
                 fc.Dirichlet(V.sub(0), top[0], slide, ([0.0, 1.0, 2.0], [0.0, 0.0, 1.0]))]
    contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load, dirichlet, contacts,
                                step_solver=fc.step_solver_for(contacts))
    return problem, contacts[0], top


def test_block_sheared_past_the_coulomb_limit():
    """A block pressed on a block, then its top dragged sideways far beyond the stick limit: every closed slave
    vertex slides, so the tangential contact force is exactly mu times the normal one (1e-10), and so is the
    ratio of the support reactions on the dragged top (from the recovered displacement)."""
    problem, c, top = _blocks(fc.make_law("coulomb", mu=MU))
    solver = fc.Solver(problem, quiet=True)
    solver.run([0.5, 1.0, 1.5, 2.0])
    assert all(r.converged for r in solver.records)
    prof = c.friction_profile()
    closed = prof["pressure"] > 0
    assert np.count_nonzero(closed) >= 4 and np.all(prof["state"][closed] == SLIP)
    N, T = c.total_force(), c.tangential_force()
    assert abs(np.linalg.norm(T) - MU * np.linalg.norm(N)) <= 1e-10 * np.linalg.norm(N), (T, N)
    assert T[0] < 0  # the lower block holds the upper one back (it is dragged along +x)
    Rx, Ry = (problem.reaction(d) for d in top)
    assert abs(abs(Rx) - MU * abs(Ry)) <= 1e-10 * abs(Ry), (Rx, Ry)
    assert abs(Ry) == pytest.approx(np.linalg.norm(N), rel=1e-8)


def test_two_identical_bodies_hertz_force_controlled():
    """The two-body Hertz case (quarter disk R = 8 on a block of its own material, E = 200, nu = 0.3, load 10,
    frictionless): force control from rest through a spring that vanishes at t = 1 (the stiffness changes with t:
    condensed again), slave and master vertices on the symmetry axis with u_x = 0 (no friction force there).
    The contact force is the load (1e-10: the spring is gone at t = 1) and p0, a are Hertz's with
    E* = E / (2 (1 - nu^2)) (as the multipliers: p0 within 0.5 %, a within 1 %)."""
    from fenics_contact.app.scenes import hertz

    kw = dict(plate="meshed", E=200.0, nu=0.3, R=8.0, load=10.0, plate_E=200.0, plate_width=16.0, plate_depth=16.0)
    setup = hertz.build(fc.make_law("coulomb", mu=0.0), **kw)
    solver = fc.Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    f = setup.figures()
    print(f"two-body Hertz, coulomb: p0 error {f['p0_error']:.2e}, a error {f['a_error']:.2e}")
    assert f["load_error"] < 1e-10
    assert f["p0_error"] < 5e-3 and f["a_error"] < 1e-2
    c = setup.contacts[0]
    roller = np.isclose(c.X[:, 0], 0.0)  # the slave vertex on the axis: u_x held, q = 0
    assert np.count_nonzero(roller) == 1 and c.friction_profile()["pressure"][roller][0] > 0
    # The whole load in one step, without the spring (the vertex touching at rest holds the disk from the first
    # iterate): frictionless exact contact has no path, so the same answer as the two steps.
    one = hertz.build(fc.make_law("coulomb", mu=0.0), steps=1, **kw)
    fc.Solver(one.problem, quiet=True).run(one.loads)
    g = one.figures()
    for k in ("total_force", "p0", "a"):
        assert g[k] == pytest.approx(f[k], rel=1e-8), (k, g[k], f[k])
    with pytest.raises(ValueError, match="steps >= 2"):  # a spring-held method cannot start without it
        hertz.build(fc.make_law("penalty", K=2.5e4), steps=1, **kw)


def test_schur_complement_is_the_dense_one():
    """condensed.schur.SchurFactor's S (MUMPS's partial factorization) against A_cc - A_ci A_ii^-1 A_ic in dense
    algebra, rows in the order asked for (not sorted), on one process and, under mpirun, on a matrix distributed
    over all (gathered on rank 0: the same S on every rank)."""
    from petsc4py import PETSc

    from fenics_contact.condensed.schur import SchurFactor

    n, rows = 40, np.array([31, 3, 17, 8])
    rng = np.random.default_rng(0)
    B = np.where(rng.random((n, n)) < 0.1, rng.random((n, n)), 0.0)
    D = B @ B.T + n * np.eye(n)  # sparse-ish, symmetric positive definite
    inner = np.setdiff1d(np.arange(n), rows)
    expected = D[np.ix_(rows, rows)] - D[np.ix_(rows, inner)] @ np.linalg.solve(D[np.ix_(inner, inner)],
                                                                                 D[np.ix_(inner, rows)])
    for comm in (MPI.COMM_SELF, MPI.COMM_WORLD):
        A = PETSc.Mat().createAIJ((n, n), comm=comm)
        A.setUp()
        lo, hi = A.getOwnershipRange()
        A.setValues(range(lo, hi), range(n), D[lo:hi])
        A.assemble()
        factor = SchurFactor(A, rows)
        S = factor.S
        factor.destroy()
        assert np.allclose(S, expected, rtol=1e-12, atol=1e-12 * np.abs(expected).max()), comm.size
        empty = SchurFactor(A, np.zeros(0, np.int64))
        assert empty.S.shape == (0, 0)  # no contact dof: nothing to factor
        empty.destroy()
        A.destroy()


def test_rigid_force_controlled_is_condensed_at_each_stiffness():
    """The shared condensation, rigid obstacle: Hertz force-controlled from rest (the vanishing spring changes
    the stiffness between steps). The contact force is the load (1e-10) and p0 Hertz's (0.5 %); a stiffness
    condensed once, at the first step, missed the load by 80 %."""
    from fenics_contact.app.scenes import hertz

    setup = hertz.build(fc.make_law("coulomb", mu=0.0), load=10.0, E=200.0, R=8.0)
    solver = fc.Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    f = setup.figures()
    assert f["load_error"] < 1e-10 and f["p0_error"] < 5e-3, (f["load_error"], f["p0_error"])


def test_refusals():
    """One-line errors before any solve: two passes, Gauss quadrature (capability matrix); a paired slave
    vertex whose normal motion is prescribed; the wrong law or surface for the classes."""
    law = fc.make_law("coulomb", mu=MU)
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 0.5, 0.5, (2, 1), (2, 1), 0.0)
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    with pytest.raises(fc.UnsupportedCombination, match="two-pass"):
        fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load, passes="two")
    with pytest.raises(fc.UnsupportedCombination, match="gauss"):
        fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load, quadrature="gauss")
    with pytest.raises(ValueError, match="Coulomb law"):
        fc.CondensedTwoBody(u, ft, "upper_bottom", "lower_top", fc.make_law("penalty", K=1.0), load)
    with pytest.raises(ValueError, match="CondensedTwoBody"):
        fc.CondensedTwoBodyCoulomb(object())
    # The slave's normal component held (a clamp on the contact surface): refused when the step solver condenses.
    (c,) = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load)
    held = fc.Dirichlet.on_facets(V, ft, "upper_bottom", 1)
    problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load, [held], [c],
                                step_solver=fc.step_solver_for([c]))
    problem.set_load(1.0)
    with pytest.raises(ValueError, match="normal motion is prescribed"):
        problem.step_solver.solve_step(problem)


@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="compares a parallel run with the serial one")
def test_parallel_equals_serial():
    """Under mpirun -n 2: the mindlin figures equal the serial ones (each rank also solves alone) to 1e-8, and the
    block's forces too."""
    _, parallel, _ = _run(MPI.COMM_WORLD)
    _, serial, _ = _run(MPI.COMM_SELF)
    for k, v in serial.items():
        if isinstance(v, float):
            assert abs(parallel[k] - v) <= 1e-8 * max(abs(v), 1e-6), (k, parallel[k], v)
    forces = []
    for comm in (MPI.COMM_WORLD, MPI.COMM_SELF):
        problem, c, _ = _blocks(fc.make_law("coulomb", mu=MU), comm)
        fc.Solver(problem, quiet=True).run([1.0, 2.0])
        forces.append(np.concatenate([c.total_force(), c.tangential_force()]))
    assert np.allclose(forces[0], forces[1], rtol=0, atol=1e-8 * np.abs(forces[1]).max()), forces


def test_master_rows_eliminated_only_for_a_held_master_body(monkeypatch):
    """The master rows are solved for the master dofs (the Newton systems halve) only when they can be: two
    separate bodies (no coupling block in S) and a master body held (S_mm positive definite); a master body held by
    the contact alone (a rigid mode of S_mm) or coupled surfaces keep the whole system. On the mindlin scene the
    elimination is taken and the answer is that of the whole system (figures to 1e-10)."""
    from fenics_contact.condensed.fixedrows import FixedRowsSolve, master_elimination

    rng = np.random.default_rng(1)
    ns_, nm = 6, 4
    A = rng.standard_normal((ns_, ns_))
    B = rng.standard_normal((nm, nm))
    S = np.zeros((ns_ + nm, ns_ + nm))
    S[:ns_, :ns_], S[ns_:, ns_:] = A @ A.T + np.eye(ns_), B @ B.T + np.eye(nm)
    M = np.hstack([rng.standard_normal((nm, ns_)), np.eye(nm)])
    D, inverse = master_elimination(S, M @ S, ns_)
    assert np.allclose((M @ S)[:, ns_:] @ D + (M @ S)[:, :ns_], 0.0, atol=1e-12)
    rigid = S.copy()
    rigid[ns_:, ns_:] = np.ones((nm, nm))  # a translation of the master surface costs nothing
    assert master_elimination(rigid, M @ rigid, ns_) is None
    coupled = S.copy()
    coupled[0, -1] = coupled[-1, 0] = 0.1
    assert master_elimination(coupled, M @ coupled, ns_) is None

    setup, f, solver = _run()
    step_solver = setup.problem.step_solver
    assert isinstance(step_solver.linear, FixedRowsSolve)
    import fenics_contact.condensed.two_body_solver as module

    monkeypatch.setattr(module, "master_elimination", lambda *args: None)
    whole = _build(MPI.COMM_WORLD)
    fc.Solver(whole.problem, quiet=True).run(whole.loads)
    assert not isinstance(whole.problem.step_solver.linear, FixedRowsSolve)
    g = whole.figures()
    for r in mindlin.RATIOS:
        assert g[f"c_{r:g}"] == f[f"c_{r:g}"] and g[f"Q_{r:g}"] == pytest.approx(f[f"Q_{r:g}"], rel=1e-10)
    assert g["P"] == pytest.approx(f["P"], rel=1e-10)
