import functools
import logging
import os
import tempfile

import numpy as np
import pytest
from mpi4py import MPI

from fenics_contact.app.jitcache import find_modules_by_name

# FFCx/UFL chatter at INFO level on every JIT compile.
logging.getLogger().setLevel(logging.WARNING)
logging.getLogger("UFL").setLevel(logging.ERROR)


# FFCx's compiled forms loaded by file name, as in the application: a session loads thousands.
find_modules_by_name()


@pytest.fixture
def comm():
    return MPI.COMM_WORLD


@pytest.fixture
def tangent_check():
    """``check(solver, x, d, eps, pairing) -> (J d, central difference of the residual along d)`` at the state
    ``x`` (PETSc vectors), asserting that ``pairing(contact)`` of every contact is the same at ``x +- eps d``
    as at ``x`` (a pairing change is a discrete event, not part of the derivative)."""
    def check(solver, x, d, eps, pairing):
        problem = solver.problem
        contacts = problem.contacts
        b = x.duplicate()
        problem.F(x, b)
        before = [pairing(c) for c in contacts]
        problem.J(x, solver.A)
        Jd = x.duplicate()
        solver.A.mult(d, Jd)
        r = []
        for s in (1.0, -1.0):
            xs = x.copy()
            xs.axpy(s * eps, d)
            bs = x.duplicate()
            problem.F(xs, bs)
            r.append(bs)
            assert all(np.array_equal(p, pairing(c)) for p, c in zip(before, contacts))
        fd = r[0].copy()
        fd.axpy(-1.0, r[1])
        fd.scale(0.5 / eps)
        return Jd, fd
    return check


@pytest.fixture
def contact_tangent_error(tangent_check):
    """``error(solver, x, d, pairing, A_bulk, master_rows) -> (relative error, master share)`` of the contact part
    of the tangent along ``d``: ``J d`` and the central difference (``tangent_check``, eps 1e-6) less the bulk
    stiffness ``A_bulk d``; relative error ``|fd - J d| / |J d|``; master share: the norm of that ``J d`` on this
    rank's ``master_rows`` (a mask of the local rows), over all ranks, over ``|J d|``."""
    def error(solver, x, d, pairing, A_bulk, master_rows):
        Jd, fd = tangent_check(solver, x, d, 1e-6, pairing)
        Bd = x.duplicate()
        A_bulk.mult(d, Bd)
        Jd.axpy(-1.0, Bd)
        fd.axpy(-1.0, Bd)
        master = np.sqrt(MPI.COMM_WORLD.allreduce(float(np.sum(Jd.array[master_rows] ** 2))))
        fd.axpy(-1.0, Jd)
        return fd.norm() / Jd.norm(), master / Jd.norm()
    return error


def pytest_configure(config):
    for marker, what in (("slow", "a study of more than a few seconds (not in make test-fast; serial only in make "
                                   "test unless also mpi)"),
                         ("scene", "a benchmark scene, its demo or the application (not in make test-fast)"),
                         ("mpi", "compares a parallel run with the serial one (in every parallel lane)"),
                         ("study", "a study of many solves whose subject a lighter test covers (only in make "
                                   "test-all)")):
        config.addinivalue_line("markers", f"{marker}: {what}")
    # Under mpirun every rank runs pytest: give each its own base temporary folder, or the
    # ranks clean up each other's folders. Tests that write from all ranks broadcast rank 0's path.
    comm = MPI.COMM_WORLD
    if comm.size > 1 and config.option.basetemp is None:
        config.option.basetemp = os.path.join(tempfile.gettempdir(), f"pytest-fc-rank{comm.rank}-of-{comm.size}")


@pytest.fixture(autouse=True)
def _petsc_options_unchanged():
    """No test may leave options in PETSc's database: a later solver with the same prefix would read them (a
    divergence tolerance, a line search, a linear solver left by one test changed another's answer)."""
    from petsc4py import PETSc

    opts = PETSc.Options()
    before = opts.getAll()
    yield
    after = opts.getAll()
    leaked = {k: v for k, v in after.items() if before.get(k) != v}
    for k in leaked:
        opts.delValue(k)
    for k, v in before.items():
        if k not in after:
            opts.setValue(k, v)
    assert not leaked, f"options left in PETSc's database: {leaked}"


