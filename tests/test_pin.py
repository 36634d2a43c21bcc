"""Plate with a hole on a rigid pin (Kikuchi & Song; Renaud & Feng 2003, example 1).

Equilibrium with the applied traction, mesh convergence of the contact angle,
load independence of the neat fit, agreement of the laws and of 1 and 2 ranks.
"""
import math

import numpy as np
import pytest
import ufl
from dolfinx import fem
from mpi4py import MPI

from fenics_contact.app import meshes
from fenics_contact.app.scenes import pin
from fenics_contact.laws import AugmentedLagrangian, CrossConstraints, SnesVI
from fenics_contact.solver import Solver


def solve(law, refinement=0, comm=MPI.COMM_WORLD, loads=None, gap="linearized", P0=pin.P0):
    """Figures after each load of ``loads`` (default: the scene's, last figures only). From rest: no initial
    guess (the scene's vanishing spring, zero at t = 1)."""
    setup = pin.build(law, refinement=refinement, comm=comm, gap=gap, P0=P0)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    figures = []
    for t in loads or setup.loads:
        solver.run([t])
        figures.append(setup.figures())
    assert all(r.converged and r.augmentation_converged for r in solver.records)
    return figures[-1] if loads is None else figures


@pytest.fixture(scope="module")
def refinements():
    """Refinements 0, 1, 2 (h at the hole R/50, R/100, R/200), augmented Lagrangian."""
    return [solve(AugmentedLagrangian(pin.DEFAULT_K), r) for r in range(3)]


def test_contact_angle_recovers_a_square_root_edge():
    """p = sqrt(1 - theta/theta_c) (p^2 linear, as at a smooth contact edge): the edge is found exactly."""
    theta = np.linspace(0.0, 180.0, 158)
    for theta_c in (61.3, 83.77, 90.0):
        p = np.sqrt(np.clip(1 - theta / theta_c, 0, None))
        assert np.isclose(pin.contact_angle(theta, p), theta_c, rtol=1e-12)
    # a second zone further on (here near the top) does not count
    p = np.sqrt(np.clip(1 - theta / 50.0, 0, None)) + (theta > 170)
    assert np.isclose(pin.contact_angle(theta, p), 50.0, rtol=1e-12)


def test_total_contact_force_is_the_applied_traction(refinements):
    for f in refinements:
        assert f["applied_force"] == pin.P0 * pin.HALF_WIDTH
        assert f["equilibrium_error"] < 1e-8
        assert abs(f["total_force_y"] + f["applied_force"]) <= 1e-8 * f["applied_force"]
        assert f["max_penetration"] < 1e-8 * pin.R  # converged augmentation: no penetration


def test_contact_angle_converges_under_two_refinements(refinements):
    angles = [f["contact_angle_deg"] for f in refinements]
    changes = np.abs(np.diff(angles))
    assert changes[1] < 1.0, angles
    assert changes[1] < changes[0], angles


def test_neat_fit_is_homogeneous_in_the_load():
    """Zero clearance, linear elasticity and the linearized gap: the pressure scales with P0 and the
    contact angle does not change."""
    half, full = (solve(AugmentedLagrangian(pin.DEFAULT_K), P0=P0) for P0 in (pin.P0 / 2, pin.P0))
    assert np.isclose(half["p_max"], full["p_max"] / 2, rtol=1e-7)
    assert np.isclose(half["total_force_y"], full["total_force_y"] / 2, rtol=1e-10)
    assert abs(half["contact_angle_deg"] - full["contact_angle_deg"]) < 1e-6


def test_exact_gap_tends_to_the_linearized_gap_at_first_order():
    """The exact gap of the deformed position differs from the linearized one by O(u/R): the
    difference of the peak pressure per unit load shrinks tenfold from t = 0.01 to t = 0.001."""
    linear = solve(AugmentedLagrangian(pin.DEFAULT_K), P0=0.001 * pin.P0)
    exact = [solve(AugmentedLagrangian(pin.DEFAULT_K), P0=t * pin.P0, gap="current") for t in (0.001, 0.01)]
    rel = [abs(e["p_max"] / t - linear["p_max"] / 0.001) / (linear["p_max"] / 0.001)
           for e, t in zip(exact, (0.001, 0.01))]
    assert 9 < rel[1] / rel[0] < 11, rel
    assert abs(exact[0]["contact_angle_deg"] - linear["contact_angle_deg"]) < 0.01


def test_cross_constraints_and_augmented_lagrangian_agree():
    """Both converged augmentations solve the same discrete problem (exact nodal non-penetration)."""
    cross = solve(CrossConstraints(pin.DEFAULT_K, F_hat=pin.P0))
    auglag = solve(AugmentedLagrangian(pin.DEFAULT_K))
    assert np.isclose(cross["contact_angle_deg"], auglag["contact_angle_deg"], rtol=1e-6)
    assert np.isclose(cross["p_max"], auglag["p_max"], rtol=1e-6)


def test_parallel_equals_serial():
    """Under mpirun -n 2 the 2-rank figures equal those of each rank solving alone (COMM_SELF)."""
    parallel = solve(CrossConstraints(pin.DEFAULT_K), comm=MPI.COMM_WORLD)
    serial = solve(CrossConstraints(pin.DEFAULT_K), comm=MPI.COMM_SELF)
    for k, v in serial.items():
        scale = max(abs(v), serial["p_max"] * 1e-6)
        assert abs(parallel[k] - v) <= 1e-8 * scale, (k, parallel[k], v)


def test_pin_plate_mesh_tags_and_measures():
    comm = MPI.COMM_WORLD
    mesh, _, tags = meshes.pin_plate(comm, R=1.0, half_width=2.0, below=3.0, above=4.0, h_contact=0.05)
    assert sorted(tags.names) == ["contact", "free", "symmetry", "top"]
    meshes.check_tags(tags, None, comm)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=tags.meshtags)

    def integral(measure):
        return comm.allreduce(fem.assemble_scalar(fem.form(fem.Constant(mesh, 1.0) * measure)), op=MPI.SUM)

    assert abs(integral(ds(tags["contact"])) - math.pi) < 1e-3  # the half hole
    assert abs(integral(ds(tags["symmetry"])) - (3.0 + 4.0 - 2.0)) < 1e-12
    assert abs(integral(ds(tags["top"])) - 2.0) < 1e-12
    assert abs(integral(ds(tags["free"])) - (2.0 + 7.0)) < 1e-12
    assert abs(integral(ufl.dx(domain=mesh)) - (2.0 * 7.0 - math.pi / 2)) < 1e-3


def test_bad_input():
    with pytest.raises(ValueError, match="refinement must be an integer >= 0"):
        pin.build(AugmentedLagrangian(1e6), refinement=-1)
    with pytest.raises(ValueError, match="gap must be one of"):
        pin.build(AugmentedLagrangian(1e6), gap="exact")
    with pytest.raises(ValueError, match="steps must be an integer >= 2"):
        pin.build(AugmentedLagrangian(1e6), steps=1)
    with pytest.raises(ValueError, match="h_contact must be in"):
        pin.build(AugmentedLagrangian(1e6), h_contact=2.0)
    with pytest.raises(ValueError, match="must extend beyond the hole radius"):
        meshes.pin_plate(MPI.COMM_WORLD, R=1.0, half_width=0.5)
    with pytest.raises(ValueError, match="vi, curved obstacle.*axis-aligned half-plane"):
        pin.build(SnesVI())
    with pytest.raises(ValueError, match="no contact at the pin's bottom"):
        pin.contact_angle(np.array([0.0, 1.0, 2.0]), np.array([0.0, 1.0, 0.0]))
