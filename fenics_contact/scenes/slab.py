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

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ..compat import function_space
from ..condensed import step_solver_for
from ..factory import contact_surface
from ..laws import ContactLaw
from ..materials import PLANES, LinearElastic
from ..meshes import BOTTOM, LEFT, RIGHT, rectangle
from ..meshes import RECT_TOP as TOP
from ..obstacles import HalfPlane
from ..problem import ContactProblem, Dirichlet
from . import Setup

__all__ = [
    "WIDTH", "HEIGHT", "E", "NU", "TOP_PRESSURE", "SIDE_PRESSURE", "NX", "NY", "SIGMA_XX", "SIGMA_YY",
    "UX_A_FRICTIONLESS", "TOP_LOAD", "SIDE_LOAD", "STATES", "profile", "tributary_lengths", "zones", "build", "BENCH"
]

WIDTH, HEIGHT, E, NU = 40.0, 40.0, 13000.0, 0.2
TOP_PRESSURE, SIDE_PRESSURE = 5.0, 10.0
NX, NY = 32, 16
SIGMA_XX, SIGMA_YY = -SIDE_PRESSURE, -TOP_PRESSURE
UX_A_FRICTIONLESS = (1 - NU**2) / E * (SIGMA_XX - NU / (1 - NU) * SIGMA_YY) * WIDTH
UX_A_FRICTIONLESS_PLANE_STRESS = (SIGMA_XX - NU * SIGMA_YY) / E * WIDTH
TOP_LOAD, SIDE_LOAD = TOP_PRESSURE * WIDTH, SIDE_PRESSURE * HEIGHT  # per unit thickness
STATES = ("separated", "sliding", "sticking")


def profile(contact) -> dict:
    """The base's profile (``x``, ``gap``, ``pressure``, ``traction``, ``state``), sorted by ``x``, on every rank."""
    if hasattr(contact, "friction_profile"):
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


def zones(x: np.ndarray, state: np.ndarray) -> dict:
    """Zone lengths from the free corner inward, boundaries (distance from A, at mid-edges) and the pattern.

    ``x``: base vertex coordinates sorted by ``x``; ``state``: 0 open, 1 slip, 2 stick.
    """
    s = WIDTH - x[:, 0]  # distance from the free corner A
    order = np.argsort(s)
    s, state = s[order], np.asarray(state)[order]
    w = tributary_lengths(s)
    lengths = {name: float(np.sum(w[state == k])) for k, name in enumerate(STATES)}
    change = np.flatnonzero(state[1:] != state[:-1])
    bounds = [float((s[i] + s[i + 1]) / 2) for i in change]
    pattern = [STATES[state[0]]] + [STATES[state[i + 1]] for i in change]
    return {**lengths, "boundaries": bounds, "pattern": pattern}


def build(law: ContactLaw, quadrature: str = "nodal", nx: int = NX, ny: int = NY, refinement: int = 0,
          steps: int = 1, comm: MPI.Comm = MPI.COMM_WORLD, plane: str = "strain") -> Setup:
    """``nx`` x ``ny`` Q1 cells times ``2**refinement`` each way; ``steps`` proportional load steps; ``plane``:
    ``strain`` (the paper's) or ``stress``."""
    if int(refinement) < 0:
        raise ValueError(f"refinement must be >= 0, got {refinement!r}")
    if int(steps) < 1:
        raise ValueError(f"steps must be >= 1, got {steps!r}")
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    nx, ny = int(nx) * 2**refinement, int(ny) * 2**refinement
    mesh, _, facet_tags = rectangle(comm, WIDTH, HEIGHT, nx, ny, quadrilateral=True)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    symmetry_x = Dirichlet.on_facets(V, facet_tags, LEFT, 0)
    dirichlet = [symmetry_x]
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags)
    tractions = [(fem.Constant(mesh, np.array([0.0, -TOP_PRESSURE])), ds(TOP)),
                 (fem.Constant(mesh, np.array([-SIDE_PRESSURE, 0.0])), ds(RIGHT))]
    contact = contact_surface(u, facet_tags, BOTTOM, HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature)
    problem = ContactProblem(u, LinearElastic(E, NU, plane=plane), load, dirichlet, [contact], tractions,
                             step_solver=step_solver_for([contact]))
    ux_a_frictionless = UX_A_FRICTIONLESS if plane == "strain" else UX_A_FRICTIONLESS_PLANE_STRESS

    # The free bottom corner A: the rank owning its vertex reports it (max over ranks of a masked value).
    corner = np.flatnonzero(np.isclose(V.tabulate_dof_coordinates()[:, 0], WIDTH)
                            & np.isclose(V.tabulate_dof_coordinates()[:, 1], 0.0))
    bs = V.dofmap.index_map_bs

    def figures() -> dict:
        prof = profile(contact)
        t = float(load.value)
        found = comm.allreduce(len(corner), op=MPI.MAX) > 0
        ua = np.array([u.x.array[corner[0] * bs + i] for i in range(2)]) if len(corner) else np.full(2, -np.inf)
        ua = np.array([comm.allreduce(v, op=MPI.MAX) for v in ua]) if found else np.full(2, np.nan)
        w = tributary_lengths(prof["x"][:, 0])
        normal, tangential = float(np.sum(w * prof["pressure"])), float(np.sum(w * prof["traction"]))
        symmetry = problem.reaction(symmetry_x.dofs)
        z = zones(prof["x"], prof["state"])
        return {"ux_A": float(ua[0]), "uy_A": float(ua[1]),
                "ux_A_frictionless": t * ux_a_frictionless,
                "zones": {k: z[k] for k in STATES}, "zone_boundaries": z["boundaries"], "zone_pattern": z["pattern"],
                "normal_force": normal, "tangential_force": tangential, "symmetry_reaction": symmetry,
                "normal_equilibrium_error": abs(normal - t * TOP_LOAD) / TOP_LOAD,
                "tangential_equilibrium_error": abs(tangential + symmetry - t * SIDE_LOAD) / SIDE_LOAD,
                "max_penetration": float(np.max(prof["gap"])), "max_pressure": float(np.max(prof["pressure"])),
                "base": {k: np.asarray(v).tolist() for k, v in prof.items()}}

    params = {"E": E, "nu": NU, "width": WIDTH, "height": HEIGHT, "top_pressure": TOP_PRESSURE,
              "side_pressure": SIDE_PRESSURE, "nx": nx, "ny": ny, "refinement": refinement, "steps": steps,
              "quadrature": quadrature, "plane": plane,
              "model": f"half slab (symmetry u_x = 0 on x = 0), Q1, plane {plane}"}
    extra = [contact.traction_out] if hasattr(contact, "traction_out") else []
    return Setup("slab", problem, [contact], [(i + 1) / steps for i in range(steps)], params, figures,
                 [u, contact.gap_out, contact.pressure_out, *extra])


# Benchmark (fenics_contact.bench): mu = 0.4; no closed form with friction, so the error is u_x(A)'s relative
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
