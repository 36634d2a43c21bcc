"""Materials: per-body materials (one per cell tag), plane stress, bad input."""
import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from fenics_contact import (
    ContactProblem,
    Dirichlet,
    HalfPlane,
    LinearElastic,
    Materials,
    NamedTags,
    NeoHookean,
    Solver,
    contact_surface,
    function_space,
    make_law,
)
from fenics_contact.app import build
from fenics_contact.app.meshes import stacked_blocks
from fenics_contact.app.scenes import block, slab
from fenics_contact.app.scenes.patch import uniform_stretches

# nu (1 + nu) / E equal (equal lateral stretch in linear plane strain): nu_upper for E 1000 / 200, nu_lower 0.45
NU_MATCHED = (-1.0 + np.sqrt(1.0 + 4.0 * 0.45 * 1.45 / 5.0)) / 2.0


@pytest.mark.parametrize("material,pressure,lower,upper,slave", [
    ("linear", 10.0, (500.0, 0.0), (2000.0, 0.0), "upper"),
    ("linear", 10.0, (1000.0, 0.45), (200.0, NU_MATCHED), "lower"),
    ("neohookean", 60.0, (500.0, 0.0), (2000.0, 0.0), "upper"),
])
def test_stacked_blocks_of_different_materials(material, pressure, lower, upper, slave):
    """Two stacked blocks of different E (and nu), one material per cell tag (Materials), dead pressure on top,
    frictionless non-matching interface (segment integration, converged augmented Lagrangian). Materials with
    equal lateral stretch (nu = 0, or nu (1 + nu) / E equal), so the piecewise-uniform uniaxial state is exact:
    each block's mean axial strain and every node's displacement equal the closed form, the interface pressure
    equals the load everywhere."""
    setup = build("patch", law_factory=lambda: make_law("auglag", K=1e6), quadrature="segment", slave=slave,
                  material=material, pressure=pressure, E_lower=lower[0], nu_lower=lower[1], E_upper=upper[0],
                  nu_upper=upper[1])
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    solver.run(setup.loads)
    rec = solver.records[-1]
    assert rec.converged and rec.augmentation_converged
    f = setup.figures()
    assert f["lateral_mismatch"] < 1e-15
    for body, (E, nu) in (("lower", lower), ("upper", upper)):
        exact = uniform_stretches(pressure, material, 2, E, nu)[1] - 1.0
        assert np.isclose(f[f"strain_{body}_exact"], exact, rtol=1e-14)
        assert np.isclose(f[f"strain_{body}"], exact, rtol=1e-8), (body, f)
    ratio = f["strain_lower"] / f["strain_upper"]
    assert ratio > 3.0 or ratio < 1 / 3.0  # the soft block strains ~ 4-6 x more
    assert f["displacement_error"] < 1e-8 and f["top_displacement_error"] < 1e-8
    assert f["pressure_deviation"] < 1e-8
    assert np.isclose(f["contact_force"], f["applied_force"], rtol=1e-9)
    assert np.isclose(f["reaction_bottom"], f["applied_force"], rtol=1e-9)


def test_one_material_per_tag_equals_one_material():
    """The per-tag energy sum over dx(tag) with one material on both tags assembles the single-material form."""
    mesh, cell_tags, _ = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (3, 2))
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    u.interpolate(lambda x: np.stack([0.1 * x[0] * x[1], -0.05 * x[1] ** 2]))
    m = NeoHookean(1000.0, 0.3)
    lower, upper = cell_tags["lower"], cell_tags["upper"]
    both = Materials(mesh, cell_tags.meshtags, {lower: m, upper: m})
    named = Materials(mesh, NamedTags(cell_tags.meshtags, {"lower": lower, "upper": upper}), {"lower": m, "upper": m})
    assert named.by_tag.keys() == both.by_tag.keys()
    with pytest.raises(ValueError, match="no region named 'top'"):
        Materials(mesh, cell_tags, {"lower": m, "top": m})
    values = [mesh.comm.allreduce(fem.assemble_scalar(fem.form(e)), op=MPI.SUM)
              for e in (m.energy_form(u), both.energy_form(u), both.energy(u) * ufl.dx,
                        ufl.inner(both.piola(u), both.piola(u)) * ufl.dx,
                        ufl.inner(m.piola(u), m.piola(u)) * ufl.dx)]
    assert np.isclose(values[0], values[1], rtol=1e-13) and np.isclose(values[0], values[2], rtol=1e-13)
    assert np.isclose(values[3], values[4], rtol=1e-13)


