"""Two deformable bodies: projection, consistent tangent (with master dofs), patch test, bad input, ranks."""
import re

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
from fenics_contact.compat import bc_dofs, function_space, petsc_vec
from fenics_contact.factory import two_body_surfaces
from fenics_contact.methods import make_law
from fenics_contact.solver import Solver
from fenics_contact.twobody import MARGIN, TwoBodySurface, leaf_boxes


@pytest.mark.parametrize("quadrature,passes,dim", [("nodal", "one", 2), ("gauss", "one", 2), ("gauss", "two", 2),
                                                    ("segment", "one", 2), ("segment", "two", 2),
                                                    ("nodal", "two", 3), ("gauss", "one", 3), ("segment", "one", 3),
                                                    ("segment", "two", 3)])
def test_consistent_tangent_with_master_dofs(quadrature, passes, dim, contact_tangent_error):
    """Central differences of the contact residual (slave and master rows) against the assembled coupling
    tangent, at a sliding configuration (upper block shifted along the interface, every node perturbed so
    that the master facets rotate), to 1e-6 relative. 2D: segments; 3D: triangle facets."""
    sizes = {} if dim == 2 else {"n_lower": (2, 2, 1), "n_upper": (3, 3, 1)}
    setup = build("patch", law_factory=lambda: make_law("penalty", K=1e3), quadrature=quadrature, passes=passes,
                  **sizes)
    problem = setup.problem
    solver = Solver(problem, quiet=True)
    problem.set_load(1.0)
    u = problem.u
    V = u.function_space
    rng = np.random.default_rng(0)
    x = petsc_vec(u).copy()
    X = V.tabulate_dof_coordinates()[: len(x.array) // dim]
    z = X[:, dim - 1]
    upper = (z > 1.0 + 1e-9) | np.isclose(z, 1.0 - 1e-6, rtol=0, atol=1e-9)
    x.array[:] = 1e-3 * rng.standard_normal(x.array.shape)
    x.array[0::dim][upper] += 0.037  # slide
    if dim == 3:  # diagonally: no slave edge nearly on a master edge (an almost parallel clip line)
        x.array[1::dim][upper] += 0.023
    x.array[dim - 1::dim][upper] -= 0.002  # press: every slave point active
    d = x.duplicate()
    d.array[:] = rng.standard_normal(d.array.shape)
    # The direction leaves the Dirichlet dofs fixed (their columns are not in the coupling). Their values: 0 for
    # the pointwise options (the lifting of boundary values uses the problem's Jacobian form, which holds their
    # slave-side contact term); perturbed for segment integration (its form is the bulk alone), else the roller
    # faces of both blocks put a slave edge exactly on a master edge, where the overlap is not differentiable.
    for bc in problem.bcs:
        d.array[bc_dofs(bc)] = 0.0
        if quadrature != "segment":
            x.array[bc_dofs(bc)] = 0.0
    # Bulk tangent (linear: its difference quotient is exact), subtracted from both sides.
    du = ufl.TrialFunction(V)
    v = ufl.TestFunction(V)
    Ab = fem_petsc.assemble_matrix(fem.form(ufl.derivative(
        ufl.derivative(problem.material.energy(u) * ufl.dx, u, v), u, du)), bcs=problem.bcs)
    Ab.assemble()
    err, master = contact_tangent_error(solver, x, d, _pairing, Ab, np.repeat(~upper, dim))
    assert master > 0.1  # master rows are nonzero: the coupling acts on both bodies
    print(f"FD check {quadrature} {passes}-pass {dim}D: relative error {err:.2e}")
    assert err <= 1e-6, err


def _pairing(c):
    """The pairing a surface's residual depends on: point pairs, and sub-segment pairs (segment quadrature)."""
    return c.pairing()


def _patch(quadrature, passes, comm=MPI.COMM_WORLD, by_body=False):
    setup = build("patch", law_factory=lambda: make_law("auglag", K=1e6), quadrature=quadrature, passes=passes,
                  comm=comm, by_body=by_body)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-8, quiet=True)
    solver.run(setup.loads)
    return setup, solver


