"""``slab``: elastic slab pressed and pushed on a rigid plate with Coulomb friction (Renaud & Feng 2003).

Half slab by symmetry, ``[0, 40] x [0, 40]``, E = 13000, nu = 0.2, linear
elasticity, plane strain, Q1 quadrilaterals (the paper's mesh: 32 x 16 cells,
561 nodes; ``refinement`` halves the cells that many times).

- Symmetry side ``x = 0`` (the paper's ED): ``u_x = 0``, ``u_y`` free.
- Top ``y = 40`` (GE): pressure 5, i.e. traction ``(0, -5)``.
- Free side ``x = 40`` (GA): pressure 10, i.e. traction ``(-10, 0)``: it pushes
  the slab toward the symmetry plane.
- Base ``y = 0`` (AD): rigid half-plane ``y <= 0`` with friction; the slab has no
  other vertical support. ``A = (40, 0)`` is the free bottom corner.

Sign convention of the figures: ``ux_A``, ``uy_A`` are the displacement
components of ``A`` along ``+x`` (from the symmetry plane toward the free
side) and ``+y`` (up, away from the plate). The side load makes ``ux_A < 0``.
With ``mu = 0`` the stress is uniform (``sigma_xx = -10``, ``sigma_yy = -5``) and
``ux_A = (1-nu^2)/E (sigma_xx - nu/(1-nu) sigma_yy) * 40 = -0.0258462``, ``uy_A = 0``
(``plane="stress"``: ``ux_A = (sigma_xx - nu sigma_yy)/E * 40``).

Zones (``zones``): lengths along the base, from the free corner ``A`` inward,
of the separated, sliding and sticking parts; each base vertex counts with its
tributary length (half of each adjacent edge) and the state given by the
contact surface's ``friction_profile()`` (0 open, 1 slip, 2 stick). A
frictionless surface without that method reports every loaded vertex as
sliding (``|t| = 0 = mu p``) and the others as open.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...condensed import CondensedContact
from ...factory import contact_surface
from ...friction import FrictionalContact
from ...laws import ContactLaw
from ...materials import PLANES
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import rectangle
from . import Option, Setup, nonnegative, poisson, positive, refuse_size

__all__ = [
    "WIDTH", "HEIGHT", "E", "NU", "TOP_PRESSURE", "SIDE_PRESSURE", "NX", "NY", "SIGMA_XX", "SIGMA_YY",
    "UX_A_FRICTIONLESS", "TOP_LOAD", "SIDE_LOAD", "STATES", "profile", "tributary_lengths", "zones", "build", "BENCH",
    "ux_a_frictionless", "K_DEMO", "OMEGA_T", "LAM0", "SOLVER_OPTIONS", "OPTIONS"
]

WIDTH, HEIGHT, E, NU = 40.0, 40.0, 13000.0, 0.2
TOP_PRESSURE, SIDE_PRESSURE = 5.0, 10.0
NX, NY = 32, 16
SIGMA_XX, SIGMA_YY = -SIDE_PRESSURE, -TOP_PRESSURE
UX_A_FRICTIONLESS = (1 - NU**2) / E * (SIGMA_XX - NU / (1 - NU) * SIGMA_YY) * WIDTH
UX_A_FRICTIONLESS_PLANE_STRESS = (SIGMA_XX - NU * SIGMA_YY) / E * WIDTH
TOP_LOAD, SIDE_LOAD = TOP_PRESSURE * WIDTH, SIDE_PRESSURE * HEIGHT  # per unit thickness
STATES = ("separated", "sliding", "sticking")
# Demo defaults of the regularized friction methods (demos/slab.py; a resting body, g = 0 everywhere at t = 0):
# the normal penalty K (BENCH's), the tangential penalty omega_t = E / h (stiffer makes Newton cycle), and the
# initial normal multiplier lam0 (auglag; cross: F_hat) = the mean contact pressure: penalty-type laws are open at
# g = 0 (no normal stiffness: the first Jacobian is singular), and lam0 > 0 closes them.
K_DEMO, OMEGA_T, LAM0 = 1e5, E / (WIDTH / NX), TOP_PRESSURE
SOLVER_OPTIONS = {"snes_linesearch_type": "bt", "snes_max_it": 200, "snes_rtol": 1e-10}  # see BENCH's note


def profile(contact) -> dict:
    """The base's profile (``x``, ``gap``, ``pressure``, ``traction``, ``state``), sorted by ``x``, on every rank."""
    if isinstance(contact, (FrictionalContact, CondensedContact)):
        return contact.friction_profile()
    x, g, p = contact.surface_values()
    loaded = p > 1e-10 * max(float(np.max(np.abs(p))), 1e-300)
    return {"x": x, "gap": g, "pressure": p, "traction": np.zeros_like(p), "state": loaded.astype(int)}


