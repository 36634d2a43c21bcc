"""Nearly incompressible rubber: the mixed displacement-pressure models (:mod:`fenics_contact.incompressible`,
Taylor-Hood P2-P1) with contact on their displacement field.

The block pressed on a frictionless rigid plane (top moved down, sides free, rollers on the symmetry planes) is
homogeneous, ``F = diag(a, .., c)``: P2 displacements and a P1 pressure hold it exactly, so the contact pressure is
the closed form to round-off, here at ``nu = 0.4999`` (``kappa / mu = 5000``). The closed form is derived from the
eliminated energy ``W(a, c) = mu/2 (J^(-2/3) I1 - 3) + kappa/2 (J - 1)^2`` (``p = kappa (J - 1)`` at the
stationary point in ``p``): the free sides give ``dW/da = 0`` (Brent's method; derivatives by complex step),
the nominal pressure on the base is ``-dW/dc``.
"""
from __future__ import annotations

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI
from scipy.optimize import brentq

import fenics_contact as fc
from fenics_contact.capabilities import UnsupportedCombination
from fenics_contact.compat import collapse
from fenics_contact.incompressible import Kinematics, MixedNeoHookean

E, NU, H, STRAIN = 1000.0, 0.4999, 1.0, 0.16


def closed_form(dim: int, E: float = E, nu: float = NU, strain: float = STRAIN) -> float:
    """Nominal contact pressure of the homogeneous uniaxial state (module docstring)."""
    lam, mu = fc.lame(E, nu)
    kappa = lam + 2 * mu / 3
    c = 1.0 - strain

    def W(a, c):  # per reference volume; plane strain: F_33 = 1
        s = [a] * (dim - 1) + [c] + [1.0] * (3 - dim)
        J = np.prod(s)
        return mu / 2 * (J ** (-2 / 3) * sum(x * x for x in s) - 3) + kappa / 2 * (J - 1) ** 2

    h = 1e-30  # complex-step derivatives: exact to round-off

    def dW_da(a):
        return W(a + 1j * h, c).imag / h

    a = brentq(dW_da, 1.0, 2.0 / c, xtol=1e-15, rtol=1e-15)
    return -W(a, c + 1j * h).imag / h


def block(dim: int, comm=MPI.COMM_WORLD, nu: float = NU, strain: float = STRAIN):
    if dim == 2:
        mesh = dmesh.create_rectangle(comm, [np.zeros(2), np.array([1.0, H])], [2, 2])
        sides = (("bottom", lambda x: np.isclose(x[1], 0.0)), ("top", lambda x: np.isclose(x[1], H)),
                 ("left", lambda x: np.isclose(x[0], 0.0)))
    else:
        mesh = dmesh.create_box(comm, [np.zeros(3), np.array([1.0, 1.0, H])], [2, 2, 2], dmesh.CellType.tetrahedron)
        sides = (("bottom", lambda x: np.isclose(x[2], 0.0)), ("top", lambda x: np.isclose(x[2], H)),
                 ("left", lambda x: np.isclose(x[0], 0.0)), ("front", lambda x: np.isclose(x[1], 0.0)))
    return mesh, fc.tag_boundary(mesh, sides)


def solve_block(dim: int, comm=MPI.COMM_WORLD, nu: float = NU, strain: float = STRAIN,
                model: str = "neohookean-mixed", E: float = E, records: list | None = None):
    """The block of the module docstring by converged augmented Lagrangian (penalty ``E / h``); returns the mean
    nominal contact pressure, the top's reaction per area and the problem; ``records``: gets the solver's step
    records."""
    mesh, ft = block(dim, comm)
    law = fc.make_law("auglag", K=10 * E / 0.5)
    u, V = fc.unknown(mesh, 2, law, model=model)
    material = fc.MODELS[model](E, nu)
    load = fem.Constant(mesh, 0.0)
    top = fc.Dirichlet.on_facets(V, ft, "top", dim - 1, -strain * H)
    dirichlet = [top, fc.Dirichlet.on_facets(V, ft, "left", 0)]
    dirichlet += [fc.Dirichlet.on_facets(V, ft, "front", 1)] if dim == 3 else []
    contact = fc.contact_surface(u, ft, "bottom", fc.HalfPlane(np.zeros(dim), np.eye(dim)[dim - 1]), law, load,
                                 "gauss", material=material)
    problem = fc.ContactProblem(u, material, load, dirichlet, [contact])
    solver = fc.Solver(problem, quiet=True, augment_max=30, augment_tol=1e-12)
    solver.run([1.0])
    assert all(r.converged for r in solver.records)
    if records is not None:
        records += solver.records
    return contact.mean_pressure(), -problem.reaction(top.dofs), problem