def test_patch_equilibrium_and_quadratic_newton():
    setup, solver = _patch("gauss", "one")
    f = setup.figures()
    assert np.isclose(f["contact_force"], f["applied_force"], rtol=1e-9)
    assert np.isclose(f["reaction_bottom"], f["applied_force"], rtol=1e-9)
    res = solver.records[0].residuals[0]
    # Quadratic convergence at the end of the first solve: r_{k+1} <= C r_k^2.
    assert res[-2] < 1e-6 * res[0] and res[-2] <= 10 * res[-3] ** 2 / res[0]
    # Converged multipliers: the slave points sit on the master (gap ~ 0).
    for c in setup.contacts:
        _, g, _ = c.point_values()
        assert np.max(np.abs(g)) < 1e-7


@pytest.mark.parametrize("passes,slave", [("one", "upper"), ("one", "lower"), ("two", "upper")])
def test_patch_passes_with_segment_integration(passes, slave):
    """Segment-to-segment integration (exact for the uniform state) passes the patch test on the non-matching
    meshes with converged multipliers (augmented Lagrangian, augmentation converged): the pressure is 10 at
    every sub-segment Gauss point to round-off (acceptance: 1e-3), total interface force = applied load =
    support reaction. The pointwise Gauss option on the same meshes does not (deviation > 0.05)."""
    setup = build("patch", law_factory=lambda: make_law("auglag", K=1e6), quadrature="segment", passes=passes,
                  slave=slave)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-9, quiet=True)
    solver.run(setup.loads)
    rec = solver.records[0]
    assert rec.converged and rec.augmentation_converged and rec.augmentations >= 1
    f = setup.figures()
    print(f"segment {passes}-pass slave {slave}: pressure deviation {f['pressure_deviation']:.2e}")
    assert f["pressure_deviation"] < 1e-8
    assert np.isclose(f["contact_force"], f["applied_force"], rtol=1e-9)
    assert np.isclose(f["reaction_bottom"], f["applied_force"], rtol=1e-9)
    for c in setup.contacts:  # converged multipliers: the slave sits on the master, no penalty penetration
        x, g, p = c.point_values()
        n_facets = MPI.COMM_WORLD.allreduce(int(np.count_nonzero(c.slave_data.owned)))
        assert len(p) > 2 * n_facets  # 2 points per sub-segment, more sub-segments than slave facets
        assert np.max(np.abs(g)) < 1e-9
    if passes == "one" and slave == "upper":
        gauss, _ = _patch("gauss", "one")
        assert gauss.figures()["pressure_deviation"] > 0.05


def test_results_have_the_surface_signatures():
    """``total_force``, ``point_values``, ``surface_values`` and ``friction_profile`` take the arguments that
    :class:`Surface` declares on every two-body surface."""
    import inspect

    from fenics_contact.mortar import SegmentSurface
    from fenics_contact.surface import Surface
    from fenics_contact.twobody.friction import FrictionalTwoBodySurface

    def params(f):
        return [(p.name, p.kind, p.default) for p in inspect.signature(f).parameters.values()]

    for cls in (TwoBodySurface, FrictionalTwoBodySurface, SegmentSurface):
        for name in ("total_force", "point_values", "surface_values", "friction_profile"):
            assert params(getattr(cls, name)) == params(getattr(Surface, name)), (cls.__name__, name)


def test_segment_point_values_at_reference_positions():
    """Segment integration after a patch solve: ``point_values(reference=True)`` gives the sub-segment Gauss points'
    reference positions (on the slave's flat reference interface, as ``segment_points``), with the gaps and
    pressures of ``point_values()`` in the same order; the current positions have moved. The law is set, and a
    frictionless surface's ``friction_profile`` raises ValueError naming it."""
    setup, _ = _patch("segment", "one")
    c = setup.contacts[0]
    assert c.law is not None and c.law.name == "auglag"
    X, gr, pr = c.point_values(reference=True)
    x, g, p = c.point_values()
    assert np.array_equal(gr, g) and np.array_equal(pr, p) and len(X) == len(x) > 0
    local = c.segment_points()["X"]
    expected = np.concatenate(MPI.COMM_WORLD.allgather(local))
    expected = expected[np.lexsort(np.round(expected, 12).T[::-1])]
    assert np.array_equal(X, expected)
    assert np.ptp(X[:, -1]) < 1e-12 and np.max(np.abs(x - X)) > 1e-4  # the interface moved down with the strain
    with pytest.raises(ValueError, match="nominal"):
        c.point_values(reference=True, kind="cauchy")
    with pytest.raises(ValueError, match=c.name):
        c.friction_profile()


