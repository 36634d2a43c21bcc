"""Exact friction with the traction an unknown (method ``lagrange`` with friction, Alart-Curnier's functions, one
semismooth Newton on the sparse system): the condensed exact method's discrete problem, rigid obstacles and two
bodies, 2D and 3D, solved without its dense block; Tresca's bound; the same on 1 and 2 ranks; what it does not take
refused up front."""
import sys
from pathlib import Path

import numpy as np
import pytest
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

import fenics_contact as fc
from fenics_contact.app.scenes import build
from fenics_contact.laws import ExactCoulomb, LagrangeMultiplier
from fenics_contact.multipliers import KRYLOV_RTOL_MAX
from fenics_contact.solver import LINEAR_SOLVERS, Solver
from fenics_contact.solver.options import solver_options

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_coulomb3d import PRESS, _box, _top_motion  # noqa: E402

SLAB_C = 1e3  # Alart-Curnier's c for the slab, E / h / 10 (steers Newton only)


def _slab(law, comm=MPI.COMM_WORLD) -> tuple[dict, Solver]:
    setup = build("slab", law=law, comm=comm)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    return setup.figures(), solver


@pytest.mark.parametrize("mu", [0.0, 0.4, 1.3, 1.5])
def test_slab_equals_the_condensed_exact_method(mu):
    """Renaud and Feng's slab (flat rigid plate, linear, small sliding): u_x(A), u_y(A), the zones and both forces
    are the condensed method's to round-off (1e-10), in at most 6 Newton iterations; also at mu = 1.5, where the
    paper's FEM diverged."""
    exact, _ = _slab(ExactCoulomb(mu))
    sparse, solver = _slab(fc.Friction(LagrangeMultiplier(SLAB_C), mu=mu))
    scale = abs(exact["ux_A"])
    assert abs(sparse["ux_A"] - exact["ux_A"]) <= 1e-10 * scale
    assert abs(sparse["uy_A"] - exact["uy_A"]) <= 1e-10 * scale
    assert sparse["zones"] == pytest.approx(exact["zones"], abs=1e-12)
    assert sparse["zone_pattern"] == exact["zone_pattern"]
    for k in ("normal_force", "tangential_force"):
        assert sparse[k] == pytest.approx(exact[k], rel=1e-10, abs=1e-10 * exact["normal_force"]), k
    assert sparse["normal_equilibrium_error"] < 1e-10 and sparse["tangential_equilibrium_error"] < 1e-10
    assert solver.records[-1].newton_iterations <= 6


def _box_on_plane(law, mu_drag, comm=MPI.COMM_WORLD, options=None, material=None):
    """The box of tests/test_coulomb3d.py on the plane z = 0, pressed then dragged 30 degrees off x; the base's
    friction profile after each of the loads (``options``: the solver's; ``material``: default linear,
    E = 1000, nu = 0)."""
    msh, facets = _box(comm)
    load = fem.Constant(msh, 0.0)
    if isinstance(law, ExactCoulomb):
        V = fc.function_space(msh, "Lagrange", 1, (3,))
        u = fem.Function(V)
    else:
        u, V = fc.unknown(msh, 1, law)
    c = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), law, load)
    step = {"step_solver": fc.step_solver_for([c])} if isinstance(law, ExactCoulomb) else {}
    problem = fc.ContactProblem(u, material or fc.LinearElastic(1000.0, 0.0), load,
                                _top_motion(V, facets, "top", mu_drag), [c], **step)
    solver = fc.Solver(problem, quiet=True, options=options)
    solver.run([1.0, 1.25, 1.5, 1.75, 2.0])
    profile = c.friction_profile()
    order = np.lexsort(np.round(profile["x"], 9).T[::-1])  # by position, whatever the round-off of the partition
    return {k: np.asarray(v)[order] for k, v in profile.items()}, solver


@pytest.mark.parametrize("mu, drag", [(0.3, 40 * PRESS), (2.0, PRESS / 20)])
def test_box_in_3d_equals_the_condensed_exact_method(mu, drag):
    """3D, the Coulomb disk: a box dragged far with little friction (every vertex slides) or a little with much
    (every vertex sticks): each base vertex's pressure and traction are the condensed method's to 1e-9 of the
    largest pressure, the same slip states."""
    exact, _ = _box_on_plane(ExactCoulomb(mu), drag)
    sparse, solver = _box_on_plane(fc.Friction(LagrangeMultiplier(100.0), mu=mu), drag)
    assert all(r.converged for r in solver.records)
    scale = np.abs(exact["pressure"]).max()
    assert np.allclose(sparse["x"], exact["x"])
    assert np.abs(sparse["pressure"] - exact["pressure"]).max() <= 1e-9 * scale
    assert np.abs(sparse["traction"] - exact["traction"]).max() <= 1e-9 * scale
    assert np.array_equal(sparse["state"], exact["state"])


