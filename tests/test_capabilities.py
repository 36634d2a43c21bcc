"""The capability matrix (:mod:`fenics_contact.capabilities`) as a grid: supported cells solve a tiny problem to
its closed form, refused cells raise the documented one-line error before any assembly.

Problems (a few dozen cells each):

- rigid: a unit block (2 x 2 squares of triangles, 2 x 2 x 2 cubes of tetrahedra) pressed on the rigid plane
  by a prescribed top displacement ``d``, rollers on the symmetry sides. Frictionless: the uniform uniaxial
  state (plane strain in 2D), nominal pressure ``p(c)`` at the stretch ``c = 1 - (d - g)/H`` (``g = p/K``
  the penalty penetration of a regularizing law, 0 for an exact method), linear or neo-Hookean. With
  friction the top is also moved sideways by more than the stick limit: every base point slides, so the
  tangential contact force is ``mu`` times the normal one.
- two-body: two stacked unit blocks with matching meshes, uniform pressure ``P`` on the top: the contact
  pressure is ``P`` at every slave point (nominal, per reference area; a dead load), whatever the law.
- self: the same blocks, their two facing sides one surface against itself: the same pressure ``P``.

Covering set (why it covers the matrix). The axes act on three independent parts of the code:

1. the *surface structure* -- kind, quadrature, passes, dim, degree -- picks the surface class, its
   measure, state space, mirror and coupling. Every supported structural cell is run for one method of
   each enforcement family: ``penalty`` (the laws: penalty, cross, auglag, compliance share
   ``ContactSurface``/``TwoBodySurface``, only ``F(g)`` differs), ``lagrange`` (multipliers; also
   penalty_multiplier), ``nitsche``, ``vi``, ``coulomb``;
2. the *law* -- every method runs once per supported kind (2D, P1, its default quadrature), so every
   ``F(g)`` and augmentation is exercised;
3. the *orthogonal options* -- model, solver, friction, geometry -- enter the bulk form, the PETSc options, the
   tangential law and the weight of every integral: each supported value is run with every family and kind at
   one structural cell, and friction with every law and structural variant of the rigid kind. Axisymmetric:
   the blocks are solid cylinders (``x = 0`` the axis, its roller ``u_r = 0``), the uniform states are the 3D
   uniaxial ones.

``FC_GRID=full`` runs every supported cell of the full product instead (506 cells, minutes; run by hand).

Refused cells: all cells of the full product are checked (no finite elements), and a few refusals are
raised through the entry points on a real mesh before any form is built.
"""
from __future__ import annotations

import itertools
import os

import numpy as np
import pytest
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI
from scipy.optimize import brentq

import fenics_contact as fc
from fenics_contact import capabilities as cap
from fenics_contact.app.meshes import rectangle, stacked_blocks
from fenics_contact.app.meshes.rectangle import tag_boundary
from fenics_contact.app.scenes.patch import uniform_stretches
from fenics_contact.solver import linear_solver_options

E, NU, H, MU = 1000.0, 0.3, 1.0, 0.2
K = 1e6  # penalty-type laws: the regularized closed form includes the penetration p / K
# rigid: top displacement (neo-Hookean: finite strain); two-body: pressure on the top
D = {"linear": 0.01, "neohookean": 0.15, "neohookean-mixed": 0.15, "linear-mixed": 0.01}
P = {"linear": 10.0, "neohookean": 100.0, "neohookean-mixed": 100.0, "linear-mixed": 10.0}
# friction: sideways top motion, beyond the stick limit mu p / omega_t, the elastic shear and the lateral expansion
SLIDE = {"linear": 0.05, "neohookean": 0.3, "neohookean-mixed": 0.3, "linear-mixed": 0.05}
EXACT = ("auglag", "vi", "lagrange", "nitsche", "coulomb")
MULTIPLIERS = ("lagrange", "penalty_multiplier")  # the pressure an unknown
# laws of the gap, friction on top (lagrange's friction is its own exact law: the multipliers' family)
LAWS = tuple(m.name for m in fc.methods.methods() if m.friction == "law" and m.name not in MULTIPLIERS)