@pytest.mark.parametrize("dim", [2, 3])
def test_block_at_nu_04999_is_the_closed_form(dim):
    """Plane strain and 3D: the contact pressure and the top's reaction are the closed form to 1e-8; the pressure
    field is ``kappa (J - 1)``, the mean stress."""
    p, reaction, problem = solve_block(dim)
    exact = closed_form(dim)
    assert abs(p - exact) <= 1e-8 * exact, (p, exact)
    assert abs(reaction - exact) <= 1e-8 * exact, (reaction, exact)  # unit top area
    w = problem.u
    Q, q_to_w = collapse(w.function_space.sub(1))
    m = problem.material
    lam = brentq(lambda a: m.uniaxial(a, 1 - STRAIN, dim)[0], 1.0, 2.0 / (1 - STRAIN))
    J = lam ** (dim - 1) * (1 - STRAIN)
    pressure = w.x.array[q_to_w]
    assert np.allclose(pressure, m.kappa * (J - 1), rtol=1e-8, atol=1e-10 * exact), (pressure, m.kappa * (J - 1))


@pytest.mark.parametrize("model", ["neohookean-mixed", "linear-mixed"])
def test_block_in_any_stress_unit(model):
    """The pressure rows are forces like the displacement rows: at E = 1e-3 the block takes the same Newton
    iterations and augmentations as at E = 1000, its pressure per E the same to 1e-8."""
    runs = []
    for modulus in (E, 1e-3):
        records = []
        p, _, _ = solve_block(2, model=model, E=modulus, records=records)
        runs.append((p / modulus, [(r.newton_iterations, r.augmentations) for r in records]))
    assert runs[1][0] == pytest.approx(runs[0][0], rel=1e-8)
    assert runs[1][1] == runs[0][1]


def test_small_strain_limit_is_linear_elasticity():
    """At a strain of 1e-6 the plane-strain pressure is ``E/(1 - nu^2) strain`` to O(strain)."""
    p, _, _ = solve_block(2, strain=1e-6)
    linear = E / (1 - NU**2) * 1e-6
    assert abs(p - linear) <= 1e-5 * linear, (p, linear)


@pytest.mark.parametrize("dim", [2, 3])
def test_herrmann_block_is_the_linear_closed_form(dim):
    """The small-strain mixed model (``linear-mixed``) at nu = 0.4999: ``E/(1 - nu^2) strain`` in plane strain,
    ``E strain`` in 3D (free sides), to 1e-8."""
    p, reaction, _ = solve_block(dim, strain=0.01, model="linear-mixed")
    exact = (E / (1 - NU**2) if dim == 2 else E) * 0.01
    assert abs(p - exact) <= 1e-8 * exact and abs(reaction - exact) <= 1e-8 * exact, (p, reaction, exact)


