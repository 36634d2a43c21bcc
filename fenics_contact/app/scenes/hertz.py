"""``hertz``: elastic cylinder on a rigid plane, plane strain, linear elasticity.

A disk of radius ``R`` pressed between two rigid plates is symmetric about
its horizontal diameter and its vertical diameter, so we model the quarter
``x >= 0, y <= R`` (the half of the lower half-disk): ``u_x = 0`` on
``x = 0``; on the diameter ``y = R`` the vertical displacement is the
uniform ``-t * approach`` (mirror symmetry of the two contacts), the
horizontal one free. The plate is the rigid half-plane ``y <= 0``. Figures
are for the whole cylinder: the quarter's force is doubled. The mesh is
graded toward the contact (gmsh, :func:`fenics_contact.app.meshes.hertz_quarter_disk`).
The richer models of the benchmark's model-reduction table are options of :func:`build`: the half disk,
the full disk between two rigid plates, a meshed stiff plate (two-body contact), neo-Hookean; they give
the quarter's figures within 0.5 % (``results/bench/model_reduction.md``, README).

Hertz (rigid plane, load ``P`` per unit length, ``E* = E/(1-nu^2)`` in plane
strain, ``E* = E`` in plane stress, ``plane="stress"``): ``a = sqrt(4 P R / (pi E*))``,
``p0 = 2P/(pi a)``. Pressures are nominal (per reference length); neo-Hookean
runs on the rigid plate also report the Cauchy peak ``p0_cauchy`` (per current length).
The default approach ``APPROACH R`` gives ``a/R ~ 0.02``, small enough for Hertz's
half-space assumption (error ``O((a/R)^2)``). Every constant below is a keyword
argument of :func:`build` (``R``, ``E``, ``nu``, ``approach``, the plate's size and
material, the refined zone), described in ``OPTIONS``.

Force control (``load=P``, quarter only): instead of the approach, the
diameter ``y = R`` carries the uniform traction ``P / (2 R)`` downward (the
quarter carries half of ``P``), so the disk is held only by the contact.
It converges from rest without a hand-made initial guess by load stepping
with a vanishing stabilisation: a spring ``k (1 - t) u`` on the disk's cells,
``k = stabilisation * E / R^2`` (default ``STABILISATION``, ``STABILISATION_MESHED`` on the meshed plate;
total stiffness about ``stabilisation * E``
per unit length: the first iterate moves the disk by about the contact's own
approach ``~ P / E``, not into the plate), which carries part of the load at
``t < 1`` and is exactly zero at the last step ``t = 1``: the final answer has
no stabilisation in it (its force balance, ``load_error``, is the check).
The figures are then against Hertz for the applied ``P``. The exact condensed
method (``coulomb``) needs no spring and may take the load in one step
(``steps=1``): its Newton runs on the condensed system, where the vertex that
touches at rest holds the disk from the first iterate.

Two deformable bodies (``plate="meshed"``): ``E* = 1/((1-nu^2)/E + (1-nu_p^2)/E_p)``
(two identical bodies: ``E/(2 (1-nu^2))``); the plate ``plate_width`` x
``plate_depth`` is fixed at its bottom, so it approximates a half-space only
when it is large against ``a``: by default it is ``PLATE_HALF_WIDTHS`` contact
half-widths ``a`` wide and deep (:func:`expected_half_width`), and at least ``PLATE_SIZE``.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...factory import contact_surface, two_body_multipliers, two_body_surfaces
from ...laws import ContactLaw, ExactCoulomb, LagrangeMultiplier, Nitsche
from ...materials import PLANES, Materials
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import hertz_quarter_disk
from . import GIVEN, Option, Setup, Stabilised, nonnegative, poisson, positive, refuse_size

__all__ = [
    "R", "E", "NU", "APPROACH", "DEFAULT_K", "PENALTY_FACTOR", "default_K", "BENCH", "BENCHES", "TWO_BODY", "hertz",
    "contact_half_width", "approach_half_width", "expected_half_width", "OPTIONS",
    "PLATE_STIFFNESS", "PLATE_SIZE", "PLATE_HALF_WIDTHS", "STABILISATION", "STABILISATION_MESHED",
    "build", "law_twin"
]

R, E, NU = 1.0, 1000.0, 0.3
APPROACH = 0.001  # vertical displacement of the diameter y = R at t = 1, per unit R (default: APPROACH R)
PENALTY_FACTOR = 10.0  # pure penalty on the rigid plate: K x this (default_K)
DEFAULT_K = 1e6  # penalty scale ~ E / h_contact (2.5 E / h at the defaults: E = 1000, h = R / 400)


def default_K(E: float = E, R: float = R, method: str = "auglag", plate: str = "rigid") -> float:
    """The penalty scale of a scene of modulus ``E`` and radius ``R``: ``DEFAULT_K`` scaled as ``E / h`` with
    ``h ~ R`` (the same dimensionless penalty; two identical bodies, E = 200, R = 8: 2.5e4, where the default's
    1e6 took Newton through cutbacks). Pure ``penalty`` on the rigid plate gets ``PENALTY_FACTOR`` times it: with
    no augmentation its penetration ``p / K`` is the error, and against a rigid plate the disk carries all the
    compliance (p0 2.1 % / 0.95 % / 0.51 % low at 1, 3, 10 x 1e6 on the default mesh); on the meshed plate the
    block's own compliance halves it and 10 x costs a cutback (two identical bodies: 0.20 % at 2.5e4)."""
    factor = PENALTY_FACTOR if method == "penalty" and plate == "rigid" else 1.0
    return factor * DEFAULT_K * (E / globals()["E"]) * (globals()["R"] / R)


