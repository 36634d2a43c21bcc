"""Bad input gets a clear error; a step that cannot converge raises after the last converged step is on disk; a
misspelt solver option and a combination the capability grid refuses are refused when the solver or the problem
is made."""
import dataclasses
import json
import re

import pytest
from dolfinx import fem
from mpi4py import MPI

from fenics_contact.app.meshes import rectangle
from fenics_contact.app.run import run
from fenics_contact.app.scenes import block
from fenics_contact.compat import function_space
from fenics_contact.contact import ContactSurface
from fenics_contact.laws import Penalty
from fenics_contact.materials import LinearElastic
from fenics_contact.obstacles import Ball, HalfPlane
from fenics_contact.solver import LINEAR_SOLVERS, ConvergenceError, Solver


def _u(comm):
    mesh, _, tags = rectangle(comm, 1.0, 1.0, 2, 2)
    return fem.Function(function_space(mesh, "Lagrange", 1, (2,))), tags


def test_absent_facet_tag_is_named(comm):
    u, tags = _u(comm)
    load = fem.Constant(u.function_space.mesh, 0.0)
    with pytest.raises(ValueError, match="facet tag 'contact'=99 is absent from the mesh"):
        ContactSurface(u, tags, 99, HalfPlane([0, 0], [0, 1]), Penalty(1e5), load)


def test_mesh_without_facet_tags(comm):
    u, _ = _u(comm)
    load = fem.Constant(u.function_space.mesh, 0.0)
    with pytest.raises(ValueError, match="no facet tags"):
        ContactSurface(u, None, 1, HalfPlane([0, 0], [0, 1]), Penalty(1e5), load)


def test_unknown_quadrature(comm):
    u, tags = _u(comm)
    load = fem.Constant(u.function_space.mesh, 0.0)
    with pytest.raises(ValueError, match="contact quadrature"):
        ContactSurface(u, tags, "bottom", HalfPlane([0, 0], [0, 1]), Penalty(1e5), load, quadrature="lobatto")


@pytest.mark.parametrize("E,nu,name", [(-1.0, 0.3, "Young's modulus"), (1.0, 0.5, "Poisson's ratio")])
def test_bad_material(E, nu, name):
    with pytest.raises(ValueError, match=name):
        LinearElastic(E, nu)


def test_bad_obstacle():
    with pytest.raises(ValueError, match="radius"):
        Ball([0, 0], -1.0)
    with pytest.raises(ValueError, match="normal"):
        HalfPlane([0, 0], [0, 0])


def test_failed_step_raises_after_writing_the_last_converged_state(tmp_path_factory, comm):
    out = comm.bcast(str(tmp_path_factory.mktemp("fail")) if comm.rank == 0 else None)
    setup = block.build(Penalty(1e5), comm=comm)
    # t = 1e-16 converges at iteration 0 (residual below the given absolute atol); no Newton step is allowed after it
    setup = dataclasses.replace(setup, loads=[1e-16, 1.0])
    with pytest.raises(ConvergenceError, match=r"load step 2 .* did not converge after 4 cutbacks"):
        run(setup, out, "penalty", {}, quiet=True, options={"snes_max_it": 0, "snes_atol": 1e-10})
    summary = json.load(open(f"{out}/summary.json"))
    assert summary["converged"] is False and summary["load_steps"] == 1 and "cutbacks" in summary["error"]
    times = re.findall(r'Time Value="([^"]+)"', open(f"{out}/block.xdmf").read())
    assert times and all(float(t) == 1e-16 for t in times)  # only the converged step
    assert MPI.COMM_WORLD.allreduce(1) == comm.size


def test_misspelt_solver_option_is_refused_at_construction(comm):
    """An option of ``Solver(options=...)`` that PETSc never reads is one line naming it and the closest known
    option, before any solve; the correct spelling and the library's own options pass."""
    setup = block.build(Penalty(1e5), comm=comm)
    with pytest.raises(ValueError, match=r"^Solver option not read by PETSc when the solver was set up .*: "
                                         r"snes_atoll \(did you mean snes_atol\?\)$"):
        Solver(setup.problem, quiet=True, options={"snes_atoll": 1e-8})
    with pytest.raises(ValueError, match=r"pc_gamg_threshold$"):  # spelt right, but LU reads no GAMG option
        Solver(setup.problem, quiet=True, options={"pc_gamg_threshold": 0.1})
    Solver(setup.problem, quiet=True, options={"snes_atol": 1e-8, **LINEAR_SOLVERS["direct"],
                                               "condition_estimate": True}).destroy()