def test_pointwise_results_and_no_friction_profile():
    """Pointwise two-body surface: ``point_values(reference=True)`` are the reference positions of
    ``point_table`` (also ``reference_points``, each once); ``friction_profile`` raises ValueError naming it."""
    setup = build("patch", law_factory=lambda: make_law("penalty", K=1e3), quadrature="gauss", passes="one")
    c = setup.contacts[0]
    assert c.law is not None and c.law.name == "penalty"
    X, g, p = c.point_values(reference=True)
    table = c.point_table()
    assert np.array_equal(X, table[0]) and np.array_equal(g, table[2]) and np.array_equal(p, table[3])
    assert np.array_equal(np.unique(np.round(c.reference_points(), 12), axis=0), np.unique(np.round(X, 12), axis=0))
    with pytest.raises(ValueError, match=f"{c.name}: this surface has no friction"):
        c.friction_profile()


def test_bad_input():
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (3, 2))
    from fenics_contact.compat import function_space

    u = fem.Function(function_space(mesh, "Lagrange", 1, (2,)))
    load = fem.Constant(mesh, 0.0)
    law = make_law("penalty", K=1.0)
    with pytest.raises(ValueError, match="slave_tag and master_tag must differ"):
        TwoBodySurface(u, ft, "lower_top", "lower_top", law, load)
    with pytest.raises(ValueError, match="absent from the mesh"):
        TwoBodySurface(u, ft.meshtags, 99, ft["lower_top"], law, load)
    with pytest.raises(ValueError, match="absent from the mesh"):
        TwoBodySurface(u, ft.meshtags, ft["upper_bottom"], 98, law, load)
    from dolfinx import mesh as dmesh

    empty = dmesh.meshtags(mesh, 1, np.zeros(0, np.int32), np.zeros(0, np.int32))
    with pytest.raises(ValueError, match="absent from the mesh"):
        TwoBodySurface(u, empty, ft["upper_bottom"], ft["lower_top"], law, load)
    with pytest.raises(ValueError, match="quadrature"):
        TwoBodySurface(u, ft, "upper_bottom", "lower_top", law, load, quadrature="simpson")
    with pytest.raises(ValueError, match="passes"):
        build("patch", law_factory=lambda: law, passes="three")
    with pytest.raises(ValueError, match="unsupported combination simpson quadrature, P1"):  # capabilities
        two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load, quadrature="simpson")



@pytest.mark.parametrize("quadrature,by_body", [("gauss", True), ("segment", True), ("segment", False)])
def test_slave_and_master_on_different_ranks_equal_serial(quadrature, by_body):
    """With 2+ ranks and ``by_body`` the lower block (master) is on rank 0 and the upper (slave) on rank 1
    (else dolfinx's partition); the figures and the pressure at every slave point equal the serial ones
    (1e-8 relative)."""
    comm = MPI.COMM_WORLD
    par, _ = _patch(quadrature, "one", comm, by_body=by_body)
    c = par.contacts[0]
    if comm.size >= 2 and by_body:
        n_slave = comm.allgather(int(np.count_nonzero(c.slave_data.owned)))
        n_master = comm.allgather(int(np.count_nonzero(c.master_data.owned)))
        assert n_slave[0] == 0 and n_slave[1] > 0 and n_master[0] > 0 and n_master[1] == 0
    ser, _ = _patch(quadrature, "one", MPI.COMM_SELF)
    fp, fs = par.figures(), ser.figures()
    for k in fs:  # pressure_deviation is relative to the applied pressure already (segment: round-off)
        floor = 1.0 if k == "pressure_deviation" else 1e-3
        assert abs(fp[k] - fs[k]) <= 1e-8 * max(abs(fs[k]), floor), (k, fp[k], fs[k])
    xp, gp, pp = c.point_values()
    xs, gs, ps = ser.contacts[0].point_values()
    assert np.allclose(xp, xs, rtol=0, atol=1e-12) and np.allclose(pp, ps, rtol=1e-8, atol=1e-8 * ps.max())