# The benchmark's view of this scene (fenics_contact.app.bench): figure, sweep, demo options.
BENCH = {"error": "p0_error", "value": "p0", "figures": ["p0", "a", "a_error", "total_force"], "target": 0.01,
         "K": DEFAULT_K,
         "mesh": ("refinement", {"quick": [0, 1], "full": [0, 1, 2]}),
         "methods": ["penalty", "cross", "auglag", "nitsche", "vi"], "demo_args": ["--steps", "1"],
         "stability": True, "reduction": True,
         # K up to 1e14 (LU: no failure, but the round-off floor); cross also with F^ = 1 ~ p0 / 11 (the paper's
         # advice: F^ below the true pressure); the control: penalty with PETSc's divergence test
         "quick_stability": {"variants": (("penalty", 0), ("cross", 10), ("cross", 10, 1.0), ("auglag", 10))}}
# The two-body Hertz case of two identical bodies (the quarter disk pressed by a force on a meshed block of its own
# material, E = 200, nu = 0.3, R = 8, load 10; block 32 x 16 = 4 R x 2 R: half-space-like, p0 within 1e-4 of
# Hertz): every two-body method and quadrature the capability matrix offers, with the time split (search,
# exchange, coupling, assembly, linear solve). K scale: default_K(200, 8) = 2.5e4, the demo's default here. The exact
# condensed method (coulomb, mu = 0) needs no vanishing spring: the whole load in one step.
TWO_BODY = ["--plate", "meshed", "--E", "200", "--nu", "0.3", "--R", "8", "--load", "10", "--plate-E", "200",
            "--plate-width", "32", "--plate-depth", "16"]
BENCHES = {"hertz_twobody": {
    "demo": "hertz", "error": "p0_error", "value": "p0", "figures": ["p0", "a", "a_error", "total_force"],
    "target": 0.005, "K": 2.5e4, "mesh": ("refinement", {"quick": [0, 1], "full": [0, 1, 2]}),
    "methods": ["penalty", "cross", "auglag", "lagrange", "coulomb", "nitsche"],
    "quadratures": ["nodal", "gauss", "segment"],
    "axes": {"kind": "two-body", "dim": 2}, "demo_args": TWO_BODY, "method_args": {"coulomb": ["--steps", "1"]},
    "quick_sweep": {"penalty": (0, 1), "other": (0,)},
    "main": {"levels": [0], "quadratures": ["nodal"]}}}  # make bench: 10 of the quick sweep's 48 runs