@pytest.fixture(autouse=True)
def _package_log_restored():
    """The package's logger as it was before the test: the command line run in-process (``cli.main``) gives it its
    own handler and stops its propagation, after which a later test's ``caplog`` (a handler of the root logger)
    would see none of its records."""
    package = logging.getLogger("fenics_contact")
    state = package.level, package.propagate, list(package.handlers)
    yield
    package.setLevel(state[0])
    package.propagate = state[1]
    package.handlers[:] = state[2]


# --- PETSc objects a test drops ----------------------------------------------------------------------------
# petsc4py (>= 3.18) does not destroy an object on a communicator when its last Python reference goes: it puts it on
# that communicator's garbage list, freed by the collective PETSc.garbage_cleanup(comm). A mesh's communicator is
# its own duplicate, freed with the mesh: a solver, surface or problem dropped without destroy() leaves its
# matrices and factorizations on a list nothing can reach any more, resident to the end of the session (one
# pytest process runs every test under mpirun). So every mesh a test's ContactProblem is built on is held until
# the test ends and its communicator's garbage is freed; a mesh something else still holds (a module's fixture)
# is kept to a later test's end.
_MESHES: list = []


@pytest.fixture(autouse=True, scope="session")
def _hold_problem_meshes():
    import gc

    from fenics_contact.problem import ContactProblem

    # What is alive now (the modules, the collected tests) is left out of every later collection: a collection
    # after each test then costs a fraction of a millisecond, not a tenth of a second.
    gc.freeze()
    init = ContactProblem.__init__

    @functools.wraps(init)  # its signature stays the documented one
    def held(self, u, *args, **kwargs):
        mesh = u.function_space.mesh
        if not any(m is mesh for m in _MESHES):
            _MESHES.append(mesh)
        init(self, u, *args, **kwargs)

    ContactProblem.__init__ = held
    yield
    ContactProblem.__init__ = init


@pytest.fixture(autouse=True)
def _free_dropped_petsc_objects(_hold_problem_meshes):
    """After the test: the garbage of every held mesh's communicator freed; meshes nothing else holds let go.
    Collective: every rank builds the same meshes in the same order (a mesh on a rank's own communicator
    cleans on that rank alone)."""
    import gc
    import sys

    from petsc4py import PETSc

    yield
    if not _MESHES:
        return
    gc.collect()  # the test's objects, cycles included: their PETSc objects go to their communicators' garbage
    PETSc.garbage_cleanup(PETSc.COMM_SELF)  # this rank's own objects (a serial reference, a gathered factor)
    kept = []
    for mesh in _MESHES:
        PETSc.garbage_cleanup(mesh.comm)
        if sys.getrefcount(mesh) > 3:  # more than _MESHES, `mesh` and the argument: held elsewhere too
            kept.append(mesh)
    _MESHES[:] = kept


def _real_stderr(config):
    """The terminal's standard error (pytest's faulthandler plugin keeps a copy of it: the process's own is
    pytest's capture file while a test runs)."""
    import sys

    import _pytest.faulthandler as plugin

    for key in ("fault_handler_stderr_fd_key", "fault_handler_stderr_key"):  # pytest >= 8, pytest 7
        if hasattr(plugin, key) and getattr(plugin, key) in config.stash:
            return config.stash[getattr(plugin, key)]
    return sys.__stderr__