def _blocks_3d(quadrature, comm=MPI.COMM_WORLD, by_body=False):
    setup = build("patch", law_factory=lambda: make_law("auglag", K=1e7), quadrature=quadrature, material="neohookean",
                  pressure=100.0, n_lower=(2, 2, 2), n_upper=(3, 3, 2), comm=comm, by_body=by_body)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-8, quiet=True)
    solver.run(setup.loads)
    return setup, solver


@pytest.mark.parametrize("quadrature", ["gauss", "segment"])
def test_3d_neo_hookean_blocks(quadrature):
    """Two stacked neo-Hookean unit cubes of tetrahedra, non-matching triangle facets at the interface (2 x 2
    against 3 x 3 cell columns), dead pressure 100 = E/10 on top (10 % strain), Gauss points (3 per
    triangle) or segment integration (clipped triangles), converged augmented Lagrangian. The exact solution
    is uniform uniaxial stress: the top face moves as the closed-form neo-Hookean stretches (measured 2.5e-10
    and 1e-15; linear elasticity would be 7.6 % off), contact force = applied load = support reaction, Newton
    quadratic; with segment integration the pressure is uniform too (the 3D patch test: measured 3.5e-11;
    Gauss points 0.33, the over-constrained multipliers). With 2+ ranks the lower block is on rank 0 and
    the upper on rank 1, and the figures equal a serial solve's (1e-8)."""
    comm = MPI.COMM_WORLD
    setup, solver = _blocks_3d(quadrature, comm, by_body=True)
    rec = solver.records[0]
    assert rec.converged and rec.augmentation_converged
    f = setup.figures()
    assert np.isclose(f["contact_force"], f["applied_force"], rtol=1e-9)
    assert np.isclose(f["reaction_bottom"], f["applied_force"], rtol=1e-9)
    assert f["top_displacement_error"] < 1e-6, f
    if quadrature == "segment":
        assert f["pressure_deviation"] < 1e-8, f
    from fenics_contact.app.scenes.patch import uniform_stretches

    linear = 2.0 * uniform_stretches(100.0, "linear", 3)[1] - 2.0
    assert abs(linear - f["top_displacement_exact"]) > 0.05 * abs(f["top_displacement_exact"])
    res = rec.residuals[0]  # (measured: 2.8e1, 3.5, 2.5e-3, 1.8e-9, ...)
    k = int(np.argmax(np.array(res) < 1e-6 * res[0]))
    assert k >= 2 and res[k] <= 10 * res[k - 1] ** 2 / res[0], res
    if comm.size > 1:
        ser, _ = _blocks_3d(quadrature, MPI.COMM_SELF)
        fs = ser.figures()
        for key in ("contact_force", "reaction_bottom", "pressure_deviation", "top_displacement_exact"):
            assert abs(f[key] - fs[key]) <= 1e-8 * max(abs(fs[key]), 1.0), (key, f[key], fs[key])
        assert abs(f["top_displacement_error"] - fs["top_displacement_error"]) <= 1e-8


