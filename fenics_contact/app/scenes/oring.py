"""``oring``: an O-ring in a rectangular gland, squeezed, then pressurised on one side; axisymmetric (default) or
the same cross-section in plane strain.

The cord (diameter ``d``) is the disk of the meridian section ``(r, z)`` centred at ``(r_in + d/2, 0)``: ``r_in``
is the inner radius of the ring as installed, on the groove bottom. The housing is rigid, four analytic
half-planes, each with its own contact surface on the whole circle (any point may touch any wall): the groove
bottom ``r >= r_in`` (fixed), the bore ``r <= r_in + d`` (it touches the cord at ``t = 0`` and moves toward the
axis by ``squeeze * d`` over ``0 < t <= 1``, then holds: :attr:`~fenics_contact.obstacles.Obstacle.path`), the
groove's side walls ``z >= -w/2`` (the pressurised side) and ``z <= w/2``, ``w`` the gland width. The rubber is
neo-Hookean, nearly incompressible (``nu = 0.4999``), mixed Taylor-Hood by default
(:mod:`~fenics_contact.incompressible`); every integral over the whole ring (``2 pi r``).

Load: the squeeze over ``0 < t <= 1`` (the steps of ``steps``: 10, 20 and 30 % of ``d`` for the default
``squeeze = 0.3``), then the fluid pressure ``pressure`` over ``1 < t <= 2``. The pressure acts on the arc of the
cord's surface within ``pressure_arc`` degrees of the ``-z`` direction, seen from the cord's centre in the
reference section (the surface the fluid reaches; it stays clear of the walls), as a follower load: ``p`` normal
to the current surface per current area, i.e. the nominal traction ``-p J F^-T N`` (``F`` with the hoop stretch;
its linearisation is in the Jacobian). A spring of stiffness ``SPRING E / d^2`` per unit volume holds the
cord's rigid motions, which the frictionless gland leaves free before contact (its force is reported:
``spring_share``, its resultant over the bore's contact force, below 1e-6); under pressure the spring is
``SPRING_PRESSURE E / d^2`` at ``t = 1`` falling linearly to exactly 0 at ``t = 2``: it holds the cord while the
fluid pushes it toward the side wall ``z = w/2`` and leaves the last state the unsprung one (the wall holds it
then).

Figures of each wall (``bore``, ``bottom``: groove bottom, ``side``: the wall ``z = w/2``): the contact force per
unit circumference (axisymmetric: the ring's radial force ``int p 2 pi r ds`` over ``2 pi r_wall``; plane strain:
per unit length), the peak contact stress (nominal, per reference area; ``_cauchy``: per current area) and the
contact width (the loaded zone along the wall in the current configuration, its ends extrapolated as Hertz's
``p^2`` linear in the squared distance, :func:`~fenics_contact.app.scenes.hertz.contact_half_width`). The balance
of axial forces: ``fluid_axial_force`` (the fluid pressure's axial resultant), ``walls_axial_force`` (the walls'
normal forces: the side walls', and those of a meshed gland's deformed walls) and ``friction_axial_force`` (the
friction of every wall; ring totals in axisymmetry) add up to 0 at the end of the pressure phase (no spring left).

References (small strain, plane strain, a cylinder of radius ``R = d/2`` between two rigid planes, ``E* = E / (1 -
nu^2)``): Hertz's half-width ``a = sqrt(4 P R / (pi E*))`` and peak ``p0 = 2 P / (pi a)`` for the computed force
``P`` per unit length, and Johnson's approach of the centre of a compressed cylinder, ``squeeze d / 2 = (a^2 /
4R) (2 ln(4R/a) - 1)`` with ``P = pi E* a^2 / (4R)`` (K. L. Johnson, Contact Mechanics, 1985, section 4.2 and
eq. 5.36; :func:`~fenics_contact.app.scenes.hertz.hertz`,
:func:`~fenics_contact.app.scenes.hertz.approach_half_width`); ``p0_error`` and ``width_error``: the bore's peak
and width against Hertz's for its force, ``force_error``: its force against Johnson's for the squeeze
(relative). The independent reference of the cord between two plates (the gland wide enough that its side walls
stay clear) is another code, FElupe, on the same problem: ``scripts/felupe/run.py``, docs/bench/felupe.md.

Variants: ``housing_E`` meshes the groove body (:func:`~fenics_contact.app.meshes.gland_section`: linear elastic,
held at its far face, its lands ``CLEARANCE d`` below the squeezed bore), in two-body contact with the cord; the bore
stays rigid. ``stroke`` makes the inner wall a rod that slides along ``+z`` by ``stroke`` after the pressure phase
(``2 < t <= 3``): with friction its drag per unit circumference is ``friction_rod`` and ``rod_mobilised`` the share of
its capacity ``int mu F(g) ds`` the drag takes (1: it slides everywhere it is loaded; 0 without friction).
"""
from __future__ import annotations

