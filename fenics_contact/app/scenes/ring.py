"""``ring``: elastic ring pressed between two rigid plates (Zavarise, Wriggers & Schrefler 1998, ring test).

R_out = 8, R_in = 6, E = 1000, nu = 0.3, linear elasticity, plane strain (the paper's; ``plane="stress"``
is an option, off the paper's figures);
the upper plate moves down by 1 in one load step, the lower one is fixed.
The problem is symmetric about the vertical diameter and (linear elasticity:
the solution is a rigid translation by half the approach plus a part
symmetric about the horizontal diameter) about the horizontal diameter, so
we model the lower-right quarter: ``u_x = 0`` on ``x = 0``, ``u_y = -t/2``
on the diameter ``y = R_out`` (``u_x`` free), contact of the outer arc with
the rigid half-plane ``y <= 0``. The quarter also removes the full model's
vertical rigid mode, which a penalty law leaves singular at the first
iterate (no closed point yet).

Contact quadrature is nodal (the paper's node-to-node elements) on a coarse
structured Q1 mesh (``n_theta`` cells on the quarter, ``n_r`` through the
thickness): with the default 8 x 2 the first step closes two vertices of the
quarter, i.e. three contact points per plate as in the paper: the centre
(on the axis, half its weight in the quarter) and one neighbour each side.
The paper's Figure 14 (its mesh) is not available; the penetrations it
quotes are compared with ours in the figures.

``K`` here is a pressure per length (force per area per penetration); a
node-to-node element's spring is ``K w_i`` with ``w_i`` the vertex's
tributary length.
"""
from __future__ import annotations

import math

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ...compat import function_space
from ...contact import ContactSurface
from ...laws import ContactLaw
from ...materials import PLANES, LinearElastic
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import ring_quarter
from . import Option, Setup, log_dofs, poisson, positive, refuse_count

__all__ = [
    "R_OUT", "R_IN", "E", "NU", "APPROACH", "K", "PAPER_PENETRATION", "PAPER_RESIDUAL_6", "build", "VARIANTS", "BENCH",
    "OPTIONS"
]

R_OUT, R_IN, E, NU, APPROACH = 8.0, 6.0, 1000.0, 0.3, 1.0
K = 1e5
# Published first-step penetrations (centre, neighbours) and residual after 6 iterations.
PAPER_PENETRATION = (0.19e-3, 0.13e-3)
PAPER_RESIDUAL_6 = 0.9e-10


OPTIONS = {
    "R_out": Option("ring's outer radius (length)"),
    "R_in": Option("ring's inner radius, < --R-out (length)", below=("R_out",)),
    "E": Option("Young's modulus (stress)"),
    "nu": Option("Poisson's ratio", "poisson"),
    "approach": Option(f"upper plate's downward displacement (length; default: {APPROACH / R_OUT:g} R_out, the "
                       f"paper's {APPROACH:g} at R_out {R_OUT:g})"),
}


def build(law: ContactLaw, quadrature: str = "nodal", n_theta: int = 44, n_r: int = 4, quadrilateral: bool = True,
          comm: MPI.Comm = MPI.COMM_WORLD, R_out: float = R_OUT, R_in: float = R_IN, E: float = E, nu: float = NU,
          approach: float | None = None, plane: str = "strain") -> Setup:
    """The quarter ring (radii ``R_in < R_out``, ``E``, ``nu``); one load step (upper plate down by ``approach``);
    ``plane``: ``strain`` or ``stress``. Defaults: the module constants, the paper's."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    positive(R_out=R_out, R_in=R_in, E=E, approach=approach)
    approach = APPROACH * R_out / R_OUT if approach is None else approach  # the same squeeze of a larger ring
    poisson(nu=nu)
    if not R_in < R_out:
        raise ValueError(f"ring: R_in must be < R_out, got R_in = {R_in}, R_out = {R_out}")
    # 2 (n_theta + 1) (n_r + 1) unknowns: the larger count is refused, the other kept
    many = log_dofs((2.0, math.sqrt((int(n_theta) + 1) * (int(n_r) + 1)), 2))
    refuse_count(*(("n_theta", n_theta) if n_theta >= n_r else ("n_r", n_r)), many, 1, comm)
    mesh, _, facet_tags = ring_quarter(comm, R_out, R_in, n_theta, n_r, quadrilateral)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    fdim = mesh.topology.dim - 1
    mid_y = fem.locate_dofs_topological(V.sub(1), fdim, facet_tags.find("mid"))
    axis_x = fem.locate_dofs_topological(V.sub(0), fdim, facet_tags.find("axis"))
    dirichlet = [Dirichlet(V.sub(1), mid_y, -approach / 2), Dirichlet(V.sub(0), axis_x)]
    contact = ContactSurface(u, facet_tags, "outer", HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                             name="lower plate")
    problem = ContactProblem(u, LinearElastic(E, nu, plane=plane), load, dirichlet, [contact])

    def figures() -> dict:
        x, g, p = contact.surface_values()
        order = np.argsort(np.arctan2(x[:, 1] - R_out, x[:, 0]))  # from the bottom (centre) outward
        g = g[order]
        force = 2 * contact.total_force()[1]
        return {"penetration_centre": float(g[0]), "penetration_neighbour": float(g[1]),
                "closed_points_quarter": int(np.count_nonzero(g > 0)),
                "closed_points_per_plate": int(2 * np.count_nonzero(g > 0) - (g[0] > 0)),
                "plate_force": force, "reaction_mid": -2 * problem.reaction(mid_y)}

    params = {"E": E, "nu": nu, "R_out": R_out, "R_in": R_in, "approach": approach, "n_theta": n_theta, "n_r": n_r,
              "quadrilateral": quadrilateral, "quadrature": quadrature,
              "plane": plane, "model": "quarter ring (symmetry x = 0 and y = R_out)"}
    return Setup("ring", problem, [contact], [1.0], params, figures, [u, contact.gap_out, contact.pressure_out])


# Benchmark (fenics_contact.app.bench): the demo runs its three laws in one process, so the harness builds the scene
# itself ("build"). No error figure: the paper's point is convergence, so the rows are iterations and time. The
# stability map sweeps K and the load step size for penalty (plain and with augmentation: the paper's cycling),
# cross-constraints and the augmented Lagrangian; plain Newton, no step cutbacks (the step size is the axis).
# (method, augmentations[, F_hat]); cross also with F^ = 2 (~ 1/10 of the peak pressure, the paper's advice)
VARIANTS = (("penalty", 0), ("penalty", 10), ("cross", 10), ("cross", 10, 2.0), ("auglag", 10))
BENCH = {"error": None, "value": "plate_force", "figures": ["penetration_centre", "closed_points_per_plate"],
         "K": K, "mesh": None, "methods": ["penalty", "cross", "auglag"], "build": {"n_theta": 44, "n_r": 4},
         "options": {"snes_linesearch_type": "basic"}, "max_cutbacks": 0,
         "stability": True, "quick_stability": {"K": (-2, 0, 2, 3, 5, 7), "steps": (1, 4), "gamma0": (),
                                                "variants": VARIANTS},
         "stability_variants": VARIANTS}
