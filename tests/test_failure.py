"""Failure diagnosis: synthetic histories, then real failed solves (KSP failure, singular Jacobian, cycling in
summary.json), MUMPS's work arrays grown after a factorization that ran out of them, and MUMPS out of memory
named as such and not cut back."""
import json

import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI

from fenics_contact.app.meshes import rectangle
from fenics_contact.app.run import run
from fenics_contact.app.scenes import block, build, ring
from fenics_contact.compat import function_space
from fenics_contact.contact import ContactSurface
from fenics_contact.failure import (
    MUMPS_WORKSPACE,
    classify,
    cutback_helps,
    find_cycle,
    fingerprint,
    mumps_error,
    mumps_factors,
    stalled,
)
from fenics_contact.laws import Penalty
from fenics_contact.materials import LinearElastic
from fenics_contact.obstacles import HalfPlane
from fenics_contact.problem import ContactProblem
from fenics_contact.solver import LINEAR_SOLVERS, ConvergenceError, Solver


def test_find_cycle():
    assert find_cycle(list("aabababab")) == {"period": 2, "start": 1, "repeats": 4.0}
    assert find_cycle(list("xabcabcabc"))["period"] == 3
    assert find_cycle(list("abcdddddd")) is None  # settled: constant tail
    assert find_cycle(list("abcdefgh")) is None  # always new sets
    assert find_cycle(list("abab"))["period"] == 2 and find_cycle(list("aba")) is None  # two full periods needed


def test_classify_synthetic_histories():
    conv = [1.0, 1e-2, 1e-5, 1e-7, 1e-8, 1e-9, 1e-10]  # slow but converging, constant active set
    assert classify("DIVERGED_MAX_IT", "CONVERGED_ITS", conv, ["a"] * 7, [1] * 7)["kind"] == "max_iterations"
    flat = [1.0, 0.5, 0.4, 0.41, 0.40, 0.39, 0.40, 0.41]
    assert classify("DIVERGED_MAX_IT", "CONVERGED_ITS", flat, list("abcdefgh"), [1] * 8)["kind"] == "stagnation"
    assert classify("DIVERGED_MAX_IT", "CONVERGED_ITS", [1.0, 10.0, 1e5], [], [])["kind"] == "divergence"
    assert classify("DIVERGED_FNORM_NAN", "CONVERGED_ITS", [1.0, np.nan], [], [])["kind"] == "divergence"
    c = classify("DIVERGED_MAX_IT", "CONVERGED_ITS", flat, list("aabababa"), [2, 2, 1, 2, 1, 2, 1, 2])
    assert c["kind"] == "cycling" and c["period"] == 2 and c["closed_points_in_cycle"] == [2, 1]
    assert classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_ITS", [1.0], [], [])["kind"] == "linear_solve"
    assert classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_PCSETUP_FAILED", [1.0], [], [])["kind"] == "ill_conditioning"
    # a failed MUMPS factorization: out of a work array is the linear solver's resources, a zero pivot the Jacobian
    room = classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_PC_FAILED", [1.0], [], [], None, (-9, 1234))
    assert room["kind"] == "linear_solve" and room["mumps_infog"] == [-9, 1234]
    assert classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_PC_FAILED", [1.0], [], [], None, (-10, 3))["kind"] == \
        "ill_conditioning"


def test_stalled_at_the_round_off_floor():
    # accepted on the step length with the residual still above rtol x first and atol: stalled
    assert stalled("CONVERGED_SNORM_RELATIVE", [2.5e3, 3e7, 56.0, 2.0, 9.0e-8, 9.0e-8], 1e-11, 1e-10)
    assert not stalled("CONVERGED_SNORM_RELATIVE", [2.5e3, 3e7, 56.0, 2.0, 1e-12, 1e-12], 1e-11, 1e-10)
    assert not stalled("CONVERGED_FNORM_ABS", [2.5e3, 9.0e-8], 1e-11, 1e-10)  # met an asked tolerance
    assert not stalled("CONVERGED_SNORM_RELATIVE", [1.0], 1e-11, 1e-10)


def test_fingerprint_is_global(comm):
    flags = np.array([comm.rank % 2 == 0, True])
    a, n = fingerprint(flags, comm)
    b, _ = fingerprint(flags, comm)
    c, _ = fingerprint(~flags if comm.rank == 0 else flags, comm)
    assert a == b and a != c and n == sum(int(np.count_nonzero(np.array([r % 2 == 0, True]))) for r in range(comm.size))


