"""Friction (formulation 1.5): return mapping, consistent tangent, dissipation, bad input, compliance3d."""
import dolfinx.fem.petsc as fem_petsc
import numpy as np
import pytest
import ufl
from dolfinx import fem, mesh
from mpi4py import MPI

from fenics_contact.app import cli
from fenics_contact.app.meshes import rectangle
from fenics_contact.app.scenes import build
from fenics_contact.compat import function_space
from fenics_contact.factory import contact_surface
from fenics_contact.friction import OPEN, SLIP, STICK, Friction
from fenics_contact.laws import CrossConstraints, NormalCompliance, Penalty, SnesVI, ufl_ops
from fenics_contact.materials import LinearElastic
from fenics_contact.obstacles import HalfPlane
from fenics_contact.problem import ContactProblem, Dirichlet
from fenics_contact.solver import Solver

LAWS = [Friction(NormalCompliance(5e5, 1.5), mu=0.3, omega_t=1e5),
        Friction(NormalCompliance(5e5, 2.0), c_t=1e5, m_t=1.2, omega_t=1e5),
        Friction(Penalty(1e5), mu=0.5, omega_t=2e4),
        Friction(CrossConstraints(1e5, 50.0), mu=0.8, omega_t=1e5)]
IDS = ["compliance-coulomb", "compliance-mt", "penalty-coulomb", "cross-coulomb"]


def _sweep(law, d):
    """Trial tractions across the friction bound: q_old fixed, slip increment ds = lam e, lam around the kink."""
    c = law.values()
    g = 2e-3
    n = np.eye(d)[-1]
    q_old = np.zeros(d)
    q_old[0] = 0.2 * law.bound(g, c)
    e = np.array([1.0, 0.0]) if d == 2 else np.array([0.6, 0.8, 0.0])  # unit slip direction in the plane
    # |q_old - omega_t lam e| = b has one positive root lam*
    b, w = law.bound(g, c), c["omega_t"]
    qe = q_old @ e
    lam_star = (qe + np.sqrt(qe**2 - q_old @ q_old + b**2)) / w
    lam = lam_star * (1 + np.array([-1e-9, 0.0, 1e-9]))
    lam = np.concatenate([np.linspace(0, 3 * lam_star, 300), lam])  # no sample on the kink
    ds = e[:, None] * lam  # component-first, as the NumPy ops want
    args = (np.full(lam.shape, g), q_old[:, None] * np.ones_like(lam), ds, n[:, None] * np.ones_like(lam), c)
    return law, lam, lam_star, b, args


@pytest.mark.parametrize("d", [2, 3])
@pytest.mark.parametrize("law", LAWS, ids=IDS)
def test_return_mapping_continuous_and_admissible(law, d):
    law, lam, lam_star, b, args = _sweep(law, d)
    q = law.traction(*args)
    q_tr = law.trial(*args[1:])
    state = law.slip_state(*args)
    norm = np.linalg.norm(q, axis=0)
    assert np.all(norm <= b * (1 + 1e-12))  # admissible
    stick = lam < lam_star * (1 - 1e-12)
    assert np.array_equal(state[:-3] == STICK, stick[:-3]) and np.all(state[:-3][~stick[:-3]] == SLIP)
    assert np.allclose(q[:, stick], q_tr[:, stick], rtol=0, atol=1e-12 * b)  # stick: the trial traction
    assert np.allclose(norm[~stick], b, rtol=1e-12)  # slip: on the bound, along the trial direction
    assert np.all(np.sum(q[:, ~stick] * q_tr[:, ~stick], axis=0) > 0)
    # continuity across the kink: a relative step 1e-9 in the slip moves q by O(1e-9 b), not O(b)
    left, mid, right = q[:, -3], q[:, -2], q[:, -1]
    assert np.linalg.norm(left - mid) < 1e-7 * b and np.linalg.norm(right - mid) < 1e-7 * b
    # and uniformly: |dq| <= omega_t |d lam| over the sweep (Lipschitz with the stick stiffness)
    dq = np.linalg.norm(np.diff(q[:, :-3], axis=1), axis=0)
    assert np.all(dq <= args[-1]["omega_t"] * np.diff(lam[:-3]) * (1 + 1e-9))
    # an open gap carries no friction and is reported open, unless the normal law has a pressure there
    # (cross-constraints with F_hat > 0: a regularized contact, with friction capacity mu F)
    g_open = -np.abs(args[0])
    if law.normal.name == "cross":
        assert np.all(law.bound(g_open, args[-1]) > 0) and np.all(law.slip_state(g_open, *args[1:]) != OPEN)
    else:
        assert np.all(law.traction(g_open, *args[1:]) == 0.0) and np.all(law.slip_state(g_open, *args[1:]) == OPEN)


