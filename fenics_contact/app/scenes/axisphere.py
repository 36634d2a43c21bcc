"""``axisphere``: an elastic sphere on a rigid plane, or two elastic spheres, axisymmetric (3D Hertz on the meridian
section ``(r, z)``).

The sphere of radius ``R`` (``E``, ``nu``) is the quarter ``r >= 0`` of its meridian section below its equator,
as the ``sphere`` octant: ``u_r = 0`` on the axis ``r = 0``, the equator moves down by ``t * approach``. Every
integral is over the whole ring (``plane="axisymmetric"``, :mod:`fenics_contact.kinematics`): the contact force
is the whole sphere's, no factor. ``partner="plane"``: the rigid half-space ``z <= 0``; ``partner="sphere"``: a
second sphere of radius ``R2`` (``E2``, ``nu2``) below it, the quarter above its equator, the equator held
(``u_z = 0``); one-pass two-body contact, the upper sphere the slave. The mesh is graded toward the contact
point (size ``h_contact`` within ``contact_width``).

Hertz (load ``P``): ``1/E* = (1 - nu^2)/E + (1 - nu2^2)/E2`` (rigid plane: the first term), ``1/R* = 1/R + 1/R2``
(plane: ``R``), ``a = (3 P R* / (4 E*))^(1/3)``, ``p0 = 3 P / (2 pi a^2)``. ``p0`` is the largest contact pressure
(on the axis), ``a`` the edge of the profile (``p^2`` extrapolated linearly in ``r^2``,
:func:`~fenics_contact.app.scenes.hertz.contact_half_width`). The default approach gives ``a/R ~ 0.07``, as the
``sphere`` scene: small strain, Hertz's half-space within its ``O((a/R)^2)``.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ...factory import contact_surface, two_body_surfaces
from ...laws import ContactLaw
from ...materials import Materials
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import hertz_quarter_disk, two_half_disks
from . import Option, Setup, log_dofs, poisson, positive, refuse_fine
from .hertz import contact_half_width

__all__ = ["R", "E", "NU", "APPROACH", "H_CONTACT", "DEFAULT_K", "PARTNERS", "BENCH", "BENCHES", "hertz_spheres",
           "OPTIONS", "build"]

R, E, NU = 1.0, 1000.0, 0.3
APPROACH = 0.005  # the equator's displacement at t = 1, per R (as the sphere scene's)
H_CONTACT = 1.0 / 400  # mesh size at the contact, per R (a / 28 at the default approach)
CONTACT_WIDTH = 0.15  # the refined zone's radius, per R
H_FAR = 0.05  # the mesh size far from the contact, per R
DEFAULT_K = 1e6  # penalty scale ~ E / h_contact
PARTNERS = ("plane", "sphere")
OVERLAP = 1e-9  # the two spheres' initial overlap, per R (they touch at one point)
# The benchmark's view (fenics_contact.app.bench): the methods the capability grid offers on the ring (SNES VI and
# the condensed Coulomb law carry no 2 pi r; two-body Nitsche neither; normal compliance, a constitutive law of the
# interface rather than an enforcement, is left out as on hertz), the mesh size at the contact refined from
# a / 7 (p0 about 2 % off Hertz) to a / 14 (quick) and a / 28 (full, the scene's default); the distance from the
# converged augmented Lagrangian on the same mesh is the limit gap (no SNES VI here).
_BENCH = {"error": "p0_error", "value": "p0", "figures": ["p0", "a", "a_error", "total_force"], "target": 0.01,
          "K": DEFAULT_K, "reference": "auglag augmented",
          "mesh": ("h-contact", {"quick": [0.01, 0.005], "full": [0.01, 0.005, 0.0025]}),
          "quick_sweep": {"penalty": (0, 1), "other": (0,), "gamma0": (10.0,)}}
BENCH = {**_BENCH, "methods": ["penalty", "cross", "auglag", "lagrange", "penalty_multiplier", "nitsche"],
         "axes": {"kind": "rigid", "dim": 2, "geometry": "axisymmetric"},
         "main": {"levels": [0.01]}}  # make bench: the coarser mesh (its runs' time is the set-up's)
# Two elastic spheres (R and 2 R, the second of half the modulus: E* and R* of the pair), one-pass two-body contact
BENCHES = {"axisphere_spheres": {
    **_BENCH, "demo": "axisphere", "methods": ["penalty", "cross", "auglag", "lagrange", "penalty_multiplier"],
    "axes": {"kind": "two-body", "dim": 2, "geometry": "axisymmetric"},
    "demo_args": ["--partner", "sphere", "--R2", "2", "--E2", "500"]}}


def hertz_spheres(P: float, R: float = R, E: float = E, nu: float = NU, R2: float = np.inf,
                  E2: float = np.inf, nu2: float = NU) -> tuple[float, float]:
    """Hertz contact radius ``a`` and peak pressure ``p0`` of two spheres (``R2 = E2 = inf``: a sphere on a rigid
    plane) under the load ``P``."""
    Rs = 1.0 / (1.0 / R + 1.0 / R2)
    Es = 1.0 / ((1 - nu**2) / E + (1 - nu2**2) / E2)
    a = (3 * P * Rs / (4 * Es)) ** (1 / 3)
    return float(a), float(3 * P / (2 * np.pi * a**2))


OPTIONS = {
    "R": Option("radius of the pressed sphere (length)"),
    "E": Option("Young's modulus of the pressed sphere (stress)"),
    "nu": Option("Poisson's ratio of the pressed sphere", "poisson"),
    "approach": Option(f"the equator's displacement toward the partner (length; default: {APPROACH:g} R)"),
    "R2": Option("radius of the second sphere (length; default: 2 R)", needs=("partner", "sphere")),
    "E2": Option("Young's modulus of the second sphere (stress; default: --E)", needs=("partner", "sphere")),
    "nu2": Option("Poisson's ratio of the second sphere (default: --nu)", "poisson", needs=("partner", "sphere")),
    "h_contact": Option(f"mesh size at the contact (length; default: R / {1 / H_CONTACT:g})"),
    "contact_width": Option(f"radius of the refined zone at the contact (length; default: {CONTACT_WIDTH:g} R)"),
    "h_far": Option(f"mesh size far from the contact (length; default: {H_FAR:g} R)"),
}


def build(law: ContactLaw, quadrature: str = "nodal", steps: int = 1, comm: MPI.Comm = MPI.COMM_WORLD,
          model: str = "linear", partner: str = "plane", R: float = R, E: float = E, nu: float = NU,
          approach: float | None = None, R2: float | None = None, E2: float | None = None, nu2: float | None = None,
          h_contact: float | None = None, contact_width: float | None = None, h_far: float | None = None,
          degree: int = 1) -> Setup:
    """``partner``: ``plane`` (rigid) or ``sphere`` (``R2``, ``E2``, ``nu2``; defaults ``2 R``, ``E``, ``nu``);
    ``h_contact``, ``contact_width``, ``h_far``: the mesh (defaults ``R / 400``, ``0.15 R``, ``0.05 R``);
    ``approach``: the equator's displacement (length; default ``0.005 R``); ``degree``: of the displacement (1 or
    2). ``OPTIONS`` describes each parameter."""
    if partner not in PARTNERS:
        raise ValueError(f"axisphere partner must be one of {PARTNERS}, got {partner!r}")
    if model not in MODELS:
        raise ValueError(f"model must be one of {tuple(MODELS)}, got {model!r}")
    if degree not in (1, 2):
        raise ValueError(f"degree must be 1 or 2, got {degree!r}")
    if int(steps) < 1:
        raise ValueError(f"steps must be >= 1, got {steps!r}")
    positive(R=R, E=E, approach=approach, R2=R2, E2=E2, h_contact=h_contact, contact_width=contact_width,
             h_far=h_far)
    poisson(nu=nu, nu2=nu2)
    sphere = partner == "sphere"
    approach = APPROACH * R if approach is None else approach
    R2 = 2 * R if R2 is None else R2
    E2, nu2 = (E if E2 is None else E2), (nu if nu2 is None else nu2)
    h = H_CONTACT * R if h_contact is None else h_contact
    width = CONTACT_WIDTH * R if contact_width is None else contact_width
    far = max(H_FAR * R if h_far is None else h_far, h)
    # At least (width / h)^2 unknowns in the refined zone and (R / far)^2 in the rest of the quarter disk (x 3 at
    # degree 2; x 2 with the partner sphere); 2.5 and 1.3 measured at the defaults
    per = (3.0 if degree == 2 else 1.0) * (2.0 if sphere else 1.0)
    refuse_fine("h_contact", h, log_dofs((per, width / h, 2)), 2, comm)
    refuse_fine("h_far", far, log_dofs((per, R / far, 2)), 2, comm)
    if approach >= 0.5 * R:
        raise ValueError(f"approach must be below R / 2 = {0.5 * R:g}, got {approach!r}")

    if sphere:  # the partner below (cells "lower"), the pressed sphere above (cells "upper")
        mesh, cells, facets = two_half_disks(comm, R2, R, h, far, width, OVERLAP * R, quarters=True)
        lower, upper, axis, slave = "lower_equator", "upper_equator", "symmetry", "upper_bottom"
    else:
        mesh, cells, facets = hertz_quarter_disk(comm, R, h, far, width)
        upper, axis, slave = "top", "symmetry", "contact"
    u, V = unknown(mesh, degree, law)
    t = fem.Constant(mesh, 0.0)
    top = fem.locate_dofs_topological(V.sub(1), 1, facets.find(upper))
    dirichlet = [Dirichlet(V.sub(1), top, -approach), Dirichlet.on_facets(V, facets, axis, 0)]  # u_r = 0 on the axis
    material = MODELS[model](E, nu, "axisymmetric")
    if sphere:
        material = Materials(mesh, cells, {"upper": material, "lower": MODELS[model](E2, nu2, "axisymmetric")})
        dirichlet.append(Dirichlet.on_facets(V, facets, lower, 1))
        contact = two_body_surfaces(u, facets, slave, "lower_top", lambda: law, t, quadrature, radius=0.1 * R,
                                    name="spheres")[0]
    else:
        contact = contact_surface(u, facets, slave, HalfPlane([0.0, 0.0], [0.0, 1.0]), law, t, quadrature,
                                  material=material)
    problem = ContactProblem(u, material, t, dirichlet, [contact])

    def figures() -> dict:
        x, _, p = contact.point_values(reference=True) if sphere else contact.surface_values()
        r = x[:, 0]
        order = np.argsort(r)
        r, p = r[order], p[order]
        P = float(contact.total_force()[1])  # over the whole ring: the whole sphere's load
        a_h, p0_h = hertz_spheres(P, R, E, nu, *((R2, E2, nu2) if sphere else ()))
        loaded = p > 1e-8 * max(float(p.max()), 1e-300)
        p0 = float(p.max())
        a = contact_half_width(r, p) if loaded.any() else 0.0
        return {"total_force": P, "reaction_top": -problem.reaction(top), "p0": p0, "a": a, "p0_hertz": p0_h,
                "a_hertz": a_h, "p0_error": abs(p0 - p0_h) / p0_h, "a_error": abs(a - a_h) / a_h,
                "contact_nodes": int(np.count_nonzero(loaded)), "h_contact": h}

    params = {"E": E, "nu": nu, "R": R, "approach": approach, "partner": partner, "material": model,
              "h_contact": h, "contact_width": width, "h_far": far, "quadrature": quadrature, "degree": degree,
              **({"R2": R2, "E2": E2, "nu2": nu2} if sphere else {}),
              "model": "axisymmetric (r, z): the quarter below the equator" + (", on a sphere's quarter above its "
                                                                               "equator" if sphere else "")}
    return Setup("axisphere", problem, [contact], np.linspace(0, 1, int(steps) + 1)[1:].tolist(), params, figures,
                 [contact.displacement_out, contact.gap_out, contact.pressure_out])