def test_plane_stress_linear_is_uniaxial_stress():
    """sigma_zz = 0: a uniaxial strain state eps = diag(e, -nu e) carries sigma = diag(E e, 0)."""
    mesh = dmesh.create_unit_square(MPI.COMM_WORLD, 1, 1)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    e, nu = 1e-3, 0.3
    u.interpolate(lambda x: np.stack([e * x[0], -nu * e * x[1]]))
    s = LinearElastic(1000.0, nu, plane="stress").stress(u)
    vals = [mesh.comm.allreduce(fem.assemble_scalar(fem.form(s[i, j] * ufl.dx)), op=MPI.SUM)
            for i, j in ((0, 0), (1, 1), (0, 1))]
    assert np.allclose(vals, [1000.0 * e, 0.0, 0.0], rtol=1e-12, atol=1e-12)


def test_bad_input():
    mesh, cell_tags, _ = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (3, 2))
    with pytest.raises(ValueError, match="plane must be one of"):
        LinearElastic(1000.0, 0.3, plane="strian")
    with pytest.raises(ValueError, match="cells carry none of the tags"):
        Materials(mesh, cell_tags, {"lower": LinearElastic(1000.0, 0.3)})
    with pytest.raises(ValueError, match="not a Material"):
        Materials(mesh, cell_tags, {"lower": LinearElastic(1000.0, 0.3), "upper": 1000.0})
    with pytest.raises(ValueError, match="at least one"):
        Materials(mesh, cell_tags, {})
    cube = dmesh.create_unit_cube(MPI.COMM_WORLD, 1, 1, 1)
    u = fem.Function(function_space(cube, "Lagrange", 1, (3,)))
    for model in (LinearElastic, NeoHookean):
        with pytest.raises(ValueError, match="plane='stress' is a 2D assumption"):
            model(1000.0, 0.3, plane="stress").energy(u)


def test_slab_plane_stress_frictionless_closed_form():
    """The slab without friction (SNES VI) is in the uniform state sigma = diag(-10, -5): plane stress gives
    u_x(A) = (sigma_xx - nu sigma_yy) / E * 40 (plane strain: (1 - nu^2)/E (sigma_xx - nu/(1-nu) sigma_yy) * 40)."""
    for plane, exact in (("strain", slab.UX_A_FRICTIONLESS), ("stress", slab.UX_A_FRICTIONLESS_PLANE_STRESS)):
        setup = slab.build(make_law("vi"), plane=plane, nx=8, ny=4)
        solver = Solver(setup.problem, quiet=True)
        solver.run(setup.loads)
        assert solver.records[-1].converged
        f = setup.figures()
        assert np.isclose(f["ux_A_frictionless"], exact, rtol=1e-15)
        assert np.isclose(f["ux_A"], exact, rtol=1e-10) and abs(f["uy_A"]) < 1e-12
    assert np.isclose(slab.UX_A_FRICTIONLESS_PLANE_STRESS, (-10.0 + 0.2 * 5.0) / 13000.0 * 40.0, rtol=1e-15)