@pytest.mark.parametrize("law", LAWS[:3], ids=IDS[:3])
def test_return_mapping_ufl_equals_numpy(law):
    """The UFL return mapping (compiled) gives the NumPy numbers on both sides of the kink, in 3D."""
    law, lam, lam_star, b, args = _sweep(law, 3)
    m = mesh.create_unit_square(MPI.COMM_SELF, 1, 1)
    g, q_old, ds, n = (fem.Constant(m, np.zeros(s)) for s in ((), (3,), (3,), (3,)))
    c = {k: fem.Constant(m, float(v)) for k, v in law.parameters().items()}
    expr = law.traction(g, q_old, ds, n, c, ufl_ops())
    forms = [fem.form(expr[i] * ufl.dx) for i in range(3)] + [
        fem.form(law.slip_state(g, q_old, ds, n, c, ufl_ops()) * ufl.dx)]
    q = law.traction(*args)
    state = law.slip_state(*args)
    for k in list(range(0, 300, 20)) + [300, 301, 302]:
        g.value, q_old.value, ds.value, n.value = args[0][k], args[1][:, k], args[2][:, k], args[3][:, k]
        values = np.array([fem.assemble_scalar(f) for f in forms])
        assert np.allclose(values[:3], q[:, k], rtol=1e-13, atol=1e-13 * b) and values[3] == state[k]


def _tiny_problem(d, law, quadrature="nodal"):
    """A small body pressed into the rigid plane with a prescribed u (no solve): stick and slip points."""
    comm = MPI.COMM_SELF
    if d == 2:
        msh, _, tags = rectangle(comm, 1.0, 0.5, 6, 2)
        base, normal = "bottom", [0.0, 1.0]
    else:
        msh = mesh.create_box(comm, [np.zeros(3), np.array([1.0, 1.0, 0.5])], [3, 3, 1], mesh.CellType.tetrahedron)
        facets = mesh.locate_entities_boundary(msh, 2, lambda x: np.isclose(x[2], 0.0))
        tags = mesh.meshtags(msh, 2, np.sort(facets).astype(np.int32), np.ones(len(facets), dtype=np.int32))
        base, normal = 1, [0.0, 0.0, 1.0]
    V = function_space(msh, "Lagrange", 1, (d,))
    u = fem.Function(V)
    load = fem.Constant(msh, 0.0)
    c = contact_surface(u, tags, base, HalfPlane(np.zeros(d), normal), law, load, quadrature)
    problem = ContactProblem(u, LinearElastic(1000.0, 0.3), load, [], [c])
    # penetration growing with x, tangential shift growing with x: stick at small x, slip at large x,
    # rotated in 3D so that the slip direction is not a coordinate axis
    def shift(x):
        r = x[0] + 0.37 * x[1] if d == 3 else x[0]
        out = np.zeros((d, x.shape[1]))
        out[0] = 0.002 * r**2 + 1e-4
        if d == 3:
            out[1] = -0.001 * r
        out[d - 1] = -0.004 - 0.003 * x[0]
        return out

    u.interpolate(shift)
    return problem, c


@pytest.mark.parametrize("d,quadrature", [(2, "nodal"), (3, "nodal"), (2, "gauss")])
def test_tangent_matches_finite_differences(d, quadrature):
    """J(u) du against the central difference of the residual, in a stick state, a slip state and a mixed one."""
    law = Friction(NormalCompliance(5e5, 1.5), mu=0.3, omega_t=1e5)
    problem, c = _tiny_problem(d, law, quadrature)
    u = problem.u
    rng = np.random.default_rng(1)
    du = rng.standard_normal(u.x.array.shape) * 1e-4
    u0 = u.x.array.copy()
    state = fem.Function(c.S)

    def residual(values):
        u.x.array[:] = values
        return fem_petsc.assemble_vector(problem.L).array.copy()

    for mu, expected in ((50.0, {STICK}), (0.3, {STICK, SLIP}), (1e-3, {SLIP})):
        c.constants["mu"].value = mu
        u.x.array[:] = u0
        c.projector.project(c.projector.compile(c.slip_state_expr), state)
        if quadrature == "nodal":  # (Gauss: the DG1 dofs are not the Gauss-point values)
            found = set(np.rint(state.x.array[c.projector.surface_dofs]).astype(int).tolist())
            assert found == expected, (mu, found)
        A = fem_petsc.assemble_matrix(problem.a)
        A.assemble()
        x, y = A.createVecs()
        x.array[:] = du
        A.mult(x, y)
        h = 1e-3
        fd = (residual(u0 + h * du) - residual(u0 - h * du)) / (2 * h)
        u.x.array[:] = u0
        err = np.linalg.norm(fd - y.array) / np.linalg.norm(y.array)
        assert err < 1e-6, (mu, err)
        A.destroy()


