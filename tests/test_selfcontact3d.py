"""Self-contact in 3D: a C-shaped (horseshoe) block of tetrahedra whose arms are bent toward each other until their
inner faces touch and press from the tips back (one body against itself), against its half on the symmetry plane
(the arm against a rigid plane): the same problem by symmetry."""
import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.app.meshes.horseshoe import horseshoe
from fenics_contact.app.scenes.tube import stiffer

E, NU = 1000.0, 0.3
LENGTH, HEIGHT, DEPTH, SPINE, ARM = 2.0, 1.2, 0.5, 0.5, 0.55  # the slot is 0.1 wide
N = (8, 2, 2)
H = ARM / N[1]  # the cell size across an arm
TIP = 0.5  # the length of each arm's outer face, from its tip, moved toward the other arm
CLOSE = 0.12  # that displacement at t = 1 (the tips touch at t ~ 0.37)
STEPS = 12
LAWS = {"penalty": dict(K=100 * E / H), "auglag": dict(K=100 * E / H), "compliance": dict(c_n=100 * E / H),
        "nitsche": dict(gamma0=10.0)}


def _doubled(method: str) -> fc.ContactLaw:
    """The half model's law: its pressure at a penetration of the plane is the full model's at twice the overlap
    (the overlap of the two arms is twice an arm's penetration of the plane)."""
    if method == "nitsche":  # p = <gamma g + p_s>: gamma doubled
        return fc.make_law(method, gamma0=2 * LAWS[method]["gamma0"])
    return stiffer(fc.make_law(method, **LAWS[method]))


def _tip(V, y: float) -> np.ndarray:
    """The y-displacement dofs of the outer face y = ``y`` within ``TIP`` of the arm's tip."""
    tol = 1e-9 * LENGTH
    vertices = dmesh.locate_entities_boundary(V.mesh, 0, lambda x: (np.abs(x[1] - y) < tol)
                                              & (x[0] > LENGTH - TIP - tol))
    return fem.locate_dofs_topological(V.sub(1), 0, vertices)


def solve(half: bool, method: str, quadrature: str = "nodal", comm=MPI.COMM_WORLD) -> tuple[list, list, float]:
    """Every step's (force on the lower arm's pushed face, contact force on the lower arm, overlap, number of the
    lower arm's points in contact), the step records and the method's tolerance on the overlap (E over the
    stiffness, a length)."""
    mesh, _, ft = horseshoe(comm, LENGTH, HEIGHT, DEPTH, SPINE, ARM, N, half)
    law = fc.make_law(method, **LAWS[method])
    u, V = fc.unknown(mesh, 1, law)
    t = fem.Constant(mesh, 0.0)
    material = fc.NeoHookean(E, NU)
    push = fc.Dirichlet(V.sub(1), _tip(V, 0.0), amplitude=CLOSE)
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "back", 0), fc.Dirichlet.on_facets(V, ft, "bottom", 2), push]
    if half:
        (fold,) = [fc.contact_surface(u, ft, "inner_low", fc.HalfPlane([0, HEIGHT / 2, 0], [0, -1, 0]),
                                      _doubled(method), t, quadrature, name="symmetry plane",
                                      material=material)]
        dirichlet.append(fc.Dirichlet.on_facets(V, ft, "cut", 1))
    else:
        ft = fc.merge_regions(mesh, ft, "inner", ["inner_low", "inner_high"])
        (fold,) = fc.self_contact_surfaces(u, ft, "inner", lambda: fc.make_law(method, **LAWS[method]), t,
                                           quadrature, material=material)
        dirichlet.append(fc.Dirichlet(V.sub(1), _tip(V, HEIGHT), amplitude=-CLOSE))
    problem = fc.ContactProblem(u, material, t, dirichlet, [fold])
    lower = ufl.conditional(ufl.lt(ufl.SpatialCoordinate(mesh)[1], HEIGHT / 2), 1.0, 0.0)
    contact_force = fem.form(lower * fold.pressure * fold.normal[1] * fold.ds)
    solver = fc.Solver(problem, quiet=True)
    figures = []
    for i in range(STEPS):
        solver.run([(i + 1) / STEPS])
        X, _, _ = fold.point_values(reference=True)
        _, _, p = fold.point_values()
        figures.append((problem.reaction(push.dofs), comm.allreduce(fem.assemble_scalar(contact_force), op=MPI.SUM),
                        fold.max_penetration() * (2.0 if half else 1.0), int(np.sum((p > 0) & (X[:, 1] < HEIGHT / 2)))))
    stiffness = LAWS[method]["gamma0"] * E / H if method == "nitsche" else next(iter(LAWS[method].values()))
    return figures, solver.records, E / stiffness


@pytest.mark.parametrize("method, quadrature", [("penalty", "nodal"), ("nitsche", "nodal"), ("auglag", "nodal"),
                                                ("compliance", "nodal"), ("penalty", "gauss"), ("nitsche", "gauss")])
def test_arms_pressed_together_equal_the_half_on_its_symmetry_plane(method, quadrature):
    """At every step past first contact the full block's pushing force and contact force equal the half's to 1e-3
    of the pushing force; the contact zone grows; the arms overlap by no more than the method's E / stiffness;
    every step converged at once in both models."""
    full, full_records, tolerance = solve(False, method, quadrature)
    half, half_records, _ = solve(True, method, quadrature)
    assert len(full_records) == len(half_records) == STEPS  # no cutback
    touched = [i for i, h in enumerate(half) if abs(h[1]) > 0]
    assert len(touched) >= 3 and touched[-1] == STEPS - 1 and touched[0] > 0
    for i in touched:
        scale = abs(half[i][0])
        assert abs(full[i][0] - half[i][0]) <= 1e-3 * scale, (i, full[i], half[i])
        assert abs(full[i][1] - half[i][1]) <= 1e-3 * scale, (i, full[i], half[i])
        assert full[i][2] <= tolerance, (i, full[i][2], tolerance)
    if quadrature == "nodal":  # the same vertices in contact (gauss: a two-body surface reports its Gauss points)
        assert [full[i][3] for i in touched] == [half[i][3] for i in touched]
    assert full[-1][3] > full[touched[0]][3] > 0  # the contact zone grows from the tips back
    assert abs(full[-1][1]) > 0.1 * abs(full[-1][0])  # the contact carries a good part of the load


def test_parallel_equals_serial():
    """Under mpirun -n 2: every figure of every step of the full block equals each rank's own serial run to 1e-8 of
    the outer face force."""
    parallel, _, _ = solve(False, "penalty")
    serial, _, _ = solve(False, "penalty", comm=MPI.COMM_SELF)
    scale = abs(serial[-1][0])
    for a, b in zip(parallel, serial):
        assert a[0] == pytest.approx(b[0], abs=1e-8 * scale) and a[1] == pytest.approx(b[1], abs=1e-8 * scale)
        assert a[2] == pytest.approx(b[2], rel=1e-6, abs=1e-8 * HEIGHT)


def test_quadratic_facets_in_3d_are_refused():
    """Refused before any assembly: a 3D self-contact surface of quadratic (curved) facets."""
    mesh, _, ft = horseshoe(MPI.COMM_WORLD, LENGTH, HEIGHT, DEPTH, SPINE, ARM, (4, 1, 1))
    law = fc.make_law("penalty", K=1e5)
    u, _ = fc.unknown(mesh, 2, law)
    with pytest.raises(fc.UnsupportedCombination, match="2D only"):
        fc.self_contact_surfaces(u, ft, "inner_low", lambda: law, fem.Constant(mesh, 0.0), "gauss")
