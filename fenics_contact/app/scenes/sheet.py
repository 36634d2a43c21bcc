"""``sheet``: elastic sheet wrapped over a much stiffer cylinder, ends pulled down (Papadopoulos & Solberg 1998, 4.2).

Data (spec): sheet thickness 1, ``lambda = 1e3, mu = 5e2`` (``E = 1333.3,
nu = 1/3``), neo-Hookean, plane strain, quadratic elements; hollow
cylinder ``R_in = 1`` (fixed), ``R_out = 3``, much stiffer; sheet ends
pulled down by ``t``, ``t`` up to 1.

Choices (the paper's geometry figure is lost in the text):

- the sheet starts stress-free and conforming on the upper half of the
  cylinder (inner radius 3, outer 4), continued by vertical legs of length
  ``leg = 2`` whose ends are pulled down by ``t`` (``u_y = -t``, ``u_x``
  free); the right half is modelled (``u_x = 0`` on ``x = 0``, both bodies);
- the cylinder (default ``cylinder="deformable"``) is the right half of the
  hollow cylinder, neo-Hookean with both Lame constants **100 x** the sheet's
  (``RATIO``: the spec's minimum, ``E = 1.33e5``), ``u = 0`` on ``r = R_in``;
  sheet and cylinder are two bodies of one mesh (two cell tags, facet tags
  ``contact`` on the sheet, ``cylinder_surface`` on the cylinder) with non-matching
  interface nodes (``n_cyl = 3 n_arc / 4`` elements per quarter arc of the
  cylinder), in contact through :mod:`twobody` on quadratic (curved 3-node)
  facets. ``cylinder="rigid"``: an analytic disk of radius 3 (the ratio's
  limit; Signorini), kept as the model-reduction comparison;
- 9-node quadrilaterals (``n_arc`` along the quarter arc, ``n_leg`` along
  the leg, ``n_thick`` through the thickness), quadratic geometry so that
  all three nodes of a contact facet start exactly on the circle.

Methods:

- ``quadrature="collocated"`` with ``lagrange`` or ``penalty_multiplier``
  (deformable cylinder only): Papadopoulos & Solberg's element
  (:mod:`~fenics_contact.collocation`): a pressure on both surfaces (an unknown
  at each vertex of each), the gap enforced at the vertices of both against the
  other's current curved facets, the middle pressure of a facet collocated from
  the opposite surface's vertex that projects nearest its middle (else the
  mean of the ends), each body loaded by its own surface's pressure (Simpson's
  rule); a vertex pair that coincides (along the surface, in the current
  configuration) has one constraint. ``penalty_multiplier`` is the paper's
  "two-point penalty" (``p = eps <g>`` at the vertices, the middle value
  collocated). Per current length (Cauchy); the figures use the nominal value.
- ``quadrature="simpson"``, ``lagrange`` and ``penalty_multiplier``: the one-pass
  two-point element, the gap enforced at the two end nodes of each contact
  facet of the sheet against the cylinder's current (curved) surface, the
  pressure an unknown, linear on the facet (its middle value the mean of the
  ends). One pass (the sheet is the slave, the cylinder takes the reaction
  through the coupling ``I``; default ``passes`` for these laws).
- ``penalty``: the "three-point" penalty, ``p = eps <g>`` at all three nodes
  of the facets of **both** surfaces (two passes, each surface slave once,
  weight 1/2; a node of one surface that coincides with one of the other,
  here at the top and at ``(3, 0)``, is constrained once).

Two-pass two-point multipliers without the collocation (``passes="two"``,
both passes weight 1/2) are refused: where a vertex of the sheet and one of
the cylinder nearly coincide their two constraints are nearly the same, and
the multipliers split the traction arbitrarily between the two passes
(n_arc = 12, t = 1: one surface's pressure 0 where the other's is twice the
traction). The collocated element is the paper's cure.

What it shows (``demos/sheet.py``, n_arc = 24, 1742 dofs, serial): the
paper's Figure 9. The collocated multipliers: the ends' pull 164.23 against
the fixed inner surface's reaction 164.28 (0.03 %), zero gap at the
constrained vertices, peak 35.9 / 72.0 at t = 0.5 / 1. Their two-point
penalty approaches them (max difference over the peak 31 % / 0.064 % at
t = 0.5, 25 % / 0.043 % at t = 1 for eps = 1e4 / 1e6; 1e6 needs the tangent
predictor and cutbacks: 27 load steps); the three-point penalty's pressure
oscillates node to node with the period of the two meshes' common nodes and
moves away as eps grows (total variation along the interface 573 -> 1854
against the multipliers' 84 at t = 1, difference 34 % -> 114 %). The one-pass
two-point multipliers (the cylinder's vertices unconstrained) are 11 % / 16 %
off at t = 0.5 / 1, at the edge of the contact. With a rigid cylinder (one
surface, Signorini) the three-point penalty is far milder (5.7 % off near the
peak at 1e6): the locking needs the constraints of both surfaces.

Linear solver: ``Solver(..., options=LINEAR_SOLVERS["iterative"])`` (demo
``--solver iterative``) solves the multipliers' saddle point by FGMRES with
the Schur complement field split (:mod:`~fenics_contact.multipliers`): the
same figures as MUMPS to 1e-12 and the same Newton iterations; collocated
multipliers, 4 load steps, serial (Krylov iterations per Newton iteration;
wall time direct / iterative, a loaded machine): n_arc = 24 (1742 dofs, 20
Newton iterations) 70, 2.5 / 4.0 s; 48 (3458, 27) 180, 5.9 / 24.5 s; 96
(6890, 28) over the 500 cap at the first step (cap 3000, 2 load steps:
1150, 255 s; direct 4 steps 23 s). GAMG on the displacement block of the thin sheet is what does not
scale; with that block by LU (``-fc_fieldsplit_free_fieldsplit_u_pc_type
lu``) the Schur split takes 16, 26, 37 per Newton iteration at the MUMPS
time. 2 ranks, n_arc = 48: 264 per Newton iteration, 166 s against 39 s.

Figures: ``profile(0)`` is the pressure field on the sheet's contact nodes
(vertices and midpoints, by reference arc length from the top; for the
three-point penalty ``eps <g>`` of the sheet's pass), ``profile(1)`` the
cylinder's (two passes or the collocated element); ``traction()`` the nodal traction on the sheet:
its contact nodal force (minus the internal force, radial component)
divided by the node's Simpson weight ``int phi_i ds``, independent of how a
formulation splits its pressure.

Equilibrium: the end's vertical reaction ``T`` (the sheet's tension at the
end, per unit thickness) equals the vertical contact force and the reaction
of the cylinder's fixed inner surface (exactly for the one-surface
elements; for the collocated element, which loads each body by its own
pressure, to its consistency: 0.31, 0.16, 0.03, 0.02 % at n_arc = 8, 12, 24,
48); on the arc the belt formula gives ``p ~ T/R`` (frictionless, thin sheet).
"""
from __future__ import annotations

