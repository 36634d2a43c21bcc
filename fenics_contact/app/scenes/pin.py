"""``pin``: elastic plate with a hole on a rigid pin, pulled by a uniform traction (Kikuchi & Song 1980,
example 1 of Renaud & Feng 2003).

Data of the paper: E = 1000, nu = 0.3, uniform traction P0 = 10, plane
strain, frictionless, half model by symmetry. The paper's Fig. 5 (the
geometry) is missing from our copy, so we choose, and say so:

- a square plate 10 x 10 with a central hole of radius R = 1 (width / hole
  diameter = 5, a typical lug), pulled by ``P0`` (per unit length) on its
  top edge ``y = 5`` in ``+y``; the bottom edge and the side are free;
- hole radius = pin radius (a neat fit): the contact is initially touching
  everywhere;
- small displacements as in the paper (linear elasticity, strains ~ P0/E =
  1 %) with the consistent, linearized gap ``g = R - |X| - n(X) . u``
  (``gap="linearized"``, the default; the paper's condensed FEM keeps the
  stiffness constant, i.e. linear kinematics). The neat-fit problem is then
  homogeneous in the load: the pressure scales with ``P0`` and the contact
  angle does not depend on it. ``gap="current"`` uses the exact gap
  ``R - |X + u|`` of the deformed position instead, as the other scenes do;
  with this soft plate (top edge displaced ~0.16 R) it shifts the angle by
  about 2 degrees at ``P0 = 10`` while the bulk stays linear, an
  inconsistent mix that we only offer for comparison;
- plane strain as in the paper;
- half model ``x >= 0`` with ``u_x = 0`` on ``x = 0`` (the pulling axis),
  which removes the horizontal translation and the rotation;
- the vertical translation is held by the pin alone: with a neat fit the
  gap is exactly 0 at ``u = 0``, where the penalty-type laws have no stiffness
  and the first Newton matrix from rest would be singular. The plate converges
  from rest without a hand-made initial guess by load stepping with a vanishing
  stabilisation (as the Hertz disk under force control): a spring
  ``k (1 - t) u`` on the plate's cells, ``k = stabilisation * E / R^2``,
  carries part of the load at the steps ``t < 1`` (the first iterate moves the
  plate toward the load by about ``P0 / E``, so the lower half of the hole
  presses on the pin and the solver finds the contact) and is exactly zero at
  the last step ``t = 1``: the figures have no stabilisation in them (the
  force balance ``equilibrium_error`` is the check). Hence ``steps >= 2``;
  the figures of the neat fit at a load ``P0`` are those of ``t = 1``.

Contact angle: the hole bears on the pin's bottom, the point ``(0, -R)``
facing away from the loaded edge. Reference polar angle of a hole point,
measured from that bottom point: ``theta = atan2(X, -Y)`` (0 at the bottom,
90 degrees at the side, 180 at the top), in the undeformed configuration as
in the paper. The contact angle is the ``theta`` where the contact zone that
starts at the bottom ends; the whole contact arc is twice that.

Pin geometry and sign convention of the gap: :class:`~fenics_contact.obstacles.Ball`
with ``body_outside=True``: ``g = R - |x|`` (> 0 = penetration).
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...compat import function_space
from ...factory import contact_surface
from ...laws import ContactLaw
from ...materials import PLANES, LinearElastic
from ...obstacles import Cylinder
from ...problem import Dirichlet
from ..meshes import pin_plate
from . import Option, Setup, Stabilised, nonnegative, poisson, positive, refuse_refined

__all__ = [
    "R", "HALF_WIDTH", "BELOW", "ABOVE", "E", "NU", "P0", "H_CONTACT", "STABILISATION", "DEFAULT_K", "LOADED_FORCE",
    "pressure_along_pin", "contact_angle", "GAPS", "OPTIONS", "build", "BENCH"
]

R, HALF_WIDTH, BELOW, ABOVE = 1.0, 5.0, 5.0, 5.0
E, NU, P0 = 1000.0, 0.3, 10.0
H_CONTACT = R / 50  # mesh size at the hole, refinement 0
STABILISATION = 1.0  # the vanishing spring's k R^2 / E (module docstring)
DEFAULT_K = 1e6  # penalty scale ~ 20 E / h_contact
LOADED_FORCE = P0 * HALF_WIDTH  # resultant of the traction on the half model's top edge (per unit thickness)


def pressure_along_pin(contact) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(theta_deg, X, gap, pressure)`` at the hole's vertices, ascending in ``theta`` (gathered on every rank).

    ``theta`` in degrees from the pin's bottom ``(0, -R)``, reference configuration.
    """
    X, g, p = contact.surface_values()
    theta = np.degrees(np.arctan2(X[:, 0], -X[:, 1]))
    order = np.argsort(theta, kind="stable")
    return theta[order], X[order], g[order], p[order]