def test_a_linear_bodys_displacement_block_keeps_its_multigrid():
    """The iterative solve of the multipliers on a linear body (its stiffness the same at every iterate): the
    displacement block's GAMG hierarchy is built at the first solve and kept (PETSc read the block's
    ``ksp_reuse_preconditioner``), and the 3D box dragged with friction (every vertex sliding) gets the direct
    solve's pressures and tractions to 1e-9 of the largest pressure and its slip states. A neo-Hookean body's block
    is set up at every solve."""
    law = fc.Friction(LagrangeMultiplier(100.0), mu=0.3)
    key = "fieldsplit_free_fieldsplit_u_ksp_reuse_preconditioner"
    direct, _ = _box_on_plane(law, 40 * PRESS)
    iterative, solver = _box_on_plane(law, 40 * PRESS, options=LINEAR_SOLVERS["iterative"])
    assert all(r.converged for r in solver.records) and solver.linear_iterations > 0
    assert key in solver.options.used
    scale = np.abs(direct["pressure"]).max()
    assert np.abs(iterative["pressure"] - direct["pressure"]).max() <= 1e-9 * scale
    assert np.abs(iterative["traction"] - direct["traction"]).max() <= 1e-9 * scale
    assert np.array_equal(iterative["state"], direct["state"])
    msh, facets = _box(MPI.COMM_WORLD)
    load = fem.Constant(msh, 0.0)
    u, V = fc.unknown(msh, 1, law)
    c = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), law, load)
    for material, kept in ((fc.LinearElastic(1000.0, 0.0), True), (fc.NeoHookean(1000.0, 0.0), False)):
        problem = fc.ContactProblem(u, material, load, _top_motion(V, facets, "top", PRESS), [c])
        assert (key in solver_options(problem, LINEAR_SOLVERS["iterative"])) == kept, material


def test_the_krylov_tolerance_follows_the_newton_residual():
    """The multipliers' iterative solve takes each Newton iteration's Krylov tolerance from the residual
    (``ksp_rtol_max``, :meth:`Newton.forcing`): the square of the last residual ratio within [ksp_rtol,
    ksp_rtol_max], loose at a solve's start, and never tighter than a linear error of a tenth of the solve's
    tolerance. On the 3D box dragged with friction (every vertex sliding) it spends
    fewer Krylov iterations than the fixed tolerance (``ksp_rtol_max`` 0: off) and gets the direct solve's
    pressures and tractions to 1e-9 of the largest pressure and its slip states."""
    law = fc.Friction(LagrangeMultiplier(100.0), mu=0.3)
    direct, _ = _box_on_plane(law, 40 * PRESS)
    runs = {}
    for name, extra in (("forcing", {}), ("fixed", {"ksp_rtol_max": 0.0})):
        profile, solver = _box_on_plane(law, 40 * PRESS, options={**LINEAR_SOLVERS["iterative"], **extra})
        assert all(r.converged for r in solver.records)
        runs[name] = profile, solver.linear_iterations, solver.newton
    scale = np.abs(direct["pressure"]).max()
    for name, (profile, _, _) in runs.items():
        assert np.abs(profile["pressure"] - direct["pressure"]).max() <= 1e-9 * scale, name
        assert np.abs(profile["traction"] - direct["traction"]).max() <= 1e-9 * scale, name
        assert np.array_equal(profile["state"], direct["state"]), name
    assert runs["forcing"][1] < runs["fixed"][1], (runs["forcing"][1], runs["fixed"][1])
    newton = runs["forcing"][2]
    assert newton.forcing_range == (1e-8, KRYLOV_RTOL_MAX) and runs["fixed"][2].forcing_range is None
    # histories in units of the last solve's tolerance T; near it the tolerance leaves a linear error of T / 10
    T = newton.tolerance()
    assert T > 0
    for history, eta in (([1e9], KRYLOV_RTOL_MAX), ([1e9, 5e8], KRYLOV_RTOL_MAX), ([1e9, 1e6], 1e-6),
                         ([1e13, 1e8], 1e-8), ([1e9, 1e4], 1e-5), ([1e9, 10.0], 1e-2)):
        newton.history = [h * T for h in history]
        assert newton.forcing() == pytest.approx(eta, rel=1e-12), history


