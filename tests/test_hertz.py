"""Cylinder on a rigid plane against Hertz (plane strain)."""
import re

import numpy as np
import pytest

from fenics_contact.app.scenes import hertz
from fenics_contact.laws import AugmentedLagrangian, CrossConstraints, Penalty
from fenics_contact.solver import Solver
from fenics_contact.solver.validity import max_strain


def solve(law, refinement=0, **kw):
    setup = hertz.build(law, refinement=refinement, **kw)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged and r.augmentation_converged for r in solver.records)
    return setup.figures()


def test_hertz_formulas():
    a, p0 = hertz.hertz(P=1.0, R=1.0, E=1.0, nu=0.0)
    assert np.isclose(a, np.sqrt(4 / np.pi)) and np.isclose(p0 * np.pi * a / 2, 1.0)
    x = np.linspace(0, 2, 21)
    p = np.sqrt(np.clip(1 - x**2 / 1.23**2, 0, None))
    assert np.isclose(hertz.contact_half_width(x, p), 1.23, rtol=1e-12)


@pytest.mark.parametrize("law", [CrossConstraints(hertz.DEFAULT_K), AugmentedLagrangian(hertz.DEFAULT_K)],
                         ids=["cross", "auglag"])
def test_p0_and_a_within_2_percent_and_equilibrium(law):
    f = solve(law)
    assert f["p0_error"] < 0.02 and f["a_error"] < 0.02
    assert f["contact_nodes"] >= 5
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


def test_plane_stress_against_hertz_with_E_star_E():
    """Plane stress: Hertz with E* = E (not E/(1-nu^2)); the same approach presses less hard (the plane-strain
    formula would be off by (1-nu^2)^(-1/2) - 1 = 4.8 % in p0)."""
    a, p0 = hertz.hertz(P=1.0, R=1.0, E=1.0, nu=0.3, plane="stress")
    assert np.isclose(a, np.sqrt(4 / np.pi))
    f = solve(AugmentedLagrangian(hertz.DEFAULT_K), plane="stress")
    strain = solve(AugmentedLagrangian(hertz.DEFAULT_K))
    assert f["p0_error"] < 0.01 and f["a_error"] < 0.02
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)
    assert f["total_force"] < strain["total_force"]


def test_refinement_reduces_p0_error():
    errors = [solve(AugmentedLagrangian(hertz.DEFAULT_K), r)["p0_error"] for r in (0, 1)]
    assert errors[1] < errors[0]


def test_snes_vi_reference_is_the_augmented_limit():
    """Exact nodal enforcement (SNES VI) and converged augmentation solve the same discrete problem."""
    from fenics_contact.laws import SnesVI

    vi = solve(SnesVI())
    aug = solve(AugmentedLagrangian(hertz.DEFAULT_K))
    assert np.isclose(vi["p0"], aug["p0"], rtol=1e-6) and np.isclose(vi["a"], aug["a"], rtol=1e-6)
    assert np.isclose(vi["total_force"], vi["reaction_top"], rtol=1e-8)


P_FORCE = 0.36  # about the default approach's load (0.363)


@pytest.mark.parametrize("method", ["auglag", "lagrange", "vi"])
def test_force_control_from_rest(method):
    """A disk held only by the contact, pressed by a force (``load``), from rest: p0 and a against Hertz for the
    applied load within the displacement-controlled tolerance; the vanishing spring is 0 at the end, so the
    contact carries the whole load."""
    from fenics_contact.methods import make_law

    law = {"auglag": lambda: AugmentedLagrangian(hertz.DEFAULT_K), "lagrange": lambda: make_law("lagrange", c=1e3),
           "vi": lambda: make_law("vi")}[method]()
    f = solve(law, load=P_FORCE)
    assert f["p0_error"] < 0.02 and f["a_error"] < 0.02
    assert f["load"] == P_FORCE and f["load_error"] < 1e-8
    assert f["contact_nodes"] >= 5