def test_eliminated_energy_and_stress_agree_with_the_mixed_ones():
    """``energy(u)`` and ``stress(u)`` without ``p`` equal the mixed ones at ``p = kappa (J - 1)``, and the Piola
    stress is the derivative of the energy (UFL), on a non-homogeneous displacement."""
    mesh = dmesh.create_unit_square(MPI.COMM_WORLD, 2, 2)
    V = fc.function_space(mesh, "Lagrange", 2, (2,))
    u = fem.Function(V)
    u.interpolate(lambda x: np.stack([0.1 * x[0] * x[1], -0.05 * x[0] ** 2 + 0.02 * x[1]]))
    m = MixedNeoHookean(E, 0.45)
    J = ufl.det(Kinematics().deformation_gradient(u))
    p = m.kappa * (J - 1)

    def norm(e):
        return np.sqrt(MPI.COMM_WORLD.allreduce(fem.assemble_scalar(fem.form(ufl.inner(e, e) * ufl.dx)), op=MPI.SUM))

    assert norm(m.energy(u) - m.energy(u, p)) <= 1e-12 * norm(m.energy(u))
    assert norm(m.stress(u) - m.stress(u, p)) <= 1e-12 * norm(m.stress(u))
    F = ufl.variable(ufl.Identity(2) + ufl.grad(u))
    P = ufl.diff(_energy_2d(m, F, p), F)
    assert norm(P - m.piola(u, p)) <= 1e-10 * norm(m.piola(u, p))
    lin, herrmann = fc.LinearElastic(E, 0.45), fc.MixedLinearElastic(E, 0.45)  # eliminated p: the linear model
    assert norm(herrmann.energy(u) - lin.energy(u)) <= 1e-12 * norm(lin.energy(u))
    assert norm(herrmann.stress(u) - lin.stress(u)) <= 1e-12 * norm(lin.stress(u))


def _energy_2d(m, F2, p):
    """The mixed energy of a plane-strain ``F_2`` written out (``F_33 = 1``)."""
    J = ufl.det(F2)
    return m.mu / 2 * (J ** (-2 / 3) * (ufl.tr(F2.T * F2) + 1) - 3) + p * (J - 1) - p**2 / (2 * m.kappa)


def test_refusals():
    """What the mixed model does not do is refused up front, with one line."""
    mesh, ft = block(2)
    with pytest.raises(UnsupportedCombination, match="second field"):
        fc.unknown(mesh, 2, fc.make_law("lagrange", c=1e4), model="neohookean-mixed")
    with pytest.raises(UnsupportedCombination, match="Taylor-Hood"):
        fc.unknown(mesh, 1, fc.make_law("penalty", K=1e4), model="neohookean-mixed")
    with pytest.raises(UnsupportedCombination, match="saddle point"):
        fc.capabilities.check(method="penalty", model="neohookean-mixed", degree=2, solver="iterative")
    with pytest.raises(UnsupportedCombination):
        fc.capabilities.check(method="nitsche", model="neohookean-mixed", degree=2)
    with pytest.raises(ValueError, match="plane strain, 3D or axisymmetric"):
        MixedNeoHookean(E, NU, plane="stress")
    with pytest.raises(UnsupportedCombination, match="pressure field"):
        fc.capabilities.check(method="nitsche", model="linear-mixed", degree=2)
    with pytest.raises(ValueError, match="every body a mixed model or none"):
        fc.Materials(mesh, _cells(mesh), {1: MixedNeoHookean(E, NU), 2: fc.NeoHookean(E, NU)})
    law = fc.make_law("penalty", K=1e4)
    u, V = fc.unknown(mesh, 2, law)  # a displacement
    load = fem.Constant(mesh, 0.0)
    contact = fc.contact_surface(u, ft, "bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, "gauss")
    with pytest.raises(ValueError, match="needs the mixed unknown"):
        fc.ContactProblem(u, MixedNeoHookean(E, NU), load, [], [contact])


def test_parallel_equals_serial():
    """Under mpirun -n 2 the 2-rank contact pressure equals that of each rank solving alone (COMM_SELF)."""
    parallel = solve_block(2, MPI.COMM_WORLD)[:2]
    serial = solve_block(2, MPI.COMM_SELF)[:2]
    assert np.allclose(parallel, serial, rtol=1e-8, atol=0.0), (parallel, serial)


def _cells(mesh):
    """Cell tags 1 (x < 1/2) and 2 (the rest)."""
    tdim = mesh.topology.dim
    n = mesh.topology.index_map(tdim).size_local + mesh.topology.index_map(tdim).num_ghosts
    cells = np.arange(n, dtype=np.int32)
    left = dmesh.locate_entities(mesh, tdim, lambda x: x[0] <= 0.5 + 1e-12)
    return dmesh.meshtags(mesh, tdim, cells, np.where(np.isin(cells, left), 1, 2).astype(np.int32))
