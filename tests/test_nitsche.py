"""Symmetric Nitsche (method nitsche) against rigid obstacles: consistency, Hertz, equilibrium."""
import dolfinx.fem.petsc as fem_petsc
import numpy as np
import pytest
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from fenics_contact.app.scenes import block, hertz
from fenics_contact.compat import petsc_vec
from fenics_contact.factory import contact_surface
from fenics_contact.laws import Nitsche
from fenics_contact.methods import make_law
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


@pytest.mark.parametrize("plane,gamma0,steps", [("strain", 10.0, 1), ("strain", 100.0, 1), ("strain", 1.0, 8),
                                                  ("stress", 100.0, 1)])
def test_neohookean_block_nominal_pressure_is_the_closed_form(plane, gamma0, steps):
    """Finite strain (16 %): the surface term in the reference configuration (n . P N, nominal) is consistent,
    so the homogeneous state F = diag(a, c, l3) of block.homogeneous_state is the discrete solution at any
    gamma (the Cauchy stress on reference integrals penetrated by O(1/gamma): 4.6e-6 at gamma0 = 1000).
    Small gamma0 loses coercivity: from rest in one step gamma0 = 1 and 3 converge to a spurious state,
    load steps reach the exact one."""
    setup = block.build(make_law("nitsche", gamma0=gamma0), model="neohookean", plane=plane, steps=steps)
    f, _ = solve(setup)
    exact = block.homogeneous_state("neohookean", plane)
    assert np.isclose(f["contact_pressure"], exact["p_nominal"], rtol=1e-6)
    assert np.isclose(f["contact_pressure_nominal"], f["contact_pressure"], rtol=0)
    assert abs(f["max_penetration"]) < 1e-12
    assert np.isclose(f["total_force"], f["reaction_top"], rtol=1e-8)
    # Cauchy (per current area) = nominal * dA/da, da/dA = J |F^-T N| = a l3 for the base
    assert np.isclose(f["contact_pressure_cauchy"], exact["p_nominal"] / (exact["a"] * exact["l3"]), rtol=1e-6)
    assert exact["p_cauchy"] < exact["p_nominal"]  # the base widens: less pressure per current area


def test_neohookean_closed_form_checks():
    """The closed form of block.homogeneous_state: tends to the linear pressure at small strain; in plane strain
    P_xx = 0 holds at the returned stretch."""
    from fenics_contact.materials import lame

    for plane in ("strain", "stress"):
        small = block.homogeneous_state("neohookean", plane, strain=1e-7)
        lin = block.homogeneous_state("linear", plane, strain=1e-7)
        assert np.isclose(small["p_nominal"], lin["p_nominal"], rtol=1e-5)
    s = block.homogeneous_state("neohookean", "strain")
    lam, mu = lame(block.E, block.NU)
    a, c = s["a"], s["c"]
    assert abs(mu * (a - 1 / a) + lam / 2 * ((a * c) ** 2 - 1) / a) < 1e-10 * mu


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
        Nitsche(gamma0=0.0)
    setup = block.build(make_law("penalty", K=1.0))
    c = setup.contacts[0]
    with pytest.raises(ValueError, match="material"):
        contact_surface(setup.problem.u, None, 0, c.obstacle, Nitsche(), setup.problem.load)
