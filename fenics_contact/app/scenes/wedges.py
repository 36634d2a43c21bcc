"""``wedges``: an elastic block pushed up an elastic incline (wedge) of angle ``alpha`` with Coulomb friction ``mu``
(2D, plane strain, two deformable bodies, node-to-segment friction).

The wedge is a rectangle ``2 L x D`` whose top, the incline, rises toward +x at the angle ``alpha`` (its bottom
fixed); the block ``2 b x h`` rests on it (placed ``1e-9 L`` into it, so that every interface point is closed at
the first iterate: the block is held normally by the contact alone). ``t`` in (0, 1]: the block's top carries
the vertical force ``N`` (a uniform traction, force control); then ``t`` in (1, 2]: its left face is pushed
horizontally by ``u_x = (t - 1) push`` (its vertical motion free) so that it slides up the incline. Once the
whole interface slides, the block's equilibrium (normal force along the incline's normal, friction ``mu`` times
it down the incline) gives the horizontal force

    H / N = (mu + tan alpha) / (1 - mu tan alpha)

(Tresca's bound ``s`` instead, on the block's bottom ``2 b``: ``H / N = tan alpha + s / (load cos alpha)``,
with ``N = load 2 b``; ``H``: the push, from the block's equilibrium: minus the contact force's x component).
The figure ``ratio`` is ``H / N`` at the last step; ``ratio_error`` its relative distance from the formula.
The deformation turns the interface by about the elastic strain (~1e-3
with the defaults): the formula's departure.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...compat import function_space
from ...factory import two_body_surfaces
from ...friction import SLIP, Friction
from ...laws import ContactLaw, ExactCoulomb
from ...materials import LinearElastic
from ...problem import ContactProblem, Dirichlet
from ..meshes.mindlin import block_on_incline
from . import Option, Setup, poisson, positive

__all__ = ["OPTIONS", "build", "wedge_ratio", "tresca_wedge_ratio", "SLIDE_STEPS", "PREDICTOR", "DEFAULT_K", "BENCH"]

E, NU = 1000.0, 0.3
ALPHA = 20.0  # degrees
LOAD = 1.0  # the vertical traction on the block's top (N = LOAD * 2 b): strains ~1e-3
LENGTH = 1.0  # the wedge's length L (its depth 0.4 L; the block 0.25 L wide and high)
PUSH = 0.05  # horizontal displacement of the pushed face at t = 2 (>> the elastic slip mu p / omega_t)
DEFAULT_K = 1e6
DEFAULT_OMEGA_T = 1e4  # ~ E / h: the elastic slip mu p / omega_t ~ 3e-5 is 1e-3 of the push
# The push's load steps and each step's start: from the last state, Newton on the penalty law fails on the whole
# interface's change from stick to slip (2 steps: 124 iterations accepted, 337 spent in 9 failed attempts); from
# the linear extrapolation of the last two states (the solver's secant predictor) in 12 steps, 39 iterations in
# 13 steps and no failed attempt (4 steps: 37 in 5; 8: 45 in 9; 16: 46 in 17), the same H / N to 1e-9.
SLIDE_STEPS = 12
PREDICTOR = "secant"


def wedge_ratio(mu: float, alpha_deg: float) -> float:
    """``(mu + tan alpha) / (1 - mu tan alpha)``: horizontal over vertical force to push a block up the incline."""
    t = math.tan(math.radians(alpha_deg))
    if mu * t >= 1.0:
        raise ValueError(f"mu tan(alpha) must be < 1 (self-locking otherwise), got mu={mu}, alpha={alpha_deg}")
    return (mu + t) / (1 - mu * t)


def tresca_wedge_ratio(s: float, load: float, alpha_deg: float) -> float:
    """``tan alpha + s / (load cos alpha)``: horizontal over vertical force to push a block whose whole bottom
    slides with Tresca's bound ``s`` up the incline, under the vertical traction ``load`` on its top."""
    a = math.radians(alpha_deg)
    return math.tan(a) + s / (load * math.cos(a))


OPTIONS = {
    "alpha": Option("wedge angle (degrees, in [0, 60])", (0.0, 60.0)),
    "E": Option("Young's modulus of the block and the wedge (stress)"),
    "nu": Option("Poisson's ratio of the block and the wedge", "poisson"),
    "load": Option("vertical traction on the block's top (stress)"),
    "push": Option("horizontal displacement of the block's left face at the end (length)"),
    "length": Option(f"the wedge's length L; its depth 0.4 L, the block 0.25 L wide and high (length; default: "
                     f"{LENGTH:g})"),
}