def tributary_lengths(s: np.ndarray) -> np.ndarray:
    """Half of each adjacent edge of the sorted positions ``s`` (the nodal quadrature weights of a line)."""
    d = np.diff(s)
    w = np.zeros_like(s)
    w[:-1] += d / 2
    w[1:] += d / 2
    return w


def ux_a_frictionless(width: float = WIDTH, E: float = E, nu: float = NU, top_pressure: float = TOP_PRESSURE,
                      side_pressure: float = SIDE_PRESSURE, plane: str = "strain") -> float:
    """``u_x(A)`` of the frictionless slab (uniform stress ``-side_pressure``, ``-top_pressure``; plane strain or
    stress)."""
    if plane == "stress":
        return (-side_pressure + nu * top_pressure) / E * width
    return (1 - nu**2) / E * (-side_pressure + nu / (1 - nu) * top_pressure) * width


def zones(x: np.ndarray, state: np.ndarray, width: float = WIDTH) -> dict:
    """Zone lengths from the free corner inward, boundaries (distance from A, at mid-edges) and the pattern.

    ``x``: base vertex coordinates sorted by ``x``; ``state``: 0 open, 1 slip, 2 stick.
    """
    s = width - x[:, 0]  # distance from the free corner A
    order = np.argsort(s)
    s, state = s[order], np.asarray(state)[order]
    w = tributary_lengths(s)
    lengths = {name: float(np.sum(w[state == k])) for k, name in enumerate(STATES)}
    change = np.flatnonzero(state[1:] != state[:-1])
    bounds = [float((s[i] + s[i + 1]) / 2) for i in change]
    pattern = [STATES[state[0]]] + [STATES[state[i + 1]] for i in change]
    return {**lengths, "boundaries": bounds, "pattern": pattern}


OPTIONS = {
    "width": Option("half slab width (length)"),
    "height": Option("slab height (length)"),
    "E": Option("Young's modulus (stress)"),
    "nu": Option("Poisson's ratio", "poisson"),
    "top_pressure": Option("pressure on the slab's top (stress)"),
    "side_pressure": Option("pressure on the slab's free side (stress)", "nonnegative"),
}


