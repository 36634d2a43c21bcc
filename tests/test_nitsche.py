"""Symmetric Nitsche (method nitsche) against rigid obstacles: consistency, Hertz, equilibrium."""
import dolfinx.fem.petsc as fem_petsc
import numpy as np
import pytest
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from fenics_contact.compat import petsc_vec
from fenics_contact.factory import contact_surface
from fenics_contact.laws import NitscheLaw, make_law
from fenics_contact.scenes import block, hertz
from fenics_contact.solver import Solver


def solve(setup):
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    assert all(r.converged for r in solver.records)
    return setup.figures(), solver


@pytest.mark.parametrize("gamma0", [1.0, 100.0])
def test_block_exact_pressure_for_any_gamma(gamma0):
    # Nitsche is consistent: the uniform state is exact whatever gamma (penalty would be off by p/K)
    f, solver = solve(block.build(make_law("nitsche", gamma0=gamma0)))
    assert np.isclose(f["contact_pressure"], block.EXACT_PRESSURE, rtol=1e-10)
    assert abs(f["max_penetration"]) < 1e-12
    assert solver.summary()["newton_iterations"] <= 3  # linear in the closed state: one step, one solve


def full_residual_reaction(problem, dofs):
    """Sum over ``dofs`` (owned) of the whole residual, bulk and contact, over all ranks."""
    r = fem.Function(problem.u.function_space)
    vec = petsc_vec(r)
    fem_petsc.assemble_vector(vec, problem.L)
    vec.ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
    owned = problem.u.function_space.dofmap.index_map.size_local * problem.u.function_space.dofmap.index_map_bs
    return problem.comm.allreduce(float(np.sum(vec.array[dofs[dofs < owned]])), op=MPI.SUM)


def test_hertz_p0_within_mesh_error_and_equilibrium():
    setup = hertz.build(make_law("nitsche", gamma0=10.0))
    f, _ = solve(setup)
    assert f["p0_error"] < 0.01 and f["a_error"] < 0.02
    # Nitsche's term -p_s dp_s[v] / gamma acts on the whole candidate surface, also where it is open,
    # and the arc reaches the top corner (R, R): the top reaction balances the contact force through
    # the full residual, while the bulk-only reaction differs by that (small, O(h)) open-part term.
    top = setup.problem.dirichlet[0].dofs
    assert np.isclose(f["total_force"], -2 * full_residual_reaction(setup.problem, top), rtol=1e-8)
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-3)


def test_bad_input():
    with pytest.raises(ValueError, match="gamma0"):
        NitscheLaw(gamma0=0.0)
    setup = block.build(make_law("penalty", K=1.0))
    c = setup.contacts[0]
    with pytest.raises(ValueError, match="material"):
        contact_surface(setup.problem.u, None, 0, c.obstacle, NitscheLaw(), setup.problem.load)