def test_3d_neohookean_cube_nominal_and_cauchy_pressure():
    """A neo-Hookean unit cube pressed 0.1 onto a rigid plane (SNES VI), free lateral faces: uniaxial stress,
    whose 3D closed form is the plane-stress block's (lateral stretches a = l3); the Cauchy pressure is the
    nominal one over da/dA = J |F^-T N| = a^2 (3D Nanson)."""
    msh = dmesh.create_unit_cube(MPI.COMM_WORLD, 2, 2, 2)
    marks = {1: lambda x: np.isclose(x[2], 0), 2: lambda x: np.isclose(x[2], 1),
             3: lambda x: np.isclose(x[0], 0), 4: lambda x: np.isclose(x[1], 0)}
    facets = [(t, dmesh.locate_entities_boundary(msh, 2, f)) for t, f in marks.items()]
    idx = np.concatenate([f for _, f in facets])
    vals = np.concatenate([np.full(len(f), t, dtype=np.int32) for t, f in facets])
    order = np.argsort(idx)
    tags = dmesh.meshtags(msh, 2, idx[order], vals[order])
    V = function_space(msh, "Lagrange", 1, (3,))
    u = fem.Function(V)
    load = fem.Constant(msh, 0.0)
    d = 0.1
    bcs = [Dirichlet(V.sub(i), fem.locate_dofs_topological(V.sub(i), 2, tags.indices[tags.values == t]), a)
           for i, t, a in [(2, 2, -d), (0, 3, 0.0), (1, 4, 0.0)]]
    c = contact_surface(u, tags, 1, HalfPlane([0, 0, 0], [0, 0, 1]), make_law("vi"), load)
    with pytest.raises(ValueError, match="Cauchy pressure needs the bulk material"):
        c.mean_pressure("cauchy")
    with pytest.raises(ValueError, match="pressure kind"):
        c.mean_pressure("true")
    solver = Solver(ContactProblem(u, NeoHookean(block.E, block.NU), load, bcs, [c]), quiet=True)
    solver.run([1.0])
    assert solver.records[-1].converged
    exact = block.homogeneous_state("neohookean", "stress", strain=d)
    assert np.isclose(c.mean_pressure(), exact["p_nominal"], rtol=1e-8)
    assert np.isclose(c.mean_pressure("cauchy"), exact["p_nominal"] / exact["a"] ** 2, rtol=1e-8)
    assert np.isclose(c.area("cauchy"), exact["a"] ** 2, rtol=1e-10) and np.isclose(c.area(), 1.0, rtol=1e-12)
    _, _, p_c = c.surface_values("cauchy")
    assert np.allclose(p_c, exact["p_cauchy"], rtol=1e-8)


@pytest.mark.parametrize("quadrature", ["nodal", "gauss"])
def test_two_body_cauchy_pressure_is_nominal_over_the_slave_stretch(quadrature):
    """Two equal neo-Hookean blocks (nu = 0.3) with matching interface meshes under a dead pressure of 60
    (pointwise contact: the uniform state is exact, pressure 60 per reference area): the slave (upper) surface
    stretches sideways by a (plane strain, da/dA = a), so at every slave point the Cauchy pressure is 60 / a.
    Segment integration refuses the Cauchy kind with a clear error."""
    a, _ = uniform_stretches(60.0, "neohookean", 2)
    assert a > 1.02
    setup = build("patch", law_factory=lambda: make_law("auglag", K=1e6), quadrature=quadrature,
                  material="neohookean", pressure=60.0, n_lower=(4, 3), n_upper=(4, 3))
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    solver.run(setup.loads)
    assert solver.records[-1].converged
    assert setup.figures()["displacement_error"] < 1e-10
    c = setup.contacts[0]
    _, _, p = c.point_values()
    _, _, pc = c.point_values(kind="cauchy")
    assert np.allclose(p, 60.0, rtol=1e-9) and np.allclose(pc, 60.0 / a, rtol=1e-9)
    with pytest.raises(ValueError, match="pressure kind"):
        c.point_values(kind="true")
    seg = build("patch", law_factory=lambda: make_law("auglag", K=1e6), quadrature="segment")
    with pytest.raises(ValueError, match="nominal pressure only"):
        seg.contacts[0].point_values(kind="cauchy")


def test_patch_geometry_is_parametric():
    """Blocks 2 wide, 0.5 and 1.5 high, E 1000 and 250 (nu = 0: equal lateral stretch), pressure 4: the
    piecewise-uniform state is still the solution (segment integration, converged augmented Lagrangian)."""
    setup = build("patch", law_factory=lambda: make_law("auglag", K=1e6), quadrature="segment", pressure=4.0,
                  E_lower=1000.0, nu_lower=0.0, E_upper=250.0, nu_upper=0.0, width=2.0, h_lower=0.5, h_upper=1.5)
    solver = Solver(setup.problem, augment_max=30, augment_tol=1e-10, quiet=True)
    solver.run(setup.loads)
    assert solver.records[-1].converged and solver.records[-1].augmentation_converged
    f = setup.figures()
    assert np.isclose(f["strain_lower"], -4.0 / 1000.0, rtol=1e-8) and np.isclose(f["strain_upper"], -4.0 / 250.0,
                                                                                     rtol=1e-8)
    assert np.isclose(f["top_displacement_exact"], -4.0 * (0.5 / 1000.0 + 1.5 / 250.0) + 1e-6, rtol=1e-12)
    assert f["displacement_error"] < 1e-8 and f["pressure_deviation"] < 1e-8
    assert np.isclose(f["applied_force"], 8.0) and np.isclose(f["reaction_bottom"], 8.0, rtol=1e-9)