def test_krylov_failure_is_a_linear_solve_failure(comm):
    setup = block.build(Penalty(1e5), comm=comm)
    solver = Solver(setup.problem, quiet=True, max_cutbacks=1,
                    options={"ksp_type": "cg", "pc_type": "none", "ksp_max_it": 1})
    with pytest.raises(ConvergenceError, match="linear_solve") as info:
        solver.run(setup.loads)
    assert info.value.failure["kind"] == "linear_solve" and info.value.failure["ksp_reason"] == "DIVERGED_MAX_IT"
    assert len(solver.failures) == 2  # the step and its one cutback, both diagnosed
    cuts = [w for w in solver.summary()["warnings"] if "cut back" in w]  # the cutback is a warning of the run
    assert len(cuts) == 1 and "step 1 (t = 1" in cuts[0] and "linear_solve" in cuts[0] and "to t = 0.5" in cuts[0]


def test_singular_jacobian_is_ill_conditioning():
    """A free block that does not reach its obstacle: no support, rigid modes, the LU factorization fails."""
    mesh, _, tags = rectangle(MPI.COMM_SELF, 1.0, 1.0, 2, 2)
    u = fem.Function(function_space(mesh, "Lagrange", 1, (2,)))
    load = fem.Constant(mesh, 0.0)
    contact = ContactSurface(u, tags, "bottom", HalfPlane([0.0, -1.0], [0.0, 1.0]), Penalty(1e5), load)
    ds_top = ufl.Measure("ds", domain=mesh, subdomain_data=tags.meshtags, subdomain_id=tags["top"])
    traction = (ufl.as_vector([0.0, -1.0]), ds_top)
    problem = ContactProblem(u, LinearElastic(1000.0, 0.3), load, [], [contact], [traction])
    solver = Solver(problem, quiet=True, max_cutbacks=0, prefix="fc_singular_",
                    options={"pc_factor_mat_solver_type": "petsc"})
    with pytest.raises(ConvergenceError) as info:
        solver.run([1.0])
    assert info.value.failure["kind"] == "ill_conditioning" and info.value.failure["condition_estimate"] > 1e12


def test_cycling_is_in_summary_json(tmp_path_factory, comm):
    out = comm.bcast(str(tmp_path_factory.mktemp("ring")) if comm.rank == 0 else None)
    setup = build("ring", law=Penalty(ring.K, augmented=True), comm=comm)
    with pytest.raises(ConvergenceError):
        run(setup, out, "penalty", {}, augment_max=1, quiet=True, options={"snes_linesearch_type": "basic"},
            max_cutbacks=0)
    s = json.load(open(f"{out}/summary.json"))
    assert s["converged"] is False and s["failure"]["kind"] == "cycling"
    assert s["failure"]["step"] == 1 and s["failure"]["iterations"] == 30 and s["failure"]["augmentation"] == 1
    assert s["steps"][-1]["failure"] == s["failure"]


def test_mumps_options_reach_the_factorization(comm):
    """``mat_mumps_*`` options of ``Solver(options=...)`` are read by MUMPS at factorization, inside the solve."""
    setup = block.build(Penalty(1e5), comm=comm)
    solver = Solver(setup.problem, quiet=True, prefix="fc_mumps_options_", options={"mat_mumps_icntl_14": 57})
    solver.run(setup.loads)
    (F,) = mumps_factors(solver.snes.getKSP())
    assert F.getMumpsIcntl(14) == 57 and F.getMumpsInfog(1) == 0


def test_multigrid_level_options_reach_the_smoothers(comm):
    """``mg_levels_*`` options of ``Solver(options=...)`` reach GAMG's level smoothers, which are made at set-up
    inside the solve (they were silently ignored)."""
    setup = block.build(Penalty(1e5), comm=comm)
    solver = Solver(setup.problem, quiet=True, prefix="fc_mg_options_",
                    options={**LINEAR_SOLVERS["iterative"], "mg_levels_ksp_max_it": 5, "mg_levels_pc_type": "sor"})
    solver.run(setup.loads)
    pc = solver.snes.getKSP().getPC()
    assert pc.getType() == "gamg" and pc.getMGLevels() > 1
    smoother = pc.getMGSmoother(1)
    assert smoother.getTolerances()[3] == 5 and smoother.getPC().getType() == "sor"