def test_master_exchange_sends_only_the_facets_near_the_slave():
    """Box exchange of the master surface (two-body Hertz: a quarter disk on a block 4 R wide): at a deformed
    state each rank receives exactly the master facets whose current box overlaps one of the boxes bounding its
    slave facets, grown by the search radius and the routes' margin (none without slave facets), fewer than
    the whole surface; the projection (pairs as global facet numbers, gaps) equals the one on the whole master
    surface (``exchange = "allgather"``), also after a small motion that keeps the routes."""
    comm = MPI.COMM_WORLD
    setup = build("hertz", law=make_law("penalty", K=2.5e4), plate="meshed", E=200.0, nu=0.3, R=8.0, load=10.0,
                  plate_E=200.0, plate_width=32.0, plate_depth=16.0)
    c = setup.contacts[0]
    u = c.u
    x = u.function_space.tabulate_dof_coordinates()[:, :2]
    u.x.array[:] = (0.05 * np.sin(x / 3.0) - [0.0, 0.2]).ravel()  # a smooth motion, bodies pressed together
    u.x.scatter_forward()
    got = {}
    for mode in ("allgather", "boxes"):
        c.exchange = mode
        c.update()
        got[mode] = (c.pairing(), c.projection["gap"].copy(), c.pairs.master["ids"].copy())
    assert np.array_equal(got["boxes"][0], got["allgather"][0])
    assert np.array_equal(got["boxes"][1], got["allgather"][1])
    assert comm.allreduce(int(np.count_nonzero(got["boxes"][0] >= 0))) > 10  # points in contact
    # The facets a rank must receive, from the whole surface's current boxes.
    md, sd = c.master_data, c.slave_data
    xm = md.X[md.owned] + u.x.array[md.comp[md.owned]]
    ids = c.pairs.exchange.ids
    xm, ids = np.concatenate(comm.allgather(xm)), np.concatenate(comm.allgather(ids))
    xs = sd.X + u.x.array[sd.comp]
    near = np.zeros(len(xm), bool)
    if len(xs):
        lo, hi = leaf_boxes(xs.min(axis=1), xs.max(axis=1), c.radius * (1 + MARGIN))
        assert np.all(np.any(np.all((lo[None] <= xs.min(axis=1)[:, None]) & (xs.max(axis=1)[:, None] <= hi[None]),
                                    axis=2), axis=1))  # every slave facet is in a box
        for a, b in zip(lo, hi):
            near |= np.all(xm.min(axis=1) <= b, axis=1) & np.all(xm.max(axis=1) >= a, axis=1)
    assert np.array_equal(np.sort(got["boxes"][2]), np.sort(ids[near]))
    assert len(got["allgather"][2]) == len(xm) and np.count_nonzero(near) < 0.8 * len(xm)
    stats = c.exchange_stats()
    assert stats["updates"] == 3 and stats["reroutes"] == 3
    # A small motion (below the margin): the routes hold, only displacements move; the same projection.
    u.x.array[:] += 1e-3 * c.radius * np.cos(np.arange(len(u.x.array)))
    u.x.scatter_forward()
    c.exchange = "boxes"
    c.update()
    assert c.exchange_stats()["reroutes"] == 3
    small = (c.pairing(), c.projection["gap"].copy())
    c.exchange = "allgather"
    c.update()
    assert np.array_equal(small[0], c.pairing()) and np.array_equal(small[1], c.projection["gap"])


def test_new_coupling_pattern_keeps_the_near_nullspace():
    """GAMG's rigid-body near-nullspace survives a Jacobian whose coupling pattern changed (MatAXPY with a new
    pattern replaces the matrix header, which dropped it: the two-body block's Krylov counts then grew)."""
    from fenics_contact.app.cli import LINEAR_SOLVERS

    setup = build("patch", law_factory=lambda: make_law("penalty", K=1e3), quadrature="nodal", passes="one")
    p, c = setup.problem, setup.contacts[0]
    solver = Solver(p, quiet=True, options=dict(LINEAR_SOLVERS["iterative"]))
    x = p.create_vector()
    p.F(x, p.create_vector())
    for _ in range(2):
        c._pattern.version += 1  # as after a pairing change
        assert p.J(x, solver.A)
        near = solver.A.getNearNullSpace()
        assert near.handle and len(near.getVecs()) == 3