def build(law: ContactLaw, quadrature: str = "nodal", nx: int = NX, ny: int = NY, refinement: int = 0,
          steps: int = 1, comm: MPI.Comm = MPI.COMM_WORLD, plane: str = "strain", width: float = WIDTH,
          height: float = HEIGHT, E: float = E, nu: float = NU, top_pressure: float = TOP_PRESSURE,
          side_pressure: float = SIDE_PRESSURE, model: str = "linear") -> Setup:
    """``nx`` x ``ny`` Q1 cells times ``2**refinement`` each way; ``steps`` proportional load steps; ``plane``:
    ``strain`` (the paper's) or ``stress``; the half slab ``width`` x ``height`` (``E``, ``nu``),
    ``top_pressure`` on its top, ``side_pressure`` on its free side (defaults: the module constants, the
    paper's); ``model``: ``linear`` (the paper's) or ``neohookean``."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    if model not in MODELS:
        raise ValueError(f"slab model must be one of {sorted(MODELS)}, got {model!r}")
    positive(width=width, height=height, E=E, top_pressure=top_pressure)
    nonnegative(side_pressure=side_pressure)
    poisson(nu=nu)
    if int(refinement) < 0:
        raise ValueError(f"refinement must be >= 0, got {refinement!r}")
    if int(steps) < 1:
        raise ValueError(f"steps must be >= 1, got {steps!r}")
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    base = math.log10(2 * int(nx) * int(ny))  # 2 nx ny unknowns at least, times 4 per refinement
    refuse_size("refinement", refinement, base + 2 * math.log10(2) * int(refinement),
                lambda most: f"0 to {max(math.floor((most - base) / (2 * math.log10(2))), 0)}", comm)
    nx, ny = int(nx) * 2**refinement, int(ny) * 2**refinement
    mesh, _, facet_tags = rectangle(comm, width, height, nx, ny, quadrilateral=True)
    u, V = unknown(mesh, 1, law)  # displacement, or (displacement, pressure) for method lagrange
    load = fem.Constant(mesh, 0.0)
    symmetry_x = Dirichlet.on_facets(V, facet_tags, "left", 0)
    dirichlet = [symmetry_x]
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags)
    tractions = [(fem.Constant(mesh, np.array([0.0, -top_pressure])), ds(facet_tags["top"])),
                 (fem.Constant(mesh, np.array([-side_pressure, 0.0])), ds(facet_tags["right"]))]
    material = MODELS[model](E, nu, plane=plane)
    contact = contact_surface(u, facet_tags, "bottom", HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                              material=material)
    problem = ContactProblem(u, material, load, dirichlet, [contact], tractions)
    top_load, side_load = top_pressure * width, side_pressure * height  # per unit thickness
    ux_free = ux_a_frictionless(width, E, nu, top_pressure, side_pressure, plane)

    # The free bottom corner A: the rank owning its vertex reports it (max over ranks of a masked value).
    disp = contact.displacement_out  # u, or its collapsed copy when u is mixed
    X = disp.function_space.tabulate_dof_coordinates()
    corner = np.flatnonzero(np.isclose(X[:, 0], width) & np.isclose(X[:, 1], 0.0))
    bs = disp.function_space.dofmap.index_map_bs

    def figures() -> dict:
        prof = profile(contact)
        t = float(load.value)
        found = comm.allreduce(len(corner), op=MPI.MAX) > 0
        contact.update_output()
        ua = np.array([disp.x.array[corner[0] * bs + i] for i in range(2)]) if len(corner) else np.full(2, -np.inf)
        ua = np.array([comm.allreduce(v, op=MPI.MAX) for v in ua]) if found else np.full(2, np.nan)
        w = tributary_lengths(prof["x"][:, 0])
        normal, tangential = float(np.sum(w * prof["pressure"])), float(np.sum(w * prof["traction"]))
        symmetry = problem.reaction(symmetry_x.dofs)
        z = zones(prof["x"], prof["state"], width)
        return {"ux_A": float(ua[0]), "uy_A": float(ua[1]),
                "ux_A_frictionless": t * ux_free,
                "zones": {k: z[k] for k in STATES}, "zone_boundaries": z["boundaries"], "zone_pattern": z["pattern"],
                "normal_force": normal, "tangential_force": tangential, "symmetry_reaction": symmetry,
                "normal_equilibrium_error": abs(normal - t * top_load) / top_load,
                "tangential_equilibrium_error": abs(tangential + symmetry - t * side_load) / max(side_load, top_load),
                "max_penetration": float(np.max(prof["gap"])), "max_pressure": float(np.max(prof["pressure"])),
                "base": {k: np.asarray(v).tolist() for k, v in prof.items()}}

    params = {"E": E, "nu": nu, "width": width, "height": height, "top_pressure": top_pressure,
              "side_pressure": side_pressure, "nx": nx, "ny": ny, "refinement": refinement, "steps": steps,
              "quadrature": quadrature, "plane": plane, "material": model,
              "model": f"half slab (symmetry u_x = 0 on x = 0), Q1, plane {plane}"}
    extra = [contact.traction_out] if isinstance(contact, (FrictionalContact, CondensedContact)) else []
    return Setup("slab", problem, [contact], [(i + 1) / steps for i in range(steps)], params, figures,
                 [disp, contact.gap_out, contact.pressure_out, *extra])


# Benchmark (fenics_contact.app.bench): mu = 0.4; no closed form with friction, so the error is u_x(A)'s relative
# distance from the exact condensed Coulomb method on the same mesh ("limit_gap", reference "coulomb"). Built by
# the harness (the demo has no PETSc options of its own): backtracking line search and a tight rtol, as
# scripts/slab_friction.py, since a tangential penalty omega_t = K >> E/h makes the default line search cycle.
# Penalty (K <g>) fails here by design of the scene: the slab rests on the plate at g = 0, where the penalty's
# tangent is 0 and the first Jacobian is singular (ill_conditioning); it stays in the sweep to show it. Normal
# compliance c_n <g> with the Coulomb bound (omega_t = c_n) is the regularized friction method that runs.
BENCH = {"error": "limit_gap", "reference": "coulomb", "value": "ux_A", "figures": ["uy_A"], "target": 1e-3,
         "K": 1e5, "mesh": ("refinement", {"quick": [0], "full": [0, 1]}),
         "methods": ["penalty", "compliance", "coulomb"], "build": {}, "demo_args": ["--mu", "0.4"],
         "options": {"snes_linesearch_type": "bt", "snes_max_it": 200, "snes_rtol": 1e-10},
         "quick_sweep": {"penalty": (0,), "other": (-1, 0, 1, 2)}}
