"""Axisymmetric bodies (``plane="axisymmetric"``): the hoop terms against Lamé's thick-walled cylinder, the ring
weight of contact against a uniform state, the axis, and the refusals of the capability grid's geometry axis."""
from __future__ import annotations

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact import capabilities as cap
from fenics_contact.app.meshes import stacked_blocks

E, NU = 1000.0, 0.3
A, B, L = 1.0, 2.0, 0.5  # inner and outer radius, axial length of the cylinder's section


def annulus_section(nr: int, r0: float = A, r1: float = B):
    """The section ``[r0, r1] x [0, L]``, ``nr x nr/2`` squares of four (crossed) triangles: a mesh symmetric about
    every square's centre, whose discrete solution has no spurious ``u_z``."""
    mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.array([r0, 0.0]), np.array([r1, L])], [nr, max(nr // 2, 1)],
                                  diagonal=dmesh.DiagonalType.crossed)
    sides = (("inner", lambda x: np.isclose(x[0], r0)), ("outer", lambda x: np.isclose(x[0], r1)),
             ("bottom", lambda x: np.isclose(x[1], 0.0)), ("top", lambda x: np.isclose(x[1], L)))
    return mesh, fc.tag_boundary(mesh, sides)


def lame_plane_strain(r, p: float, E_: float = E, nu: float = NU):
    """Radial displacement of the thick-walled cylinder ``A <= r <= B`` under internal pressure ``p``, its ends held
    axially (plane strain): ``u_r = (1 + nu)/E ((1 - 2 nu) C1 r + C2 / r)``, ``C1 = p A^2/(B^2 - A^2)``,
    ``C2 = p A^2 B^2/(B^2 - A^2)``."""
    c1, c2 = p * A**2 / (B**2 - A**2), p * A**2 * B**2 / (B**2 - A**2)
    return (1 + nu) / E_ * ((1 - 2 * nu) * c1 * r + c2 / r)


def solve_cylinder(model: str, p: float, degree: int, nr: int):
    mesh, ft = annulus_section(nr)
    V = fc.function_space(mesh, "Lagrange", degree, (2,))
    u = fem.Function(V)
    load = fem.Constant(mesh, 0.0)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft.meshtags, subdomain_id=ft["inner"])
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "bottom", 1), fc.Dirichlet.on_facets(V, ft, "top", 1)]
    # the internal pressure p pushes the inner wall outward: traction (p, 0) on r = A (a dead load)
    problem = fc.ContactProblem(u, fc.MODELS[model](E, NU, "axisymmetric"), load, dirichlet, [],
                                [(ufl.as_vector((p, 0.0)), ds)])
    solver = fc.Solver(problem, quiet=True)
    solver.run([1.0])
    assert all(r.converged for r in solver.records)
    X = V.tabulate_dof_coordinates()
    ur = u.x.array.reshape(-1, 2)[:, 0]
    n = V.dofmap.index_map.size_local
    return X[:n, 0], ur[:n], problem


@pytest.mark.parametrize("degree,nr,tol", [(1, 8, 2e-3), (2, 4, 5e-4)])
def test_linear_thick_cylinder_is_lame(degree, nr, tol):
    """The hoop strain ``u_r / r`` and the ``2 pi r`` measure: the linear axisymmetric thick-walled cylinder under
    internal pressure has Lamé's radial displacement (plane strain) at every node, P1 and P2."""
    p = 10.0
    r, ur, _ = solve_cylinder("linear", p, degree, nr)
    ref = lame_plane_strain(r, p)
    err = MPI.COMM_WORLD.allreduce(float(np.max(np.abs(ur - ref), initial=0.0)), op=MPI.MAX)
    assert err <= tol * lame_plane_strain(A, p), err


def test_lame_converges_at_second_order_in_p1():
    """P1 nodal error of the Lamé cylinder falls as h^2 (the hoop terms are consistent; measured 1.95, 1.93)."""
    p, errs = 10.0, []
    for nr in (4, 8, 16):
        r, ur, _ = solve_cylinder("linear", p, 1, nr)
        errs.append(MPI.COMM_WORLD.allreduce(float(np.max(np.abs(ur - lame_plane_strain(r, p)), initial=0.0)),
                                             op=MPI.MAX))
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(rates > 1.8), (errs, rates)