def test_parameters_change_the_answer_as_hertz_says():
    """E halved at the same force: a scales as 1/sqrt(E), p0 as sqrt(E) (E halved, not doubled: a
    larger contact spans more elements, whose edge estimate is then within 2 %); the parameters are recorded."""
    from fenics_contact.methods import make_law

    f1 = solve(make_law("lagrange", c=1e3), load=P_FORCE)
    setup = hertz.build(make_law("lagrange", c=1e3), load=P_FORCE, E=hertz.E / 2)
    assert setup.parameters["E"] == hertz.E / 2 and setup.parameters["load"] == P_FORCE
    Solver(setup.problem, quiet=True).run(setup.loads)
    f2 = setup.figures()
    assert f2["p0_error"] < 0.02 and f2["a_error"] < 0.02
    assert f2["p0"] / f1["p0"] == pytest.approx(1 / np.sqrt(2), rel=1e-2)
    assert f2["a"] / f1["a"] == pytest.approx(np.sqrt(2), rel=2e-2)


def test_two_identical_bodies_force_controlled():
    """The two-body Hertz case of two identical bodies (E = 200, nu = 0.3, R = 8, load 10): the quarter disk
    pressed by a force on a deformable block 2R x 2R of the same material, from rest, multipliers. Hertz with
    E* = E / (2 (1 - nu^2)) (both bodies deform)."""
    from fenics_contact.methods import make_law

    kw = dict(plate="meshed", E=200.0, nu=0.3, R=8.0, load=10.0, plate_E=200.0, plate_width=16.0, plate_depth=16.0)
    f = solve(make_law("lagrange", c=1e3), **kw)
    a, p0 = hertz.hertz(10.0, R=8.0, E=200.0, nu=0.3, E2=200.0, nu2=0.3)
    assert p0 == pytest.approx(2 * 10.0 / (np.pi * np.sqrt(4 * 10.0 * 8.0 * 2 * (1 - 0.3**2) / (np.pi * 200.0))))
    assert f["p0_hertz"] == pytest.approx(p0, rel=1e-12) and f["a_hertz"] == pytest.approx(a, rel=1e-12)
    assert f["p0_error"] < 5e-3 and f["a_error"] < 1e-2
    assert f["load_error"] < 1e-8



@pytest.mark.parametrize("method", ["penalty", "lagrange"])
def test_curved_non_matching_interface_pointwise_pressure(method):
    """The guide's choice for a curved interface between non-matching meshes (docs/guide/two_bodies.md): one pass,
    the curved body the slave, nodal. The quarter disk (R = 8) pressed by a force 10 on a block 32 x 16 of its
    own material, from rest: the pressure at every slave vertex within 0.8 a of the axis follows Hertz's
    ``p0 sqrt(1 - x^2 / a^2)`` to 1.5 % of p0, and the contact force balances the load."""
    from fenics_contact.methods import make_law

    law = make_law("penalty", K=2.5e4) if method == "penalty" else make_law("lagrange", c=1e3)
    setup = hertz.build(law, plate="meshed", E=200.0, nu=0.3, R=8.0, load=10.0, plate_E=200.0, plate_width=32.0,
                        plate_depth=16.0)
    Solver(setup.problem, quiet=True).run(setup.loads)
    f = setup.figures()
    x, _, p = setup.problem.contacts[0].point_values(reference=True)
    inside = np.abs(x[:, 0]) < 0.8 * f["a_hertz"]
    assert np.count_nonzero(inside) >= 20
    exact = f["p0_hertz"] * np.sqrt(1 - (x[inside, 0] / f["a_hertz"]) ** 2)
    assert np.abs(p[inside] - exact).max() < 0.015 * f["p0_hertz"]
    assert f["load_error"] < 1e-8

def test_bad_parameters():
    law = AugmentedLagrangian(hertz.DEFAULT_K)
    for kw, match in (({"nu": 0.5}, r"nu must be in \[0, 0.5\)"), ({"E": -1.0}, "E must be a finite number > 0"),
                      ({"R": 0.0}, "R must be"), ({"load": -1.0}, "load must be"),
                      ({"plate_nu": -0.1}, "plate_nu must be in"), ({"contact_width": float("nan")}, "contact_width"),
                      ({"load": 1.0, "symmetry": "half"}, "force control"), ({"stabilisation": -1.0}, "stabilisation")):
        with pytest.raises(ValueError, match=match):
            hertz.build(law, **kw)