def law_for(method: str, friction: bool):
    law = {"penalty": lambda: fc.make_law("penalty", K=K), "cross": lambda: fc.make_law("cross", K_hat=K),
           "auglag": lambda: fc.make_law("auglag", K=K), "compliance": lambda: fc.make_law("compliance", c_n=K),
           "vi": lambda: fc.make_law("vi"), "coulomb": lambda: fc.make_law("coulomb", mu=MU if friction else 0.0),
           "lagrange": lambda: fc.make_law("lagrange", c=K), "penalty_multiplier": lambda: fc.make_law(
               "penalty_multiplier", K=K), "nitsche": lambda: fc.make_law("nitsche", gamma0=10.0)}[method]()
    if friction and method != "coulomb":
        return fc.Friction(law, mu=MU, omega_t=K)
    return law


def uniaxial_pressure(stretch: float, model: str, dim: int) -> float:
    """Nominal pressure of the uniform uniaxial state at axial stretch ``stretch`` (lateral faces free;
    plane strain in 2D)."""
    if model in ("linear", "linear-mixed"):  # linear-mixed: its eliminated energy is the linear one
        return (E if dim == 3 else E / (1 - NU**2)) * (1.0 - stretch)
    if model == "neohookean-mixed":  # free sides: P_lateral(a, stretch) = 0
        m = fc.MixedNeoHookean(E, NU)
        a = brentq(lambda a: m.uniaxial(a, stretch, dim)[0], 1.0, 2.0 / stretch)
        return -m.uniaxial(a, stretch, dim)[1]
    return brentq(lambda p: uniform_stretches(p, model, dim)[1] - stretch, 1e-9, 0.9 * E)


def rigid_reference(method: str, model: str, dim: int) -> float:
    d = D[model]
    if method in EXACT:
        return uniaxial_pressure(1.0 - d / H, model, dim)
    return brentq(lambda p: p - uniaxial_pressure(1.0 - (d - p / K) / H, model, dim), 1e-9, 0.9 * E)


def rigid_mesh(dim: int):
    if dim == 2:
        return rectangle(MPI.COMM_WORLD, 1.0, H, 2, 2)[::2]
    mesh = dmesh.create_box(MPI.COMM_WORLD, [np.zeros(3), np.array([1.0, 1.0, H])], [2, 2, 2],
                            dmesh.CellType.tetrahedron)
    sides = (("bottom", lambda x: np.isclose(x[2], 0.0)), ("top", lambda x: np.isclose(x[2], H)),
             ("left", lambda x: np.isclose(x[0], 0.0)), ("front", lambda x: np.isclose(x[1], 0.0)),
             ("back", lambda x: np.isclose(x[1], 1.0)))
    return mesh, tag_boundary(mesh, sides)


def solve(problem, method: str, solver: str, augment: int = 0, steps: int = 1):
    s = fc.Solver(problem, options=linear_solver_options(solver), quiet=True, augment_max=augment, augment_tol=1e-10)
    s.run([(i + 1) / steps for i in range(steps)])
    assert all(r.converged for r in s.records)