# --- a test that does not end -------------------------------------------------------------------------------
# A lane must fail, naming the test, rather than hang until CI's own limit: a test still running after
# $FC_TEST_TIMEOUT seconds (default 1200) prints every thread's Python traceback and ends its process (under
# mpirun the launcher then ends the other ranks; under xdist the worker is replaced and the test reported).
# Under mpirun, a test that fails on one rank before a collective call leaves the other ranks waiting in it:
# after each test function every rank waits at most $FC_TEST_DESYNC seconds (default 600) for the others to end it too,
# then says so and aborts the job.
@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    import faulthandler

    faulthandler.dump_traceback_later(float(os.environ.get("FC_TEST_TIMEOUT", "1200")), exit=True,
                                      file=_real_stderr(item.config))
    try:
        yield
    finally:
        faulthandler.cancel_dump_traceback_later()


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_call(item):
    """After the test function (before its fixtures' teardown, which makes collective calls of its own)."""
    import sys
    import time

    outcome = yield
    comm = MPI.COMM_WORLD
    if comm.size == 1:
        return
    limit = float(os.environ.get("FC_TEST_DESYNC", "600"))
    request, start = comm.Ibarrier(), time.monotonic()
    while not request.Test():
        if time.monotonic() - start > limit:
            if outcome.excinfo is not None:
                sys.stderr.write(f"rank {comm.rank}: {item.nodeid} failed: {outcome.excinfo[1]!r}\n")
            sys.stderr.write(f"rank {comm.rank}: {item.nodeid} ended here; another rank was still inside it "
                             f"{limit:g} s later (a failure on one rank before a collective call): aborting\n")
            sys.stderr.flush()
            comm.Abort(1)
        time.sleep(0.001)


def pytest_runtest_logfinish(nodeid, location):
    """With ``$FC_TEST_RSS`` set (a path prefix): each rank appends its resident memory (VmRSS, MB) after every
    test to ``<prefix>.<rank>``, to find what a session accumulates."""
    prefix = os.environ.get("FC_TEST_RSS")
    if prefix:
        with open("/proc/self/status") as status:
            rss = next(int(line.split()[1]) for line in status if line.startswith("VmRSS:")) / 1024
        with open(f"{prefix}.{MPI.COMM_WORLD.rank}", "a") as log:
            log.write(f"{rss:9.1f} {nodeid}\n")


