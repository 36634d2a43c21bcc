"""The solver's load-step predictors: on a linear problem the tangent (Euler) predictor is the solution of the next
step; a bad predictor name is refused."""
import pytest
from mpi4py import MPI

from fenics_contact.app.scenes import build
from fenics_contact.laws import Penalty
from fenics_contact.solver import Solver


def first_residuals(predictor):
    setup = build("block", law=Penalty(1e5), steps=4)  # linear elasticity, flat obstacle, penalty
    solver = Solver(setup.problem, quiet=True, predictor=predictor)
    solver.run(setup.loads)
    return solver.records


def same_history(a, b):
    """Two Newton residual histories of one step are the same to round-off of its first residual: on several ranks
    the multipliers' field split solves its free block with MUMPS distributed over the ranks, whose solve sums the
    ranks' parts in the order they arrive (not bit-reproducible from run to run), so a quadratically falling residual
    differs after a few iterates in its own trailing digits but not against the step's scale."""
    import numpy as np

    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and bool(np.all(np.abs(a - b) <= 1e-12 * a[0]))


def test_tangent_predictor_is_exact_on_a_linear_problem():
    # once the whole base is closed (steps 2-4) the block is a linear problem in (u, t): the tangent of the load
    # path at the last converged state reaches the next one; without a predictor the step starts far from it
    plain, tangent = first_residuals(False), first_residuals("tangent")
    for p, r in zip(plain[1:], tangent[1:]):
        assert r.residuals[0][0] < 1e-7 * p.residuals[0][0]  # forward difference of dR/dt: ~1e-10 relative
        assert r.predictor_scale == 1.0 and r.newton_iterations <= 1
    assert all(r.converged for r in tangent)


def test_bad_predictor_names_the_parameter():
    setup = build("block", law=Penalty(1e5))
    with pytest.raises(ValueError, match="predictor"):
        Solver(setup.problem, predictor="quadratic")


def test_a_far_predicted_state_does_not_pass_the_relative_tolerance():
    """Two-body Hertz from rest (penalty, force control): the tangent predictor of the first step drives the disk
    through the block (residual ~3e11). Newton's relative tolerance then refers to the out-of-balance of the last
    converged state at the new load, not to the predicted one: every step ends converged in absolute terms (it
    stopped at a residual of 2.0, "converged" at 1e-11 x 3e11, before)."""
    from fenics_contact.methods import make_law

    setup = build("hertz", law=make_law("penalty", K=2.5e4), refinement=1, plate="meshed", E=200.0, nu=0.3, R=8.0,
                  load=10.0, plate_E=200.0, plate_width=32.0, plate_depth=16.0)
    solver = Solver(setup.problem, quiet=True, predictor="tangent")
    solver.run(setup.loads)
    for r in solver.records:
        assert r.converged and r.residuals[-1][-1] < 1e-9, (r.load, r.residuals[-1])
    f = setup.figures()
    assert f["load_error"] < 1e-9 and f["p0_error"] < 5e-3, (f["load_error"], f["p0_error"])


def test_a_singular_tangent_is_dropped_for_the_last_converged_state():
    """The seal under a penalty law at t = 0: its points touch with g = 0, where the law has no stiffness, so the
    tangent of the load path is singular. The run reaches its last load. Where the factors of the singular Jacobian
    give a direction whose predicted state is far out of balance (PETSc 3.18's MUMPS: ~1e17 times), the tangent is
    dropped (``PREDICTOR_WORSE``) and (serially) the first step, its cutback included, is the one without a
    predictor, iterate for iterate; where they give one along which the energy has its minimum next to the last
    state (PETSc 3.22's: at s ~ 1e-16), the step starts there, no further out of balance than the plain run's
    first step."""
    from fenics_contact.app.scenes import seal

    runs = {}
    for predictor in (False, "tangent"):
        setup = build("seal", law=Penalty(1e5), h=0.5)
        setup.loads = setup.loads[:2]
        solver = Solver(setup.problem, quiet=True, predictor=predictor, options=seal.SOLVER_OPTIONS)
        solver.run(setup.loads)
        assert all(r.converged for r in solver.records) and solver.records[-1].load == setup.loads[-1]
        runs[predictor] = solver
    if MPI.COMM_WORLD.size > 1:  # a singular system's factors depend on the partition: the run's end alone
        return
    plain, tangent = runs[False], runs["tangent"]
    first, start = plain.records[0], tangent.records[0]
    if start.predictor_scale == 0.0:
        assert [(f["load"], f["kind"]) for f in tangent.failures] == [(f["load"], f["kind"]) for f in plain.failures]
        assert same_history(start.residuals[-1], first.residuals[-1]), (start.residuals[-1], first.residuals[-1])
        assert start.newton_iterations == first.newton_iterations
    else:
        assert start.predictor_scale < 1e-6 and start.residuals[0][0] < 10 * first.residuals[0][0], \
            (start.predictor_scale, start.residuals[0][0], first.residuals[0][0])


def test_a_load_undefined_at_the_last_state_solves_nothing():
    """mindlin's tangential traction is ``amplitude (t - 1)+ / t`` (the problem scales it by ``t``): 0/0 at t = 0, so
    ``dR/dt`` there is not finite. The tangent is dropped before any linear solve (a solve of a NaN right-hand side
    ends before a nested field split is set up; PETSc 3.18's ``-ksp_view`` of it crashes), and the first step is the
    one without a predictor."""
    import numpy as np

    import fenics_contact as fc
    from fenics_contact.app.scenes import mindlin
    from fenics_contact.methods import make_law

    runs = {}
    for predictor in (False, "tangent"):
        law = fc.Friction(make_law("lagrange"), mu=0.3, omega_t=mindlin.DEFAULT_OMEGA_T)
        setup = build("mindlin", law=law, sliding="small", ratios=(0.5,))
        solver = Solver(setup.problem, quiet=True, predictor=predictor)
        linear, rhs = solver.newton.linear, []
        solve = linear.solve
        linear.solve = lambda A, b, x, rhs=rhs, solve=solve: (rhs.append(b.norm()), solve(A, b, x))[1]
        solver.run(setup.loads[:1])
        assert np.all(np.isfinite(rhs)) and solver.records[0].converged
        runs[predictor] = solver.records[0]
    assert runs["tangent"].predictor_scale == 0.0
    assert same_history(runs["tangent"].residuals[-1], runs[False].residuals[-1]), (runs["tangent"].residuals[-1],
                                                                                 runs[False].residuals[-1])