def run_rigid(method, quadrature, dim, degree, model, solver, friction, geometry="cartesian") -> tuple[float, float]:
    """(measured, reference): the mean contact pressure, or with friction the ratio tangential / normal force."""
    law = law_for(method, friction)
    mesh, ft = rigid_mesh(dim)
    u, V = fc.unknown(mesh, degree, law, model=model)
    load = fem.Constant(mesh, 0.0)
    material = fc.MODELS[model](E, NU, "axisymmetric" if geometry == "axisymmetric" else "strain")
    v = dim - 1
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "top", v, -D[model])]
    if friction:
        dirichlet += [fc.Dirichlet.on_facets(V, ft, "top", 0, SLIDE[model])]
        if dim == 3:  # u_y = 0 everywhere: every point slides along x (a lateral slip component, which a
            # neo-Hookean tetrahedral mesh has, makes |sum q| < sum |q| = mu N)
            Vy = V.sub(1)
            mesh.topology.create_connectivity(dim, dim)
            dirichlet += [fc.Dirichlet(Vy, fem.locate_dofs_topological(
                Vy, dim, np.arange(mesh.topology.index_map(dim).size_local, dtype=np.int32)))]
    else:
        dirichlet += [fc.Dirichlet.on_facets(V, ft, "left", 0)]
        dirichlet += [fc.Dirichlet.on_facets(V, ft, "front", 1)] if dim == 3 else []
    plane = fc.HalfPlane(np.zeros(dim), np.eye(dim)[v])
    contact = fc.contact_surface(u, ft, "bottom", plane, law, load, quadrature, material=material)
    problem = fc.ContactProblem(u, material, load, dirichlet, [contact], step_solver=fc.step_solver_for([contact]))
    solve(problem, method, solver, augment=30 if method == "auglag" else 0,
          steps=4 if friction and model == "neohookean" else 1)
    if friction:
        if method == "coulomb":
            f = contact.contact_force()
            return abs(f[0]) / abs(f[v]), MU
        assert isinstance(contact, fc.FrictionalContact)
        return float(np.linalg.norm(contact.tangential_force())) / abs(contact.total_force()[v]), MU
    if method == "coulomb":
        prof = contact.friction_profile()
        return float(np.mean(prof["pressure"])), rigid_reference(method, model, dim)
    return contact.mean_pressure(), rigid_reference(method, model, 3 if geometry == "axisymmetric" else dim)


def run_two_body(method, quadrature, passes, dim, degree, model, solver, friction=False,
                 geometry="cartesian", kind="two-body") -> tuple[float, float]:
    """(largest |p - P| / P over the slave points of every surface, 0). With friction: the same (the two blocks
    expand alike under P, nothing slides) and no tangential force."""
    law = law_for(method, friction)
    n = (2, 2) if dim == 2 else (2, 2, 1)
    mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, n, n, 1e-6)
    u, V = fc.unknown(mesh, degree, law, model=model)
    load = fem.Constant(mesh, 0.0)
    dirichlet = [fc.Dirichlet.on_facets(V, ft, "lower_bottom", dim - 1), fc.Dirichlet.on_facets(V, ft, "left", 0)]
    if dim == 3:
        dirichlet.append(fc.Dirichlet.on_facets(V, ft, "front", 1))
    if kind == "self":  # the two facing sides as one surface, against itself
        ft = fc.merge_regions(mesh, ft, "interface", ["upper_bottom", "lower_top"])
        contacts = fc.self_contact_surfaces(u, ft, "interface", lambda: law_for(method, friction), load, quadrature,
                                            material=fc.MODELS[model](E, NU))
    elif method in MULTIPLIERS:
        contacts = fc.two_body_multipliers(u, ft, "upper_bottom", "lower_top", law, load, passes=passes,
                                        work_quadrature=None if quadrature == "nodal" else quadrature)
    else:
        contacts = fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law_for(method, friction), load,
                                        quadrature, passes, material=fc.MODELS[model](E, NU))
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=ft.meshtags, subdomain_id=ft["upper_top"])
    traction = (ufl.as_vector((0.0,) * (dim - 1) + (-P[model],)), ds)
    plane = "axisymmetric" if geometry == "axisymmetric" else "strain"
    problem = fc.ContactProblem(u, fc.MODELS[model](E, NU, plane), load, dirichlet, contacts, [traction],
                                step_solver=fc.step_solver_for(contacts))
    solve(problem, method, solver, augment=30 if method == "auglag" else 0)
    dev = max(float(np.max(np.abs(c.point_values()[2] - P[model]))) for c in contacts) / P[model]
    if friction:
        dev = max(dev, *(float(np.max(np.abs(c.tangential_force()))) / P[model] for c in contacts))
    return dev, 0.0


