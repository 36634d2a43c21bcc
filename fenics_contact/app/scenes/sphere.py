"""``sphere``: elastic sphere on a rigid plane (3D Hertz), linear elasticity; the scaling scene.

A ball of radius ``R`` pressed between two rigid plates is symmetric about
its equatorial plane and about two vertical planes through its axis, so we
model the octant ``x >= 0, y >= 0, z <= R``: ``u_x = 0`` on ``x = 0``,
``u_y = 0`` on ``y = 0``, the equator ``z = R`` moves down uniformly by
``t * approach`` (in-plane free), the plate is the rigid half-space
``z <= 0``. Figures are for the whole sphere on one plate: the octant's
force times 4. Linear elasticity: the approach gives ``a/R ~ 0.07`` and
strains of a few per cent at most under the contact.

Hertz (sphere on a rigid plane, load ``P``, ``E* = E/(1-nu^2)``):
``a = (3 P R / (4 E*))^(1/3)``, ``p0 = 3 P / (2 pi a^2)``.

Two deformable bodies (``plate="meshed"``, the 3D two-body case of the scaling run): the octant on the
block ``plate_width^2 x plate_depth`` (``plate_E = E``, ``plate_nu = nu`` by default: two identical bodies),
in the same mesh and graded toward the contact like the ball, the block fixed at its bottom and on the same
symmetry planes; the ball's surface is the slave of a one-pass two-body contact (:mod:`twobody`), the block's
top the master. Hertz with ``1/E* = (1-nu^2)/E + (1-nu_p^2)/E_p``. The block is by default
``PLATE_HALF_WIDTHS`` expected contact radii ``a = sqrt(R approach)`` wide and deep (Hertz's approach
``a^2 / R``), and at least ``PLATE_SIZE``: the clamped block stiffens the force per approach, not the
pressure profile per force (p0 for the measured force moves by 0.1 % from a block 7 a to 14 a). One-pass
node-to-surface contact on non-matching meshes scatters the pointwise pressure (it does not pass the patch
test): its nodal maximum is 2-17 % off at every mesh size, and a Hertz profile fitted to the pointwise pressures
(:func:`hertz_fit`, ``p0_fit``) does not converge either (0.7-0.9 % below Hertz from size 0.7 to 0.25: the
vertices on the symmetry planes carry pressures ~8 % below the others' at size 0.7, and their share of the fit
changes with the mesh). ``p0`` is the peak of the Hertz profile with the contact forces' first two moments
(:func:`hertz_peak_from_moments`): integrals of the pressure, in which the scatter averages out. The penalty's
interface layer ``E* / K`` widens the contact at every mesh size, an error that does not fall with the mesh at a
fixed ``K``: the block's default penalty (:func:`default_K`) is ``BLOCK_PENALTY E* / h_contact``, growing as the mesh
is refined.

``level`` scales every mesh size by ``LEVELS[level]``, chosen so that the dofs run from about
1e4 (level 0) to about 1e6 (level 3). The iterative linear solver (``--solver iterative``) is
meant for the finer levels. ``R``, ``E``, ``nu``, ``approach`` and the refined zone
``contact_width`` are keyword arguments of :func:`build` (defaults: the module constants).
Force control (``load=P``, the whole sphere's force): the equator carries the
uniform traction ``P / 4`` per the meshed equator's area downward and the octant is held only by the
contact; from rest through the vanishing spring of :class:`~fenics_contact.Stabilised`
(``k = stabilisation * E / R^2`` on the body, exactly 0 at the last step), as in ``hertz``.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...condensed import CondensedTwoBody
from ...factory import contact_surface, two_body_surfaces
from ...laws import ContactLaw, Nitsche
from ...materials import Materials
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import sphere_octant
from . import GIVEN, Option, Setup, Stabilised, nonnegative, poisson, positive, refuse_size

__all__ = ["R", "E", "NU", "APPROACH", "DEFAULT_K", "LEVELS", "PLATE_SIZE", "PLATE_HALF_WIDTHS", "FIT_INNER",
           "BLOCK_PENALTY", "BENCH", "BENCHES", "mesh_sizes", "pair_modulus", "default_K", "hertz3d", "hertz_fit",
           "hertz_peak_from_moments", "OPTIONS", "build"]

R, E, NU = 1.0, 1000.0, 0.3
APPROACH = 0.005  # vertical displacement of the equator z = R at t = 1, per unit R (default: APPROACH R)
DEFAULT_K = 1e6  # ~ 10 E / h_contact at level 0
CONTACT_WIDTH = 0.15  # the refined zone around the contact point, per unit R
STABILISATION = 1.0  # force control: the vanishing spring's k R^2 / E
PLATE_SIZE = (0.5, 0.5)  # the meshed block (plate="meshed"): least width (x and y), depth, per unit R
# ... and at least this many expected contact radii a = sqrt(R approach) wide and deep (7 a = 0.5 R at the default
# approach: p0 for the measured force 0.55 % / 0.66 % off Hertz on blocks of 7 a / 14 a at size 0.5)
PLATE_HALF_WIDTHS = 7.0
# Two bodies: one-pass node-to-surface contact does not pass the patch test on non-matching meshes, so the pointwise
# pressure scatters by ~15-20 % about its mean at every mesh size and its maximum does not converge; p0_fit is the
# Hertz profile's peak fitted to the points within FIT_INNER of the contact radius (hertz_fit).
FIT_INNER = 0.8
# The meshed block's default penalty K h_contact / E* (dimensionless; E* of the pair; K = 1.1e6 at size 0.5 with the
# defaults). The layer E* / K lowers p0 by about 1.1 E* / (K a) (measured at size 1.0, K = 1e6 to 1e8): with K ~ 1 / h
# by 0.055 h / a, 0.76 % at size 0.5 and 0.18 % at 0.115, falling with the mesh below the discretisation error
BLOCK_PENALTY = 20.0
# Mesh-size factor per level: h_contact = 0.02 f, h_far = 0.15 f (dofs 11931, 68208, 230964, 1178016).
LEVELS = (0.5, 0.25, 0.16, 0.09)
# The benchmark's view of this scene (fenics_contact.app.bench): level 0 only in the quick sweep.
BENCH = {"error": "p0_error", "value": "p0", "figures": ["p0", "a", "a_error", "total_force"], "target": 0.05,
         "K": DEFAULT_K,
         "mesh": ("level", {"quick": [0], "full": [0, 1]}), "methods": ["penalty", "auglag", "nitsche", "vi"],
         "demo_args": ["--solver", "iterative"], "quick_sweep": {"penalty": (0, 1), "other": (0,), "gamma0": (10.0,)},
         # SNES VI's reduced system changes size between iterations, which GAMG cannot follow: LU
         "method_args": {"vi": ["--solver", "direct"]},
         # the iterative solver shows the conditioning: Krylov iterations per Newton iteration against K; auglag at
         # K = 1e12 fails slowly (91 Newton iterations over 4 cutbacks, 60 s): left out of the quick map
         "stability": True, "reduction": True,
         "quick_stability": {"K": (0, 2, 4, 6, 8), "steps": (1,), "gamma0": (10.0, 1e3, 1e5), "dtol": False,
                             "skip": [("auglag", 6)]}}
# The 3D two-body case: the octant on a deformable block of its own material (one-pass, the ball's surface the
# slave), GMRES + GAMG; p0 the Hertz peak of the contact forces' moments (hertz_peak_from_moments)
BENCHES = {"sphere_block": {
    "demo": "sphere", "error": "p0_error", "value": "p0", "figures": ["p0", "p0_fit", "p0_max", "a", "a_error"],
    "target": 0.05,
    "K": DEFAULT_K, "mesh": ("level", {"quick": [0], "full": [0, 1]}), "methods": ["penalty", "auglag"],
    "quadratures": ["nodal", "gauss"], "axes": {"kind": "two-body", "dim": 3},
    "demo_args": ["--plate", "meshed", "--solver", "iterative"], "quick_sweep": {"penalty": (0,), "other": (0,)}}}


def mesh_sizes(f: float, R: float = R) -> tuple[float, float]:
    """The mesh sizes at the contact and far from it of the mesh-size factor ``f`` (``LEVELS``)."""
    return 0.02 * f * R, 0.15 * f * R


def pair_modulus(E: float, nu: float, plate_E: float | None = None, plate_nu: float = NU) -> float:
    """Hertz's ``E*`` (stress): ``E / (1 - nu^2)`` on a rigid plane (``plate_E`` None), else
    ``1 / E* = (1 - nu^2) / E + (1 - plate_nu^2) / plate_E``."""
    return E / (1 - nu**2) if plate_E is None else 1.0 / ((1 - nu**2) / E + (1 - plate_nu**2) / plate_E)


def default_K(E: float = E, R: float = R, nu: float = NU, plate: str = "rigid", level: int = 0,
              size: float | None = None, plate_E: float | None = None, plate_nu: float | None = None) -> float:
    """The default penalty ``K`` (stress per length) of the scene with these :func:`build` arguments: on the rigid
    plate ``DEFAULT_K`` scaled as ``E / R``; on the meshed block ``BLOCK_PENALTY E* / h_contact`` (``E*`` of the
    pair, ``plate_E``/``plate_nu`` default ``E``/``nu``; ``h_contact`` the mesh size at the contact of ``size``, else
    of ``level``)."""
    if plate != "meshed":
        return DEFAULT_K * (E / globals()["E"]) * (globals()["R"] / R)
    Es = pair_modulus(E, nu, E if plate_E is None else plate_E, nu if plate_nu is None else plate_nu)
    return BLOCK_PENALTY * Es / mesh_sizes(LEVELS[level] if size is None else size, R)[0]


def hertz3d(P: float, R: float = R, E: float = E, nu: float = NU, plate_E: float | None = None,
            plate_nu: float = NU) -> tuple[float, float]:
    """Hertz contact radius ``a`` and peak pressure ``p0`` of a sphere on a rigid plane (``plate_E`` None) or on
    an elastic half-space (``plate_E``, ``plate_nu``) under load ``P``."""
    Es = pair_modulus(E, nu, plate_E, plate_nu)
    a = (3 * P * R / (4 * Es)) ** (1 / 3)
    return float(a), float(3 * P / (2 * np.pi * a**2))


def hertz_fit(x: np.ndarray, p: np.ndarray, a: float, inner: float = FIT_INNER) -> float:
    """Peak pressure of the Hertz profile ``p^2 = p0^2 (1 - r^2 / a^2)`` fitted by least squares (``p^2`` linear
    in ``r^2``) to the pressures ``p`` at the points ``x`` (n, 3) within ``inner a`` of the axis (``a``: the
    contact radius; the fit sets its own). NaN with fewer than 3 points."""
    r2 = x[:, 0] ** 2 + x[:, 1] ** 2
    inside = r2 < (inner * a) ** 2
    if np.count_nonzero(inside) < 3:
        return float("nan")
    slope, intercept = np.polyfit(r2[inside], p[inside] ** 2, 1)
    return float(np.sqrt(max(intercept, 0.0)))


def hertz_peak_from_moments(m0: float, m2: float) -> float:
    """Peak pressure of the Hertz profile ``p = p0 sqrt(1 - r^2 / a^2)`` whose quarter disk (the octant's contact)
    carries the force ``m0 = int p dA`` with the second moment ``m2 = int p r^2 dA`` (``r`` from the axis): the
    whole disk's moments are ``M0 = 2 pi a^2 p0 / 3`` and ``M2 = 4 pi a^4 p0 / 15``, so ``a^2 = 5 m2 / (2 m0)`` and
    ``p0 = 12 m0^2 / (5 pi m2)`` (stress, for ``m0`` a force and ``m2`` a force times length^2). NaN if ``m2 <= 0``."""
    return float(12 * m0**2 / (5 * math.pi * m2)) if m2 > 0 else float("nan")


OPTIONS = {
    "R": Option("sphere radius (length)"),
    "E": Option("sphere's Young's modulus (stress)"),
    "nu": Option("sphere's Poisson's ratio", "poisson"),
    "approach": Option(f"displacement control: the equator's displacement toward the plate (length; default: "
                       f"{APPROACH:g} R, when --load is not given)", excludes="load"),
    "load": Option("force control instead of --approach: the sphere's total force (force; rigid plate; "
                   "default: not used)", needs=("plate", "rigid")),
    "stabilisation": Option(f"force control: the vanishing spring's k R^2 / E (dimensionless; default: "
                            f"{STABILISATION:g})", "nonnegative", needs=("load", GIVEN)),
    "contact_width": Option(f"radius of the refined zone at the contact (length; default: {CONTACT_WIDTH:g} R)"),
    "size": Option("mesh-size factor instead of the level's (dimensionless; default: the level's)"),
    "plate_E": Option("meshed plate's Young's modulus (stress; default: --E)", needs=("plate", "meshed")),
    "plate_nu": Option("meshed plate's Poisson's ratio (default: --nu)", "poisson", needs=("plate", "meshed")),
    "plate_width": Option(f"meshed plate's width in x and y (length; default: {PLATE_HALF_WIDTHS:g} sqrt(R approach), "
                          f"at least {PLATE_SIZE[0]:g} R)", needs=("plate", "meshed")),
    "plate_depth": Option(f"meshed plate's depth (length; default: {PLATE_HALF_WIDTHS:g} sqrt(R approach), at least "
                          f"{PLATE_SIZE[1]:g} R)", needs=("plate", "meshed")),
}


def build(law: ContactLaw, quadrature: str = "nodal", level: int = 0, steps: int = 1,
          comm: MPI.Comm = MPI.COMM_WORLD, model: str = "linear", approach: float | None = None, R: float = R,
          E: float = E, nu: float = NU, load: float | None = None, contact_width: float | None = None,
          stabilisation: float | None = None, size: float | None = None, plate: str = "rigid",
          plate_E: float | None = None, plate_nu: float | None = None, plate_width: float | None = None,
          plate_depth: float | None = None) -> Setup:
    """``level`` in ``0 .. len(LEVELS) - 1`` picks the mesh size (about 1e4 to 1e6 dofs); ``size``, if given,
    is the mesh-size factor instead (``LEVELS[0] = 0.5``; e.g. 1.0 for a tiny smoke-test mesh); ``approach``
    (displacement control) or ``load`` (force control: the sphere's total force); ``contact_width``: the
    refined zone (default ``0.15 R``). ``plate``: ``rigid`` (the half-space z <= 0, default) or ``meshed`` (the
    block ``plate_width^2 x plate_depth``, default ``PLATE_HALF_WIDTHS sqrt(R approach)``, at least ``PLATE_SIZE``
    times ``R``, of ``plate_E``, ``plate_nu``,
    default ``E``, ``nu``: two-body contact, displacement control only). ``OPTIONS`` describes each parameter."""
    if approach is not None and load is not None:
        raise ValueError(f"give approach or load, not both (got approach {approach!r}, load {load!r})")
    positive(R=R, E=E, approach=approach, load=load, contact_width=contact_width, plate_E=plate_E,
             plate_width=plate_width, plate_depth=plate_depth)
    if plate not in ("rigid", "meshed"):
        raise ValueError(f"sphere plate must be 'rigid' or 'meshed', got {plate!r}")
    if plate == "meshed" and load is not None:
        raise ValueError("sphere plate 'meshed' takes displacement control (approach), not load")
    nonnegative(stabilisation=stabilisation)
    if load is not None and int(steps) < 2:
        raise ValueError(f"force control (load) needs steps >= 2 (the vanishing spring acts before the last), "
                         f"got {steps!r}")
    poisson(nu=nu, plate_nu=plate_nu)
    if int(steps) < 1:
        raise ValueError(f"steps must be >= 1, got {steps!r}")
    approach = APPROACH * R if approach is None and load is None else approach
    stabilisation = STABILISATION if stabilisation is None else stabilisation
    contact_width = CONTACT_WIDTH * R if contact_width is None else contact_width
    if not (isinstance(level, int) and 0 <= level < len(LEVELS)):
        raise ValueError(f"sphere level must be an integer in [0, {len(LEVELS) - 1}], got {level!r}")
    if size is not None and not (np.isfinite(size) and size > 0):
        raise ValueError(f"sphere mesh size factor must be > 0, got {size!r}")
    f = LEVELS[level] if size is None else float(size)
    # At least 1.5 (contact_width / h)^3 unknowns in the refined zone (6.6 at size 1, 2.0 at level 3: measured)
    zone = math.log10(1.5) + 3 * math.log10(contact_width / (0.02 * R))
    refuse_size("size" if size is not None else "level", f if size is not None else level, zone - 3 * math.log10(f),
                lambda most: f">= {10 ** ((zone - most) / 3):.2g}", comm)
    h, h_far = mesh_sizes(f, R)
    meshed = plate == "meshed"
    plate_E, plate_nu = (E if plate_E is None else plate_E), (nu if plate_nu is None else plate_nu)
    a_expected = math.sqrt(R * approach) if approach is not None else 0.0  # Hertz: approach = a^2 / R
    plate_size = (max(PLATE_SIZE[0] * R, PLATE_HALF_WIDTHS * a_expected) if plate_width is None else plate_width,
                  max(PLATE_SIZE[1] * R, PLATE_HALF_WIDTHS * a_expected) if plate_depth is None else plate_depth)
    mesh, cell_tags, facet_tags = sphere_octant(comm, R, h_contact=h, h_far=h_far, contact_width=contact_width,
                                                plate=plate_size if meshed else None)
    u, V = unknown(mesh, 1, law)  # displacement, or (displacement, pressure) for method lagrange
    t = fem.Constant(mesh, 0.0)  # the load parameter
    fdim = mesh.topology.dim - 1

    top_z = fem.locate_dofs_topological(V.sub(2), fdim, facet_tags.find("top"))
    dirichlet = [Dirichlet(V.sub(0), fem.locate_dofs_topological(V.sub(0), fdim, facet_tags.find("symmetry"))),
                 Dirichlet(V.sub(1), fem.locate_dofs_topological(V.sub(1), fdim, facet_tags.find("symmetry_y")))]
    if load is None:
        dirichlet.insert(0, Dirichlet(V.sub(2), top_z, -approach))
    material = MODELS[model](E, nu)
    if meshed:  # per-body materials; the block clamped at its bottom (its symmetry faces are the octant's tags)
        material = Materials(mesh, cell_tags, {"ball": material, "plate": MODELS[model](plate_E, plate_nu)})
        dirichlet += [Dirichlet(V.sub(i), fem.locate_dofs_topological(V.sub(i), fdim, facet_tags.find("plate_bottom")))
                      for i in range(3)]
        # Nitsche: unbiased (each side slave once, its own stress); the ball's pass gives the figures
        contacts = two_body_surfaces(u, facet_tags, "contact", "plate_top", lambda: law, t, quadrature,
                                     "two" if isinstance(law, Nitsche) else "one", radius=0.1 * R, name="plate",
                                     material=material)
        contact = contacts[0]
    else:
        contact = contact_surface(u, facet_tags, "contact", HalfPlane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]), law, t,
                                  quadrature, material=material)
        contacts = [contact]
    if load is None:
        problem = ContactProblem(u, material, t, dirichlet, contacts)
    else:  # a quarter of P on the octant's equator; the vanishing spring on the body
        ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags)(facet_tags["top"])
        # per the meshed equator's area (a polygon: ~1e-3 below pi R^2 / 4), so that the octant carries P / 4
        area = comm.allreduce(fem.assemble_scalar(fem.form(fem.Constant(mesh, 1.0) * ds)), op=MPI.SUM)
        traction = fem.Constant(mesh, np.array([0.0, 0.0, -load / (4 * area)]))
        problem = Stabilised(u, material, t, dirichlet, contacts, [(traction, ds)], stabilisation * E / R**2,
                             ufl.dx(domain=mesh))

    # The two-body contact pressure's moments int p dA, int p r^2 dA (forms compiled when needed). Unbiased Nitsche
    # (two passes): the weighted mean of the ball's and the block's passes, as the force on the ball is (one pass
    # alone is not in equilibrium on a coarse mesh: 17 % above the reaction at size 1). A nodal condensed surface
    # (method coulomb) has no pressure field: its vertex forces p_i w_i (w_i = int phi_i dA) are the rule.
    passes = [(c, float(c.weight.value)) for c in contacts] if meshed and len(contacts) == 2 else [(contact, 1.0)]
    moments: list = []

    def force_moments() -> tuple[float, float]:
        if isinstance(contact, CondensedTwoBody):
            x, _, p = contact.point_values(reference=True)
            f = p * contact.weight
            return float(f.sum()), float(np.sum(f * (x[:, 0] ** 2 + x[:, 1] ** 2)))
        if not moments:
            X = ufl.SpatialCoordinate(mesh)
            for c, w in passes:
                p = w * c.ring * c.pressure
                moments.append((fem.form(p * c.ds_work), fem.form(p * (X[0] ** 2 + X[1] ** 2) * c.ds_work)))
        return tuple(comm.allreduce(sum(fem.assemble_scalar(m[k]) for m in moments), op=MPI.SUM) for k in (0, 1))

    def contact_force() -> float:
        """The contact force on the ball (z; the octant's: a quarter)."""
        if len(passes) == 1:
            return float(contact.total_force()[2])
        (ball, w_ball), (block, w_block) = passes
        return w_ball * float(ball.total_force()[2]) - w_block * float(block.total_force()[2])

    def figures() -> dict:
        # the two-body slave points at their reference positions (nodal or Gauss points)
        x, _, p = contact.point_values(reference=True) if meshed else contact.surface_values()
        P = 4 * contact_force()
        applied = None if load is None else float(t.value) * load  # force control: Hertz for the applied load
        a_h, p0_h = hertz3d(P if applied is None else applied, R, E, nu, *((plate_E, plate_nu) if meshed else ()))
        loaded = p > 1e-8 * max(p.max(), 1e-300)
        a = float(np.hypot(x[loaded, 0], x[loaded, 1]).max()) if loaded.any() else 0.0  # outermost loaded node
        p0 = hertz_peak_from_moments(*force_moments()) if meshed else float(p.max())
        out = {**({"p0_max": float(p.max()), "p0_fit": hertz_fit(x, p, a)} if meshed else {}), "total_force": P,
               "reaction_top": -4 * problem.reaction(top_z) if applied is None else applied,
               "p0": p0, "a": a, "p0_hertz": p0_h, "a_hertz": a_h, "p0_error": abs(p0 - p0_h) / p0_h,
               "a_error": abs(a - a_h) / a_h, "contact_nodes": int(np.count_nonzero(loaded)), "h_contact": h}
        if applied is not None:  # the spring is off at t = 1: the contact carries the whole load
            out["load"], out["load_error"] = applied, abs(P - applied) / applied
        if model != "linear":  # p0 is nominal (per reference area); the peak per current area too
            out["p0_nominal"], out["p0_cauchy"] = p0, float(contact.surface_values("cauchy")[2].max())
        return out

    params = {"E": E, "nu": nu, "R": R, "material": model, "h_contact": h, "level": level,
              "contact_width": contact_width,
              **({"approach": approach} if load is None else {"load": load, "stabilisation": stabilisation}),
              "quadrature": quadrature, "plate": plate,
              **({"plate_E": plate_E, "plate_nu": plate_nu, "plate_width": plate_size[0], "plate_depth": plate_size[1]}
                 if meshed else {}),
              "model": "octant (symmetry x = 0, y = 0, z = R)" + (f", meshed block E = {plate_E:g}" if meshed else "")}
    return Setup("sphere", problem, contacts, np.linspace(0, 1, steps + 1)[1:].tolist(), params, figures,
                 [contact.displacement_out, contact.gap_out, contact.pressure_out])
