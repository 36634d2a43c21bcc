"""The mixed nearly incompressible models on axisymmetric bodies (``plane="axisymmetric"``): the hoop stretch
``1 + u_r / r`` in ``F``, the ``2 pi r`` weight on the energy and on the pressure equation.

The solid cylinder (radius ``R0``, height ``H``) pressed on a frictionless rigid plane, its side free, is the
homogeneous 3D uniaxial state ``F = diag(a, c, a)`` in ``(r, z, theta)``: ``u_r = (a - 1) r`` and ``u_z`` are
linear, so P2 holds them exactly and ``u_r / r = a - 1`` is exact; the contact pressure is the 3D closed form of
:func:`tests.test_incompressible.closed_form` (``nu = 0.4999``), the force over the ring ``p pi R0^2``.

Lamé's thick-walled cylinder under internal pressure, its ends held axially (plane strain in ``z``), at
``nu = 0.4999``: the Herrmann model (``linear-mixed``, P2-P1) has Lamé's radial displacement; the
displacement-only P1 model locks (its displacement is far too small).
"""
from __future__ import annotations

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI
from scipy.optimize import brentq
from test_axisymmetric import A, annulus_section, lame_plane_strain
from test_incompressible import NU, STRAIN, E, closed_form

import fenics_contact as fc
from fenics_contact.compat import collapse
from fenics_contact.incompressible import Kinematics, MixedNeoHookean

R0, H = 1.0, 1.0


def solve_cylinder_on_plane(model: str, strain: float, comm=MPI.COMM_WORLD):
    """The solid cylinder of the module docstring, pressed by ``strain H`` (augmented Lagrangian, Gauss points);
    returns the mean nominal contact pressure, the total contact force, the top's reaction and the problem."""
    mesh = dmesh.create_rectangle(comm, [np.zeros(2), np.array([R0, H])], [2, 2])
    ft = fc.tag_boundary(mesh, (("axis", lambda x: np.isclose(x[0], 0.0)), ("bottom", lambda x: np.isclose(x[1], 0.0)),
                                ("top", lambda x: np.isclose(x[1], H))))
    law = fc.make_law("auglag", K=10 * E / 0.5)
    u, V = fc.unknown(mesh, 2, law, model=model)
    material = fc.MODELS[model](E, NU, "axisymmetric")
    load = fem.Constant(mesh, 0.0)
    top = fc.Dirichlet.on_facets(V, ft, "top", 1, -strain * H)
    contact = fc.contact_surface(u, ft, "bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, "gauss",
                                 material=material)
    problem = fc.ContactProblem(u, material, load, [top, fc.Dirichlet.on_facets(V, ft, "axis", 0)], [contact])
    solver = fc.Solver(problem, quiet=True, augment_max=30, augment_tol=1e-12)
    solver.run([1.0])
    assert all(r.converged for r in solver.records)
    return contact.mean_pressure(), float(contact.total_force()[1]), -problem.reaction(top.dofs), problem


def test_neohookean_cylinder_at_nu_04999_is_the_closed_form():
    """Finite strain (16 %): the contact pressure, the ring's contact force and the top's reaction are the 3D closed
    form to 1e-8; the pressure field is ``kappa (J - 1)`` with ``J = a^2 c`` (the hoop stretch counted)."""
    p, force, reaction, problem = solve_cylinder_on_plane("neohookean-mixed", STRAIN)
    exact = closed_form(3)
    ring = exact * np.pi * R0**2
    assert abs(p - exact) <= 1e-8 * exact, (p, exact)
    assert abs(force - ring) <= 1e-8 * ring, (force, ring)
    assert abs(reaction - ring) <= 1e-8 * ring, (reaction, ring)
    m = problem.material
    a = brentq(lambda x: m.uniaxial(x, 1 - STRAIN, 3)[0], 1.0, 2.0 / (1 - STRAIN))
    w = problem.u
    _, q_to_w = collapse(w.function_space.sub(1))
    pressure = w.x.array[q_to_w]
    expected = m.kappa * (a * a * (1 - STRAIN) - 1)
    assert np.allclose(pressure, expected, rtol=1e-8, atol=1e-10 * exact), (pressure, expected)