def test_history_advances_only_on_commit_and_rolls_back():
    """The solver's snapshot (state) and rollback (restore) carry the friction history; commit advances it."""
    problem, c = _tiny_problem(2, Friction(NormalCompliance(5e5, 1.5), mu=0.3, omega_t=1e5))
    before = c.state()
    assert all(np.all(q.x.array == 0.0) for q in c.q_old)
    c.commit()
    assert any(np.any(q.x.array != 0.0) for q in c.q_old) and c.dissipated > 0
    c.restore(before)
    assert all(np.array_equal(f.x.array, a) for f, a in zip(c.history, before["history"])) and c.dissipated == 0.0


def test_dissipation_over_a_closed_cycle():
    """Press, drag right, drag back, lift off (2D, Coulomb mu = 0.5 on normal compliance). The body ends
    stress-free and open, so the net work of the loading platen over the cycle is the dissipated energy:
    it is positive, every step dissipates >= 0, and the two agree to the time-discretization error."""
    comm = MPI.COMM_SELF
    msh, _, tags = rectangle(comm, 1.0, 0.5, 8, 4)
    V = function_space(msh, "Lagrange", 1, (2,))
    u = fem.Function(V)
    load = fem.Constant(msh, 0.0)
    top = tags.find("top")
    dofs = [fem.locate_dofs_topological(V.sub(i), 1, top) for i in (0, 1)]
    ts = [0, 1, 2, 3, 4]
    bcs = [Dirichlet(V.sub(0), dofs[0], 1.0, (ts, [0, 0, 0.02, 0.0, 0.0])),
           Dirichlet(V.sub(1), dofs[1], 1.0, (ts, [0, -0.01, -0.01, -0.01, 0.001]))]
    c = contact_surface(u, tags, "bottom", HalfPlane([0, 0], [0, 1]),
                        Friction(NormalCompliance(1e5, 1.0), mu=0.5, omega_t=1e4), load)
    problem = ContactProblem(u, LinearElastic(1000, 0.3), load, bcs, [c])
    solver = Solver(problem, quiet=True)
    work, R_prev, u_prev, slid = 0.0, np.zeros(2), np.zeros(2), False
    for t in np.linspace(0, 4, 41)[1:]:
        solver.run([t])
        R = np.array([problem.reaction(d) for d in dofs])  # platen on the body
        u_top = np.array([b.at(t) for b in bcs])
        work += 0.5 * (R + R_prev) @ (u_top - u_prev)  # trapezoid rule
        R_prev, u_prev = R, u_top
        slid |= c.state_areas()["slip"] > 0.5
    D = c.dissipated
    steps = np.diff([0.0] + [s["dissipated"] for s in c.log])
    assert slid and D > 0 and np.all(steps >= -1e-15 * D)
    assert np.all(c.friction_profile()["state"] == OPEN) and np.allclose(c.tangential_force(), 0, atol=1e-12)
    assert work > 0 and abs(work - D) < 0.03 * D, (work, D)