import dolfinx.fem.petsc  # noqa: F401 (fem.petsc)
import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI
from petsc4py import PETSc

from ...collocation import collocated_surfaces
from ...compat import function_space, petsc_vec
from ...contact import contact_measure
from ...factory import contact_surface, two_body_multipliers, two_body_surfaces
from ...laws import ContactLaw, LagrangeMultiplier
from ...materials import NeoHookean
from ...multipliers import unknown
from ...obstacles import Cylinder
from ...problem import ContactProblem, Dirichlet
from ...projection import SurfaceProjector
from ..meshes import sheet_over_cylinder
from . import Option, Setup, log_dofs, positive, refuse_count

__all__ = [
    "R", "THICKNESS", "LMBDA", "MU", "LEG", "PULL", "R_IN", "RATIO", "RADIUS", "CYLINDERS", "arc_length",
    "total_variation", "oscillation", "OPTIONS", "build", "Scaled"
]

R, THICKNESS, LMBDA, MU, LEG = 3.0, 1.0, 1e3, 5e2, 2.0
PULL = 1.0  # the ends' downward displacement at t = 1
R_IN = 1.0  # the fixed inner radius of the cylinder (no role with a rigid cylinder)
RATIO = 100.0  # cylinder's Lame constants / sheet's (the spec: "much stiffer", at least 100)
RADIUS = 0.5  # two-body search radius (a few element sizes; the interface slides little)
CYLINDERS = ("deformable", "rigid")


def arc_length(x: np.ndarray, R: float = R) -> np.ndarray:
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


