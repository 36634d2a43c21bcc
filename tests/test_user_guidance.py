"""What a user learns from the library itself, without its source: every limit the solver meets is a warning of
the run (augmentation stopped at ``augment_max``, a cutback), a displacement-only model that locks is named at
set-up with the mixed models to use instead, the progress lines show in a plain script, the form compiler's
commands stay out of a script's INFO log, and the errors and docstrings say what to use."""
import logging
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.models import MIXED_MODELS

ROOT = Path(__file__).resolve().parents[1]
E, H, W, D = 1000.0, 2.0, 1.0, 0.02


def block(nu=0.3, law=None, material=None, model=None, degree=1, quadrature="nodal"):
    """The block of the first tutorial on the rigid plane (4 x 8 cells): its problem and contact."""
    mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.zeros(2), np.array([W, H])], [4, 8])
    facets = fc.tag_boundary(mesh, [("base", lambda x: np.isclose(x[1], 0.0)),
                                     ("top", lambda x: np.isclose(x[1], H)),
                                     ("left", lambda x: np.isclose(x[0], 0.0))])
    law = law or fc.make_law("penalty", K=1e5)
    u, V = fc.unknown(mesh, degree, law, model=model)
    load = fem.Constant(mesh, 0.0)
    contact = fc.contact_surface(u, facets, "base", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load,
                                 quadrature)
    material = material or fc.LinearElastic(E, nu)
    problem = fc.ContactProblem(u, material, load, [fc.Dirichlet.on_facets(V, facets, "top", 1, -D),
                                                    fc.Dirichlet.on_facets(V, facets, "left", 0)], [contact])
    return problem, contact


def test_augmentation_stopped_at_its_limit_is_a_warning(caplog):
    problem, _ = block(law=fc.make_law("auglag", K=1e3))  # a soft K: many augmentations to the tolerance
    solver = fc.Solver(problem, augment_max=1, augment_tol=1e-12, quiet=True)
    with caplog.at_level(logging.WARNING, logger="fenics_contact"):
        solver.run([0.5, 1.0])
    warnings = solver.summary()["warnings"]
    assert [r.augmentation_converged for r in solver.records] == [False, False]
    assert len(warnings) == 2 and all("augment_max = 1" in w for w in warnings)
    assert "step 2 (t = 1)" in warnings[1]
    if MPI.COMM_WORLD.rank == 0:
        assert sum("augmentation stopped" in r.getMessage() for r in caplog.records) == 2
    # reaching the tolerance: no warning
    problem, _ = block(law=fc.make_law("auglag", K=1e3))
    solver = fc.Solver(problem, augment_max=50, augment_tol=1e-10, quiet=True)
    solver.run([1.0])
    assert solver.records[0].augmentation_converged and solver.summary()["warnings"] == []


@pytest.mark.parametrize("material", [fc.LinearElastic(E, 0.4999), fc.NeoHookean(E, 0.49)], ids=["linear", "neo"])
def test_displacement_model_that_locks_is_named_at_setup(material, caplog):
    with caplog.at_level(logging.WARNING, logger="fenics_contact"):
        problem, _ = block(material=material)
    assert len(problem.warnings) == 1 and "locking" in problem.warnings[0]
    assert all(m in problem.warnings[0] for m in MIXED_MODELS) and set(MIXED_MODELS) == {"neohookean-mixed",
                                                                                           "linear-mixed"}
    if MPI.COMM_WORLD.rank == 0:
        assert any("locking" in r.getMessage() for r in caplog.records)
    solver = fc.Solver(problem, quiet=True)
    assert solver.summary()["warnings"] == problem.warnings  # the run's warnings start with the set-up's


def test_compressible_and_mixed_models_do_not_warn_of_locking():
    assert block(nu=0.3)[0].warnings == []
    law = fc.make_law("penalty", K=1e5)
    mixed = fc.MixedLinearElastic(E, 0.4999)
    assert block(law=law, material=mixed, model="linear-mixed", degree=2,
                 quadrature="gauss")[0].warnings == []


def test_strain_warning_of_a_nearly_incompressible_body_names_the_mixed_model():
    from fenics_contact.solver.validity import strain_warning

    problem, _ = block(nu=0.4999)
    problem.u.interpolate(lambda x: np.stack([0.2 * x[0], 0.0 * x[1]]))  # 20 % strain
    warnings = []
    strain_warning(problem, 1, 1.0, warnings, {"validity_s": 0.0})
    assert len(warnings) == 1 and "(neohookean-mixed)" in warnings[0]


def test_sphere_in_2d_says_to_use_a_ball():
    with pytest.raises(ValueError, match=r"fc\.Ball.*axisymmetric"):
        fc.Sphere([0.0, 1.0], 1.0)


def test_docstrings_say_what_a_user_asked():
    assert "axisymmetric" in fc.LinearElastic.__doc__.split("Args:")[1]
    doc = fc.ContactProblem.min_jacobian.__doc__
    assert "weakly" in doc and "incompressib" in doc


def test_compiler_commands_stay_out_of_the_root_log():
    """setuptools logs the commands of a form's first JIT to the root logger at INFO from its distutils modules;
    the user's own INFO records to the root logger pass."""
    root = logging.getLogger()
    distutils = root.makeRecord("root", logging.INFO, str(Path("setuptools") / "_distutils" / "dist.py"), 1,
                                "running build_ext", (), None)
    mine = root.makeRecord("root", logging.INFO, "/home/user/script.py", 1, "my line", (), None)
    warning = root.makeRecord("root", logging.WARNING, str(Path("setuptools") / "_distutils" / "dist.py"), 1,
                              "a compiler warning", (), None)
    assert not root.filter(distutils) and root.filter(mine) and root.filter(warning)


SCRIPT = """
import sys
sys.path.insert(0, {tests!r})
from test_user_guidance import block
import fenics_contact as fc
problem, _ = block()
fc.Solver(problem).run([1.0])
"""


@pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="a script of its own: serial lane")
def test_progress_shows_in_a_script_without_logging_configured():
    proc = subprocess.run([sys.executable, "-c", SCRIPT.format(tests=str(ROOT / "tests"))], capture_output=True,
                          text=True, timeout=300, cwd=ROOT)
    assert proc.returncode == 0, proc.stderr
    assert "step   1" in proc.stderr and "running build_ext" not in proc.stdout + proc.stderr