@pytest.mark.parametrize("make,match", [
    (lambda: Friction(Penalty(1e5), mu=-0.1), "mu must be"),
    (lambda: Friction(Penalty(1e5), mu=0.3, omega_t=0.0), "omega_t must be"),
    (lambda: Friction(Penalty(1e5), c_t=-1.0), "c_t must be"),
    (lambda: Friction(Penalty(1e5), c_t=1.0, m_t=0.5), "m_t must be"),
    (lambda: Friction(Penalty(1e5), mu=0.3, c_t=1.0), "exactly one of mu"),
    (lambda: Friction(SnesVI(), mu=0.3), "normal law"),
    (lambda: NormalCompliance(0.0, 1.5), "c_n must be"),
    (lambda: NormalCompliance(1e5, 0.9), "m_n must be"),
    (lambda: cli.law_from_args(cli.parse(cli.parser("x", 1e5), ["--method", "compliance", "--mu", "-0.2"])),
     "--mu must be"),  # the command line checks the range before any work
    (lambda: cli.law_from_args(cli.parse(cli.parser("x", 1e5), ["--method", "compliance", "--m-n", "0.5"])),
     "--m-n must be"),
    (lambda: cli.law_from_args(cli.parse(cli.parser("x", 1e5), ["--method", "compliance", "--c-n", "0"])),
     "--c-n must be"),
    (lambda: cli.law_from_args(cli.parse(cli.parser("x", 1e5), ["--method", "vi", "--mu", "0.3"])), "no friction"),
])
def test_bad_friction_input(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def _compliance3d(comm, mu=0.3, drag=0.03):
    setup = build("compliance3d", law=Friction(NormalCompliance(5e5, 1.5), mu=mu, omega_t=1e5), nx=8, ny=4, nz=2,
                  drag=drag, drag_steps=6, comm=comm)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    return setup, solver


def _rate(r):
    """How many times the digits gained so far grow in the last iteration above the round-off floor
    (1e-10 of the first residual; below it the assembly's round-off is what is left): 2 is quadratic."""
    r = np.asarray(r)
    r = r[r > 1e-10 * r[0]]
    return np.log(r[-1] / r[0]) / np.log(r[-2] / r[0])


def test_compliance3d_sticks_then_slides_in_equilibrium():
    setup, solver = _compliance3d(MPI.COMM_WORLD)
    f = setup.figures()
    log = f["friction_steps"]
    assert f["equilibrium_x"] < 1e-8 and f["equilibrium_z"] < 1e-8
    assert f["coulomb_limit_holds"] and f["open_fraction"] == 0.0
    # the press leaves a sticking centre; the drag first slides part of the face, then all of it, when the
    # tangential force reaches the Coulomb limit mu N (to the slip direction's last turn)
    first_drag = next(s for s in log if s["load"] > 1)
    assert 0.1 < first_drag["stick"] < 0.9 and 0.1 < first_drag["slip"] < 0.9
    assert f["slip_fraction"] == pytest.approx(1.0, abs=1e-12)
    assert 0.999 < f["tangential_over_mu_normal"] <= 1.0 + 1e-12
    assert all(abs(s["tangential_force"]) <= s["capacity"] * (1 + 1e-12) for s in log)
    # Newton: quadratic at the end of a sliding step (consistent tangent of the slip branch)
    r = solver.records[-1].residuals[-1]
    assert r[-1] < 1e-10 * r[0] and _rate(r) > 1.8, r


def test_compliance3d_quadratic_newton_in_stick():
    """mu = 5: the whole face sticks during the press and the drag; every step converges quadratically."""
    setup, solver = _compliance3d(MPI.COMM_WORLD, mu=5.0, drag=0.006)
    assert all(s["stick"] == pytest.approx(1.0, abs=1e-12) for s in setup.figures()["friction_steps"])
    for rec in solver.records:
        r = rec.residuals[-1]
        assert r[-1] < 1e-10 * r[0] and len(r) <= 8 and _rate(r) > 1.8, r


def test_compliance3d_parallel_equals_serial():
    """Under mpirun -n 2: the 2-rank figures equal the serial ones (each rank also solves alone)."""
    parallel = _compliance3d(MPI.COMM_WORLD)[0].figures()
    serial = _compliance3d(MPI.COMM_SELF)[0].figures()
    for k, v in serial.items():
        if isinstance(v, float) and not k.startswith("equilibrium"):
            assert abs(parallel[k] - v) <= 1e-8 * max(abs(v), 1e-3 * serial["normal_force"]), (k, parallel[k], v)


# --- slab (Renaud & Feng): penalty-type Coulomb friction against the exact condensed method -----------------
SLAB_OPTIONS = {"snes_linesearch_type": "bt", "snes_max_it": 200,  # l2 cycles once omega_t >> E/h
                "snes_rtol": 1e-10}  # c_n = 1e6: the round-off floor of the residual is ~3e-11 of its start


_EXACT = {}


def _slab_exact(mu):
    """Figures of the exact condensed method on COMM_WORLD (solved once per mu in this module)."""
    from fenics_contact.laws import ExactCoulomb

    if mu not in _EXACT:
        _EXACT[mu] = _slab(ExactCoulomb(mu))[0]
    return _EXACT[mu]


def _slab(law, comm=MPI.COMM_WORLD):
    from fenics_contact.app.scenes import slab

    setup = build("slab", law=law, comm=comm)
    solver = Solver(setup.problem, quiet=True, options=SLAB_OPTIONS)
    solver.run(setup.loads)
    return setup.figures(), slab, solver


@pytest.mark.parametrize("mu", [0.4, 0.8, 1.0, 1.3])
def test_slab_penalty_coulomb_agrees_with_exact(mu):
    """c_n = omega_t = 1e5 (10 E/h): u_x(A) within 1 % of the exact condensed method, the same zones
    (separated, sliding, sticking from the free corner) with boundaries within one element, equilibrium."""
    exact = _slab_exact(mu)
    f, slab, _ = _slab(Friction(NormalCompliance(1e5, 1.0), mu=mu, omega_t=1e5))
    assert abs(f["ux_A"] - exact["ux_A"]) < 0.01 * abs(exact["ux_A"])
    assert f["zone_pattern"] == exact["zone_pattern"] == ["separated", "sliding", "sticking"]
    h = slab.WIDTH / slab.NX
    assert all(abs(a - b) <= h * (1 + 1e-9) for a, b in zip(f["zone_boundaries"], exact["zone_boundaries"]))
    assert f["normal_equilibrium_error"] < 1e-8 and f["tangential_equilibrium_error"] < 1e-8


def test_slab_frictionless_closed_form_and_fully_sliding():
    """mu = 0 with the perturbed-Lagrangian path: u_x(A) is the closed form (the uniform state does not
    depend on the penalty's penetration) and every base vertex slides."""
    f, slab, _ = _slab(Friction(NormalCompliance(1e5, 1.0), mu=0.0, omega_t=1e5))
    assert f["ux_A"] == pytest.approx(slab.UX_A_FRICTIONLESS, rel=5e-3)
    assert f["zones"]["sliding"] == pytest.approx(slab.WIDTH) and f["zones"]["sticking"] == 0.0


def test_slab_penalty_coulomb_tends_to_exact():
    """mu = 1: the difference to the exact u_x(A) falls like 1 / (c_n = omega_t)."""
    exact = _slab_exact(1.0)["ux_A"]
    d = [abs(_slab(Friction(NormalCompliance(k, 1.0), mu=1.0, omega_t=k))[0]["ux_A"] - exact) / abs(exact)
         for k in (1e4, 1e5, 1e6)]
    assert d[0] > 5 * d[1] > 25 * d[2] and d[2] < 1e-3, d


def test_slab_parallel_equals_serial():
    law = lambda: Friction(NormalCompliance(1e5, 1.0), mu=1.0, omega_t=1e5)  # noqa: E731
    figs = [_slab(law(), comm)[0] for comm in (MPI.COMM_WORLD, MPI.COMM_SELF)]
    for k in ("ux_A", "uy_A", "normal_force", "tangential_force", "symmetry_reaction"):
        assert figs[0][k] == pytest.approx(figs[1][k], rel=1e-8, abs=1e-12), k
    assert figs[0]["zones"] == pytest.approx(figs[1]["zones"], abs=1e-12)


@pytest.mark.parametrize("mu", [0.4, 1.3, 1.5])
def test_slab_augmented_friction_equals_exact(mu):
    """Uzawa on both multipliers (normal: augmented Lagrangian K = 1e5, lam0 = 1 so that the resting slab has a
    regular first Jacobian; tangential: the trial restarts from the current traction, omega_t = E/h = 1e4)
    removes both penalty errors: the exact condensed method's u_x(A) to 1e-7 and its zones exactly, with the
    default line search, also at mu = 1.5 (where Renaud & Feng's FEM diverged)."""
    from fenics_contact.laws import AugmentedLagrangian

    exact = _slab_exact(mu)
    setup = build("slab", law=Friction(AugmentedLagrangian(1e5, lam0=1.0), mu=mu, omega_t=1e4))
    solver = Solver(setup.problem, quiet=True, augment_max=60, augment_tol=1e-9)
    solver.run(setup.loads)
    f = setup.figures()
    assert solver.records[-1].augmentation_converged
    assert abs(f["ux_A"] - exact["ux_A"]) < 1e-7 * abs(exact["ux_A"])
    assert f["zones"] == pytest.approx(exact["zones"], abs=1e-12)
    assert f["normal_equilibrium_error"] < 1e-8 and f["tangential_equilibrium_error"] < 1e-8