def test_tresca_bound_on_the_slab():
    """Tresca (a fixed bound s on the closed points): pushed harder than s times the base can hold, the slab is held
    at the symmetry plane; the friction force on the sliding part is s per unit length, every closed vertex's
    traction at most s, the sliding ones at s."""
    s = 1.0
    f, _ = _slab(fc.Friction(LagrangeMultiplier(SLAB_C), tresca=s))
    base = f["base"]
    closed = np.asarray(base["pressure"]) > 0
    q = np.abs(np.asarray(base["traction"]))
    state = np.asarray(base["state"])
    assert np.all(q[closed] <= s * (1 + 1e-10))
    assert np.allclose(q[closed & (state == 1)], s, rtol=1e-10)
    assert f["zones"]["sliding"] > 0 and f["tangential_equilibrium_error"] < 1e-10


def test_parallel_equals_serial():
    """Under mpirun -n 2 the slab's figures (mu = 0.4) equal each rank's own serial run to 1e-10."""
    law = lambda: fc.Friction(LagrangeMultiplier(SLAB_C), mu=0.4)  # noqa: E731
    parallel, _ = _slab(law(), MPI.COMM_WORLD)
    serial, _ = _slab(law(), MPI.COMM_SELF)
    for k in ("ux_A", "uy_A", "normal_force", "tangential_force", "symmetry_reaction"):
        assert parallel[k] == pytest.approx(serial[k], rel=1e-10, abs=1e-12), k
    assert parallel["zones"] == pytest.approx(serial["zones"], abs=1e-12)


@pytest.mark.parametrize("scene, h", [("mindlin", 4.0), ("mindlin3d", 2.0)])
def test_cattaneo_mindlin_equals_the_condensed_exact_method(scene, h):
    """Two bodies, small sliding: Cattaneo-Mindlin's cylinder (2D) and sphere (3D) on a block, the contact mesh
    coarsened by ``h``: the force, each ratio's shear and stick radii, the contact radius and the errors against
    Cattaneo-Mindlin (relative figures: to 1e-9 absolutely) are the condensed method's to 1e-9."""
    from fenics_contact.app.scenes import mindlin, mindlin3d

    size = {"mindlin": mindlin.R / 600, "mindlin3d": mindlin3d.H_CONTACT * mindlin3d.R}[scene]
    figures = []
    for law in (ExactCoulomb(0.3), fc.Friction(LagrangeMultiplier(1e3), mu=0.3)):
        setup = build(scene, law=law, h_contact=h * size)
        with fc.Solver(setup.problem, quiet=True) as solver:
            solver.run(setup.loads)
            assert all(r.converged for r in solver.records)
        figures.append(setup.figures())
    exact, sparse = figures
    compared = [k for k, v in exact.items() if isinstance(v, float) and k in sparse]
    assert {"P", "Q_0.5", "a", "c_0.5"} <= set(compared)
    for k in compared:  # the errors are relative figures: to 1e-9 absolutely (the fits' round-off on the ranks)
        assert sparse[k] == pytest.approx(exact[k], rel=1e-9, abs=1e-9 if "error" in k else 1e-12), k


def test_what_it_does_not_take_is_refused():
    """Quadratic displacements and a normal-compliance bound are refused before any assembly."""
    from fenics_contact.app.meshes import stacked_blocks

    law = fc.Friction(LagrangeMultiplier(1e3), mu=0.3)
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (2, 2), 1e-6)
    u, _ = fc.unknown(mesh, 1, law)
    with pytest.raises(fc.UnsupportedCombination, match="degree 1"):
        fc.unknown(mesh, 2, law)
    with pytest.raises(ValueError, match="not c_t"):
        fc.contact_surface(u, ft, "lower_bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]),
                           fc.Friction(LagrangeMultiplier(1e3), c_t=1e3), fem.Constant(mesh, 0.0))


