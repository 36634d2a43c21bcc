"""slab scene and the exact Signorini-Coulomb method on the condensed system (method ``coulomb``)."""
import numpy as np
import pytest
from dolfinx import fem
from mpi4py import MPI

from fenics_contact.app.meshes import rectangle
from fenics_contact.app.scenes import block, build, slab
from fenics_contact.compat import function_space
from fenics_contact.factory import contact_surface
from fenics_contact.laws import ExactCoulomb, SnesVI
from fenics_contact.methods import make_law
from fenics_contact.obstacles import Cylinder, HalfPlane
from fenics_contact.solver import ConvergenceError, Solver


def solve(law, comm=MPI.COMM_WORLD, **kw):
    setup = build("slab", law=law, comm=comm, **kw)
    solver = Solver(setup.problem, quiet=True)
    solver.run(setup.loads)
    return setup, solver


@pytest.mark.parametrize("law", [lambda: ExactCoulomb(0.0), lambda: SnesVI(), lambda: make_law("lagrange", c=1e5)],
                         ids=["coulomb", "vi", "lagrange"])
def test_frictionless_closed_form(law):
    setup, _ = solve(law())
    f = setup.figures()
    assert f["ux_A"] == pytest.approx(slab.UX_A_FRICTIONLESS, rel=5e-3)
    assert abs(f["uy_A"]) < 1e-10 * abs(slab.UX_A_FRICTIONLESS)
    assert f["zones"] == pytest.approx({"separated": 0.0, "sliding": slab.WIDTH, "sticking": 0.0})
    assert f["max_pressure"] == pytest.approx(slab.TOP_PRESSURE, rel=1e-8)


@pytest.mark.parametrize("mu", [0.4, 1.0])
def test_equilibrium_and_coulomb_law(mu):
    """Total contact forces balance the loads; every base vertex satisfies Signorini and Coulomb."""
    setup, solver = solve(ExactCoulomb(mu))
    f = setup.figures()
    assert f["normal_equilibrium_error"] < 1e-8 and f["tangential_equilibrium_error"] < 1e-8
    assert f["normal_force"] == pytest.approx(slab.TOP_LOAD, rel=1e-8)
    prof = setup.contacts[0].friction_profile()
    p, t, g, state = prof["pressure"], prof["traction"], prof["gap"], prof["state"]
    scale = slab.TOP_PRESSURE
    assert np.all(p >= -1e-10 * scale) and np.all(g <= 1e-12)
    assert np.all(np.abs(p * g) <= 1e-12 * scale)
    assert np.all(np.abs(t) <= mu * p + 1e-10 * scale)
    # Slip at the vertices (tangential displacement, one load step from rest), gathered like the profile.
    u = setup.problem.u
    V = u.function_space
    X = V.tabulate_dof_coordinates()
    n = V.dofmap.index_map.size_local
    base = np.flatnonzero(np.isclose(X[:n, 1], 0.0))
    xs = np.concatenate(setup.problem.comm.allgather(X[base, 0]))
    ux = np.concatenate(setup.problem.comm.allgather(u.x.array[2 * base]))
    ux = ux[np.argsort(xs)]
    assert np.all(np.abs(ux[state == 2]) <= 1e-10 * np.max(np.abs(ux)))  # stick: no slip
    slip = state == 1
    assert np.all(t[slip] * ux[slip] <= 0)  # friction opposes the slip
    assert np.all(np.abs(np.abs(t[slip]) - mu * p[slip]) <= 1e-10 * scale)
    assert 0 < solver.records[0].newton_iterations <= 20


def test_zones_move_with_mu():
    """More friction: more sticking, less sliding, a wider lift-off at the free corner, a smaller u_x."""
    results = [solve(ExactCoulomb(mu))[0].figures() for mu in (0.4, 0.8, 1.3)]
    for a, b in zip(results, results[1:]):
        assert b["zones"]["sticking"] > a["zones"]["sticking"]
        assert b["zones"]["sliding"] < a["zones"]["sliding"]
        assert b["zones"]["separated"] >= a["zones"]["separated"]
        assert slab.UX_A_FRICTIONLESS < a["ux_A"] < b["ux_A"] < 0
    for r in results:
        assert r["zone_pattern"] == ["separated", "sliding", "sticking"]