def test_misspelt_option_read_inside_a_solve_is_refused_after_the_first_step(comm):
    """MUMPS reads its options at factorization: a misspelt one is refused once the first load step has been
    solved (a linear system factored), naming it."""
    setup = block.build(Penalty(1e5), comm=comm)
    solver = Solver(setup.problem, quiet=True, options={"mat_mumps_icntl14": 30})
    with pytest.raises(ValueError, match=r"first load step's solves .*: mat_mumps_icntl14 \(did you mean "
                                         r"mat_mumps_icntl_14\?\)"):
        solver.run(setup.loads)
    assert len(solver.records) == 1
    solver.destroy()


@pytest.mark.parametrize("body", ["rigid", "two-body"])
def test_coulomb_with_a_neohookean_body_is_refused_when_the_problem_is_made(body, comm):
    """Method coulomb condenses a constant stiffness: a neo-Hookean body is refused by the capability grid when
    the problem binds its material, not at the first solve."""
    from fenics_contact.app.meshes import stacked_blocks
    from fenics_contact.capabilities import UnsupportedCombination
    from fenics_contact.condensed import step_solver_for
    from fenics_contact.factory import contact_surface, two_body_surfaces
    from fenics_contact.laws import ExactCoulomb
    from fenics_contact.materials import NeoHookean
    from fenics_contact.problem import ContactProblem

    if body == "rigid":
        u, tags = _u(comm)
        load = fem.Constant(u.function_space.mesh, 0.0)
        contacts = [contact_surface(u, tags, "bottom", HalfPlane([0.0, 0.0], [0.0, 1.0]), ExactCoulomb(0.3), load)]
    else:
        mesh, _, tags = stacked_blocks(comm, 1.0, 0.5, 0.5, (4, 2), (3, 2))
        u = fem.Function(function_space(mesh, "Lagrange", 1, (2,)))
        load = fem.Constant(mesh, 0.0)
        contacts = two_body_surfaces(u, tags, "upper_bottom", "lower_top", lambda: ExactCoulomb(0.3), load)
    with pytest.raises(UnsupportedCombination, match="coulomb, neohookean .*use model 'linear'"):
        ContactProblem(u, NeoHookean(1000.0, 0.3), load, [], contacts, step_solver=step_solver_for(contacts))


@pytest.mark.parametrize("options, said", [
    ({123: 1}, r"^Solver option name 123: accepted: a PETSc option name"),
    ("snes_rtol", r"^Solver options must be a dict .*got str 'snes_rtol'$"),
    ({"snes_max_it": -5}, r"^Solver option snes_max_it = -5: .*must be non-negative"),
    ({"snes_type": "notatype"}, r"^Solver option snes_type = 'notatype': .*notatype; accepted: .*newtonls"),
    ({"snes_rtol": "abc"}, r"^Solver option snes_rtol = 'abc': .*no numeric value"),
    ({"snes_rtol": True}, r"^Solver option snes_rtol = True: .*no numeric value"),
    ({"snes_max_it": 2.5}, r"^Solver option snes_max_it = 2.5: .*no integer value"),
    ({"snes_rtol": float("nan")}, r"^Solver option snes_rtol = nan: accepted: a finite number$"),
    ({"snes_rtol": -1}, r"^Solver option snes_rtol = -1: .*must be non-negative"),
    ({"snes_max_it": None}, r"^Solver option snes_max_it = None: this option takes a value"),
    ({"ksp_type": "notakrylov"}, r"^Solver option ksp_type = 'notakrylov': .*; accepted: .*gmres"),
    ({"ksp_rtol_max": 2.0}, r"^Solver option ksp_rtol_max = 2.0: accepted: a number in \[0, 1\)"),
])
def test_a_solver_option_petsc_cannot_use_is_refused_naming_it(options, said, comm):
    """``Solver(options=...)`` is checked as the command line's PETSc options are, when the solver is made: a value
    PETSc rejects, a non-finite number, a flag (None) for an option that takes a value, a name or a container that
    is not one, each one line naming the option and what it accepts (not PETSc's bare error code at ``run``)."""
    setup = block.build(Penalty(1e5), comm=comm)
    with pytest.raises(ValueError, match=said):
        Solver(setup.problem, quiet=True, options=options)
    Solver(setup.problem, quiet=True, options={"snes_monitor": None, "snes_max_it": 20, "snes_rtol": "1e-10",
                                               "snes_ksp_ew": False}).destroy()