def test_neohookean_inverted_state_is_rejected_and_cut_back():
    """Neo-Hookean, approach 0.01 in 3 steps with SNES VI: the first Newton solve converges to a state with
    inverted elements (min det F < 0) whose contact force is far off; the solver rejects it as
    ``inverted_elements``, cuts the step back and reaches the state of the multipliers (min det F ~ 0.96)."""
    from fenics_contact.methods import make_law

    setup = hertz.build(make_law("vi"), model="neohookean", approach=0.01, steps=3)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    assert any(f["kind"] == "inverted_elements" and f["min_jacobian"] <= 0 for f in solver.failures)
    assert setup.problem.min_jacobian() > 0.9
    f = setup.figures()
    ref = hertz.build(make_law("lagrange"), model="neohookean", approach=0.01, steps=2)
    ref_solver = Solver(ref.problem, quiet=True)
    ref_solver.run(ref.loads)
    assert not ref_solver.failures
    assert np.isclose(f["total_force"], ref.figures()["total_force"], rtol=1e-8)
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


def test_meshed_plate_with_multipliers():
    """Two-body contact of the disk on the meshed stiff plate with the slave pressure as an unknown (method
    lagrange): Hertz within 2 % and equilibrium."""
    from fenics_contact.laws import LagrangeMultiplier

    setup = hertz.build(LagrangeMultiplier(hertz.DEFAULT_K), plate="meshed")
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    f = setup.figures()
    assert f["p0_error"] < 0.02 and f["a_error"] < 0.02, (f["p0_error"], f["a_error"])
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)


def test_linear_elastic_inversion_is_a_failure_not_an_answer(tmp_path_factory, comm, capsys):
    """An approach of 2 R (the quarter disk pushed through the plate by twice its radius) with linear elasticity:
    the small-strain solve converges at every load, to a displacement that turns cells over (det(I + grad u) <= 0)
    past an approach of R. Each such solve fails as ``inverted_elements``; the step is cut back, and after the
    cutbacks the demo ends with exit status 1 and one line naming the cause."""
    import importlib.util
    from pathlib import Path

    from fenics_contact.app import cli

    path = Path(__file__).resolve().parent.parent / "fenics_contact" / "app" / "demos" / "hertz.py"
    spec = importlib.util.spec_from_file_location("demo_hertz", path)
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    out = comm.bcast(str(tmp_path_factory.mktemp("approach")) if comm.rank == 0 else None)
    with pytest.raises(SystemExit) as ended:
        cli.main(demo.main, ["--approach", "2.0", "--steps", "1", "--method", "penalty", "--out", out,
                             "--no-pictures", "--no-xdmf", "--quiet"])
    assert ended.value.code == cli.EXIT_ERROR
    err = capsys.readouterr().err.strip().splitlines()
    if comm.rank == 0:
        line = err[-1]
        assert "did not converge" in line and "inverted_elements" in line, line
        found = re.search(r"with (\d+) of (\d+) cells inverted", line)
        assert found and int(found[1]) > 0, line
        last = float(re.search(r"the last converged state is t = ([0-9.e-]+)", line)[1])
        assert last <= 0.5  # an approach of R at most: beyond it the disk's top has passed its bottom


def test_small_strain_model_past_its_range_is_flagged_not_failed():
    """Linear elasticity at an approach of 0.1 R: the mean vertical strain of the quarter is t x approach / R, 0.05
    at the first of two steps, so the largest principal strain is at least that and the run is flagged there (a
    warning in the record and the summary, not a failure); at the default approach (1e-3 R) it is not."""
    from fenics_contact.laws import Penalty
    from fenics_contact.materials import SMALL_STRAIN

    setup = hertz.build(Penalty(hertz.DEFAULT_K), approach=0.1, steps=2)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    warnings = solver.summary()["warnings"]
    assert all(r.converged for r in solver.records) and len(warnings) == 1, warnings
    found = re.search(r"^small-strain model past its range: strain ([0-9.e+-]+) .* at step 1 \(t = 0.5\)", warnings[0])
    assert found and SMALL_STRAIN < float(found[1]) and 0.5 * 0.1 <= float(found[1])
    assert max_strain(setup.problem) >= 0.1

    setup = hertz.build(Penalty(hertz.DEFAULT_K), steps=1)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert solver.summary()["warnings"] == []
    assert hertz.APPROACH / hertz.R <= max_strain(setup.problem) < SMALL_STRAIN