def test_neohookean_small_load_is_lame():
    """The finite-strain axisymmetric neo-Hookean cylinder (hoop stretch ``1 + u_r / r``) under a small pressure:
    Lamé's linear answer to the order of the strain (p / E = 1e-4)."""
    p = 0.1
    r, ur, _ = solve_cylinder("neohookean", p, 2, 4)
    ref = lame_plane_strain(r, p)
    err = MPI.COMM_WORLD.allreduce(float(np.max(np.abs(ur - ref), initial=0.0)), op=MPI.MAX)
    assert err <= 2e-3 * lame_plane_strain(A, p), err


def solid_cylinder(n: int = 4):
    """The section ``[0, 1] x [0, 1]`` of a solid cylinder of radius 1: the axis ``x = 0``."""
    mesh = dmesh.create_unit_square(MPI.COMM_WORLD, n, n)
    sides = (("axis", lambda x: np.isclose(x[0], 0.0)), ("bottom", lambda x: np.isclose(x[1], 0.0)),
             ("top", lambda x: np.isclose(x[1], 1.0)))
    return mesh, fc.tag_boundary(mesh, sides)


@pytest.mark.parametrize("quadrature", ["nodal", "gauss"])
def test_cylinder_on_a_rigid_plane_carries_the_ring_force(quadrature):
    """Contact patch test on the ring: a solid cylinder (radius 1, height 1) pressed by ``d`` on a rigid plane, its
    side free: the uniaxial state ``p = E d / H`` at every contact point, the total force ``p pi R^2`` over the
    ring (nodal quadrature: the node on the axis carries its row-sum share, the nodal forces add up to it)."""
    mesh, ft = solid_cylinder()
    law = fc.make_law("auglag", K=1e6)
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    material = fc.LinearElastic(E, NU, "axisymmetric")
    d = 0.01
    contact = fc.contact_surface(u, ft, "bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                                 material=material)
    problem = fc.ContactProblem(u, material, load, [fc.Dirichlet.on_facets(V, ft, "top", 1, -d),
                                                    fc.Dirichlet.on_facets(V, ft, "axis", 0)], [contact])
    solver = fc.Solver(problem, quiet=True, augment_max=30, augment_tol=1e-10)
    solver.run([1.0])
    p = E * d
    _, _, pressure = contact.point_values()
    assert np.allclose(pressure, p, rtol=1e-8)
    assert contact.total_force()[1] == pytest.approx(p * np.pi, rel=1e-8)
    assert problem.reaction(fem.locate_dofs_topological(V.sub(1), 1, ft.find("top"))) == pytest.approx(
        -p * np.pi, rel=1e-8)
    if quadrature == "nodal":
        forces = MPI.COMM_WORLD.allreduce(float(np.sum(contact.point_forces()[1])), op=MPI.SUM)
        assert forces == pytest.approx(p * np.pi, rel=1e-8)


def test_hoop_strain_on_the_axis_is_its_limit():
    """At a point of the axis ``u_r / r`` is its limit ``d u_r / d r``: the nodal interpolation of the hoop strain
    of ``u_r = c r`` is ``c`` everywhere, the axis included (no division by zero)."""
    mesh, _ = solid_cylinder(2)
    V = fc.function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    u.interpolate(lambda x: np.stack([0.3 * x[0], 0.0 * x[1]]))
    f = fem.Function(fc.function_space(mesh, "Lagrange", 1))
    fc.interpolate_expression(f, fc.kinematics.hoop_strain(u))
    assert np.allclose(f.x.array, 0.3)


def test_geometry_refusals():
    """The capability grid's geometry axis: an axisymmetric body with vi, coulomb, segment-to-segment or a 3D
    displacement is refused before any assembly, with one line."""
    assert not cap.supported(method="vi", geometry="axisymmetric")
    assert not cap.supported(method="coulomb", geometry="axisymmetric")
    assert not cap.supported(method="penalty", kind="two-body", quadrature="segment", geometry="axisymmetric")
    assert not cap.supported(method="penalty", dim=3, geometry="axisymmetric")
    mesh, ft = solid_cylinder(2)
    material = fc.LinearElastic(E, NU, "axisymmetric")
    for method in ("vi", "coulomb"):
        law = fc.make_law(method)
        u, _ = fc.unknown(mesh, 1, law)
        with pytest.raises(cap.UnsupportedCombination, match="axisymmetric geometry"):
            fc.contact_surface(u, ft, "bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law,
                               fem.Constant(mesh, 0.0), material=material)
    # a two-body surface does not see the material: the problem refuses it (segment-to-segment integration)
    blocks, _, ftb = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (2, 2), 1e-6)
    u = fem.Function(fc.function_space(blocks, "Lagrange", 1, (2,)))
    load = fem.Constant(blocks, 0.0)
    segment = fc.two_body_surfaces(u, ftb, "upper_bottom", "lower_top", lambda: fc.make_law("penalty", K=1e6), load,
                                   "segment")
    with pytest.raises(cap.UnsupportedCombination, match="segment quadrature"):
        fc.ContactProblem(u, material, load, [], segment)
    box = dmesh.create_unit_cube(MPI.COMM_WORLD, 1, 1, 1)
    w = fem.Function(fc.function_space(box, "Lagrange", 1, (3,)))
    with pytest.raises(ValueError, match="plane='axisymmetric' is a 2D assumption"):
        material.energy(w)
    with pytest.raises(ValueError, match="all axisymmetric or none"):
        tags = dmesh.meshtags(mesh, 2, np.arange(mesh.topology.index_map(2).size_local, dtype=np.int32),
                              np.r_[np.ones(1, np.int32), 2 * np.ones(mesh.topology.index_map(2).size_local - 1,
                                                                      np.int32)])
        fc.Materials(mesh, tags, {1: material, 2: fc.LinearElastic(E, NU)})


