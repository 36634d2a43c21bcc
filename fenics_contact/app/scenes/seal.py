"""``seal``: flattening of a double-curved seal between two rigid plates (Zavarise et al. 1998, sealing test).

E = 1000, nu = 0.3, compressible neo-Hookean (finite strain, large
rotations), plane strain; plates y = 0 (fixed) and y = 7 (moving down by
``t``); loads ``t`` = 0.5, 1.0, ..., 5.5, then 5.6, ..., 6.0 (plates 1 apart
= the band's thickness at the end). The paper's Figure 17 is not available:
the cross-section is our design from its data, a band of thickness 1
bounded by circular arcs of radii R_out = 10 and R_in = 9 (documented in the
module docstring of :mod:`fenics_contact.app.meshes`), in one of three shapes:

``shape="wave"`` (default, :func:`~fenics_contact.app.meshes.seal_wave_section`)
    three annular sectors of alternating curvature, a crown convex upward in
    the middle (touching the upper plate at x = 0) between two humps convex
    downward (touching the lower plate); symmetric about x = 0, half model
    (``u_x = 0`` on x = 0, which also holds the crown's section against
    rotation: the band is a real structure between the plates, not a
    mechanism). It gives the paper's sequence: pressed at the crown, each
    half pivots on its hump, whose contact point travels toward the middle
    (x = 13.86 to 11.83 by t = 2), while the outer end rises until its upper
    right corner touches the upper plate (t = 2); the crown zone leaves the
    middle and splits in two (t = 5), then the zone under each hump splits
    in two that move apart (t = 5.5).
``shape="S"`` (:func:`~fenics_contact.app.meshes.seal_s_section`)
    two annular sectors of opposite curvature. Between frictionless plates
    the S *rolls* until its ends touch (t <= 2.5): a rigid rotation that
    changes the plate distance at no force, i.e. a mechanism whose
    equilibrium only the contact law's open branch fixes (Newton needs 11-19
    iterations per step there). Point-symmetric about P0 = (0, 3.5), the
    middle of the junction: ``u(P0) = (0, -t/2)`` is imposed (the reaction
    is reported, ~0).
``shape="U"`` (:func:`~fenics_contact.app.meshes.seal_section`)
    one annular sector curved as a valley, its inner corners touching the
    upper plate and its bottom the lower plate; half model (``u_x = 0`` on
    x = 0). The bottom zone splits in two at t = 4.5; the contacts do not
    move toward the middle.

Both plates are analytic half-planes, each with its own contact surface on
the whole free boundary (any part may touch either plate; nodal
quadrature). Contact zones (:meth:`ContactSurface.contact_zones`) are
counted for the whole section (a zone of a half model touching x = 0 is one
zone, any other has its mirror image). Cross-constraints ``K^ = 1e5`` with
``F^ = 1e-3`` (``F_HAT``): the paper's seal uses ``F^ = 0``, but then a point
that touches with g = 0 exactly (the crown and the humps in the initial
configuration) has no stiffness and the first Newton step moves the band
rigidly; 1e-3 is 0.1 % of the contact pressures here (~1) and changes them by
as much. Newton without line search (``SOLVER_OPTIONS``): the suite's default
``l2`` line search damps the steps where contacts switch (up to 17
iterations instead of 8). Each step starts from the tangent predictor
(``PREDICTOR``, :meth:`fenics_contact.solver.predictor.Predictor.tangent`; the
S keeps the secant one, see ``PREDICTOR``): the secant one (extrapolating the
last increment) drives the outer corner 0.42 and 0.49 through the upper plate
at t = 2.0 and 2.5, after it has landed at t = 1.78 and the band has become
ten times stiffer, and Newton then rocks (16 and 17 iterations; README); the
tangent keeps the converged contact set and is scaled back to the energy's
minimum along it (3-8 iterations).
"""
from __future__ import annotations

import math

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...compat import function_space
from ...contact import ContactSurface
from ...laws import ContactLaw
from ...materials import PLANES, NeoHookean
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import seal_s_geometry, seal_s_section, seal_section, seal_wave_section
from . import Option, Setup, log_dofs, poisson, positive, refuse_fine

__all__ = [
    "E", "NU", "R_OUT", "R_IN", "GAP", "K_HAT", "F_HAT", "SOLVER_OPTIONS", "PREDICTOR", "SHAPES", "LOADS", "build",
    "BENCH", "OPTIONS"
]

E, NU, R_OUT, R_IN, GAP = 1000.0, 0.3, 10.0, 9.0, 7.0
K_HAT = 1e5
F_HAT = 1e-3  # 0.1 % of the contact pressures: stiffness K_hat for the points that touch at g = 0 (docstring)
SOLVER_OPTIONS = {"snes_linesearch_type": "basic"}  # full Newton steps (module docstring)
# The state each step starts from, per shape (module docstring): the tangent predictor, but the secant one for the
# S, whose rolling is a mechanism: its tangent is fixed only by the 1e-8-wide open branch (roundoff decides it).
PREDICTOR = {"wave": "tangent", "U": "tangent", "S": "secant"}
SHAPES = {"wave": seal_wave_section, "S": seal_s_section, "U": seal_section}
LOADS = [0.5 * k for k in range(1, 12)] + [5.5 + 0.1 * k for k in range(1, 6)]


OPTIONS = {
    "h": Option("cell size of the quadrilaterals (length; 0.5: 2 cells through the thickness)"),
    "E": Option("Young's modulus (stress)"),
    "nu": Option("Poisson's ratio", "poisson"),
    "R_out": Option("section's outer radius (length)"),
    "R_in": Option("section's inner radius, < --R-out (length)", below=("R_out",)),
    "plate_distance": Option("distance between the two plates at the start (length)"),
}