import copy
import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...contact import displacement
from ...domain import merge_regions
from ...factory import contact_surface, two_body_surfaces
from ...kinematics import AXISYMMETRIC, deformation_gradient
from ...laws import ContactLaw
from ...materials import Materials
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...paths import load_factor
from ...problem import ContactProblem, Dirichlet
from ..cli import GIVEN
from ..meshes import cord_section, gland_section
from . import Option, Setup, log_dofs, poisson, positive, refuse_fine
from .hertz import approach_half_width, contact_half_width, hertz

__all__ = ["D", "E", "NU", "DEFAULT_K", "OMEGA_T", "SQUEEZE", "PRESSURE", "PLANES", "SPRING", "WALLS", "BENCH",
           "profile_width",
           "OPTIONS", "build", "references"]

D, E, NU = 1.0, 1000.0, 0.4999
R_IN = 5.0  # the groove bottom's radius, per d (ring inner diameter 10 d)
GLAND_WIDTH = 1.5  # per d: the squeezed cord clears the side walls up to 30 % squeeze
SQUEEZE = 0.3  # of d
PRESSURE = 0.1  # per E
PRESSURE_ARC = 40.0  # degrees about -z
H = 1.0 / 16  # the mesh size, per d
OMEGA_T = 1.0  # the demo's stick penalty per E / h with friction (100 E / h, the normal K, diverges from the start)
DEFAULT_K = 100.0  # penalty per E / h: the penetration ~1e-3 d, below the P2 chords' own sag (max_penetration)
SPRING = 1e-6  # per E / d^2, while squeezed (module docstring)
SPRING_PRESSURE = 1e-2  # per E / d^2, at the start of the pressure phase, falling to 0 at its end
# ... with a meshed gland: its walls are found by a search, which a cord pushed through the side wall by a pressure
# step's first Newton iterate (the spring alone resists it then) escapes; this spring keeps that iterate within d / 30
HOUSING_SPRING_PRESSURE = 1.0
PLANES = (AXISYMMETRIC, "strain")
HOUSING_NU = 0.3  # the meshed gland's Poisson's ratio (steel, aluminium)
CLEARANCE = 0.05  # the meshed gland's extrusion gap, per d: the lands sit this far below the squeezed bore
SQUEEZE_PATH = ([0.0, 1.0, 2.0], [0.0, 1.0, 1.0])  # the bore's radial motion: squeezed up to t = 1, then held
STROKE_PATH = ([0.0, 2.0, 3.0], [0.0, 0.0, 1.0])  # the rod's axial motion: after the pressure phase
# The bulk's quadrature: degree 4, twice the P2 displacement's (UFL's estimate for J^(-2/3) and u_r / r is 112
# points per cell, several times the cost for figures that agree to 0.4 %: measured on the default mesh)
QUADRATURE_DEGREE = 4
WALLS = ("bottom", "bore", "upstream", "side")  # the groove bottom, the bore, the pressurised side's wall, the other
# The benchmark's view (fenics_contact.app.bench): the methods the capability grid offers on the mixed P2 ring with
# Gauss points (lagrange, penalty_multiplier and nitsche refuse a mixed model, vi the ring's 2 pi r; compliance, a
# law of the interface, is left out as on hertz). The accuracy rows: 10 % squeeze in one step, no pressure (the
# closest to Hertz's range), h = 0.1 d and 0.07 d (quick), 0.05 d (full); error: the bore's p0 against Hertz's for its
# force (Hertz's own error at a/R = 0.32 is ~(a/R)^2/4 = 2.6 %: the target). The stability map: the whole load (30 %
# squeeze, then the pressure) on 0.1 d. The locking map (bench.locking): P1 and P2
# displacement-only neo-Hookean and the mixed model on 0.07 d, each against the mixed model on 0.04 d at its nu.
BENCH = {"error": "p0_error", "value": "p0_bore", "target": 0.03, "K": 1e6, "reference": "auglag augmented",
         "figures": ["force_bore", "force_error", "width_bore", "width_error", "p0_hertz", "force_side"],
         "mesh": ("h", {"quick": [0.1, 0.07], "full": [0.1, 0.07, 0.05]}), "methods": ["penalty", "cross", "auglag"],
         "axes": {"kind": "rigid", "dim": 2, "degree": 2, "model": "neohookean-mixed", "geometry": AXISYMMETRIC},
         "quadratures": ["gauss"], "demo_args": ["--squeeze", "0.1", "--steps", "1", "--pressure", "0"],
         "quick_sweep": {"penalty": (0, 1), "other": (0,)},
         "stability": True, "stability_args": ["--squeeze", repr(SQUEEZE), "--pressure", repr(PRESSURE * E)],
         "quick_stability": {"K": (0, 2, 4), "steps": (1, 3), "gamma0": (), "dtol": False,
                             "variants": (("penalty", 0), ("cross", 10), ("auglag", 10))},
         "locking": {"method": "penalty", "quadrature": "gauss", "nu": (0.45, 0.49, 0.499, 0.4999),
                     "figures": ("force_bore", "p0_bore"), "args": ["--h", "0.07"],
                     "variants": (("P1 displacement (neohookean)", ["--model", "neohookean", "--degree", "1"]),
                                  ("P2 displacement (neohookean)", ["--model", "neohookean"]),
                                  ("P2-P1 mixed (neohookean-mixed)", [])),
                     "reference": ("P2-P1 mixed, h = 0.04 d", ["--h", "0.04"])}}