def hertz(P: float, R: float = R, E: float = E, nu: float = NU, plane: str = "strain", E2: float = math.inf,
          nu2: float = NU) -> tuple[float, float]:
    """Hertz half-width ``a`` and peak pressure ``p0`` for load ``P`` per unit length, a cylinder (``E``, ``nu``)
    on a half-space (``E2``, ``nu2``; default rigid): ``1/E* = c(E, nu) + c(E2, nu2)`` with ``c = (1-nu^2)/E``
    (``plane``: ``strain``) or ``1/E`` (``stress``)."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")

    def compliance(E_: float, nu_: float) -> float:
        return (1 - nu_**2) / E_ if plane == "strain" else 1.0 / E_

    Es = 1.0 / (compliance(E, nu) + compliance(E2, nu2))
    a = np.sqrt(4 * P * R / (np.pi * Es))
    return float(a), float(2 * P / (np.pi * a))


def approach_half_width(approach: float, R: float = R) -> float:
    """The contact half-width ``a`` of a disk of radius ``R`` whose centre approaches a rigid plane by
    ``approach`` (plane strain or stress alike): Johnson, Contact Mechanics, eq. 5.36, ``approach = (a^2 / 4R)
    (2 ln(4R/a) - 1)`` (``P / (pi E*) = a^2 / 4R``), solved for ``a`` by bisection in ``(0, R]`` (``R`` when the
    approach is past the formula's range). Independent of ``E``."""
    def f(a: float) -> float:
        return a * a / (4 * R) * (2 * math.log(4 * R / a) - 1)

    if approach >= f(R):
        return R
    lo, hi = 0.0, R
    for _ in range(100):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < approach else (lo, mid)
    return 0.5 * (lo + hi)


def expected_half_width(R: float, E: float, nu: float, plane: str = "strain", approach: float | None = None,
                        load: float | None = None, E2: float = math.inf, nu2: float = NU) -> float:
    """The contact half-width the scene will reach, before solving it: Hertz's ``a`` for ``load`` (against the
    half-space ``E2``, ``nu2``), else :func:`approach_half_width` (the disk alone on a rigid plane: a compliant
    plate takes part of the approach, so this is an upper bound)."""
    if load is not None:
        return hertz(load, R, E, nu, plane, E2, nu2)[0]
    return approach_half_width(APPROACH * R if approach is None else approach, R)


def contact_half_width(x: np.ndarray, p: np.ndarray) -> float:
    """Edge of the pressure profile ``p(x)`` (``x`` ascending from the centre).

    Hertz's ``p^2`` is linear in ``x^2``; it is extrapolated linearly in
    ``x^2`` from the last two loaded points to zero, and clamped to the
    interval between the last loaded and the first unloaded point.
    """
    loaded = np.flatnonzero(p > 1e-8 * p.max())
    i = loaded[-1]
    if i == 0 or i + 1 >= len(x):
        return float(x[i])
    x2, p2 = x[i - 1 : i + 1] ** 2, p[i - 1 : i + 1] ** 2
    edge2 = x2[1] - p2[1] * (x2[1] - x2[0]) / (p2[1] - p2[0]) if p2[0] != p2[1] else x2[1]
    return float(np.sqrt(np.clip(edge2, x[i] ** 2, x[i + 1] ** 2)))


PLATE_STIFFNESS = 1000.0  # the meshed plate's E / the disk's E (model-reduction check)
PLATE_SIZE = (0.5, 0.25)  # meshed plate: least width, depth per unit R (the rigid-plate check's model reduction)
# ... and at least this many contact half-widths a wide and deep. The plate is fixed at its bottom, so it is a
# half-space only far from the contact: p0's error against Hertz falls as about (a / size)^2 (two identical bodies,
# E = 200, R = 8, load 10, a = 0.96, square plates of 3, 5, 8, 12 a: 1.8 %, 0.63 %, 0.19 %, 0.03 %); 10 a
# (0.35 % with the default mesh's own error) leaves the 1 % target to the discretisation, at 2 % more unknowns.
PLATE_HALF_WIDTHS = 10.0
CONTACT_WIDTH = 0.1  # the refined zone's half-width per unit R (mesh size R / 400 within it at refinement 0)
STABILISATION = 1.0  # force control: the vanishing spring's k R^2 / E (module docstring)
# ... on the meshed plate: the compliant plate makes the contact softer, so a spring of 1.0 carries most of the load
# before the last step, and removing it there throws Newton far off (two identical bodies, E = 200, R = 8, load 10:
# penalty 2 cutbacks at 1.0, none at 0.1; lagrange 21 Newton iterations either way)
STABILISATION_MESHED = 0.1


OPTIONS = {
    "R": Option("disk radius (length)"),
    "E": Option("disk's Young's modulus (stress)"),
    "nu": Option("disk's Poisson's ratio", "poisson"),
    "approach": Option(f"displacement control: the disk's centre moved toward the plate (length; default: "
                       f"{APPROACH:g} R, when --load is not given)", excludes="load"),
    "load": Option("force control instead of --approach: total force on the whole cylinder per unit length "
                   "(force / length; quarter symmetry; default: not used)", needs=("symmetry", "quarter")),
    "stabilisation": Option(f"force control: the vanishing spring's k R^2 / E (default: {STABILISATION:g}, "
                            f"{STABILISATION_MESHED:g} on the meshed plate)", "nonnegative", needs=("load", GIVEN)),
    "plate_E": Option(f"meshed plate's Young's modulus (stress; default: {PLATE_STIFFNESS:g} E)",
                      needs=("plate", "meshed")),
    "plate_nu": Option("meshed plate's Poisson's ratio (default: --nu)", "poisson", needs=("plate", "meshed")),
    "plate_width": Option(f"meshed plate's width from the symmetry line (length; default: {PLATE_HALF_WIDTHS:g} "
                          f"contact half-widths a, from Hertz for --load or Johnson's disk approach for --approach, "
                          f"at least {PLATE_SIZE[0]:g} R)", needs=("plate", "meshed")),
    "plate_depth": Option(f"meshed plate's depth (length; default: {PLATE_HALF_WIDTHS:g} contact half-widths a as "
                          f"--plate-width, at least {PLATE_SIZE[1]:g} R)", needs=("plate", "meshed")),
    "contact_width": Option(f"half-width of the refined zone at the contact, mesh size R / 400 within it (length; "
                            f"< --R; default: {CONTACT_WIDTH:g} R)", below=("R",)),
}


def build(law: ContactLaw, quadrature: str = "nodal", refinement: int = 0, steps: int = 2,
          comm: MPI.Comm = MPI.COMM_WORLD, model: str = "linear", approach: float | None = None,
          symmetry: str = "quarter", plate: str = "rigid", plane: str = "strain", R: float = R, E: float = E,
          nu: float = NU, load: float | None = None, plate_E: float | None = None, plate_nu: float | None = None,
          plate_width: float | None = None, plate_depth: float | None = None, contact_width: float | None = None,
          stabilisation: float | None = None) -> Setup:
    """``refinement`` halves the mesh size that many times (default: h = R/400 at the contact);
    ``model``: ``linear`` (default: strains ~1e-3), ``neohookean`` (the model-reduction check) or
    ``neohookean-mixed`` or ``linear-mixed`` (nearly incompressible: Taylor-Hood P2-P1, quadrature ``gauss`` or
    ``simpson``);
    ``symmetry``: ``quarter`` (default), ``half`` (the lower half disk, ``u_x = 0`` at the centre
    only: the same problem without the mirror about ``x = 0``) or ``full`` (the whole disk between the
    lower plate and an upper rigid plate that moves down by ``2 approach``: no mirror at all; the rigid
    modes are removed by ``u_x = 0`` at the centre and the upper pole and ``u_y = -approach`` at the
    centre, point values of the exact symmetric solution, whose reaction ``centre_reaction`` measures
    how far the two contacts are from balance); ``plate``: ``rigid`` (the analytic half-plane, default)
    or ``meshed`` (quarter only: a plate of ``PLATE_STIFFNESS`` x E, fixed at its bottom,
    in the same mesh, in two-body contact, one pass, the disk's arc the slave; method ``nitsche``: two passes,
    unbiased). The last three are the
    model-reduction checks. ``plane``: ``strain`` (default) or ``stress`` (disk and plate).

    Physical parameters (defaults: the module constants): the disk's ``R``, ``E``, ``nu``; ``approach``
    (displacement control) or ``load`` (force control: the total force ``P`` per unit length of the whole
    cylinder, quarter only; module docstring), ``stabilisation`` its vanishing spring; the meshed plate's
    ``plate_E`` (default ``PLATE_STIFFNESS * E``), ``plate_nu`` (default ``nu``), ``plate_width`` and
    ``plate_depth`` (default ``PLATE_HALF_WIDTHS`` times :func:`expected_half_width`, at least ``PLATE_SIZE``
    times ``R``); ``contact_width``: the refined zone (default ``0.1 R``). ``OPTIONS`` describes each."""
    if approach is not None and load is not None:
        raise ValueError(f"give approach or load, not both (got approach {approach!r}, load {load!r})")
    positive(R=R, E=E, approach=approach, load=load, plate_E=plate_E, plate_width=plate_width,
             plate_depth=plate_depth, contact_width=contact_width)
    nonnegative(stabilisation=stabilisation)
    if stabilisation is None:
        stabilisation = STABILISATION_MESHED if plate == "meshed" else STABILISATION
    # The condensed exact method needs no spring: the vertex that touches at rest holds the body from its first
    # iterate (its Newton runs on the condensed system), so it may take the whole load in one step.
    if load is not None and int(steps) < 2 and not isinstance(law, ExactCoulomb):
        raise ValueError(f"force control (load) needs steps >= 2 (the vanishing spring acts before the last; "
                         f"method coulomb: >= 1), got {steps!r}")
    poisson(nu=nu, plate_nu=plate_nu)
    if int(refinement) < 0:
        raise ValueError(f"refinement must be >= 0, got {refinement!r}")
    if int(steps) < 1:
        raise ValueError(f"steps must be >= 1, got {steps!r}")
    if load is not None and symmetry != "quarter":
        raise ValueError(f"hertz load (force control) needs symmetry 'quarter', got {symmetry!r}")
    plate_E = PLATE_STIFFNESS * E if plate_E is None else plate_E
    plate_nu = nu if plate_nu is None else plate_nu
    if load is None and approach is None:
        approach = APPROACH * R
    if plate == "meshed" and None in (plate_width, plate_depth):
        least = PLATE_HALF_WIDTHS * expected_half_width(R, E, nu, plane, approach if load is None else None, load,
                                                    plate_E, plate_nu)
    plate_size = (max(PLATE_SIZE[0] * R, least) if plate_width is None and plate == "meshed" else plate_width,
                  max(PLATE_SIZE[1] * R, least) if plate_depth is None and plate == "meshed" else plate_depth)
    contact_width = CONTACT_WIDTH * R if contact_width is None else contact_width
    if not contact_width < R:  # a zone beyond the disk meshes all of it at the contact's size
        raise ValueError(f"contact_width must be in (0, R = {R:g}), got {contact_width!r}")
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {sorted(MODELS)}, got {model!r}")
    MODELS[model](E, nu, plane=plane)  # a plane the model refuses (the mixed one: plane strain), before any work
    if symmetry not in ("quarter", "half", "full"):
        raise ValueError(f"hertz symmetry must be 'quarter', 'half' or 'full', got {symmetry!r}")
    if plate not in ("rigid", "meshed"):
        raise ValueError(f"hertz plate must be 'rigid' or 'meshed', got {plate!r}")
    if plate == "meshed" and symmetry != "quarter":
        raise ValueError(f"hertz plate 'meshed' needs symmetry 'quarter', got {symmetry!r}")
    # At least 1.8 (contact_width / h)^2 unknowns in the refined zone (2.5 at refinement 0, 1.84 at 3: measured)
    zone = math.log10(1.8) + 2 * math.log10(contact_width * 400 / R)
    refuse_size("refinement", refinement, zone + 2 * math.log10(2) * int(refinement),
                lambda most: f"0 to {math.floor((most - zone) / (2 * math.log10(2)))}"
                if most >= zone else f"none with contact_width {contact_width:g} (it fits below "
                f"{contact_width * 10 ** ((most - zone) / 2):.3g})", comm)
    h = R / 400 / 2**refinement
    mesh, cell_tags, facet_tags = hertz_quarter_disk(comm, R, h_contact=h, h_far=R / 10, contact_width=contact_width,
                                                     half=symmetry == "half", full=symmetry == "full",
                                                     plate=plate_size if plate == "meshed" else None)
    # displacement P1, or (displacement, pressure): P1-P1 for method lagrange, Taylor-Hood P2-P1 for the mixed model
    u, V = unknown(mesh, 2 if MODELS[model].mixed else 1, law, model=model)
    t = fem.Constant(mesh, 0.0)  # the load parameter
    fdim = mesh.topology.dim - 1
    # the full disk has no top side (its u_y is held at the centre, below)
    top = facet_tags.find("top") if symmetry != "full" else np.empty(0, np.int32)
    top_y = fem.locate_dofs_topological(V.sub(1), fdim, top)
    copies = 1
    if symmetry == "quarter":
        fix_x = fem.locate_dofs_topological(V.sub(0), fdim, facet_tags.find("symmetry"))
        copies = 2  # the figures are for the whole contact: the quarter carries half of it
    else:  # the centre (0, R) keeps the half disk from sliding sideways
        mesh.topology.create_connectivity(0, mesh.topology.dim)
        centre = dmesh.locate_entities(mesh, 0, lambda x: _at(x, 0.0, R, R))
        fix_x = fem.locate_dofs_topological(V.sub(0), 0, centre)
    dirichlet = [Dirichlet(V.sub(0), fix_x)] if load is not None else [Dirichlet(V.sub(1), top_y, -approach),
                                                                        Dirichlet(V.sub(0), fix_x)]
    material = MODELS[model](E, nu, plane=plane)
    contacts, pair = [], []
    if symmetry == "full":  # the rigid modes: u_y at the centre, u_x at the centre and the upper pole
        pole = dmesh.locate_entities(mesh, 0, lambda x: _at(x, 0.0, 2 * R, R))
        top_y = fem.locate_dofs_topological(V.sub(1), 0, centre)  # its reaction: the imbalance of the contacts
        dirichlet = [Dirichlet(V.sub(1), top_y, -approach), Dirichlet(V.sub(0), fix_x),
                     Dirichlet(V.sub(0), fem.locate_dofs_topological(V.sub(0), 0, pole))]
        contacts.append(contact_surface(u, facet_tags, "contact_upper",
                                        HalfPlane([0.0, 2 * R], [0.0, -1.0], motion=[0.0, -2 * approach]), law_twin(
                                            law), t, quadrature, material=material, name="upper_plate"))
    if plate == "meshed":
        # per-body materials: the plate's E and nu (same model)
        material = Materials(mesh, cell_tags, {"disk": material,
                                               "plate": MODELS[model](plate_E, plate_nu, plane=plane)})
        bottom = facet_tags.find("plate_bottom")
        side = facet_tags.find("plate_symmetry")
        dirichlet += [Dirichlet(V.sub(1), fem.locate_dofs_topological(V.sub(1), fdim, bottom)),
                      Dirichlet(V.sub(0), fem.locate_dofs_topological(V.sub(0), fdim, np.concatenate([bottom, side])))]
        if isinstance(law, LagrangeMultiplier):  # the slave pressure an unknown (P1: quadrature 'nodal')
            contact = two_body_multipliers(u, facet_tags, "contact", "plate_top", law, t, radius=0.1 * R,
                                           name="plate", work_quadrature=quadrature)[0]
        else:  # Nitsche: unbiased (each side slave once, its own stress); the disk's pass gives the figures
            pair = two_body_surfaces(u, facet_tags, "contact", "plate_top", lambda: law, t, quadrature,
                                     "two" if isinstance(law, Nitsche) else "one", radius=0.1 * R, name="plate",
                                     material=material)
            contact = pair[0]
            contacts += pair[1:]
    else:
        contact = contact_surface(u, facet_tags, "contact", HalfPlane([0.0, 0.0], [0.0, 1.0]), law, t, quadrature,
                                  material=material)
    contacts.insert(0, contact)
    if load is None:
        problem = ContactProblem(u, material, t, dirichlet, contacts)
    else:  # the quarter's half of P on its diameter; the vanishing spring on the disk (module docstring)
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags)
        traction = fem.Constant(mesh, np.array([0.0, -load / (2 * R)]))
        # the spring's dx as the bulk energy's (dolfinx 0.9: one subdomain data per integral type in a form):
        # per body (cell tags) with the meshed plate, over the whole mesh (the disk) otherwise
        dx = ufl.Measure("dx", domain=mesh, subdomain_data=cell_tags.meshtags)(cell_tags["disk"]) \
            if plate == "meshed" else ufl.dx(domain=mesh)
        problem = Stabilised(u, material, t, dirichlet, contacts, [(traction, ds(facet_tags["top"]))],
                             stabilisation * E / R**2, dx)

    def figures() -> dict:
        if plate == "meshed":
            # segment: the sub-segment Gauss points (current positions: they move by ~ the approach)
            x, _, p = contact.point_values() if quadrature == "segment" else contact.point_values(reference=True)
        else:
            x, _, p = contact.surface_values()
        lower = x[:, 1] <= R  # the full disk: the lower contact
        x, p = x[lower], p[lower]
        right = x[:, 0] >= -1e-12 * R  # the half model: the profile from the centre to the right
        # two passes (Nitsche, unbiased): the force on the disk is the weighted mean of the disk's pass and the
        # reaction of the plate's pass
        P = copies * (contact.total_force()[1] if len(pair) < 2 else
                      float(pair[0].weight.value) * pair[0].total_force()[1]
                      - float(pair[1].weight.value) * pair[1].total_force()[1])
        applied = None if load is None else float(t.value) * load  # force control: Hertz for the applied load
        a_h, p0_h = hertz(P if applied is None else applied, R, E, nu, plane,
                          *((plate_E, plate_nu) if plate == "meshed" else ()))
        p0, a = float(p.max()), contact_half_width(x[right, 0], p[right])
        reaction = -copies * problem.reaction(top_y) if applied is None else applied
        out = {"total_force": P, "reaction_top": reaction, "p0": p0, "a": a,
               "p0_hertz": p0_h, "a_hertz": a_h, "p0_error": abs(p0 - p0_h) / p0_h,
               "a_error": abs(a - a_h) / a_h, "contact_nodes": int(np.count_nonzero(p > 1e-8 * p.max())),
               "h_contact": h}
        if applied is not None:  # the spring is off at t = 1: the contact carries the whole load
            out["load"], out["load_error"] = applied, abs(P - applied) / applied
        if model != "linear" and plate == "rigid":  # the peak per current length too (nominal / (da/dA))
            xc, _, pc = contact.surface_values("cauchy")
            out["p0_nominal"], out["p0_cauchy"] = p0, float(pc[(xc[:, 1] <= R)].max())
        if symmetry == "full":  # the centre's reaction is the difference of the two contact forces
            out["reaction_top"] = -contacts[1].total_force()[1]
            out["centre_reaction"] = out["reaction_top"] - P
        return out

    params = {"E": E, "nu": nu, "R": R, "material": model, "h_contact": h, "contact_width": contact_width,
              "plane": plane,
              "refinement": refinement, "quadrature": quadrature, "plate": plate,
              **({"approach": approach} if load is None else {"load": load, "stabilisation": stabilisation}),
              **({"plate_E": plate_E, "plate_nu": plate_nu, "plate_width": plate_size[0], "plate_depth": plate_size[1]}
                 if plate == "meshed" else {}),
              "model": {"quarter": "quarter disk (symmetry x = 0 and y = R)", "half": "half disk (symmetry y = R)",
                        "full": "full disk between two rigid plates"}[symmetry]
              + (f", meshed plate E = {plate_E:g}" if plate == "meshed" else "")}
    return Setup("hertz", problem, contacts, np.linspace(0, 1, steps + 1)[1:].tolist(), params, figures,
                 [contact.displacement_out, contact.gap_out, contact.pressure_out])


def _at(x: np.ndarray, x0: float, y0: float, R: float) -> np.ndarray:
    """Flags of the points ``x`` (3 x n) at ``(x0, y0)`` to round-off of the disk's radius ``R``."""
    return (np.abs(x[0] - x0) <= 1e-9 * R) & (np.abs(x[1] - y0) <= 1e-9 * R)


def law_twin(law: ContactLaw) -> ContactLaw:
    """A fresh law with ``law``'s parameters, for a second contact surface (its fields are per surface)."""
    import copy

    return copy.deepcopy(law)