# --- the covering set --------------------------------------------------------------------------------------
FAMILIES = ("penalty", "lagrange", "nitsche", "vi", "coulomb")
DEFAULT = {"method": "penalty", "kind": "rigid", "quadrature": "nodal", "passes": "one", "dim": 2, "degree": 1,
           "model": "linear", "solver": "direct", "friction": False, "obstacle": "aligned", "geometry": "cartesian"}
# the covering set's obstacle per kind (run_rigid's plane)
OBSTACLE = {"rigid": "aligned", "two-body": "none", "self": "none"}


def _structural(kind):
    for q in cap.AXES["quadrature"]:
        for passes in cap.AXES["passes"]:
            for dim in cap.AXES["dim"]:
                for degree in cap.AXES["degree"]:
                    yield {"kind": kind, "quadrature": q, "passes": passes, "dim": dim, "degree": degree,
                           "obstacle": OBSTACLE[kind]}


def _first_supported(**fixed):
    """A supported cell with ``fixed`` values, the other axes as in DEFAULT where possible (or None)."""
    kind = fixed.get("kind", "rigid")
    first = {**DEFAULT, "obstacle": OBSTACLE[kind], **fixed}
    for c in [first] + [{**DEFAULT, **s, **fixed} for s in _structural(kind)]:
        if cap.supported(**c):
            return c
    return None


def covering_cells() -> list[dict]:
    cells = []
    for method in FAMILIES:  # 1. every supported structural cell per family
        for kind in cap.AXES["kind"]:
            cells += [c for s in _structural(kind) if cap.supported(**(c := {**DEFAULT, **s, "method": method}))]
    for method in cap.AXES["method"]:  # 2. every law per kind
        for kind in cap.AXES["kind"]:
            cells.append(_first_supported(method=method, kind=kind))
    for method in FAMILIES:  # 3. orthogonal options per family and kind
        for kind in cap.AXES["kind"]:
            for axis in ("model", "solver", "geometry"):
                for value in cap.AXES[axis]:
                    cells.append(_first_supported(method=method, kind=kind, **{axis: value}))
    for method in LAWS + ("coulomb", "lagrange"):  # friction: every law; structural variants with penalty
        cells.append(_first_supported(method=method, friction=True))
    cells += [c for s in _structural("rigid") if cap.supported(**(c := {**DEFAULT, **s, "friction": True}))]
    for model in ("neohookean", "neohookean-mixed"):  # friction on the displacement field of a mixed unknown too
        cells.append(_first_supported(method="penalty", friction=True, model=model))
    for method in LAWS + ("coulomb", "lagrange"):  # two-body friction: every law; structural variants with penalty
        cells.append(_first_supported(method=method, kind="two-body", friction=True))
    cells += [c for s in _structural("two-body") if cap.supported(**(c := {**DEFAULT, **s, "friction": True}))]
    unique = {tuple(c.items()): c for c in cells if c is not None}
    return list(unique.values())


COVER = covering_cells()
# FC_GRID=full: every supported cell of the full product instead of the covering set (506 cells; minutes).
if os.environ.get("FC_GRID") == "full":
    COVER = [c for values in itertools.product(*cap.AXES.values())
             if cap.supported(**(c := dict(zip(cap.AXES, values))))]


def _id(c):
    return "-".join(str(v) for k, v in c.items() if c[k] != DEFAULT.get(k) or k in ("method", "kind"))


@pytest.mark.parametrize("cell", COVER, ids=[_id(c) for c in COVER])
def test_supported_cell_solves_to_its_closed_form(cell):
    c = dict(cell)
    if c["kind"] == "rigid":
        got, ref = run_rigid(c["method"], c["quadrature"], c["dim"], c["degree"], c["model"], c["solver"],
                             c["friction"], c["geometry"])
        assert abs(got - ref) <= 1e-6 * abs(ref), (got, ref)
    else:
        dev, _ = run_two_body(c["method"], c["quadrature"], c["passes"], c["dim"], c["degree"], c["model"],
                              c["solver"], c["friction"], c["geometry"], c["kind"])
        assert dev <= 1e-6, dev


def _family(method: str) -> str:
    return "penalty" if method in LAWS else "lagrange" if method in MULTIPLIERS else method