OPTIONS = {
    "d": Option("cord diameter of the O-ring's cross-section (length)"),
    "r_in": Option(f"inner radius of the ring as installed, the groove bottom's radius (length; default: "
                   f"{R_IN:g} d)"),
    "E": Option("Young's modulus of the rubber (stress)"),
    "nu": Option("Poisson's ratio of the rubber (0.4999: nearly incompressible)", "poisson"),
    "squeeze": Option(f"the bore's radial motion, a fraction of d (default {SQUEEZE:g})", (0.01, 0.45)),
    "gland_width": Option(f"axial width of the groove (length; default: {GLAND_WIDTH:g} d)"),
    "pressure": Option(f"fluid pressure on the side z < 0 after the squeeze (stress; default: {PRESSURE:g} E; 0: "
                       "squeeze only)", "nonnegative"),
    "pressure_arc": Option(f"half-angle of the arc the pressure acts on, about -z (degrees; default "
                           f"{PRESSURE_ARC:g})", (5.0, 80.0)),
    "h": Option(f"mesh size on the cord's surface (length; default: d / {1 / H:g})"),
    "stroke": Option("axial travel of the rod (the inner wall r = r_in) toward +z after the pressure phase, over "
                     "2 < t <= 3 (length; default 0: the rod stays)", "nonnegative"),
    "housing_E": Option("Young's modulus of a meshed, linear elastic gland (stress; default: none, the walls rigid "
                        "analytic planes; steel beside rubber: 1e4-1e5 E)"),
    "housing_nu": Option(f"Poisson's ratio of the meshed gland (default {HOUSING_NU:g})", "poisson",
                         needs=("housing_E", GIVEN)),
}