def test_the_run_takes_the_sparse_method_where_the_condensed_one_is_too_large(monkeypatch, caplog):
    """A scene built with method coulomb whose condensed system exceeds its dense limit (lowered here to 10 contact
    dofs) is solved by the sparse exact method instead, said in one line with the size it refused (also in the run's
    parameters): the same answer to round-off."""
    import logging

    from fenics_contact.condensed import operator
    from fenics_contact.multiplier_friction import MultiplierFrictionalContact

    exact, _ = _slab(ExactCoulomb(0.4))
    monkeypatch.setattr(operator, "MAX_CONDENSED", 10)
    with caplog.at_level(logging.WARNING, logger="fenics_contact"):
        setup = build("slab", law=ExactCoulomb(0.4))
    assert isinstance(setup.contacts[0], MultiplierFrictionalContact)
    refused = setup.parameters["condensed_contact_dofs"]  # the size it refused, recorded with the run
    assert refused > 10
    if MPI.COMM_WORLD.rank == 0:
        said = [r.getMessage() for r in caplog.records if "sparse exact method instead" in r.getMessage()]
        assert len(said) == 1 and f"{refused} contact dofs, more than its dense condensed system's 10" in said[0], said
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert abs(setup.figures()["ux_A"] - exact["ux_A"]) <= 1e-10 * abs(exact["ux_A"])


def test_coulomb_takes_the_iterative_solver_only_where_it_switches_to_the_sparse_method(monkeypatch, tmp_path_factory):
    """Method coulomb with ``--solver iterative``: refused in one line, before anything is written, where the condensed
    system solves the scene (it factors the stiffness itself); where the condensed system is too large (its limit
    lowered here) the run takes the sparse exact method with that solver, and the condensed method's answer (1e-8).
    A 3D demo's own default solver (mindlin3d: iterative) serves the switched run when ``--solver`` is not given."""
    from fenics_contact.app.cli import UsageError
    from fenics_contact.app.demos import mindlin3d, slab
    from fenics_contact.condensed import operator

    tmp_path = Path(MPI.COMM_WORLD.bcast(str(tmp_path_factory.mktemp("switch"))))  # one folder for all ranks
    argv = ["--method", "coulomb", "--mu", "0.4", "--solver", "iterative", "--no-pictures", "--quiet"]
    out = tmp_path / "condensed"
    with pytest.raises(UsageError, match="^--solver iterative: method coulomb solves this scene on its condensed"):
        slab.main(argv + ["--out", str(out)])
    assert not out.exists()
    exact, _ = _slab(ExactCoulomb(0.4))
    default_limit = operator.MAX_CONDENSED
    monkeypatch.setattr(operator, "MAX_CONDENSED", 10)
    summary = slab.main(argv + ["--out", str(tmp_path / "sparse")])
    assert summary["parameters"]["solved_by"].startswith("lagrange") and summary["parameters"]["solver"] == "iterative"
    assert summary["ux_A"] == pytest.approx(exact["ux_A"], rel=1e-8)

    seen = {}
    monkeypatch.setattr(mindlin3d, "run", lambda setup, *a, **k: seen.update(k) or {})
    for limit, solver in ((10, "iterative"), (default_limit, "direct")):
        monkeypatch.setattr(operator, "MAX_CONDENSED", limit)
        mindlin3d.main(["--method", "coulomb", "--h-contact", "0.015", "--out", str(tmp_path / "m"), "--no-pictures"])
        assert seen["args"].solver == solver and seen["options"]["ksp_type"] == LINEAR_SOLVERS[solver]["ksp_type"]


def test_the_bodies_constant_jacobian_is_added_not_assembled_again():
    """Linear elasticity: the bodies' Jacobian is assembled once and added to the contact's at every Newton
    iteration; the slab (mu = 0.4) then has the figures (to 1e-12) and Newton iterations of a run that assembles
    it every time. A neo-Hookean body's Jacobian changes with the displacement: assembled every time."""
    runs = []
    for reuse in (False, True):
        setup = build("slab", law=fc.Friction(LagrangeMultiplier(SLAB_C), mu=0.4))
        setup.problem.bulk_jacobian.reuse = reuse
        with Solver(setup.problem, quiet=True) as solver:
            solver.run(setup.loads)
            runs.append((setup.figures(), [r.newton_iterations for r in solver.records]))
        assert (setup.problem.bulk_jacobian.matrix is not None) == reuse
    (fresh, its_fresh), (reused, its_reused) = runs
    assert its_fresh == its_reused
    for k in ("ux_A", "uy_A", "normal_force", "tangential_force"):
        assert reused[k] == pytest.approx(fresh[k], rel=1e-12, abs=1e-12 * abs(fresh["normal_force"])), k
    assert reused["zones"] == pytest.approx(fresh["zones"], abs=1e-12)
    setup = build("slab", law=fc.make_law("penalty", K=1e5), model="neohookean")
    with Solver(setup.problem, quiet=True) as solver:
        solver.run(setup.loads[:1])
    assert setup.problem.bulk_jacobian.matrix is None