def test_covering_set_covers_every_supported_cell():
    """The covering claim of the module docstring, for every supported cell of the full matrix: its family runs
    its structural cell, its method runs its kind, and its family runs each of its model, solver and friction
    values with its kind."""
    structural = ("kind", "quadrature", "passes", "dim", "degree")
    runs = {"structure": set(), "law": set(), **{a: set() for a in ("model", "solver", "friction", "geometry")}}
    cover = covering_cells()  # (also when FC_GRID=full runs every cell)
    for c in cover:
        assert cap.supported(**c), c
        runs["structure"].add((_family(c["method"]),) + tuple(c[a] for a in structural))
        runs["law"].add((c["method"], c["kind"]))
        for a in ("model", "solver", "friction", "geometry"):
            runs[a].add((_family(c["method"]), c["kind"], c[a]))
    n = 0
    for c in cap.cells():
        if not cap.supported(**c):
            continue
        n += 1
        assert (_family(c["method"]),) + tuple(c[a] for a in structural) in runs["structure"], c
        assert (c["method"], c["kind"]) in runs["law"], c
        for a in ("model", "solver", "friction", "geometry"):
            assert (_family(c["method"]), c["kind"], c[a]) in runs[a], (a, c)
    assert n > len(cover)


# --- refusals ------------------------------------------------------------------------------------------------
def test_every_refused_cell_names_its_combination():
    refused = 0
    for c in cap.cells():
        rule = cap.refusal(**c)
        if rule is None:
            continue
        refused += 1
        with pytest.raises(cap.UnsupportedCombination) as exc:
            cap.check(**c)
        msg = str(exc.value)
        assert "\n" not in msg and msg.startswith("unsupported combination ") and " use " in msg
        assert cap.describe(**c) in msg  # the whole combination
        assert cap.describe(**{a: c[a] for a in rule.when}) in msg  # the refused values
    assert 0 < refused < len(list(cap.cells()))


def test_unknown_axis_value_is_a_plain_value_error():
    with pytest.raises(ValueError, match="quadrature must be one of"):
        cap.check(method="penalty", quadrature="trapezoid")


@pytest.mark.parametrize("kwargs,match", [
    ({"kind": "two-body", "method": "vi"}, "two-body"),
    ({"kind": "rigid", "method": "lagrange", "quadrature": "gauss"}, "lagrange"),
    ({"kind": "rigid", "method": "penalty", "degree": 2, "quadrature": "nodal"}, "P2"),
    ({"kind": "two-body", "method": "lagrange", "passes": "two"}, "two-pass"),
    ({"kind": "two-body", "method": "penalty", "friction": True, "quadrature": "segment"}, "friction"),
    ({"kind": "two-body", "method": "penalty", "friction": True, "degree": 2, "quadrature": "simpson"}, "friction"),
    ({"kind": "two-body", "method": "penalty", "degree": 2, "quadrature": "nodal"}, "P2"),
])
def test_entry_points_refuse_before_assembly(kwargs, match):
    """The entry points raise the documented error on a real mesh before any form is compiled."""
    c = {**DEFAULT, **kwargs}
    law = law_for(c["method"], c["friction"])
    if c["kind"] == "rigid":
        mesh, ft = rigid_mesh(2)
        u, _ = fc.unknown(mesh, c["degree"], law)
        with pytest.raises(cap.UnsupportedCombination, match=match):
            fc.contact_surface(u, ft, "bottom", fc.HalfPlane([0.0, 0.0], [0.0, 1.0]), law, fem.Constant(mesh, 0.0),
                            c["quadrature"], material=fc.MODELS["linear"](E, NU))
    else:
        mesh, _, ft = stacked_blocks(MPI.COMM_WORLD, 1.0, 1.0, 1.0, (2, 2), (2, 2), 1e-6)
        u, _ = fc.unknown(mesh, c["degree"], law)
        call = fc.two_body_multipliers if c["method"] in MULTIPLIERS else None
        with pytest.raises(cap.UnsupportedCombination, match=match):
            if call is not None:
                call(u, ft, "upper_bottom", "lower_top", law, fem.Constant(mesh, 0.0), passes=c["passes"])
            else:
                fc.two_body_surfaces(u, ft, "upper_bottom", "lower_top", lambda: law, fem.Constant(mesh, 0.0),
                                  c["quadrature"], c["passes"])