def contact_angle(theta: np.ndarray, p: np.ndarray, rel_tol: float = 1e-8) -> float:
    """End of the contact zone that starts at ``theta[0]`` (``theta`` ascending, ``p`` the pressure), in
    the units of ``theta``.

    Loaded: ``p > rel_tol * max(p)``. Near a smooth contact edge ``p^2`` is
    linear in the distance to it. The last loaded vertex carries the reaction
    of a tributary length that straddles the edge, so its value is not on that
    trend: the edge is extrapolated linearly in ``p^2`` from the two loaded
    vertices before it, and clamped to the interval between the last loaded
    vertex and the first unloaded one (the discrete edge).
    """
    loaded = p > rel_tol * p.max()
    if not loaded[0]:
        raise ValueError("pin: no contact at the pin's bottom (theta = 0)")
    unloaded = np.flatnonzero(~loaded)
    if not unloaded.size:
        return float(theta[-1])
    i = unloaded[0] - 1  # last loaded vertex of the zone
    if i < 2:
        return float(theta[i])
    (t1, t2), (q1, q2) = theta[i - 2 : i], p[i - 2 : i] ** 2
    edge = t2 + q2 * (t2 - t1) / (q1 - q2) if q1 > q2 else theta[i + 1]
    return float(np.clip(edge, theta[i], theta[i + 1]))


GAPS = ("linearized", "current")


OPTIONS = {
    "h_contact": Option("mesh size at the hole (length; default: R / 50, halved per --refinement)"),
    "R": Option("radius of the hole and pin (length)", below=("half_width", "below", "above")),
    "half_width": Option(f"plate's half-width (length; default: {HALF_WIDTH / R:g} R)"),
    "below": Option(f"plate's extent below the pin's centre (length; default: {BELOW / R:g} R)"),
    "above": Option(f"plate's extent above the pin's centre (length; default: {ABOVE / R:g} R)"),
    "E": Option("plate's Young's modulus (stress)"),
    "nu": Option("plate's Poisson's ratio", "poisson"),
    "P0": Option("traction on the plate's top (stress)"),
    "stabilisation": Option("the vanishing spring's k R^2 / E (dimensionless)", "nonnegative"),
}