def test_demo_flags_hertz_beyond_its_range(tmp_path_factory, comm):
    """The demo at an approach of 0.1 R: a/R = 0.31, past the Hertz range (0.2): the check says so (and still
    passes within its tolerance), the summary's warnings carry the flag and the small-strain warning."""
    import importlib.util
    from pathlib import Path

    from fenics_contact.app.checks import HERTZ_RANGE

    path = Path(__file__).resolve().parent.parent / "fenics_contact" / "app" / "demos" / "hertz.py"
    spec = importlib.util.spec_from_file_location("demo_hertz", path)
    demo = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(demo)
    out = comm.bcast(str(tmp_path_factory.mktemp("far")) if comm.rank == 0 else None)
    summary = demo.main(["--approach", "0.1", "--method", "penalty", "--out", out, "--no-pictures", "--no-xdmf",
                         "--quiet"])
    assert summary["a_hertz"] / hertz.R > HERTZ_RANGE
    flag = summary["check"]["flag"]
    assert flag and flag.startswith(f"a/R = {summary['a_hertz'] / hertz.R:.3g} > {HERTZ_RANGE:g}")
    assert f"check: {flag}" in summary["warnings"]
    assert any(w.startswith("small-strain model past its range") for w in summary["warnings"])


@pytest.mark.parametrize("mixed_model, model", [("neohookean-mixed", "neohookean"), ("linear-mixed", "linear")])
def test_mixed_model_does_not_lock_where_the_displacement_model_does(mixed_model, model):
    """Rubber, ``nu = 0.4999``, neo-Hookean at finite strain (or linear) under a small load (``a/R = 0.02``), on
    one mesh (refined zone 0.04 R, ``h = R/800``), penalty ``1e5 E/R`` (penetration ~1e-4 of the approach): the
    mixed model (Taylor-Hood P2-P1, Simpson contact points) is within 2 % of Hertz in ``p0`` and ``a`` and in
    equilibrium; the displacement-only one (P1) locks: stiffer for the same approach, its contact too narrow and
    its peak too high for its own force."""
    kw = dict(nu=0.4999, refinement=1, contact_width=0.04, steps=1)
    K = 1e5 * hertz.E / hertz.R
    mixed = solve(Penalty(K), model=mixed_model, quadrature="simpson", **kw)
    locked = solve(Penalty(K), model=model, quadrature="nodal", **kw)
    assert mixed["p0_error"] < 0.02 and mixed["a_error"] < 0.02, mixed
    assert np.isclose(mixed["total_force"], mixed["reaction_top"], rtol=1e-8)
    assert locked["a"] < 0.8 * locked["a_hertz"] and locked["p0"] > 1.3 * locked["p0_hertz"], locked
    assert locked["total_force"] > 1.1 * mixed["total_force"]


@pytest.mark.parametrize("d", [2, 3])
def test_max_strain_is_the_largest_principal_value(d):
    """The 2D closed form (mean of the diagonal plus Mohr's radius) and the 3D filtered eigenvalues give the
    largest absolute principal value of random symmetric tensors, as numpy's eigenvalues do."""
    from mpi4py import MPI

    rng = np.random.default_rng(7)
    pairs = [(i, j) for i in range(d) for j in range(i, d)]
    values = rng.normal(size=(50, 3, len(pairs)))
    values[7, 1] *= 40.0  # one point far above the rest, another whose largest value is negative
    values[9, 2] = -values[7, 1]

    class Problem:
        comm = MPI.COMM_SELF

        def vertex_kinematics(self):
            return np.ones(values.shape[:2]), values

    tensor = np.zeros((values.shape[0] * values.shape[1], d, d))
    for k, (i, j) in enumerate(pairs):
        tensor[:, i, j] = tensor[:, j, i] = values.reshape(-1, len(pairs))[:, k]
    assert np.isclose(max_strain(Problem()), np.abs(np.linalg.eigvalsh(tensor)).max(), rtol=1e-13)


@pytest.mark.parametrize("quadrature", ["gauss", "simpson"])
def test_contact_width_from_the_gap_within_one_element_of_hertz(quadrature):
    """P2 (the quadratic facets Simpson's rule needs): the width where the gap closes is Hertz's half-width within
    one element; with Gauss points the loaded vertices (``p > 0``, recovered at the vertices) reach past it."""
    setup = hertz.build(Penalty(hertz.DEFAULT_K), quadrature=quadrature, model="linear-mixed")
    Solver(setup.problem, quiet=True).run(setup.loads)
    f, contact = setup.figures(), setup.contacts[0]
    width = contact.contact_area()
    assert abs(width - f["a_hertz"]) < f["h_contact"]
    if quadrature == "gauss":  # the pressure spilt onto the first open vertex: the loaded vertices reach further
        loaded = contact.contact_zones()[0]["X_max"][0]
        assert abs(loaded - f["a_hertz"]) > abs(width - f["a_hertz"])