def test_docs_match_the_declaration():
    from pathlib import Path

    doc = Path(__file__).resolve().parents[1] / "docs" / "capabilities.md"
    assert doc.read_text() == cap.markdown(), "regenerate: python -m fenics_contact.capabilities > docs/capabilities.md"


def test_two_pass_coinciding_points_carry_the_one_pass_pressure(monkeypatch):
    """Two passes whose slave points coincide (matching meshes, no initial overlap): every point of both passes
    carries the applied pressure. (With the node-on-node exclusion the first pass alone carried it at weight
    1/2: pressure 2 P, the +98 % p0 of a two-body Hertz case with a node on the axis in both meshes.)"""
    from fenics_contact.app.scenes import build, patch

    monkeypatch.setattr(patch, "OVERLAP", 0.0)
    for quadrature in ("nodal", "gauss"):  # compliance: stiffness at g = 0, the blocks only touch at the start
        setup = build("patch", law_factory=lambda: fc.make_law("compliance", c_n=1e6), quadrature=quadrature,
                      passes="two", n_lower=(4, 2), n_upper=(4, 2))
        solve(setup.problem, "compliance", "direct")
        for c in setup.contacts:
            assert np.allclose(c.point_values()[2], patch.PRESSURE, rtol=1e-8), (quadrature, c.point_values()[2])


@pytest.mark.parametrize("method", ["vi"])
def test_solver_refuses_an_iterative_solve_it_cannot_do(method):
    """The linear solver is known only to the Solver: it refuses GAMG for SNES VI's changing reduced system, with
    the documented one-line error, before any assembly. (The multipliers' saddle point has its own iterative
    solve: the Schur complement field split, tests/test_sheet.py.)"""
    from fenics_contact.app.scenes import build

    setup = build("block", law=fc.make_law(method), nx=2, ny=2)
    with pytest.raises(cap.UnsupportedCombination, match=f"{method}, iterative solver"):
        fc.Solver(setup.problem, quiet=True, options=dict(fc.LINEAR_SOLVERS["iterative"]))


def test_a_users_own_law_is_not_refused_for_its_name():
    """A law class of the user's own (a name outside METHODS): the method-specific rules are skipped, the others
    still apply."""

    class Linear(fc.ContactLaw):
        name = "my_law"
        scalars, fields = {"K": 1e3}, {}

    assert cap.of(Linear())["method"] is None
    cap.check(**cap.of(Linear()), kind="rigid", quadrature="gauss", dim=3, degree=1)  # no error
    with pytest.raises(cap.UnsupportedCombination, match="segment quadrature"):
        cap.check(**cap.of(Linear()), kind="rigid", quadrature="segment")


@pytest.mark.parametrize("method", ["vi", "coulomb"])
def test_an_obstacle_vi_and_coulomb_cannot_do_is_refused_by_the_grid(method):
    """vi and coulomb work on the displacement component along an axis-aligned normal: a curved or inclined
    obstacle is refused by the capability grid's obstacle axis, before any assembly."""
    mesh, ft = rigid_mesh(2)
    law = fc.make_law(method)
    u, _ = fc.unknown(mesh, 1, law)
    for obstacle in (fc.Cylinder([0.5, -1.0], 1.0), fc.HalfPlane([0.0, 0.0], [1.0, 1.0])):
        with pytest.raises(cap.UnsupportedCombination, match="axis-aligned"):
            fc.contact_surface(u, ft, "bottom", obstacle, law, fem.Constant(mesh, 0.0))
    assert fc.HalfPlane([0.0, 0.0], [0.0, 2.0]).shape == "aligned" and fc.Sphere([0, 0, 1], 1.0).shape == "curved"