def references(squeeze: float, force: float, d: float, E: float, nu: float) -> dict:
    """Plane-strain small-strain references of a cord of diameter ``d`` squeezed by ``squeeze * d`` between two
    rigid planes carrying ``force`` per unit length: Hertz's contact width ``2 a`` and peak ``p0`` for ``force``,
    and Johnson's force and width for the squeeze (module docstring)."""
    R = 0.5 * d
    a, p0 = hertz(force, R, E, nu) if force > 0 else (0.0, 0.0)
    a_j = approach_half_width(0.5 * squeeze * d, R)
    Es = E / (1 - nu**2)
    return {"width_hertz": 2 * a, "p0_hertz": p0, "force_johnson": math.pi * Es * a_j**2 / (4 * R),
            "width_johnson": 2 * a_j}


def _relative(value: float, reference: float) -> float:
    """``|value - reference| / reference``; NaN for a zero reference."""
    return abs(value - reference) / reference if reference > 0 else float("nan")


def profile_width(s: np.ndarray, p: np.ndarray) -> float:
    """Width of the loaded zone of ``p(s)`` along the wall coordinate ``s``: each side of the peak extrapolated
    as Hertz's edge (:func:`contact_half_width`)."""
    if not np.any(p > 0):
        return 0.0
    k = int(np.argmax(p))
    width = 0.0
    for side in (s >= s[k], s <= s[k]):
        x = np.abs(s[side] - s[k])
        order = np.argsort(x)
        width += contact_half_width(x[order], p[side][order])
    return float(width)