# --- lanes --------------------------------------------------------------------------------------------------
# Which lane runs a test (Makefile): `make test-fast` runs what is neither `slow` nor `scene` (the library's
# unit and closed-form tests, under 2 minutes), `make test` runs everything but `study` serially and, in
# parallel (and on Debian 13), what is neither `slow` nor `scene`, and every `mpi`; `make test-all` runs
# everything, serially and in parallel. The tables below are the one place
# that says so, by node id (file::test[parameters]; ``*`` matches anything). A pattern of a collected file that matches
# no test is an error: a renamed test cannot silently leave its lane.
SCENE = (  # a benchmark scene, its demo, or the application around it (harness, command line)
    "test_block.py", "test_hertz.py", "test_sphere.py", "test_pin.py", "test_slab.py", "test_ring.py",
    "test_seal.py", "test_cylinders.py", "test_sheet.py", "test_rings.py", "test_mindlin.py", "test_mindlin3d.py",
    "test_wedges.py", "test_ironing.py", "test_tube.py", "test_lipseal.py", "test_demos.py", "test_bench.py",
    "test_model_reduction.py",
    "test_scenes.py", "test_cli.py", "test_run.py", "test_records.py", "test_options.py", "test_bench_pages.py",
    "test_bench_run.py", "test_restarts.py",
    "test_units.py::test_*scene*", "test_units.py::test_rings_*", "test_axisphere.py", "test_oring.py",
    "test_cells.py::test_a_program_reading_a_tangled_mesh_file_ends_in_one_line", "test_plotting.py",
)
SLOW = (  # studies of more than a few seconds each
    "test_units.py::test_slow_scene_any_units*",
    "test_axisphere.py::test_two_elastic_spheres_are_hertz", "test_axisphere.py::test_parallel_equals_serial",
    "test_axisymmetric.py::test_lame_converges_at_second_order_in_p1",
    "test_incompressible_axisymmetric.py::test_parallel_equals_serial",
    "test_oring.py::test_parallel_equals_serial", "test_oring.py::test_rod_seal_parallel_equals_serial",
    "test_bench.py::test_slab_error_from_the_exact_coulomb_reference", "test_bench.py::test_sweep_block",
    "test_bench.py::test_stability_harness_classifies_the_ring", "test_bench.py::test_ring_through_the_scene_runner",
    "test_capabilities.py::test_supported_cell_solves_to_its_closed_form[*two-body*]",
    "test_capabilities.py::test_supported_cell_solves_to_its_closed_form[*-3*]",
    "test_capabilities.py::test_supported_cell_solves_to_its_closed_form[*self*]",
    "test_capabilities.py::test_two_pass_coinciding_points_carry_the_one_pass_pressure",
    "test_selfcontact3d.py::test_arms_pressed_together_equal_the_half_on_its_symmetry_plane[auglag-nodal]",
    "test_selfcontact3d.py::test_arms_pressed_together_equal_the_half_on_its_symmetry_plane[compliance-nodal]",
    "test_selfcontact3d.py::test_arms_pressed_together_equal_the_half_on_its_symmetry_plane[*-gauss]",
    "test_checkpoint.py::test_restart_gives_the_uninterrupted_figures[ironing]",
    "test_cli.py::test_gmsh_out_of_memory_is_one_line",
    "test_hertz.py::test_curved_non_matching_interface_pointwise_pressure[*]",
    "test_cli.py::test_failed_check_exits_3_after_writing_its_outputs[mindlin-auglag]",
    "test_collocation.py::test_collocated_multipliers_exact_on_the_curved_interface",
    "test_cylinders.py::test_hertz_both_surfaces_and_equilibrium[segment]",
    "test_docs.py::test_html_documentation_builds_without_warnings",  # a Sphinx build of the documentation
    "test_demos.py::test_demo_passes_its_check[sheet]", "test_demos.py::test_demo_passes_its_check[ironing]",
    "test_demos.py::test_demo_passes_its_check[mindlin]", "test_demos.py::test_demo_passes_its_check[oring]",
    "test_friction.py::test_tangent_matches_finite_differences[2-*",
    "test_materials.py::test_two_body_cauchy_pressure_is_nominal_over_the_slave_stretch*",
    "test_mindlin3d.py::test_stick_radius_against_cattaneo_mindlin",
    "test_model_reduction.py::*",
    "test_multipliers.py::test_two_body_multipliers_equal_augmented_cross_constraints",
    "test_options.py::test_two_identical_bodies_from_options_alone_within_1_percent",
    "test_multipliers.py::test_two_body_multipliers_hertz_and_equilibrium",
    "test_nitsche.py::test_neohookean_block_nominal_pressure_is_the_closed_form[stress-100.0-1]",
    "test_obstacles_and_bulk.py::test_moving_rigid_cylinder_indents_a_block*",
    "test_parallel.py::test_parallel_equals_serial[hertz-cross]",
    "test_pin.py::test_total_contact_force_is_the_applied_traction",
    "test_pin.py::test_exact_gap_tends_to_the_linearized_gap_at_first_order",
    "test_pin.py::test_neat_fit_is_homogeneous_in_the_load",
    "test_predictor.py::test_a_far_predicted_state_does_not_pass_the_relative_tolerance",
    "test_records.py::test_killed_demo_keeps_its_steps_and_restarts_to_the_same_figures[*",
    "test_rings.py::test_p1_chord_sag_converges", "test_rings.py::test_penalty_approaches_the_multipliers",
    "test_rings.py::test_serial_equals_ranks", "test_rings.py::test_two_point_multipliers_against_lame",
    "test_sheet.py::*",
    "test_slab.py::test_regularized_friction_methods_converge_over_mu*", "test_slab.py::test_refinement_convergence",
    "test_sphere.py::*",
    "test_twobody.py::test_consistent_tangent_with_master_dofs[nodal-two-3]",
    "test_twobody_friction.py::test_tresca_bound_and_slip",
    "test_twobody_nitsche.py::test_consistent_tangent_with_master_dofs[nodal-two-3-1.0-None]",
    "test_twobody_nitsche.py::test_patch_matching_interface_to_round_off[gauss-0.0-None]",
    "test_twobody_nitsche.py::test_small_sliding_tangent_and_fixed_pairs*",
    "test_twobody_nitsche.py::test_mindlin_small_sliding_default_mesh",
    "test_twobody_nitsche.py::test_two_body_hertz", "test_twobody_nitsche.py::test_wedges_*",
    "test_twobody_nitsche.py::test_mindlin_stick_zone", "test_twobody_nitsche.py::test_mindlin_default_mesh_newton",
    "test_twobody_nitsche.py::test_consistent_tangent_with_master_dofs[nodal-two-3-1.0-coulomb]",
    "test_twobody_nitsche.py::test_consistent_tangent_with_master_dofs[nodal-two-2-1.0-coulomb]",
    "test_wedges.py::test_force_ratio_of_a_block_sliding_up_a_wedge[0.3-20.0]",
    "test_sparse_friction.py::test_cattaneo_mindlin_equals_the_condensed_exact_method[mindlin3d-2.0]",
)
MPI_COMPARED = (  # compares a parallel run with the serial one: in the parallel lanes even when slow
    "test_axisphere.py::test_parallel_equals_serial",
    "test_checkpoint.py::test_restart_gives_the_uninterrupted_figures[ironing]",  # a restart on every rank
    "test_collocation.py::test_serial_equals_ranks", "test_condensed_twobody.py::test_parallel_equals_serial",
    "test_cylinders.py::test_ranks_agree*", "test_friction.py::test_compliance3d_parallel_equals_serial",
    "test_friction.py::test_slab_parallel_equals_serial", "test_incompressible.py::test_parallel_equals_serial",
    "test_incompressible_axisymmetric.py::test_parallel_equals_serial",
    "test_oring.py::test_parallel_equals_serial", "test_oring.py::test_rod_seal_parallel_equals_serial",
    "test_ironing.py::test_parallel_equals_serial",
    "test_mindlin.py::test_parallel_equals_serial", "test_mindlin3d.py::test_parallel_equals_serial",
    "test_mindlin3d.py::test_exact_coulomb_parallel_equals_serial",
    "test_coulomb3d.py::test_parallel_equals_serial",
    "test_multipliers.py::test_parallel_equals_serial*",
    "test_multipliers.py::test_two_body_multipliers_parallel_equals_serial", "test_parallel.py::*",
    "test_pin.py::test_parallel_equals_serial", "test_rings.py::test_serial_equals_ranks",
    "test_sheet.py::test_collocated_serial_equals_ranks",
    "test_sheet.py::test_multipliers_independent_of_c_and_of_ranks",
    "test_sheet.py::test_three_point_penalty_independent_of_ranks", "test_slab.py::test_parallel_equals_serial",
    "test_sparse.py::test_a_rank_without_rows",
    "test_tutorials.py::test_tutorial_runs[03_two_blocks_patch]",
    "test_twobody.py::test_slave_and_master_on_different_ranks_equal_serial*",
    "test_twobody_nitsche.py::test_serial_equals_two_ranks*",
    "test_twobody_nitsche.py::test_wedges_serial_equals_ranks",
    "test_twobody_nitsche.py::test_segment_serial_equals_two_ranks",
    "test_tube.py::test_parallel_equals_serial", "test_selfcontact3d.py::test_parallel_equals_serial",
    "test_lipseal.py::test_parallel_equals_serial", "test_sparse_friction.py::test_parallel_equals_serial",
)