@pytest.mark.parametrize("dim", [2, 3])
def test_an_overhang_past_the_master_surface_carries_no_pressure(dim):
    """An upper block wider than the lower one, pressed down by a platen: the master surface (the lower block's
    top) ends at the block's edge, so the overhang's points past it (beyond the extension of a tenth of a master
    facet) carry no contact pressure, as the master surface went on past its edge they would (penetration of its
    plane: the overhang is pressed down too); the points above the lower block carry the load."""
    n_lower, n_upper = ((8, 4), (12, 4)) if dim == 2 else ((4, 4, 2), (6, 6, 2))
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 0.5, 0.5, n_lower, n_upper, upper_span=(-0.25, 1.25))
    law = lambda: make_law("penalty", K=1e5)  # noqa: E731
    u, V = fc.unknown(mesh, 1, law())
    load = fem.Constant(mesh, 0.0)
    bcs = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", i) for i in range(dim)]
    bcs += [fc.Dirichlet.on_facets(V, ft, "upper_top", i, -0.01 if i == dim - 1 else 0.0) for i in range(dim)]
    (c,) = two_body_surfaces(u, ft, "upper_bottom", "lower_top", law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(1000, 0.3), load, bcs, [c])
    solver = Solver(problem, quiet=True)
    solver.run([1.0])
    assert solver.records[0].converged
    x, _, p = c.point_values(reference=True)
    h = 1.0 / n_lower[0]  # the master facets' size across the edge
    past = np.any((x[:, :dim - 1] < -0.1 * h) | (x[:, :dim - 1] > 1 + 0.1 * h), axis=1)
    over = np.all((x[:, :dim - 1] > 0.2) & (x[:, :dim - 1] < 0.8), axis=1)
    comm = MPI.COMM_WORLD
    assert comm.allreduce(int(past.sum())) > 0 and comm.allreduce(float(np.max(p[past], initial=0.0)),
                                                                   op=MPI.MAX) == 0.0
    assert comm.allreduce(float(np.min(p[over], initial=np.inf)), op=MPI.MIN) > 5.0  # about E x strain = 20


@pytest.mark.parametrize("method", ["penalty", "coulomb"])
def test_small_sliding_past_its_range_is_a_warning(method):
    """Small sliding keeps each slave point's reference pair. An upper block pressed on a lower one (master facets
    0.25 long) and dragged along the interface by 0.6 facets slides off its pairs: the run's warnings say so, with
    the slide (0.6 facets, the rigid drag) and the step; dragged by 0.2 facets it stays on them: no warning.
    Pointwise penalty and the condensed exact method (small sliding by construction)."""
    facet = 0.25
    found = {}
    for drag in (0.2, 0.6):
        mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 0.5, 0.25, (4, 2), (3, 2), upper_span=(0.25, 0.75))
        u = fem.Function(function_space(mesh, "Lagrange", 1, (2,)), name="u")
        V = u.function_space
        load = fem.Constant(mesh, 0.0)
        law = (lambda: make_law("penalty", K=1e5)) if method == "penalty" else (lambda: make_law("coulomb", mu=0.3))
        contacts = two_body_surfaces(u, ft, "upper_bottom", "lower_top", law, load, "nodal", sliding="small",
                                     material=fc.LinearElastic(1000.0, 0.3))
        dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 0), fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1),
                     fc.Dirichlet.on_facets(V, ft, "upper_top", 1, -1e-3),
                     fc.Dirichlet.on_facets(V, ft, "upper_top", 0, drag * facet)]
        problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load, dirichlet, contacts,
                                    step_solver=fc.step_solver_for(contacts))
        with Solver(problem, quiet=True) as solver:
            solver.run([0.5, 1.0])
            found[drag] = [w for w in solver.record.warnings if "small sliding" in w]
    assert found[0.2] == []
    assert len(found[0.6]) == 1, found[0.6]
    slid = float(re.search(r"a point slid ([0-9.e+-]+) of its master facet", found[0.6][0]).group(1))
    assert abs(slid - 0.6) < 0.01, found[0.6]
    assert "at step 2 (t = 1)" in found[0.6][0]  # 0.3 facets at the first step: within range