def test_refinement_convergence():
    """mu = 1: u_x(A) converges (differences shrink by > 2 per halving) and the zone boundaries move by less
    than half a coarse cell between the last two meshes."""
    f = [solve(ExactCoulomb(1.0), refinement=r)[0].figures() for r in (0, 1, 2)]
    d1, d2 = abs(f[1]["ux_A"] - f[0]["ux_A"]), abs(f[2]["ux_A"] - f[1]["ux_A"])
    assert d2 < d1 / 2
    h0 = slab.WIDTH / slab.NX
    assert len(f[1]["zone_boundaries"]) == len(f[2]["zone_boundaries"]) == 2
    assert np.allclose(f[1]["zone_boundaries"], f[2]["zone_boundaries"], atol=h0 / 2)


def test_proportional_loading_is_step_independent():
    """Coulomb friction with a homogeneous law: proportional loading from a touching rest state gives the same
    solution in one step or in three (each step's slip is measured from the previous converged step)."""
    one = solve(ExactCoulomb(1.0))[0]
    three = solve(ExactCoulomb(1.0), steps=3)[0]
    # two meshes built one after the other may be partitioned differently: compare by position, not local index
    assert np.allclose(_by_position(three.problem.u), _by_position(one.problem.u), rtol=0,
                       atol=1e-10 * abs(slab.UX_A_FRICTIONLESS))


def _by_position(u):
    """All owned values of the vector function ``u``, gathered on every rank and sorted by node position."""
    V = u.function_space
    n, bs = V.dofmap.index_map.size_local, V.dofmap.index_map_bs
    x = V.tabulate_dof_coordinates()[:n]
    x, vals = (np.concatenate(a) for a in zip(*V.mesh.comm.allgather((x, u.x.array[: n * bs].reshape(n, bs)))))
    # rounded: a node's coordinates may differ in the last bit between partitions, which would reorder columns
    return vals[np.lexsort(np.round(x, 9).T[::-1])]


def test_parallel_equals_serial():
    figs = [solve(ExactCoulomb(1.0), comm)[0].figures() for comm in (MPI.COMM_WORLD, MPI.COMM_SELF)]
    for k in ("ux_A", "uy_A", "normal_force", "tangential_force", "symmetry_reaction"):
        assert figs[0][k] == pytest.approx(figs[1][k], rel=1e-8, abs=1e-12), k
    assert figs[0]["zones"] == pytest.approx(figs[1]["zones"], abs=1e-12)


def test_block_with_prescribed_displacement():
    """The block (top moved down, Dirichlet data scaled by the load) with mu = 0 gives the exact pressure."""
    setup = build("block", law=ExactCoulomb(0.0))
    Solver(setup.problem, quiet=True).run(setup.loads)
    assert setup.contacts[0].friction_profile()["pressure"] == pytest.approx(block.EXACT_PRESSURE, rel=1e-10)


def test_failure_names_the_step():
    setup = build("slab", law=ExactCoulomb(1.0))
    setup.problem.step_solver.max_it = 2
    with pytest.raises(ConvergenceError, match=r"load step \d+ .*coulomb.*no convergence in 2 iterations"):
        Solver(setup.problem, quiet=True, max_cutbacks=1).run(setup.loads)
    assert np.all(setup.problem.u.x.array == 0.0)  # rolled back to the last converged state (rest)