def build(law: ContactLaw, quadrature: str = "nodal", h: float = 0.5, loads: list[float] | None = None,
          comm: MPI.Comm = MPI.COMM_WORLD, shape: str = "wave", E: float = E, nu: float = NU, R_out: float = R_OUT,
          R_in: float = R_IN, plate_distance: float = GAP, plane: str = "strain") -> Setup:
    """``h``: cell size of the structured quadrilaterals (0.5: 2 cells through the thickness); ``shape``:
    ``"wave"``, ``"S"`` or ``"U"`` (module docstring). Solve with ``SOLVER_OPTIONS`` and ``PREDICTOR[shape]``.
    The section's radii ``R_in < R_out``, the plates ``plate_distance`` apart at t = 0, ``E``, ``nu``
    (defaults: the module constants). ``plane``: ``strain`` (default, the figures of the module docstring) or
    ``stress`` (neo-Hookean with the out-of-plane stretch of :class:`~fenics_contact.materials.NeoHookean`)."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    positive(E=E, R_out=R_out, R_in=R_in, plate_distance=plate_distance, h=h)
    poisson(nu=nu)
    if not R_in < R_out:
        raise ValueError(f"seal: R_in must be < R_out, got R_in = {R_in}, R_out = {R_out}")
    if shape not in SHAPES:
        raise ValueError(f"seal shape must be one of {', '.join(map(repr, SHAPES))}, got {shape!r}")
    half = shape != "S"
    # At least 1.5 unknowns per cell of a half arc of the section: (pi R_in / h) x ((R_out - R_in) / h)
    refuse_fine("h", h, log_dofs((1.5, math.sqrt(math.pi * R_in * (R_out - R_in)) / h, 2)), 2, comm)
    mesh, _, facet_tags = SHAPES[shape](comm, h, R_out, R_in, plate_distance)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    if half:
        sym = fem.locate_dofs_topological(V.sub(0), 1, facet_tags.find("symmetry"))
        dirichlet = [Dirichlet(V.sub(0), sym)]
    else:  # the S: u(P0) = (0, -t/2) at the centre of symmetry
        p0 = np.array(seal_s_geometry(R_out, R_in, plate_distance)["P0"])
        centre = dmesh.locate_entities(mesh, 0, lambda x: np.hypot(x[0] - p0[0], x[1] - p0[1]) < 1e-8)
        mesh.topology.create_connectivity(0, mesh.topology.dim)  # vertex dofs (dolfinx >= 0.6 needs it)
        cx, cy = (fem.locate_dofs_topological(V.sub(i), 0, centre) for i in (0, 1))
        dirichlet = [Dirichlet(V.sub(0), cx), Dirichlet(V.sub(1), cy, -0.5)]
    lower = ContactSurface(u, facet_tags, "boundary", HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                           name="lower plate")
    upper = ContactSurface(u, facet_tags, "boundary",
                           HalfPlane([0.0, plate_distance], [0.0, -1.0], motion=[0.0, -1.0]), _copy(law), load,
                           quadrature, name="upper plate")
    problem = ContactProblem(u, NeoHookean(E, nu, plane=plane), load, dirichlet, [lower, upper])

    def figures() -> dict:
        zl, zu = lower.contact_zones(), upper.contact_zones()
        fl, fu = lower.total_force(), upper.total_force()
        m = 2 if half else 1
        whole = lambda zones: sum(1 if half and z["X_min"][0] <= 1e-9 else m for z in zones)  # noqa: E731
        return {"plate_force_lower": m * float(fl[1]), "plate_force_upper": -m * float(fu[1]),
                **({} if half else {"reaction_P0_x": problem.reaction(cx), "reaction_P0_y": problem.reaction(cy)}),
                "zones_lower": whole(zl), "zones_upper": whole(zu),
                "zones_lower_x": [[z["X_min"][0], z["X_max"][0]] for z in zl],
                "zones_upper_x": [[z["X_min"][0], z["X_max"][0]] for z in zu],
                "max_penetration": max(lower.max_penetration(), upper.max_penetration())}

    params = {"E": E, "nu": nu, "R_out": R_out, "R_in": R_in, "plate_distance": plate_distance, "h": h, "shape": shape,
              "quadrature": quadrature, "material": "neohookean", "plane": plane,
              "model": f"half of the {shape}-shaped section (symmetry x = 0)" if half else
              "whole S-shaped section, u(P0) = (0, -t/2) at its centre of symmetry"}
    fields = [u, lower.gap_out, lower.pressure_out]
    return Setup("seal", problem, [lower, upper], list(loads or LOADS), params, figures, fields)


def _copy(law: ContactLaw) -> ContactLaw:
    """A second law object with the same parameters (each surface owns its state)."""
    import copy

    return copy.deepcopy(law)


# Benchmark (fenics_contact.app.bench): no closed form or exact reference for the flattened seal, so no error figure:
# the rows are convergence, Newton iterations and time over the 16-step history (plate force as the value).
# Built by the harness (the demo runs fixed laws): the scene's full Newton steps and predictor; cross with F^.
BENCH = {"error": None, "value": "plate_force_lower", "figures": ["zones_lower", "max_penetration"], "K": K_HAT,
         "F_hat": F_HAT, "mesh": None, "methods": ["penalty", "cross", "auglag"], "build": {"h": 0.5},
         "options": SOLVER_OPTIONS, "predictor": PREDICTOR["wave"],
         "quick_sweep": {"penalty": (-1, 0, 1), "other": (0, 1)}}