# Of those, the comparisons alone (each rank's serial run against the ranks' run): the same run twice in a serial
# session, where they are skipped.
RANKS_ONLY = ("*::test_*parallel_equals_serial*", "*::test_*serial_equals*ranks*",
              "test_sheet.py::test_three_point_penalty_independent_of_ranks",
              "test_twobody.py::test_slave_and_master_on_different_ranks_equal_serial*")


STUDY = (  # studies of many solves (refinement series, heavy scenes rescaled): slow, and only in make test-all
    "test_twobody_nitsche.py::test_mindlin_stick_zone",  # make test: the wedges and two-body Hertz with it
    "test_twobody_nitsche.py::test_mindlin_default_mesh_newton",
    "test_twobody_nitsche.py::test_mindlin_two_passes_force_is_the_reaction",
    # make test: the linear two-pass symmetric patch, the one-pass skew tangent and the rank comparison
    "test_twobody_nitsche.py::test_patch_non_matching_segment_to_round_off[two--1.0-linear]",
    "test_twobody_nitsche.py::test_patch_non_matching_segment_to_round_off[one-0.0-linear]",
    "test_twobody_nitsche.py::test_patch_non_matching_segment_to_round_off[two-1.0-neohookean]",
    "test_twobody_nitsche.py::test_segment_tangent_neohookean*",
    "test_twobody_nitsche.py::test_consistent_tangent_with_master_dofs[segment-two-2-1.0-None]",
    "test_records.py::test_killed_demo_keeps_its_steps_and_restarts_to_the_same_figures[SIGTERM-mpirun-2]",
    "test_sphere.py::test_sphere_on_block_inexact_newton", "test_sphere.py::test_sphere_on_block_p0_converges_to_hertz",
    "test_sphere.py::test_sphere_multipliers_equal_snes_vi",  # make test: the same equality in 2D
    "test_units.py::test_slow_scene_any_units[mindlin3d]", "test_units.py::test_slow_scene_any_units[wedges]",
    "test_units.py::test_slow_scene_any_units[sphere]",  # make test: every other scene rescaled
    "test_units.py::test_scene_at_small_lengths[*",  # make test: the same scenes at lengths x 0.05 (decimal units)
    "test_repeatable.py::test_wedges_twice_the_same",  # make test: the linear solve's same bits, its cause
    "test_model_reduction.py::test_axisymmetric_section_is_the_octants_limit",
    "test_slab.py::test_regularized_friction_methods_converge_over_mu[compliance]",  # make test: [cross]
    "test_slab.py::test_regularized_friction_methods_converge_over_mu[auglag]",
    "test_oring.py::test_peak_contact_stress_is_hertz_*",  # make test: the squeeze and pressure on a coarse mesh
    "test_oring.py::test_squeeze_then_pressure_converges_and_balances[strain]",  # make test: [axisymmetric]
    "test_oring.py::test_friction_holds_the_cord_against_the_pressure",
    "test_oring.py::test_meshed_gland_converges_squeezed_and_pressurised",  # make test: its stiff limit
    "test_oring.py::test_rod_seal_breaks_out_to_sliding_friction",  # make test: mu = 0 and its ranks
    "test_units.py::test_slow_scene_any_units[oring]",
    "test_mindlin3d.py::test_exact_coulomb_stick_radius_against_cattaneo_mindlin",  # make test: its ranks, coarse
)