def build(law: ContactLaw, quadrature: str = "gauss", steps: int = 3, pressure_steps: int = 2,
          comm: MPI.Comm = MPI.COMM_WORLD, model: str = "neohookean-mixed", plane: str = AXISYMMETRIC,
          degree: int = 2, d: float = D, r_in: float | None = None, E: float = E, nu: float = NU,
          squeeze: float = SQUEEZE, gland_width: float | None = None, pressure: float | None = None,
          pressure_arc: float = PRESSURE_ARC, h: float | None = None, stroke: float = 0.0,
          stroke_steps: int = 4, housing_E: float | None = None, housing_nu: float | None = None) -> Setup:
    """``steps`` squeeze steps up to ``squeeze`` (t in (0, 1]), then ``pressure_steps`` pressure steps (t in
    (1, 2]; none if ``pressure`` is 0); ``plane``: ``axisymmetric`` or ``strain``; ``model``: a bulk model of
    :data:`~fenics_contact.models.MODELS` (P2: Taylor-Hood for the mixed ones); ``degree``: the displacement's
    (1 or 2; the mixed models take 2 only). ``OPTIONS`` describes each parameter; the module docstring the
    model. ``housing_E``: the groove body meshed (:func:`~fenics_contact.app.meshes.gland_section`), linear
    elastic (``linear-mixed`` beside a mixed rubber model), two-body contact of the cord (slave) with the groove's
    walls (masters; ``quadrature`` ``simpson`` on the P2 cord); the bore stays a rigid plane."""
    if plane not in PLANES:
        raise ValueError(f"oring plane must be one of {PLANES}, got {plane!r}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {tuple(MODELS)}, got {model!r}")
    if degree not in (1, 2) or (degree == 1 and MODELS[model].mixed):
        raise ValueError(f"degree must be 1 or 2 (2 with the mixed model {model!r}), got {degree!r}")
    for name, n in (("steps", steps), ("pressure_steps", pressure_steps), ("stroke_steps", stroke_steps)):
        if int(n) != n or n < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {n!r}")
    positive(d=d, E=E, r_in=r_in, gland_width=gland_width, h=h, housing_E=housing_E)
    poisson(nu=nu, housing_nu=housing_nu)
    housing_nu = HOUSING_NU if housing_nu is None else housing_nu
    if not 0.01 <= squeeze <= 0.45:
        raise ValueError(f"squeeze must be in [0.01, 0.45], got {squeeze!r}")
    if not (math.isfinite(stroke) and stroke >= 0):
        raise ValueError(f"stroke must be a finite number >= 0, got {stroke!r}")
    if not 5.0 <= pressure_arc <= 80.0:
        raise ValueError(f"pressure_arc must be in [5, 80] degrees, got {pressure_arc!r}")
    r_in = R_IN * d if r_in is None else r_in
    w = GLAND_WIDTH * d if gland_width is None else gland_width
    p_fluid = PRESSURE * E if pressure is None else pressure
    if p_fluid < 0 or not math.isfinite(p_fluid):
        raise ValueError(f"pressure must be a finite number >= 0, got {pressure!r}")
    if w <= d:
        raise ValueError(f"gland_width must be above d = {d:g} (the cord fits the groove), got {w!r}")
    h = H * d if h is None else h
    # At least 1.5 (d / h)^2 unknowns on the cord's disk (P1; 6 with P2): 1.8 and 7.6 measured at h = d / 16
    refuse_fine("h", h, log_dofs((1.5 if degree == 1 else 6.0, d / h, 2)), 2, comm)
    rc = r_in + 0.5 * d

    elastic = housing_E is not None
    if elastic:  # the lands CLEARANCE d below the squeezed bore
        land = r_in + d * (1 - squeeze - CLEARANCE)
        mesh, cells, facets = gland_section(comm, d, (rc, 0.0), h, pressure_arc, w, land)
        dx_cord = ufl.Measure("dx", domain=mesh, subdomain_data=cells.meshtags, subdomain_id=cells["cord"])
    else:
        mesh, _, facets = cord_section(comm, d, (rc, 0.0), h, pressure_arc)
        dx_cord = ufl.dx
    u, V = unknown(mesh, degree, law, model=model)
    t = fem.Constant(mesh, 0.0)
    material = MODELS[model](E, nu, plane)
    material.quadrature_degree = QUADRATURE_DEGREE
    bore = HalfPlane([r_in + d, 0.0], [-1.0, 0.0], motion=[-squeeze * d, 0.0])
    bore.path = SQUEEZE_PATH
    rod = HalfPlane([r_in, 0.0], [1.0, 0.0], motion=[0.0, stroke] if stroke > 0 else None)  # or the groove bottom
    if stroke > 0:
        rod.path = STROKE_PATH
    walls = {"bottom": rod, "bore": bore,
             "upstream": HalfPlane([0.0, -0.5 * w], [0.0, 1.0]), "side": HalfPlane([0.0, 0.5 * w], [0.0, -1.0])}
    dirichlet = []
    if elastic:  # the groove's walls meshed, held at the groove body's far face; the bore stays rigid
        metal = MODELS["linear-mixed" if MODELS[model].mixed else "linear"](housing_E, housing_nu, plane)
        metal.quadrature_degree = QUADRATURE_DEGREE
        material = Materials(mesh, cells, {"cord": material, "groove": metal})
        if stroke > 0:
            raise ValueError("stroke needs the rigid gland (no housing_E): the rod is the meshed groove's bottom")
        dirichlet = [Dirichlet.on_facets(V, facets, "groove_fixed", i) for i in (0, 1)]
        # the walls' pairing radius 3 d: the first Newton iterate of a pressure step may push the cord through the side
        # wall by more than d (the spring alone holds it then); the wall must still see it to push it back. A side
        # wall and its land are one master surface: the cord extruding into the clearance gap past the wall's corner
        # meets the land (a master surface ends at its last facet).
        for side in ("upstream", "side"):
            facets = merge_regions(mesh, facets, f"{side}_face", [f"{side}_wall", f"{side}_land"])
        names = {"bottom": "bottom_wall", "upstream": "upstream_face", "side": "side_face"}
        walls = {name: names.get(name, wall) for name, wall in walls.items()}
    contacts = {name: contact_surface(u, facets, "surface", wall, copy.deepcopy(law), t, quadrature, name=name,
                                      material=material) if isinstance(wall, HalfPlane) else
                two_body_surfaces(u, facets, "surface", wall, lambda: copy.deepcopy(law), t, quadrature, name=name,
                                  material=material, radius=3.0 * d)[0] for name, wall in walls.items()}

    # the fluid pressure: a follower load on the reference arc within pressure_arc of -z
    x = ufl.SpatialCoordinate(mesh)
    cos_arc = math.cos(math.radians(pressure_arc))
    arc = ufl.conditional(ufl.ge(-x[1] / ufl.sqrt((x[0] - rc) ** 2 + x[1] ** 2), cos_arc - 1e-9), 1.0, 0.0)
    wu = displacement(u)
    F = deformation_gradient(wu, plane)
    N = ufl.FacetNormal(mesh)
    nominal = -p_fluid * ufl.det(F) * ufl.dot(ufl.inv(F).T, ufl.as_vector([N[0], N[1], 0.0]))
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags, subdomain_id=facets["surface"])
    k = E / d**2

    def spring_factor(s: float) -> float:
        if s <= 1.0 or p_fluid == 0:
            return SPRING
        return (HOUSING_SPRING_PRESSURE if elastic else SPRING_PRESSURE) * max(0.0, 2.0 - s)

    loads = [(ufl.as_vector([nominal[0], nominal[1]]) * arc, ds, ([0.0, 1.0, 2.0], [0.0, 0.0, 1.0])),
             (-k * wu, dx_cord, spring_factor)]
    problem = ContactProblem(u, material, t, dirichlet, list(contacts.values()), loads)
    # the fluid's axial resultant (ring total in axisymmetry) at the full pressure, for the balance of forces
    fluid_form = fem.form(nominal[1] * arc * material.weight(wu) * ds)
    spring_forms = [fem.form(k * wu[i] * material.weight(wu) * dx_cord) for i in range(2)]

    def wall_values(name: str, kind: str = "nominal") -> tuple[np.ndarray, np.ndarray]:
        """The wall's contact pressure at the cord's surface vertices on the wall's half of the circle (the P2
        facets' mid-side nodes, inside the circle, carry none of the recovered pressure) and their current
        coordinate along the wall, sorted by it."""
        c = contacts[name]
        X, _, _ = c.point_values(reference=True)
        x, _, p = c.point_values(reference=False, kind=kind)
        facing = {"bottom": rc - X[:, 0], "bore": X[:, 0] - rc, "upstream": -X[:, 1], "side": X[:, 1]}[name]
        keep = (np.hypot(X[:, 0] - rc, X[:, 1]) >= 0.5 * d * (1 - 1e-9)) & (facing >= 0)
        along = x[keep, 1 if name in ("bottom", "bore") else 0]
        order = np.argsort(along)
        return along[order], p[keep][order]

    def wall_figures(name: str) -> dict:
        s, p = wall_values(name)
        _, pc = wall_values(name, "cauchy")
        c = contacts[name]
        force = float(abs(c.total_force()[0 if name in ("bottom", "bore") else 1]))
        if plane == AXISYMMETRIC:  # per unit circumference
            squeezed = load_factor(SQUEEZE_PATH, float(t.value)) * squeeze * d
            r_wall = r_in if name == "bottom" else (r_in + d - squeezed) if name == "bore" else rc
            force /= 2 * math.pi * r_wall
        return {f"force_{name}": force, f"p0_{name}": float(p.max(initial=0.0)),
                f"p0_cauchy_{name}": float(pc.max(initial=0.0)), f"width_{name}": profile_width(s, p)}

    def figures() -> dict:
        s = load_factor(SQUEEZE_PATH, float(t.value)) * squeeze
        out = {"t": float(t.value), "squeeze": s, "pressure": p_fluid * max(0.0, min(1.0, float(t.value) - 1.0))}
        for name in WALLS:
            out.update(wall_figures(name))
        ref = references(s, out["force_bore"], d, E, nu)
        # the bore's figures against the references (relative; NaN before contact)
        ref.update({"p0_error": _relative(out["p0_bore"], ref["p0_hertz"]),
                    "width_error": _relative(out["width_bore"], ref["width_hertz"]),
                    "force_error": _relative(out["force_bore"], ref["force_johnson"])})
        spring = spring_factor(float(t.value)) * np.hypot(*[comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM)
                                                             for f in spring_forms])
        total = out["force_bore"] * (2 * math.pi * (r_in + d - s * d) if plane == AXISYMMETRIC else 1.0)
        fluid = out["pressure"] / p_fluid * comm.allreduce(fem.assemble_scalar(fluid_form), op=MPI.SUM) \
            if p_fluid > 0 else 0.0
        # every wall's normal force along z: the side walls', and a meshed wall's, whose deformed normal tilts
        walls_axial = sum(float(c.total_force()[1]) for c in contacts.values())
        friction_axial = sum(float(c.tangential_force()[1]) for c in contacts.values())
        # the rod's friction: the axial force the rod's tangential tractions put on the cord (the drag on the rod,
        # opposing its motion), per unit circumference of the rod; the share of its capacity mu F(g) it mobilises
        # (1: every loaded point slides)
        rod = contacts["bottom"]
        drag = float(rod.tangential_force()[1]) / (2 * math.pi * r_in if plane == AXISYMMETRIC else 1.0)
        capacity = float(rod.capacity()) if hasattr(rod, "capacity") else 0.0
        mobilised = abs(float(rod.tangential_force()[1])) / capacity if capacity > 0 else 0.0  # 0: no friction
        out.update({"stroke": stroke * load_factor(STROKE_PATH, float(t.value)), "friction_rod": drag,
                    "rod_mobilised": mobilised})
        out.update({**ref, "spring_share": spring / total if total > 0 else 0.0, "fluid_axial_force": fluid,
                    "walls_axial_force": walls_axial, "friction_axial_force": friction_axial,
                    "max_penetration": max(c.max_penetration() for c in contacts.values())})
        return out

    def profiles() -> dict:
        """Per wall: the current position along the wall and the nominal contact pressure at the surface
        vertices, sorted."""
        return {name: wall_values(name) for name in WALLS}

    loads_t = [(i + 1) / steps for i in range(int(steps))]
    if p_fluid > 0:
        loads_t += [1.0 + (i + 1) / pressure_steps for i in range(int(pressure_steps))]
    if stroke > 0:
        loads_t += [2.0 + (i + 1) / stroke_steps for i in range(int(stroke_steps))]
    params = {"d": d, "r_in": r_in, "E": E, "nu": nu, "squeeze": squeeze, "gland_width": w, "pressure": p_fluid,
              "pressure_arc": pressure_arc, "h": h, "stroke": stroke, "plane": plane, "material": model,
              "quadrature": quadrature, "degree": degree,
              "housing": f"meshed, linear elastic, E {housing_E:g}, nu {housing_nu:g}" if elastic else "rigid",
              "model": ("axisymmetric (r, z)" if plane == AXISYMMETRIC else "plane strain") + ": the cord's whole "
              "cross-section in a " + ("meshed elastic" if elastic else "rigid") + " rectangular gland"}
    setup = Setup("oring", problem, list(contacts.values()), loads_t, params, figures,
                  [contacts["bore"].displacement_out, contacts["bore"].pressure_out])
    setup.profiles = profiles
    return setup