def test_bad_input():
    for mu in (-0.1, float("nan"), float("inf")):
        with pytest.raises(ValueError, match="friction coefficient mu"):
            make_law("coulomb", mu=mu)
    mesh, _, tags = rectangle(MPI.COMM_WORLD, 1.0, 1.0, 2, 2)
    u = fem.Function(function_space(mesh, "Lagrange", 1, (2,)))
    load = fem.Constant(mesh, 0.0)
    with pytest.raises(ValueError, match="coulomb, curved obstacle.*axis-aligned half-plane"):
        contact_surface(u, tags, "bottom", Cylinder([0.5, -1.0], 1.0), ExactCoulomb(0.3),
                        load)
    with pytest.raises(ValueError, match="nodal"):
        contact_surface(u, tags, "bottom", HalfPlane([0.0, 0.0], [0.0, 1.0]), ExactCoulomb(0.3), load,
                        quadrature="gauss")
    with pytest.raises(ValueError, match="linear"):  # refused by the capability matrix, before any assembly
        setup = build("block", law=ExactCoulomb(0.3), model="neohookean")
        Solver(setup.problem, quiet=True).run(setup.loads)



def test_frictionless_hertz_equals_vi():
    """An independent exact method: on the Hertz scene (curved body, triangles, prescribed approach) mu = 0
    gives the figures of the SNES VI reference."""
    figs = []
    for law in (ExactCoulomb(0.0), SnesVI()):
        setup = build("hertz", law=law)
        Solver(setup.problem, quiet=True).run(setup.loads)
        figs.append(setup.figures())
    for k in ("p0", "a", "total_force", "reaction_top"):
        assert figs[0][k] == pytest.approx(figs[1][k], rel=1e-9), k


@pytest.mark.parametrize("method", ["cross", "auglag", "compliance"])
def test_regularized_friction_methods_converge_over_mu(method):
    """Every regularized friction method the demo offers converges on the resting slab at every mu of the demo's
    sweep with the demo's defaults (K_DEMO, OMEGA_T, lam0 = F_hat = LAM0, SOLVER_OPTIONS), on a small mesh, and
    meets the frictionless closed form at mu = 0 and the equilibrium of the loads at every mu."""
    from fenics_contact.friction import Friction

    normal = {"cross": lambda: make_law("cross", K_hat=slab.K_DEMO, F_hat=slab.LAM0),
              "auglag": lambda: make_law("auglag", K=slab.K_DEMO, lam0=slab.LAM0),
              "compliance": lambda: make_law("compliance", c_n=slab.K_DEMO, m_n=1.0)}[method]
    augment = 0 if method == "compliance" else 10
    ux = []
    for mu in (0.0, 0.4, 0.8, 1.0, 1.3):
        law = Friction(normal(), mu=mu, omega_t=slab.OMEGA_T) if mu else normal()
        setup = build("slab", law=law, nx=8, ny=4)
        solver = Solver(setup.problem, quiet=True, options=slab.SOLVER_OPTIONS, augment_max=augment,
                        augment_tol=1e-9)
        solver.run(setup.loads)
        assert all(r.converged for r in solver.records), mu
        f = setup.figures()
        assert f["normal_equilibrium_error"] < 1e-8 and f["tangential_equilibrium_error"] < 1e-8, mu
        ux.append(f["ux_A"])
    # mu = 0: the uniform state (regularization: penetration K^-1 p, no effect on u_x); friction holds the slab back
    assert ux[0] == pytest.approx(slab.UX_A_FRICTIONLESS, rel=1e-6)
    assert all(a < b < 0 for a, b in zip(ux, ux[1:]))


def test_parameters_scale_the_closed_form():
    """The slab's constants are build arguments: doubled E halves u_x(A); doubled side pressure moves it as the
    frictionless closed form says."""
    f = {}
    for key, kw in {"ref": {}, "E": {"E": 2 * slab.E}, "side": {"side_pressure": 2 * slab.SIDE_PRESSURE}}.items():
        setup, _ = solve(ExactCoulomb(0.0), nx=8, ny=4, **kw)
        f[key] = setup.figures()
        assert f[key]["ux_A"] == pytest.approx(slab.ux_a_frictionless(**kw), rel=1e-8), key
    assert f["E"]["ux_A"] == pytest.approx(f["ref"]["ux_A"] / 2, rel=1e-8)
    with pytest.raises(ValueError, match="nu must be in"):
        build("slab", law=ExactCoulomb(0.0), nu=0.5)
    with pytest.raises(ValueError, match="width must be"):
        build("slab", law=ExactCoulomb(0.0), width=-1.0)