def build(law: ContactLaw, alpha: float = ALPHA, E: float = E, nu: float = NU, load: float = LOAD,
          push: float = PUSH, slide_steps: int = SLIDE_STEPS, comm: MPI.Comm = MPI.COMM_WORLD,
          mesh: tuple = ((40, 8), (12, 6)), length: float = LENGTH) -> Setup:
    """``law``: a Coulomb (``mu > 0``) or Tresca (``tresca > 0``) :class:`~fenics_contact.friction.Friction`;
    ``alpha`` in degrees, in [0, 60]; ``load`` the vertical traction on the block's top; ``push`` the horizontal
    displacement of its left face at the end; ``slide_steps`` load steps of the push (solve them with the
    predictor :data:`PREDICTOR`); ``mesh`` the (nx, ny) of the wedge and the block; ``length`` the wedge's length
    ``L`` (its depth ``0.4 L``, the block ``0.25 L`` wide and high)."""
    positive(E=E, load=load, push=push, length=length)
    poisson(nu=nu)
    alpha = float(alpha)
    if not (math.isfinite(alpha) and 0.0 <= alpha <= 60.0):
        raise ValueError(f"alpha must be in [0, 60] degrees, got {alpha!r}")
    # The push prescribes u_x on the block's lower left corner, a slave vertex with the largest pressure (4 times
    # the mean); method coulomb gives a slave vertex with a prescribed component no friction (condensed.
    # two_body_solver), which takes 6 % (alpha 0) to 8 % (alpha 20 deg) off H / N. With that corner's u_x free
    # it matches the closed form to 1e-12 at both angles.
    if isinstance(law, ExactCoulomb):
        raise ValueError("method coulomb is refused on wedges: the push prescribes u_x at the block's lower corner, "
                         "a slave vertex, and coulomb gives such a vertex no friction (H / N 6-8 % low); use "
                         "penalty, auglag, cross or nitsche")
    bound = law.scalars.get("mu", law.scalars.get("tresca", 0.0)) if isinstance(law, Friction) else 0.0
    if not bound > 0 or "c_t" in law.scalars:
        raise ValueError(f"wedges needs a Coulomb (mu > 0, e.g. --mu 0.3) or Tresca (tresca > 0) friction law, "
                         f"got {law!r}")
    if int(slide_steps) < 1:
        raise ValueError(f"slide_steps must be >= 1, got {slide_steps!r}")
    mu = float(law.scalars["mu"]) if "mu" in law.scalars else None
    # refuses a self-locking wedge before any work
    reference = wedge_ratio(mu, alpha) if mu is not None else tresca_wedge_ratio(bound, load, alpha)
    L, D, b, h = length, 0.4 * length, 0.25 * length, 0.25 * length
    msh, cells, facets = block_on_incline(comm, math.radians(alpha), L, D, b, h, *mesh, overlap=1e-9 * L)
    V = function_space(msh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    t = fem.Constant(msh, 0.0)
    left = fem.locate_dofs_topological(V.sub(0), 1, facets.find("block_left"))  # pushed along x
    dirichlet = [Dirichlet.on_facets(V, facets, "wedge_bottom", 0), Dirichlet.on_facets(V, facets, "wedge_bottom", 1),
                 Dirichlet(V.sub(0), left, 1.0, ([0.0, 1.0, 2.0], [0.0, 0.0, push]))]
    material = LinearElastic(E, nu)
    contact = two_body_surfaces(u, facets, "block_bottom", "wedge_top", lambda: law, t, "nodal", name="incline",
                                material=material)[0]
    ds = ufl.Measure("ds", domain=msh, subdomain_data=facets.meshtags)
    # Tractions are scaled by t: this vector times t is (0, -load) from t = 1 on.
    top = ufl.as_vector((0.0, -load * ufl.min_value(t, 1.0) / t))
    problem = ContactProblem(u, material, t, dirichlet, [contact], [(top, ds(facets["block_top"]))])
    top_length = 2 * b  # the top is turned, its length is 2 b; the traction is per unit length
    N = load * top_length
    loads = [1.0] + [1.0 + (i + 1) / slide_steps for i in range(slide_steps)]

    def figures() -> dict:
        prof = contact.friction_profile()
        closed = prof["state"] > 0
        force = contact.total_force() + contact.tangential_force()  # of the wedge on the block
        # The push H from the block's equilibrium: the pushed face's reaction also holds the contact force of the
        # slave vertex at its lower corner, so the contact force is the exact measure.
        H = -float(force[0])
        return {"N": N, "H": H, "ratio": H / N, "ratio_reference": reference,
                "ratio_error": abs(H / N - reference) / reference,
                "slip_fraction": float(np.mean(prof["state"][closed] == SLIP)) if closed.any() else 0.0,
                "contact_force_y": float(force[1]), "vertical_equilibrium_error": abs(float(force[1]) - N) / N}

    params = {"E": E, "nu": nu, "alpha": alpha, **({"mu": mu} if mu is not None else {"tresca": bound}),
              "load": load, "push": push, "N": N,
              "mesh": [list(m) for m in mesh], "quadrature": "nodal",
              "model": "block pushed up an incline, two deformable bodies, node-to-segment "
                       f"{'Coulomb' if mu is not None else 'Tresca'} friction"}
    return Setup("wedges", problem, [contact], loads, params, figures,
                 [u, contact.gap_out, contact.pressure_out, contact.traction_out, contact.state_out])


# Speed against accuracy (fenics_contact.app.bench): H / N against its closed form, the demo's defaults (920 dofs, the
# push in SLIDE_STEPS steps from the secant predictor); every friction-capable law the capability matrix offers on
# two bodies in 2D except method coulomb (refused by build: see there).
BENCH = {"error": "ratio_error", "value": "ratio", "figures": ["slip_fraction", "vertical_equilibrium_error"],
         "target": 0.01, "K": DEFAULT_K, "mesh": None,
         "methods": ["penalty", "cross", "auglag", "compliance", "nitsche"],
         "axes": {"kind": "two-body", "dim": 2, "friction": True}, "demo_args": [],
         "quick_sweep": {"penalty": (-1, 0, 1), "other": (0,)}, "quadratures": ["nodal"]}