def test_herrmann_cylinder_at_nu_04999_is_the_closed_form():
    """Small strain (1 %), ``linear-mixed``: the uniaxial ``p = E strain`` and the ring force ``p pi R0^2`` to
    1e-8."""
    p, force, reaction, _ = solve_cylinder_on_plane("linear-mixed", 0.01)
    exact = E * 0.01
    assert abs(p - exact) <= 1e-8 * exact, (p, exact)
    assert abs(force - exact * np.pi) <= 1e-8 * exact * np.pi and abs(reaction - exact * np.pi) <= 1e-8 * exact * np.pi


def solve_lame(model: str, degree: int, nr: int, p: float = 10.0):
    """Lamé's cylinder (``A <= r <= 2A``, internal pressure ``p``, ``u_z = 0`` on both ends) at ``nu = 0.4999``;
    returns the largest nodal error of ``u_r`` relative to Lamé's ``u_r(A)``."""
    mesh, ft = annulus_section(nr)
    law = fc.make_law("penalty", K=1.0)  # no contact: the law only selects the unknown
    u, V = fc.unknown(mesh, degree, law, model=model)
    load = fem.Constant(mesh, 0.0)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft.meshtags, subdomain_id=ft["inner"])
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "bottom", 1), fc.Dirichlet.on_facets(V, ft, "top", 1)]
    problem = fc.ContactProblem(u, fc.MODELS[model](E, NU, "axisymmetric"), load, dirichlet, [],
                                [(ufl.as_vector((p, 0.0)), ds)])
    fc.Solver(problem, quiet=True).run([1.0])
    Vc, to_u = collapse(V) if V is not u.function_space else (V, np.arange(u.x.array.size))
    X = Vc.tabulate_dof_coordinates()
    n = Vc.dofmap.index_map.size_local
    ur = u.x.array[np.asarray(to_u)].reshape(-1, 2)[:n, 0]
    err = MPI.COMM_WORLD.allreduce(float(np.max(np.abs(ur - lame_plane_strain(X[:n, 0], p, nu=NU)), initial=0.0)),
                                   op=MPI.MAX)
    return err / lame_plane_strain(A, p, nu=NU)


def test_lame_at_nu_04999_mixed_does_not_lock_displacement_only_does():
    """The Herrmann model has Lamé's ``u_r`` within 1e-3 of ``u_r(A)``; the displacement-only P1 model on the same
    mesh is off by more than half of it (locking: its ``u_r`` is too small)."""
    mixed = solve_lame("linear-mixed", 2, 4)
    locked = solve_lame("linear", 1, 4)
    assert mixed <= 1e-3, mixed
    assert locked >= 0.5, locked


def test_kinematics_of_the_plane():
    """The mixed models' kinematics follow ``plane``; a kinematics of another plane is refused."""
    assert MixedNeoHookean(E, NU, "axisymmetric").kinematics.plane == "axisymmetric"
    assert MixedNeoHookean(E, NU, "axisymmetric").axisymmetric
    with pytest.raises(ValueError, match="kinematics of plane 'strain' given for plane 'axisymmetric'"):
        MixedNeoHookean(E, NU, "axisymmetric", kinematics=Kinematics())


def test_parallel_equals_serial():
    """Under mpirun -n 2 the axisymmetric mixed cylinder's pressure and force equal each rank's serial ones."""
    parallel = solve_cylinder_on_plane("neohookean-mixed", STRAIN)[:3]
    serial = solve_cylinder_on_plane("neohookean-mixed", STRAIN, MPI.COMM_SELF)[:3]
    assert np.allclose(parallel, serial, rtol=1e-8, atol=0.0), (parallel, serial)