def test_min_jacobian_includes_the_hoop_stretch():
    """``min_jacobian`` of an axisymmetric neo-Hookean body is ``det F_2 (1 + u_r / r)``: ``u_r = -0.5 r`` (a
    uniform radial contraction, ``u_z = 0``) gives ``0.5 x 0.5``, on the axis too."""
    mesh, _ = solid_cylinder(2)
    V = fc.function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    u.interpolate(lambda x: np.stack([-0.5 * x[0], 0.0 * x[1]]))
    problem = fc.ContactProblem(u, fc.NeoHookean(E, NU, "axisymmetric"), fem.Constant(mesh, 0.0))
    assert problem.min_jacobian() == pytest.approx(0.25, rel=1e-12)


def _pressed_section(r0: float, r1: float, scale: float = 1.0, axis_noise: float = 0.0):
    """The solid cylinder's contact problem on the section ``[r0, r1] x [0, 1]`` (times ``scale``), its vertices
    on ``r = 0`` moved to ``r = axis_noise``."""
    mesh = dmesh.create_rectangle(MPI.COMM_WORLD, [np.array([r0, 0.0]), np.array([r1, 1.0])], [4, 4])
    mesh.geometry.x[np.isclose(mesh.geometry.x[:, 0], 0.0), 0] = axis_noise
    mesh.geometry.x[:, :2] *= scale
    ft = fc.tag_boundary(mesh, (("bottom", lambda x: np.isclose(x[1], 0.0)),
                                ("top", lambda x: np.isclose(x[1], scale))))
    law = fc.make_law("penalty", K=1e6 / scale)
    u, V = fc.unknown(mesh, 1, law)
    load = fem.Constant(mesh, 0.0)
    material = fc.LinearElastic(E, NU, "axisymmetric")
    contact = fc.contact_surface(u, ft, "bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load,
                                 material=material)
    return fc.ContactProblem(u, material, load, [fc.Dirichlet.on_facets(V, ft, "top", 1, -0.01 * scale)], [contact])


@pytest.mark.parametrize("r0, r1, count, where", [(-2.0, -1.0, 25, r"in the box \(-2, 0\) to \(-1, 1\)"),
                                                  (-0.5, 0.5, 10, r"in the box \(-0.5, 0\) to \(-0.25, 1\)")])
def test_a_section_past_the_axis_is_refused(r0, r1, count, where):
    """An axisymmetric section at ``r < 0`` (its ring force would be negative) or across the axis (the two sides
    cancel) is refused before any form is compiled: one line counting the vertices at ``r < 0`` and saying where."""
    with pytest.raises(fc.MeshError, match=rf"^the axisymmetric mesh has {count} of 25 vertices at r = x\[0\] < 0 "
                                           rf"{where}: the meridian section"):
        _pressed_section(r0, r1)


@pytest.mark.parametrize("scale", [1e-9, 1.0, 1e9])
def test_the_axis_tolerates_round_off_of_the_mesh_size(scale):
    """Vertices on the axis within round-off of the mesh's size (1e-15 of it) are on it, in any units; 1e-6 of it
    past the axis is past it (not an absolute tolerance: at ``scale`` 1e9 that is 1e3 length units, at 1e-9 1e-15)."""
    _pressed_section(0.0, 1.0, scale, axis_noise=-1e-15)
    with pytest.raises(fc.MeshError, match="has 5 of 25 vertices at r = x"):
        _pressed_section(0.0, 1.0, scale, axis_noise=-1e-6)