def _lane_patterns(table: tuple) -> list[str]:
    return [p if "::" in p else f"{p}::*" for p in table]


def _matches(name: str, pattern: str) -> bool:
    import re

    return re.fullmatch(".*".join(re.escape(part) for part in pattern.split("*")), name) is not None


@pytest.hookimpl(tryfirst=True)  # before -m deselects: every collected test gets its markers
def pytest_collection_modifyitems(config, items):
    tables = {"scene": _lane_patterns(SCENE), "slow": _lane_patterns(SLOW + STUDY), "mpi": _lane_patterns(MPI_COMPARED),
              "study": _lane_patterns(STUDY)}
    used = {p: False for ps in tables.values() for p in ps}
    for item in items:
        name = item.nodeid.split("/")[-1]
        for marker, patterns in tables.items():
            hits = [p for p in patterns if _matches(name, p)]
            for p in hits:
                used[p] = True
            if hits:
                item.add_marker(getattr(pytest.mark, marker))
    if MPI.COMM_WORLD.size == 1:
        skip = pytest.mark.skip(reason="compares ranks: under mpirun only")
        for item in items:
            name = item.nodeid.split("/")[-1]
            if item.get_closest_marker("mpi") and any(_matches(name, p) for p in RANKS_ONLY):
                item.add_marker(skip)
    # make test runs every comparison of ranks: none of them may be left to make test-all
    both = [i.nodeid for i in items if i.get_closest_marker("mpi") and i.get_closest_marker("study")]
    if both:
        raise pytest.UsageError(f"tests in both MPI_COMPARED and STUDY of tests/conftest.py: {both}")
    # Files collected whole (not single tests of them, no -k): each of their patterns must match a test.
    partial = {a.split("::")[0].split("/")[-1] for a in config.args if "::" in a}
    whole = {i.nodeid.split("/")[-1].split("::")[0] for i in items} - partial
    stale = [p for p, hit in used.items() if not hit and p.split("::")[0] in whole]
    if stale and not config.getoption("keyword"):
        raise pytest.UsageError(f"lane patterns of tests/conftest.py that match no test: {stale}")