def build(law: ContactLaw, quadrature: str = "nodal", refinement: int = 0, h_contact: float | None = None,
          steps: int = 2, gap: str = "linearized", comm: MPI.Comm = MPI.COMM_WORLD, R: float = R,
          half_width: float | None = None, below: float | None = None, above: float | None = None, E: float = E,
          nu: float = NU,
          P0: float = P0, stabilisation: float = STABILISATION, plane: str = "strain") -> Setup:
    """``refinement`` halves the mesh size at the hole (``h_contact``, default ``R/50``) that many times; ``steps``
    load steps (>= 2: the vanishing spring acts before the last); ``gap``: ``linearized`` (small displacements,
    default) or ``current`` (exact gap of the deformed position). The plate ``2 half_width`` wide, from ``below``
    under to ``above`` over the pin's centre (defaults: the module constants in units of ``R``), the hole
    of radius ``R``, ``E``, ``nu``, the traction ``P0`` on its top; ``stabilisation``: the vanishing spring's
    ``k R^2 / E`` (module docstring). Defaults: the module constants. ``plane``: ``strain`` (the
    paper's, default; its figures are plane strain) or ``stress``."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    positive(R=R, half_width=half_width, below=below, above=above, E=E, P0=P0, h_contact=h_contact)
    # the plate's size in units of the hole's radius: a larger pin keeps the same plate around it
    half_width, below, above = (v * R / globals()["R"] if g is None else g for v, g in
                                ((HALF_WIDTH, half_width), (BELOW, below), (ABOVE, above)))
    nonnegative(stabilisation=stabilisation)
    poisson(nu=nu)
    if not (R < half_width and R < below and R < above):
        raise ValueError(f"pin: the hole (R = {R}) must lie inside the plate (half_width {half_width}, below {below}, "
                         f"above {above})")
    h_contact = R / 50 if h_contact is None else h_contact
    if gap not in GAPS:
        raise ValueError(f"pin: gap must be one of {GAPS}, got {gap!r}")
    if not (isinstance(refinement, (int, np.integer)) and refinement >= 0):
        raise ValueError(f"pin: refinement must be an integer >= 0, got {refinement!r}")
    if not (isinstance(steps, (int, np.integer)) and steps >= 2):
        raise ValueError(f"pin: steps must be an integer >= 2 (the vanishing spring acts before the last step), "
                         f"got {steps!r}")
    if not (0 < h_contact <= R / 4):
        raise ValueError(f"pin: h_contact must be in (0, R/4 = {R / 4}], got {h_contact!r}")
    # At least (2 pi R band) / h^2 unknowns in the band of size h around the hole (2.0 x that at refinement 1,
    # 1.6 at 2: measured), band = R / 10
    zone = math.log10(2 * math.pi * R * (R / 10) / h_contact**2)
    refuse_refined("h_contact", h_contact, refinement, zone + 2 * math.log10(2) * int(refinement), 2,
                   2 * math.log10(2), comm)
    h = h_contact / 2**refinement
    mesh, _, facet_tags = pin_plate(comm, R, half_width, below, above, h_contact=h, h_far=R / 2, band=R / 10)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    dirichlet = [Dirichlet.on_facets(V, facet_tags, "symmetry", 0)]
    pin = Cylinder([0.0, 0.0], R, body_outside=True)
    contact = contact_surface(u, facet_tags, "contact", pin, law, load, quadrature,
                              linearized=gap == "linearized")
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags, subdomain_id=facet_tags["top"])
    traction = ufl.as_vector([0.0, P0])
    # from rest: the vanishing spring on the plate (module docstring)
    problem = Stabilised(u, LinearElastic(E, nu, plane=plane), load, dirichlet, [contact], [(traction, ds)],
                         stabilisation * E / R**2, ufl.dx(domain=mesh))

    def figures() -> dict:
        theta, _, g, p = pressure_along_pin(contact)
        force = contact.total_force()
        applied = float(load.value) * P0 * half_width  # the traction's resultant on the half model's top
        return {"contact_angle_deg": contact_angle(theta, p), "p_max": float(p.max()),
                "p_bottom": float(p[0]),
                "total_force_y": float(force[1]), "total_force_x": float(force[0]), "applied_force": applied,
                "equilibrium_error": abs(force[1] + applied) / applied, "max_penetration": float(g.max()),
                "contact_nodes": int(np.count_nonzero(p > 1e-8 * p.max())), "h_contact": h}

    params = {"E": E, "nu": nu, "P0": P0, "R": R, "plate": [2 * half_width, below + above], "clearance": 0.0,
              "stabilisation": stabilisation,
              "gap": gap,
              "h_contact": h, "refinement": refinement, "steps": steps, "quadrature": quadrature,
              "plane": plane, "model": f"half plate (symmetry x = 0), plane {plane}, linear elasticity"}
    return Setup("pin", problem, [contact], np.linspace(0, 1, steps + 1)[1:].tolist(), params, figures,
                 [u, contact.gap_out, contact.pressure_out])


# Benchmark (fenics_contact.app.bench): SNES VI needs an axis-aligned half-plane (the pin is a circle), so the error is
# the contact angle's relative distance from the exact-constraint solution on the same mesh, taken as the limit of
# converged augmentation (the last converged "auglag augmented" run: tolerance 1e-10). Mesh discretisation error
# (the angle moves by ~0.1 degree from refinement 0 to 2) is not in this figure: it compares the methods.
BENCH = {"error": "limit_gap", "reference": "auglag augmented", "value": "contact_angle_deg",
         "figures": ["p_max"], "target": 1e-4, "K": DEFAULT_K,
         "mesh": ("refinement", {"quick": [0, 1], "full": [0, 1, 2]}),
         "methods": ["penalty", "cross", "auglag"], "demo_args": []}
