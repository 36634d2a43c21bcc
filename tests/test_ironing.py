"""ironing: a stiff punch pressed into a soft neo-Hookean block and dragged along it, node-to-segment Coulomb friction
between the two deformable bodies (large sliding, finite strain). A short drag on the demo's contact mesh (h = 0.05:
on h = 0.1 two or three slave nodes sample the contact on each fillet and the ratio swings by 4 % of mu, its farthest
step 2.8 % off; docs/scenes.md)."""
import dolfinx.fem.petsc as fem_petsc
import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

import fenics_contact as fc
import fenics_contact.app as app
from fenics_contact.app.scenes import ironing

from solved import solved

MU = 0.3
# A drag of 0.35 in 8 steps of 0.044 (0.875 h: the punch takes 8 positions between two slave nodes), the window
# from 0.15 on (after the first two steps the whole contact slides), the block 0.5 beyond the punch at both ends.
SHORT = {"drag": 0.35, "drag_steps": 8, "steady_from": 0.15, "margin": 0.5}


def _law():
    return fc.Friction(fc.make_law("penalty", K=ironing.DEFAULT_K), mu=MU, omega_t=ironing.DEFAULT_OMEGA_T)


def _run(comm=MPI.COMM_WORLD):
    """The short drag solved (once per communicator size): setup, solver, figures (convergence is a test)."""
    return solved("ironing short drag", lambda c: app.build("ironing", law=_law(), comm=c, **SHORT), comm,
                  converged=False, predictor=ironing.PREDICTOR)


def test_drag_converges_and_the_steady_force_ratio_is_mu():
    """At the scene's defaults (penalty, predictor, the demo's drag step): no failed Newton attempt (no cutback), at
    most 5 Newton iterations per step on average (measured 4.6 on this short drag, 4.3 on the demo's) and 10 in any
    step; in the steady window every step's tangential over normal force on the punch (its frame) is within 2 % of
    mu, every closed point slides, and the ratio is the pressure resultant's tilt psi turned by Coulomb's angle,
    (mu + tan psi) / (1 - mu tan psi), to round-off."""
    setup, solver, f = _run()
    its = [r.newton_iterations for r in solver.records]
    print(f"ironing: Newton iterations per step {its} (mean {np.mean(its):.2f}); window ratio mean "
          f"{f['ratio_mean']:.6f}, peak to peak {f['ratio_peak_to_peak']:.2e}, farthest from mu {f['ratio_worst']:.6f}")
    assert all(r.converged for r in solver.records) and len(solver.records) == len(setup.loads)
    assert not solver.failures, solver.failures
    assert np.mean(its) <= 5 and max(its) <= 10, its
    assert f["window_steps"] >= 4
    assert f["ratio_max_error"] <= 0.02, f
    assert f["slip_fraction"] == 1.0
    assert f["coulomb_identity_error"] <= 1e-10, f
    assert f["face_angle_max"] < 1e-3  # the punch's frame is (nearly) the global one: the 100x stiffer punch
    assert abs(f["ratio_global_mean"] - f["ratio_mean"]) <= 0.01 * MU
    assert f["min_jacobian"] < 0.9  # finite strain: the block's volume changes by more than 10 % somewhere


def test_equilibrium_of_both_bodies():
    """The contact forces on the two bodies are equal and opposite (the contact residual over both bodies sums to
    zero, 1e-8 of the normal force) and the punch's top reaction balances the contact force on the punch (1e-8)."""
    setup, _, f = _run()
    c = setup.contacts[0]
    u = setup.problem.u
    b = fem_petsc.assemble_vector(fem.form(c.residual(ufl.TestFunction(u.function_space))))
    b.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    c.add_residual(b)
    total = [MPI.COMM_WORLD.allreduce(float(np.sum(b.array[i::2]))) for i in (0, 1)]
    F = np.array([f["Fx"], f["Fy"]])
    assert max(abs(v) for v in total) <= 1e-8 * abs(F[1]), total
    b.destroy()
    top = [d for d in setup.problem.dirichlet if d.path is not None]  # the punch's top: x then y
    reaction = np.array([setup.problem.reaction(d.dofs) for d in top])
    print(f"ironing: contact force on the punch {F}, top reaction {reaction}")
    assert np.allclose(reaction, -F, rtol=0, atol=1e-8 * abs(F[1])), (reaction, F)


def test_dissipation_is_nonnegative_and_the_sliding_work():
    """The friction work dissipated grows at every committed step and over the steady window it is the tangential
    force times the punch's travel to within the block surface's own motion (5 %)."""
    setup, _, f = _run()
    rows = setup.history()
    d = np.array([r["dissipated"] for r in rows])
    assert np.all(np.diff(d) >= 0.0) and d[-1] > 0.0
    window = [r for r in rows if r["load"] > 1.0 and r["travel"] >= SHORT["steady_from"] - 1e-12]
    work = sum(-0.5 * (a["Ft"] + b["Ft"]) * (b["travel"] - a["travel"]) for a, b in zip(window, window[1:]))
    dissipated = window[-1]["dissipated"] - window[0]["dissipated"]
    print(f"ironing: dissipated over the window {dissipated:.6g}, tangential force x travel {work:.6g}")
    assert 0.95 * work <= dissipated <= 1.05 * work


@pytest.mark.skipif(MPI.COMM_WORLD.size == 1, reason="compares a parallel run with the serial one")
def test_parallel_equals_serial():
    """Under mpirun -n 2: the figures and the per-step force history equal the serial ones (each rank also solves
    alone) to 1e-8."""
    parallel_setup, _, parallel = _run(MPI.COMM_WORLD)
    serial_setup, _, serial = _run(MPI.COMM_SELF)
    for k, v in serial.items():
        if isinstance(v, float) and k != "face_angle_max":
            assert abs(parallel[k] - v) <= 1e-8 * max(abs(v), 1e-6), (k, parallel[k], v)
    for a, b in zip(parallel_setup.history(), serial_setup.history()):
        for k in ("Fx", "Fy", "ratio", "dissipated"):
            assert abs(a[k] - b[k]) <= 1e-8 * max(abs(b["Fy"]), 1e-6), (k, a[k], b[k])


def test_bad_input():
    with pytest.raises(ValueError, match="theta must be in"):
        app.build("ironing", law=_law(), theta=120.0)
    with pytest.raises(ValueError, match="depth must be below"):
        app.build("ironing", law=_law(), depth=0.6)
    with pytest.raises(ValueError, match="Coulomb friction law with mu > 0"):
        app.build("ironing", law=fc.make_law("penalty", K=1e5))
    with pytest.raises(ValueError, match="method nitsche is refused on ironing"):
        app.build("ironing", law=fc.Friction(fc.make_law("nitsche", gamma0=10.0), mu=MU))
    with pytest.raises(ValueError, match="drag_steps must be an integer"):
        app.build("ironing", law=_law(), drag_steps=0)