def test_the_jacobian_holds_only_what_can_be_nonzero():
    """The traction lives on the whole mesh (fixed to 0 off the contact): dolfinx's pattern couples every pair of a
    cell's dofs, traction too, where the bodies couple the displacement alone. The Jacobian's matrix holds the
    displacement's pairs, the contact cells' blocks and the diagonal: the 3D box's Jacobian after the drag equals,
    entry for entry, the one assembled in dolfinx's pattern, with fewer stored entries (a little over half: most of
    the small box's cells touch its base; at mindlin3d's default mesh 0.32)."""
    from dolfinx.fem.petsc import assemble_matrix

    from fenics_contact.compat import petsc_vec

    law = fc.Friction(LagrangeMultiplier(100.0), mu=0.3)
    msh, facets = _box(MPI.COMM_WORLD)
    load = fem.Constant(msh, 0.0)
    u, V = fc.unknown(msh, 1, law)
    c = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), law, load)
    problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.0), load, _top_motion(V, facets, "top", 40 * PRESS),
                                [c])
    with Solver(problem, quiet=True) as solver:
        solver.run([1.0, 1.5])
    assert solver.records[-1].converged
    x = petsc_vec(u)
    trimmed, full = problem.create_matrix(), assemble_matrix(problem._a_parts[0])  # full: its pattern filled
    full.assemble()
    for A in (trimmed, full):
        problem.J(x, A)
        A.assemble()
    info = PETSc.Mat.InfoType.GLOBAL_SUM
    assert trimmed.getInfo(info)["nz_used"] < 0.6 * full.getInfo(info)["nz_used"]
    scale = full.norm(PETSc.NormType.INFINITY)
    lo, hi = full.getOwnershipRange()
    for i in range(lo, hi):  # row by row: every entry of the full pattern, zero where the trimmed one has none
        cols, values = full.getRow(i)
        kept, kept_values = trimmed.getRow(i)
        at = np.searchsorted(cols, kept)
        assert np.array_equal(cols[at], kept), i
        values[at] -= kept_values
        assert np.abs(values).max() <= 1e-14 * scale, i


def test_inexact_newton_is_refused_up_front():
    """Inexact Newton (``snes_ksp_ew``, the demos' ``--inexact``) with method lagrange with friction is refused
    before any work, naming the option: a loose linear solve let mindlin3d's cap, held along x by friction alone,
    slide 0.48 R off its contact and "converge" with no contact force."""
    setup = build("slab", law=fc.Friction(LagrangeMultiplier(SLAB_C), mu=0.4))
    with pytest.raises(ValueError, match="snes_ksp_ew = True .*combination lagrange, inexact solver, friction"):
        Solver(setup.problem, quiet=True, options={"snes_ksp_ew": True})
    # declared on the capability grid: the frictionless method takes it
    assert not fc.capabilities.supported(method="lagrange", friction=True, solver="inexact")
    assert fc.capabilities.supported(method="lagrange", friction=False, solver="inexact")


@pytest.mark.slow
def test_the_iterative_solve_gives_the_direct_solves_answer():
    """Cattaneo-Mindlin's sphere (mindlin3d, the contact mesh coarsened 2 x) with the sparse exact method solved by
    FGMRES with the multipliers' field split and GAMG (the u rows' augmentation ``AUGMENT`` c keeps the Krylov
    iterations per Newton iteration low) has the figures of MUMPS LU to 1e-8: the same discrete problem."""
    from fenics_contact.app.scenes import mindlin3d, scale_alart_curnier
    from fenics_contact.solver import LINEAR_SOLVERS

    figures = []
    for options in (LINEAR_SOLVERS["direct"], mindlin3d.ITERATIVE):
        setup = build("mindlin3d", law=fc.Friction(LagrangeMultiplier(1.0), mu=0.3),
                      h_contact=2 * mindlin3d.H_CONTACT * mindlin3d.R)
        scale_alart_curnier(setup)
        with Solver(setup.problem, quiet=True, options=options) as solver:
            solver.run(setup.loads)
            assert all(r.converged for r in solver.records)
        figures.append(setup.figures())
    direct, iterative = figures
    for k in ("P", "Q_0.2", "Q_0.5", "Q_0.8", "c_0.2", "c_0.5", "c_0.8", "a"):
        assert iterative[k] == pytest.approx(direct[k], rel=1e-8), k