def test_coupling_products_kept_while_the_pairing_stays():
    """The coupling's matrix products keep their pattern while the pairing stays (only their values are computed):
    the Jacobian at a new state with the same pairing (the upper block lifted, then pressed in: every point's
    coupling changes) equals the one made with products from scratch."""
    from fenics_contact.app.cli import LINEAR_SOLVERS

    setup = build("patch", law_factory=lambda: make_law("penalty", K=1e3), quadrature="nodal", passes="one")
    p, c = setup.problem, setup.contacts[0]
    solver = Solver(p, quiet=True, options=dict(LINEAR_SOLVERS["iterative"]))
    p.set_load(1.0)
    x, b = p.create_vector(), p.create_vector()
    V = p.u.function_space
    upper = V.tabulate_dof_coordinates()[: len(x.array) // 2, 1] > 1.0 - 1e-9
    jacobians, operators = [], []
    for shift in (1e-3, -2e-3):  # open, then pressed: the same master facets below every slave point
        x.array[:] = 0.0
        x.array[1::2][upper] = shift
        p.F(x, b)
        p.J(x, solver.A)
        jacobians.append(solver.A.copy())
        operators.append(c.coupling.operator)
    assert operators[1] is operators[0] and c.coupling._products[0] is operators[0]  # the same pairing: reused
    c.coupling._destroy_products()
    p.J(x, solver.A)  # products from scratch
    opened, pressed = jacobians
    opened.axpy(-1.0, pressed)
    assert opened.norm() > 1e-3 * pressed.norm()  # the coupling changed
    pressed.axpy(-1.0, solver.A)
    assert pressed.norm() <= 1e-13 * solver.A.norm()


def _kept_blocks_states(method):
    """A two-body problem with small sliding (method ``lagrange``: mindlin with friction; ``penalty``: patch), its
    solver and two states of the same pairing: pressed (the first load step solved) and open (its opposite)."""
    from fenics_contact.app.scenes import mindlin
    from fenics_contact.compat import petsc_vec

    if method == "lagrange":
        law = fc.Friction(make_law("lagrange"), mu=0.3, omega_t=mindlin.DEFAULT_OMEGA_T)
        setup = build("mindlin", law=law, sliding="small", ratios=(0.5,))
    else:
        setup = build("patch", law=make_law("penalty", K=1e3), quadrature="nodal", passes="one", sliding="small")
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads[:1])
    pressed = petsc_vec(setup.problem.u).copy()
    opened = pressed.copy()
    opened.scale(-1.0)
    return setup, solver, (opened, pressed)


@pytest.mark.parametrize("method, kept", [("lagrange", [(0, True), (1, False), (2, False)]),
                                          ("penalty", [(0, True), (1, True), (2, True)])])
def test_coupling_blocks_kept_while_their_inputs_stay(method, kept):
    """With small sliding and multipliers the master rows are linear in the pressure alone: ``A_wu`` is assembled
    again only when its inputs change (not at a new state of the same pairing) and ``A_ww`` is zero (its product
    left out); a penalty's master rows follow the gap (every block at every Jacobian). The Jacobian so made equals
    the one with every block assembled and multiplied from scratch, open and pressed."""
    setup, solver, states = _kept_blocks_states(method)
    p, coupling = setup.problem, setup.contacts[0].coupling
    b = p.create_vector()
    assembled = []
    original = coupling._assemble
    coupling._assemble = lambda i, bcs: assembled.append((i, original(i, bcs))) or assembled[-1][1]
    jacobians, couplings = [], []
    for x in states:
        p.F(x, b)
        del assembled[:]
        p.J(x, solver.A)
        calls = list(assembled)
        jacobians.append(solver.A.copy())
        parts = coupling.matrices(p.bcs)  # the same values again (inputs unchanged): their sum
        total = parts[0].duplicate(copy=True)
        for m in parts[1:]:
            total.axpy(1.0, m, structure=PETSc.Mat.Structure.DIFFERENT_NONZERO_PATTERN)
        couplings.append(total)
    assert calls == kept  # the pressed state's Jacobian
    assert (coupling._products[3] is None) == (method == "lagrange")  # A_ww zero: no product
    coupling._values = [None, None, None]  # from scratch: every block and product
    coupling._destroy_products()
    p.J(x, solver.A)
    assert [a for _, a in assembled[-3:]] == [True, True, True]
    opened, pressed = couplings
    opened.axpy(-1.0, pressed)
    assert opened.norm() > 1e-3 * pressed.norm()  # the coupling changed
    pressed = jacobians[1]
    pressed.axpy(-1.0, solver.A)
    assert pressed.norm() <= 1e-13 * solver.A.norm()
