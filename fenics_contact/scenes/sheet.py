"""``sheet``: elastic sheet wrapped over a much stiffer cylinder, ends pulled down (Papadopoulos & Solberg 1998, 4.2).

Data (spec): sheet thickness 1, ``lambda = 1e3, mu = 5e2`` (``E = 1333.3,
nu = 1/3``), neo-Hookean, plane strain, quadratic elements; hollow
cylinder ``R_in = 1`` (fixed), ``R_out = 3``, much stiffer; sheet ends
pulled down by ``t``, ``t`` up to 1.

Choices (the paper's geometry figure is lost in the text):

- the sheet starts stress-free and conforming on the upper half of the
  cylinder (inner radius 3, outer 4), continued by vertical legs of length
  ``leg = 2`` whose ends are pulled down by ``t`` (``u_y = -t``, ``u_x``
  free); the right half is modelled (``u_x = 0`` on ``x = 0``);
- **the cylinder is rigid** (an analytic disk of radius ``R_out = 3``):
  the limit of the stiffness ratio -> infinity. ``R_in`` plays no role. The
  two-body version (a deformable cylinder at a stiffness ratio >= 100) needs
  the two-body projection (``twobody``), which is not in this branch yet;
- 9-node quadrilaterals (``n_arc`` along the quarter arc, ``n_leg`` along
  the leg, ``n_thick`` through the thickness), quadratic geometry so that
  all three nodes of a contact facet start exactly on the cylinder.

Methods (``quadrature="simpson"``: the pressure's work integrated with
Simpson's rule over each quadratic facet):
``lagrange`` and ``penalty_multiplier`` (``p = eps <g>``) are the "two-point"
element (gap at the two end nodes, pressure linear on the facet);
``penalty`` with Simpson's rule is the "three-point" penalty
(``p = eps <g>`` at all three nodes).

What the rigid limit shows (n_arc = 24, t = 1): the two-point penalty
approaches the multipliers (max difference 6.7 % of the peak at eps = 1e4,
0.11 % at 1e6); the three-point penalty oscillates between vertices and
midpoints more as eps grows and stays 5.7 % off near the peak and the
contact edge at 1e6 (0.09 % elsewhere). The paper's surface locking
(three-point pressure not converging at all) needs two deformable surfaces,
each enforcing the gap against the other: for a rigid obstacle (Signorini)
a quadratic pressure is admissible, as the paper remarks. Missing for the
deformable cylinder: two-body projection of quadratic (curved, 3-node)
facets and quadrilaterals (``twobody`` handles flat P1 simplex facets), and
the two-pass multiplier element (pressure on both surfaces, the middle
pressure collocated from the opposite surface).

Equilibrium: the end's vertical reaction ``T`` (the sheet's tension at the
end, per unit thickness) equals the vertical contact force; on the arc the
belt formula gives ``p ~ T/R`` (frictionless, thin sheet).
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ..bounds import contact_surface
from ..compat import function_space
from ..contact import contact_measure
from ..laws import ContactLaw
from ..materials import MODELS
from ..meshes import CONTACT, END, SYMMETRY, sheet_over_cylinder
from ..multipliers import unknown
from ..obstacles import Cylinder
from ..problem import ContactProblem, Dirichlet
from ..projection import SurfaceProjector
from . import Setup

R, THICKNESS, LMBDA, MU, LEG = 3.0, 1.0, 1e3, 5e2, 2.0
R_IN = 1.0  # the fixed inner radius of the cylinder (no role with a rigid cylinder)


def arc_length(x: np.ndarray) -> np.ndarray:
    """Reference arc length along the inner surface from the top (0, R): ``R theta`` on the arc, then down the leg."""
    theta = np.arctan2(x[:, 0], x[:, 1])
    return np.where(x[:, 1] >= 0, R * np.clip(theta, 0, np.pi / 2), R * np.pi / 2 - x[:, 1])


def total_variation(p: np.ndarray) -> float:
    """``sum |p_(i+1) - p_i|`` over the nodes in order along the interface."""
    return float(np.sum(np.abs(np.diff(p))))


def oscillation(p: np.ndarray) -> float:
    """Node-to-node oscillation of a nodal profile along quadratic facets (vertices at even positions):
    the total variation over all nodes minus that over the vertices alone (0 when every midpoint value
    lies between its facet's end values, e.g. a pressure linear on each facet)."""
    return total_variation(p) - total_variation(p[::2])


def build(law: ContactLaw, quadrature: str = "simpson", n_arc: int = 24, n_thick: int = 2, n_leg: int = 8,
          steps: int = 4, comm: MPI.Comm = MPI.COMM_WORLD) -> Setup:
    """Loads ``t = 1/steps, ..., 1`` (include 0.5 for the paper's first profile: even ``steps``)."""
    mesh, _, facet_tags = sheet_over_cylinder(comm, R, THICKNESS, LEG, n_arc, n_thick, n_leg, order=2)
    u, V = unknown(mesh, 2, law)
    load = fem.Constant(mesh, 0.0)
    fdim = mesh.topology.dim - 1
    end_y = fem.locate_dofs_topological(V.sub(1), fdim, facet_tags.indices[facet_tags.values == END])
    sym_x = fem.locate_dofs_topological(V.sub(0), fdim, facet_tags.indices[facet_tags.values == SYMMETRY])
    dirichlet = [Dirichlet(V.sub(1), end_y, -1.0), Dirichlet(V.sub(0), sym_x)]
    contact = contact_surface(u, facet_tags, CONTACT, Cylinder([0.0, 0.0], R), law, load, quadrature)
    material = MODELS["neohookean"].from_lame(LMBDA, MU)
    problem = ContactProblem(u, material, load, dirichlet, [contact])

    # Pressure at every node of the quadratic contact facets (Simpson points): exact projection on P2.
    P2 = function_space(mesh, "Lagrange", 2)
    nodes = SurfaceProjector(P2, contact_measure(mesh, facet_tags, CONTACT, "simpson"))
    nodes_rhs = nodes.compile(contact.pressure)
    p_nodes = fem.Function(P2, name="contact_pressure")
    X2 = P2.tabulate_dof_coordinates()

    def profile() -> dict:
        """Pressure at the contact nodes (vertices and midpoints), ordered along the interface, on every rank."""
        nodes.project(nodes_rhs, p_nodes)
        dofs = nodes.surface_dofs
        X = np.concatenate(comm.allgather(X2[dofs, :2]))
        p = np.concatenate(comm.allgather(p_nodes.x.array[dofs]))
        s = arc_length(X)
        order = np.argsort(s)
        return {"s": s[order], "x": X[order, 0], "y": X[order, 1], "p": p[order]}

    def figures() -> dict:
        prof = profile()
        on_arc = prof["y"] > 0
        T = -problem.reaction(end_y)  # vertical force pulling the end down (per unit thickness)
        return {"end_force": T, "contact_force_y": contact.total_force()[1], "p_max": float(prof["p"].max()),
                "p_mean_arc": float(np.mean(prof["p"][on_arc])), "belt_T_over_R": T / R,
                "total_variation": total_variation(prof["p"]), "oscillation": oscillation(prof["p"]),
                "max_penetration": contact.max_penetration()}

    params = {"lambda": LMBDA, "mu": MU, "thickness": THICKNESS, "R_out": R, "R_in": R_IN, "leg": LEG,
              "n_arc": n_arc, "n_thick": n_thick, "n_leg": n_leg, "quadrature": quadrature, "material": "neohookean",
              "elements": "9-node quadrilaterals, quadratic geometry", "cylinder": "rigid (stiffness ratio infinite)",
              "model": "right half (symmetry x = 0)"}
    setup = Setup("sheet", problem, [contact], [(i + 1) / steps for i in range(steps)], params, figures,
                  [contact.displacement_out])  # XDMF needs the mesh's degree (2): the pressure goes to CSV
    setup.profile = profile  # the demo records it at t = 0.5 and 1
    return setup
