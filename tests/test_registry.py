"""The method registry: a method of one's own, declared in one file and registered once, goes through the
surface factory, the command line, the capability grid and a benchmark row without any other change.

The toy method is a quadratic penalty ``F = K <g>^2``. On the block (a uniform state on a frictionless rigid
base, plane strain) its pressure has a closed form: with ``E' = E / (1 - nu^2)``, the top moved down by ``d``
and the penetration ``g``, equilibrium ``E' (d - g) / H = K g^2`` gives ``g`` (the positive root) and
``p = K g^2``.
"""
import importlib
import math
import re
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact import capabilities, methods
from fenics_contact.app import bench, build, cli
from fenics_contact.app.scenes import block

# The toy method's module is the one the developer guide shows (docs/adding_a_method.md): the page is tested.
GUIDE = Path(__file__).resolve().parents[1] / "docs" / "adding_a_method.md"
TOY = re.search(r"```python\n(.*?)```", GUIDE.read_text(), re.S).group(1)
K = 1e7


def closed_form(K: float) -> float:
    """The block's pressure under the quadratic penalty (see the module docstring)."""
    Es, d, H = block.E / (1 - block.NU**2), block.DISPLACEMENT, block.HEIGHT
    a = Es / H
    g = (-a + math.sqrt(a * a + 4 * K * a * d)) / (2 * K)
    return K * g * g


@pytest.fixture
def toy(tmp_path, monkeypatch):
    """The toy method's module, written to a folder on the path and registered (and, through the environment,
    registered in child processes too); unregistered afterwards."""
    folder = tmp_path / f"plugins{MPI.COMM_WORLD.rank}"
    folder.mkdir()
    (folder / "toy_quadratic.py").write_text(TOY)
    monkeypatch.syspath_prepend(str(folder))
    monkeypatch.setenv("PYTHONPATH", f"{folder}:" + __import__("os").environ.get("PYTHONPATH", ""))
    monkeypatch.setenv(methods.PLUGINS, "toy_quadratic")
    module = importlib.import_module("toy_quadratic")
    yield module
    methods.unregister("quadratic")
    sys.modules.pop("toy_quadratic", None)


def test_toy_method_through_the_factory(toy):
    law = fc.make_law("quadratic", K=K)
    assert isinstance(law, toy.QuadraticPenalty) and "quadratic" in fc.METHODS
    setup = build("block", law=law)
    assert type(setup.contacts[0]) is fc.ContactSurface  # the default surface of a law of the gap
    fc.Solver(setup.problem, quiet=True).run(setup.loads)
    assert setup.figures()["contact_pressure"] == pytest.approx(closed_form(K), rel=1e-9)


def test_toy_method_through_the_command_line(toy):
    p = cli.parser("toy", default_K=1.0)
    args = cli.parse(p, ["--method", "quadratic", "--K", "2.5e6"])
    law = cli.law_from_args(args)
    assert isinstance(law, toy.QuadraticPenalty) and law.scalars["K"] == 2.5e6
    assert cli.method_parameters(args)["K"] == 2.5e6 and args.augment == 0
    with pytest.raises(ValueError, match="method 'quadratic' has no friction"):
        cli.law_from_args(cli.parse(p, ["--method", "quadratic", "--mu", "0.3"]))
    with pytest.raises(cli.UsageError, match="--K"):
        cli.parse(p, ["--method", "quadratic", "--K", "-1"])


def test_toy_method_on_the_capability_grid(toy):
    assert "quadratic" in capabilities.axes()["method"]
    assert capabilities.supported(method="quadratic", kind="two-body", quadrature="segment")
    with pytest.raises(capabilities.UnsupportedCombination, match="no tangential law"):
        capabilities.check(method="quadratic", friction=True)
    assert "| quadratic | rigid | nodal |" in capabilities.markdown()


def test_toy_method_in_a_benchmark_row(toy, tmp_path):
    cfg = bench.run_config("quadratic", K)
    row = bench.run_one("block", cfg, tmp_path / f"bench{MPI.COMM_WORLD.rank}")
    assert row["converged"], (tmp_path / f"bench{MPI.COMM_WORLD.rank}" / "log.txt").read_text()
    exact = block.EXACT_PRESSURE
    assert row["error"] == pytest.approx(abs(closed_form(K) - exact) / exact, rel=1e-6)
    assert bench.parameter_label("quadratic") == "K" and bench._colour("quadratic") == "tab:brown"


def test_methods_page_is_the_registry():
    """docs/methods.md is what the declarations say (``make docs`` writes it)."""
    page = Path(__file__).resolve().parents[1] / "docs" / "methods.md"
    assert page.read_text() == methods.markdown()


@pytest.mark.parametrize("method", ["penalty", "lagrange", "penalty_multiplier", "coulomb"])
def test_one_call_builds_every_two_body_method(method):
    """``fc.two_body_surfaces`` builds the two-body surface of every method the grid offers for two bodies (the
    multipliers' and the condensed one's too): two blocks pressed by a traction p, equilibrium of the contact force
    with the load."""
    import ufl
    from dolfinx import fem

    from fenics_contact.app.meshes import stacked_blocks

    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (3, 3), 1e-6)
    law = fc.make_law(method, **({"K": 1e6} if method in ("penalty", "penalty_multiplier") else {}))
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, load)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft.meshtags, subdomain_id=ft["upper_top"])
    bcs = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", 1), fc.Dirichlet.on_facets(V, ft, "left", 0)]
    problem = fc.ContactProblem(u, fc.LinearElastic(1000.0, 0.3), load, bcs, contacts,
                                [(ufl.as_vector((0.0, -10.0)), ds)], step_solver=fc.step_solver_for(contacts))
    fc.Solver(problem, quiet=True).run([1.0])
    force = sum(c.total_force() for c in contacts)
    assert force[1] == pytest.approx(10.0, rel=1e-8)  # the traction p on a unit width