OPTIONS = {
    "ratio": Option("cylinder's Lame constants / the sheet's (dimensionless)"),
    "R": Option("cylinder's outer radius (length)"),
    "thickness": Option("sheet thickness (length)"),
    "leg": Option("length of the sheet's legs (length)"),
    "R_in": Option("cylinder's fixed inner radius, < --R (length)", below=("R",)),
    "lmbda": Option("sheet's first Lame constant (stress)"),
    "mu": Option("sheet's shear modulus (stress)"),
    "radius": Option("two-body search radius (length)"),
    "pull": Option("downward displacement of the sheet's ends at t = 1 (length)"),
}


def build(law: ContactLaw, quadrature: str = "simpson", n_arc: int = 24, n_thick: int = 2, n_leg: int = 8,
          steps: int = 4, cylinder: str = "deformable", ratio: float = RATIO, n_cyl: int | None = None,
          n_rad: int = 3, passes: str | None = None, comm: MPI.Comm = MPI.COMM_WORLD, R: float = R,
          thickness: float = THICKNESS, leg: float = LEG, R_in: float = R_IN, lmbda: float = LMBDA, mu: float = MU,
          radius: float = RADIUS, pull: float = PULL) -> Setup:
    """Loads ``t = 1/steps, ..., 1`` (include 0.5 for the paper's first profile: even ``steps``).
    ``cylinder``: ``deformable`` (the paper's: neo-Hookean, Lame constants ``ratio`` x the sheet's, two-body
    contact through :mod:`twobody`, ``n_cyl`` elements along each quarter of its outer arc, default
    ``3 n_arc / 4``: non-matching with the sheet, ``n_rad`` through its wall) or ``rigid`` (an analytic disk:
    the limit ``ratio -> infinity``, Signorini; the model-reduction comparison). The cylinder of radius ``R``
    (its fixed inner radius ``R_in``), the sheet ``thickness`` thick with legs ``leg`` long, the sheet's Lame
    constants ``lmbda``, ``mu`` (the cylinder's ``ratio`` x these), the two-body search ``radius``, the ends pulled
    down by ``t pull``; defaults: the module constants."""
    if cylinder not in CYLINDERS:
        raise ValueError(f"cylinder must be one of {CYLINDERS}, got {cylinder!r}")
    collocated = quadrature == "collocated"
    if collocated and (cylinder != "deformable" or not isinstance(law, LagrangeMultiplier)):
        raise ValueError("quadrature 'collocated' (Papadopoulos & Solberg's two-body element) needs cylinder "
                         f"'deformable' and method 'lagrange' or 'penalty_multiplier', got cylinder {cylinder!r}, "
                         f"method {law.name!r}")
    if not (np.isfinite(ratio) and ratio >= 1):
        raise ValueError(f"stiffness ratio must be a finite number >= 1, got {ratio!r}")
    positive(R=R, thickness=thickness, leg=leg, R_in=R_in, lmbda=lmbda, mu=mu, radius=radius, pull=pull)
    if not R_in < R:
        raise ValueError(f"R_in must be < R = {R!r}, got {R_in!r}")
    deformable = cylinder == "deformable"
    two_point = isinstance(law, LagrangeMultiplier) and not collocated
    if collocated:
        passes = "both"  # both surfaces carry a pressure (not a two-body "passes" option)
    elif passes is None:
        passes = "one" if two_point else "two"
    if n_cyl is None:
        n_cyl = max(3 * int(n_arc) // 4, 1)
    # 9-node quadrilaterals: at least 5 unknowns per cell of the sheet's arc, legs and (n_cyl per quarter) the cylinder
    cells = (int(n_arc) + int(n_leg)) * int(n_thick) + (4 * int(n_cyl) * int(n_rad) if deformable else 0)
    refuse_count("n_arc", n_arc, log_dofs((5.0, cells, 1)), 1, comm)
    mesh, cell_tags, facet_tags = sheet_over_cylinder(comm, R, thickness, leg, n_arc, n_thick, n_leg, order=2,
                                                      cylinder=(R_in, n_cyl, n_rad) if deformable else None)
    u, V = unknown(mesh, 2, law)
    load = fem.Constant(mesh, 0.0)
    end = Dirichlet.on_facets(V, facet_tags, "end", 1, -pull)  # the ends pulled down by t pull
    dirichlet = [end, Dirichlet.on_facets(V, facet_tags, "symmetry", 0)]
    material = Scaled.from_lame(lmbda, mu)
    fixed_y = np.zeros(0, np.int32)
    if deformable:
        dirichlet += [Dirichlet.on_facets(V, facet_tags, "cylinder_fixed", i) for i in (0, 1)]
        fixed_y = dirichlet[-1].dofs
        material.factor = fem.Function(function_space(mesh, "DG", 0), name="stiffness_factor")
        cyl = cell_tags.find("cylinder")
        material.factor.x.array[:] = 1.0
        material.factor.x.array[_cell_dofs(material.factor.function_space, cyl)] = ratio
        if collocated:  # the gap at the vertices of both surfaces, each body loaded by its own pressure
            contacts = collocated_surfaces(u, facet_tags, "contact", "cylinder_surface", law, load, radius,
                                           "interface")
        elif isinstance(law, LagrangeMultiplier):  # two-point: constraint at the end nodes, p linear on the facet
            if quadrature != "simpson":
                raise ValueError(f"method {law.name!r} on the sheet is the two-point element (Simpson's rule for "
                                 f"the work): quadrature must be 'simpson', got {quadrature!r}")
            contacts = two_body_multipliers(u, facet_tags, "contact", "cylinder_surface", law, load, radius,
                                            "interface", passes=passes, work_quadrature="simpson")
        else:  # three-point: the law at all three nodes (simpson)
            contacts = two_body_surfaces(u, facet_tags, "contact", "cylinder_surface", lambda: law, load, quadrature,
                                         passes, radius, "interface")
        for c in contacts:  # one name per field in the XDMF file
            c.gap_out.name, c.pressure_out.name = f"gap_{c.name}", f"contact_pressure_{c.name}"
    else:
        contacts = [contact_surface(u, facet_tags, "contact", Cylinder([0.0, 0.0], R), law, load, quadrature)]
    contact = contacts[0]
    problem = ContactProblem(u, material, load, dirichlet, contacts)

    if not deformable:
        # Pressure at every node of the quadratic contact facets (Simpson points): exact projection on P2.
        P2 = function_space(mesh, "Lagrange", 2)
        nodes = SurfaceProjector(P2, contact_measure(mesh, facet_tags, "contact", "simpson"))
        nodes_rhs = nodes.compile(contact.pressure)
        p_nodes = fem.Function(P2, name="contact_pressure")
        X2 = P2.tabulate_dof_coordinates()

    def profile(surface: int = 0) -> dict:
        """Pressure at the contact nodes (vertices and midpoints) of the sheet (``surface`` 0) or of the
        cylinder (1, deformable cylinder with two passes or the collocated element), ordered along the interface
        by reference arc length from the top, on every rank; deformable cylinder: also ``gap`` (penetration
        positive; ``-inf`` where not constrained, e.g. the collocated element's middle nodes)."""
        g = None
        if deformable:
            X, x, g, p = contacts[surface].point_table()
            s = arc_length(X, R) if surface == 0 else R * np.arctan2(X[:, 0], X[:, 1])
        else:
            nodes.project(nodes_rhs, p_nodes)
            dofs = nodes.surface_dofs
            X = np.concatenate(comm.allgather(X2[dofs, :2]))
            p = np.concatenate(comm.allgather(p_nodes.x.array[dofs]))
            s = arc_length(X, R)
        order = np.argsort(s)
        out = {"s": s[order], "x": X[order, 0], "y": X[order, 1], "p": p[order]}
        if g is not None:  # the gap at the constrained points (-inf elsewhere: collocated middle nodes, unpaired)
            out["gap"] = g[order]
        return out

    if deformable:
        # Simpson weight of every node of the sheet's contact surface (int phi_i ds, reference configuration).
        sd = contacts[0].slave_data
        P2 = function_space(mesh, "Lagrange", 2)
        weights = fem.Function(P2)
        simpson = contact_measure(mesh, facet_tags, "contact", "simpson")
        fem.petsc.assemble_vector(petsc_vec(weights), fem.form(ufl.TestFunction(P2) * simpson))
        petsc_vec(weights).ghostUpdate(addv=PETSc.InsertMode.ADD, mode=PETSc.ScatterMode.REVERSE)
        weights.x.scatter_forward()
        w_nodes = np.array([P2.dofmap.cell_dofs(c)[lo] for c, lo in zip(sd.cells, sd.local)],
                           dtype=np.int32).reshape(-1, 3)

    def traction() -> dict:
        """The contact traction on the sheet at its contact nodes (vertices and midpoints), ordered by
        reference arc length: for the rigid cylinder the pressure field; for the deformable one the contact
        force on each node (= minus the internal force: nothing else loads the interface), signed along the
        outward radius, divided by the node's Simpson weight ``int phi_i ds`` (a smooth pressure's
        consistent nodal forces are its values times these weights). Formulation-independent: the pressures
        of the two passes (weight 1/2 each) can split one traction between nearby nodes of the two
        surfaces, the nodal forces cannot."""
        if not deformable:
            return profile(0)
        f = problem.internal_force()[sd.comp]  # (nf, 3, 2)
        X = sd.X
        radial = np.where((X[..., 1] >= 0)[..., None], X / np.linalg.norm(X, axis=-1, keepdims=True),
                          np.array([1.0, 0.0]))
        fn = np.einsum("fkj,fkj->fk", f, radial)
        w = weights.x.array[w_nodes]
        own = sd.owned
        data = [np.concatenate(a) for a in zip(*comm.allgather((X[own].reshape(-1, 2), (fn / w)[own].ravel())))]
        Xr = np.round(data[0], 12)
        _, first = np.unique(Xr, axis=0, return_index=True)
        Xn, pn = data[0][first], data[1][first]
        s = arc_length(Xn, R)
        order = np.argsort(s)
        return {"s": s[order], "x": Xn[order, 0], "y": Xn[order, 1], "p": pn[order]}

    def figures() -> dict:
        prof = traction()
        on_arc = prof["y"] > 0
        T = -problem.reaction(end.dofs)  # vertical force pulling the end down (per unit thickness)
        if deformable:  # the force the fixed inner surface takes
            support = problem.reaction(fixed_y)
            # the constrained points: the end nodes (two-point) or all three nodes (three-point) of each facet
            # (collocated: the vertices of both surfaces)
            gaps = [c.point_table()[2] if collocated else c.projection["gap"][:, [0, 2]] if two_point
                    else c.projection["gap"] for c in contacts]
            pen = comm.allreduce(float(max(np.max(g[np.isfinite(g)], initial=-np.inf) for g in gaps)), op=MPI.MAX)
            extra = {"cylinder_support_y": support, "max_penetration": pen,
                     "pairing_changes": int(sum(c.pairing_changes for c in contacts))}
        else:
            extra = {"contact_force_y": contact.total_force()[1], "max_penetration": contact.max_penetration()}
        return {"end_force": T, "p_max": float(prof["p"].max()),
                "p_mean_arc": float(np.mean(prof["p"][on_arc])), "belt_T_over_R": T / R,
                "total_variation": total_variation(prof["p"]), "oscillation": oscillation(prof["p"]), **extra}

    params = {"lambda": lmbda, "mu": mu, "thickness": thickness, "R_out": R, "R_in": R_in, "leg": leg, "pull": pull,
              "n_arc": n_arc, "n_thick": n_thick, "n_leg": n_leg, "quadrature": quadrature, "material": "neohookean",
              "elements": "9-node quadrilaterals, quadratic geometry", "cylinder": cylinder,
              "model": "right half (symmetry x = 0)"}
    if deformable:
        params.update({"stiffness_ratio": ratio, "lambda_cylinder": ratio * lmbda, "mu_cylinder": ratio * mu,
                       "n_cyl": n_cyl, "n_rad": n_rad, "passes": passes})
    setup = Setup("sheet", problem, contacts, [(i + 1) / steps for i in range(steps)], params, figures,
                  [contact.displacement_out])  # XDMF needs the mesh's degree (2): the pressure goes to CSV
    setup.profile = profile  # the demo records it at t = 0.5 and 1
    setup.traction = traction
    return setup


def _cell_dofs(V, cells: np.ndarray) -> np.ndarray:
    """Dofs of a DG0 space on ``cells``."""
    return np.array([V.dofmap.cell_dofs(c)[0] for c in cells], dtype=np.int32)


class Scaled(NeoHookean):
    """Neo-Hookean with both Lame constants scaled by the cell field ``factor`` (1 in the sheet, the
    stiffness ratio in the cylinder): ``W = factor W_sheet``."""

    factor = 1.0

    def energy(self, u):
        return self.factor * super().energy(u)

    def stress(self, u):
        return self.factor * super().stress(u)