def test_mumps_out_of_workspace_grows_icntl14_and_retries(comm):
    """After INFOG(1) in MUMPS_WORKSPACE the solver doubles ICNTL(14) (on the factor and for the next one) up to
    MUMPS_WORKSPACE_MAX, and the step goes on with it; a zero pivot (-10) is not retried that way."""
    setup = block.build(Penalty(1e5), comm=comm)
    solver = Solver(setup.problem, quiet=True, prefix="fc_mumps_grow_")
    solver.run(setup.loads[:1])
    (F,) = mumps_factors(solver.snes.getKSP())
    assert F.getMumpsIcntl(14) == 20 and -9 in MUMPS_WORKSPACE
    grown, failure = [], {"mumps_infog": [-9, 5000]}
    while solver._grow_mumps_workspace(failure):
        grown.append(F.getMumpsIcntl(14))
    assert grown == [40, 80, 160, 320, 640] and "ICNTL(14) 320 -> 640" in failure["message"]
    assert not solver._grow_mumps_workspace({"mumps_infog": [-10, 0]})
    solver.run(setup.loads[1:])
    assert solver.records[-1].converged and mumps_factors(solver.snes.getKSP())[0].getMumpsIcntl(14) == 640


def test_mumps_out_of_memory_is_its_own_kind():
    """INFOG(1) = -13 (an allocation failed; INFOG(2) < 0: millions of entries) is out_of_memory with a message
    naming it, and not cut back; a work array too small is still linear_solve, named too."""
    oom = classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_PCSETUP_FAILED", [1.0], [], [], None, (-13, -3900))
    assert oom["kind"] == "out_of_memory" and oom["mumps_infog"] == [-13, -3900]
    assert "INFOG(1) = -13" in oom["message"] and "3.9e+09" in oom["message"] and "31.2 GB" in oom["message"]
    assert not cutback_helps(oom)
    cap = classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_PCSETUP_FAILED", [1.0], [], [], None, (-19, 5000))
    assert cap["kind"] == "out_of_memory" and "ICNTL(23)" in cap["message"]
    room = classify("DIVERGED_LINEAR_SOLVE", "DIVERGED_PC_FAILED", [1.0], [], [], None, (-9, 1234))
    assert room["kind"] == "linear_solve" and "work array" in room["message"] and cutback_helps(room)


def test_mumps_out_of_memory_stops_at_once(comm):
    """A factorization MUMPS cannot allocate (ICNTL(14): 1e8 percent more room, some 30 GB) fails the step as
    out_of_memory without the four cutbacks, which would factor the same pattern again."""
    setup = block.build(Penalty(1e5), comm=comm)
    solver = Solver(setup.problem, quiet=True, prefix="fc_mumps_oom_", options={"mat_mumps_icntl_14": 100000000})
    with pytest.raises(ConvergenceError, match=r"a cutback cannot help.*out_of_memory.*INFOG\(1\) = -13") as info:
        solver.run(setup.loads)
    assert info.value.failure["kind"] == "out_of_memory" and len(solver.failures) == 1


def test_mumps_error_only_after_a_failed_factorization():
    """A MUMPS LU never factored has no INFOG to read (None, not a crash), one factored with a zero pivot has
    INFOG(1) = -10."""
    from petsc4py import PETSc

    A = PETSc.Mat().createAIJ([4, 4], nnz=1, comm=PETSc.COMM_SELF)
    A.setUp()
    for i in range(4):
        A.setValue(i, i, 0.0 if i == 2 else 1.0)
    A.assemble()
    ksp = PETSc.KSP().create(PETSc.COMM_SELF)
    ksp.setOperators(A)
    ksp.setType("preonly")
    ksp.getPC().setType("lu")
    ksp.getPC().setFactorSolverType("mumps")
    assert mumps_error(ksp) is None
    b, x = A.createVecLeft(), A.createVecRight()
    b.set(1.0)
    ksp.solve(b, x)
    assert mumps_error(ksp)[0] == -10
    for obj in (ksp, A, b, x):
        obj.destroy()
