"""``cylinders``: two neo-Hookean cylinders pressed together between two rigid plates (Papadopoulos &
Solberg 1998, section 4.1).

Radii ``R = 18`` (lower, on the fixed plate ``y = 0``) and ``R = 8`` (upper, under the plate that moves
down by ``t``), ``lambda = 288``, ``mu = 192`` (E = 499.2, nu = 0.3), plane strain, compressible
neo-Hookean (finite strain: ``t = 15`` squeezes the stack of height 52 by 29 %). The paper does not say
which cylinder is on top; we put the smaller one there.

Model: the scene is symmetric about the vertical axis through the centres (both cylinders, both plates
and the load), so we model the right halves ``x >= 0`` with ``u_x = 0`` on the axis; no other symmetry
exists (the radii differ); the whole disks (``symmetry="full"``) give the same figures to 0.03 % at twice
the dofs (model-reduction table). One mesh holds both half disks, graded toward the four points where they
touch each other and the plates (gmsh). The plates are analytic rigid half-planes (contact surfaces of
:mod:`contact`); the cylinders touch each other through :mod:`twobody` (two-pass by default: each
surface is slave once, as the paper's two simultaneous Signorini problems, so each surface has its own
pressure). The cylinders are only held by contact: they start with an overlap ``OVERLAP`` at each of
the three contacts so that penalty-type laws have stiffness at the first iteration; the rigid motion
that removes it is part of the first load step (``t`` is the plate motion from that state).

Method. P1 chords of two circles of different radii sag by different amounts (``h^2 / 8R``), so with
exact enforcement at the points of both surfaces (two-pass, converged multipliers) the problem is
over-constrained and the two pressures oscillate (the paper's surface locking: we measured 25-40 %
mismatch with augmented Lagrangian). The defaults are therefore a penalty regularization,
``K = DEFAULT_K``, two-pass with Gauss points: the penalty penetration ``p/K`` is large against the sagitta
(so both passes see the same overlap) and small against the elastic compliance ``a/E*``.

Figures (whole cylinders: forces of the half model doubled): ``total_force`` (contact force between the
cylinders per unit length), ``plate_force`` (force of the upper plate), ``p0`` (peak pressure),
``a`` (contact half-width, edge extrapolated as in the hertz scene), ``p0_hertz``, ``a_hertz`` (two
cylinders: ``1/R = 1/R1 + 1/R2``, ``1/E* = 2 (1 - nu^2)/E``, for the computed force),
``pressure_mismatch`` (two-pass only: largest difference of the two surfaces' pressures at the same ``x``
within 0.9 ``a``, over ``p0``).

Measured (``demos/cylinders.py``, h = 0.05, grading 0.04, 21886 dofs, 2 ranks): at ``t = 0.2``
``p0`` 2.0 % and ``a`` 1.9 % from Hertz, mismatch 0.03 % of ``p0``; ``t = 15`` in 31 steps of 7-10
Newton iterations (``P = 2512``, ``p0 = 208`` against Hertz's 199: the deviation grows with ``t``).
"""
from __future__ import annotations

import math

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...factory import contact_surface, two_body_multipliers, two_body_surfaces
from ...laws import ContactLaw, LagrangeMultiplier
from ...materials import PLANES, LinearElastic, Material, NeoHookean
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import two_half_disks
from . import Option, Setup, log_dofs, poisson, positive, refuse_fine
from .hertz import contact_half_width

__all__ = [
    "R_LOWER", "R_UPPER", "LAMBDA", "MU", "T_END", "OVERLAP", "DEFAULT_K", "T_HERTZ", "hertz_two_cylinders", "build",
    "reference_E",
    "BENCH", "OPTIONS"
]

R_LOWER, R_UPPER, LAMBDA, MU, T_END = 18.0, 8.0, 288.0, 192.0, 15.0
OVERLAP = 1e-4
DEFAULT_K = 1e4  # penalty: large against E*/a (~500 at t = 0.2), small against p0 / (sagitta of a P1 chord)
T_HERTZ = 0.2  # a/R = 0.1 at t = 0.2: small enough for Hertz (half-space error O((a/R)^2))


def reference_E() -> float:
    """Young's modulus of the scene's Lame constants ``LAMBDA``, ``MU`` (the default material)."""
    return float(Material.from_lame(LAMBDA, MU).E)


def hertz_two_cylinders(P: float, R1: float = R_LOWER, R2: float = R_UPPER, plane: str = "strain",
                        E: float | None = None, nu: float | None = None) -> tuple[float, float]:
    """Hertz half-width ``a`` and peak pressure ``p0`` of two cylinders of the same material (``E``, ``nu``;
    default: the scene's Lame constants), load ``P`` per unit length (``1/E* = 2 (1 - nu^2)/E`` in plane strain,
    ``2/E`` in plane stress)."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    mat = Material.from_lame(LAMBDA, MU)
    E, nu = (mat.E if E is None else E), (mat.nu if nu is None else nu)
    R = 1.0 / (1.0 / R1 + 1.0 / R2)
    Es = 1.0 / (2.0 * ((1.0 - nu**2) if plane == "strain" else 1.0) / E)
    a = np.sqrt(4.0 * P * R / (np.pi * Es))
    return float(a), float(2.0 * P / (np.pi * a))


OPTIONS = {
    "h_contact": Option("mesh size at the contacts (length)"),
    "h_far": Option("mesh size far from the contacts (length)"),
    "contact_width": Option("half-width of the zone of mesh size --h-contact around each contact (length)"),
    "grading": Option("growth of the mesh size per unit distance beyond --contact-width (dimensionless)"),
    "R_lower": Option("radius of the lower cylinder (length)"),
    "R_upper": Option("radius of the upper cylinder (length)"),
    "E": Option(f"Young's modulus of both cylinders (stress; default: from the Lame constants {LAMBDA:g}, {MU:g})"),
    "nu": Option(f"Poisson's ratio of both cylinders (default: from the Lame constants {LAMBDA:g}, {MU:g})",
                 "poisson"),
    "overlap": Option(f"initial overlap of each contact, the plates' and the cylinders' (length; default: "
                      f"{OVERLAP:g})"),
}


def build(law_factory=None, law: ContactLaw | None = None, quadrature: str = "gauss", passes: str = "two",
          h_contact: float = 0.05, h_far: float = 2.0, contact_width: float = 1.0, grading: float = 0.25,
          loads: list[float] | None = None, comm: MPI.Comm = MPI.COMM_WORLD, model: str = "neohookean",
          symmetry: str = "half", plane: str = "strain", R_lower: float = R_LOWER, R_upper: float = R_UPPER,
          E: float | None = None, nu: float | None = None, overlap: float = OVERLAP) -> Setup:
    """``law_factory()`` gives a fresh contact law for each of the contact surfaces (plates and cylinders).
    ``grading``: growth of the mesh size per unit distance beyond ``contact_width`` (the contact zone
    reaches x ~ 7 at t = 15: the demo uses a slow grading). ``loads``: the plate motions ``t``
    (default: ``T_HERTZ``, then steps of 0.5 to 15). Model-reduction checks: ``model`` ``linear`` (small
    strain; only for small ``t``) instead of ``neohookean``; ``symmetry`` ``full`` (the whole disks instead of
    the right halves: the horizontal rigid modes of each cylinder, held by frictionless contact alone, are
    removed by ``u_x = 0`` at its two poles, values of the exact symmetric solution). ``plane``: ``strain``
    (the paper's) or ``stress``. The cylinders' radii ``R_lower``, ``R_upper``; ``E``, ``nu`` (both bodies;
    default: the Lame constants ``LAMBDA``, ``MU``); ``overlap``: the initial overlap at each contact."""
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    positive(R_lower=R_lower, R_upper=R_upper, E=E, h_contact=h_contact, h_far=h_far, contact_width=contact_width,
             grading=grading, overlap=overlap)
    poisson(nu=nu)
    if model not in ("neohookean", "linear"):
        raise ValueError(f"cylinders model must be 'neohookean' or 'linear', got {model!r}")
    if symmetry not in ("half", "full"):
        raise ValueError(f"cylinders symmetry must be 'half' or 'full', got {symmetry!r}")
    if law_factory is None:
        if law is None:
            raise ValueError("give law_factory (or law)")
        law_factory = lambda: law  # noqa: E731
    # At least (contact_width / h_contact)^2 unknowns in a contact zone, (R / h_far)^2 in a disk and, where the size
    # grows by grading per unit distance, (2 / grading^2) ln(1 + grading R / h_contact) (the cells of that annulus)
    R_max = max(R_lower, R_upper)
    refuse_fine("h_contact", h_contact, log_dofs((1.0, contact_width / h_contact, 2)), 2, comm)
    refuse_fine("h_far", h_far, log_dofs((1.0, R_max / h_far, 2)), 2, comm)
    refuse_fine("grading", grading, log_dofs((2 * math.log1p(min(grading * R_max, h_far) / h_contact), 1 / grading,
                                              2)), 2, comm)
    mesh, _, facet_tags = two_half_disks(comm, R_lower, R_upper, h_contact, h_far, contact_width, overlap,
                                         grading, full=symmetry == "full")
    u, V = unknown(mesh, 1, law_factory())  # displacement, or (displacement, pressure) for method lagrange
    load = fem.Constant(mesh, 0.0)
    fdim = mesh.topology.dim - 1
    if symmetry == "half":
        sym = fem.locate_dofs_topological(V.sub(0), fdim, facet_tags.find("symmetry"))
    else:  # the four poles, on the axis x = 0
        mesh.topology.create_connectivity(fdim, mesh.topology.dim)  # for the boundary search
        sym = fem.locate_dofs_topological(V.sub(0), 0, dmesh.locate_entities_boundary(
            mesh, 0, lambda x: np.isclose(x[0], 0.0, atol=1e-9)))
    dirichlet = [Dirichlet(V.sub(0), sym)]
    top = 2 * R_lower + 2 * R_upper - overlap
    plate_quadrature = "gauss" if quadrature == "segment" else quadrature  # segment: two-body integration only
    lower_plate = contact_surface(u, facet_tags, "lower_bottom", HalfPlane([0.0, overlap], [0.0, 1.0]),
                                 law_factory(), load, plate_quadrature, name="lower_plate")
    upper_plate = contact_surface(u, facet_tags, "upper_top",
                                 HalfPlane([0.0, top - overlap], [0.0, -1.0], motion=[0.0, -1.0]),
                                 law_factory(), load, plate_quadrature, name="upper_plate")
    if isinstance(law_factory(), LagrangeMultiplier):  # one pass: the upper surface's vertices are constrained
        if passes != "one" or quadrature != "nodal":
            raise ValueError(f"method 'lagrange' on the cylinders is one-pass at the vertices: use passes 'one' and "
                             f"quadrature 'nodal' (got {passes!r}, {quadrature!r}); two passes over-constrain "
                             "P1 surfaces (surface locking)")
        pair = two_body_multipliers(u, facet_tags, "upper_bottom", "lower_top", law_factory(), load,
                                    radius=max(2.0, 4 * h_far), name="cylinders")
    else:
        pair = two_body_surfaces(u, facet_tags, "upper_bottom", "lower_top", law_factory, load, quadrature,
                                 passes, radius=max(2.0, 4 * h_far), name="cylinders")
    contacts = [lower_plate, upper_plate, *pair]
    Model = NeoHookean if model == "neohookean" else LinearElastic
    reference = Material.from_lame(LAMBDA, MU)  # the paper's constants, exactly, unless E or nu is given
    bulk = Model.from_lame(LAMBDA, MU, plane=plane) if E is None and nu is None else Model(
        reference.E if E is None else E, reference.nu if nu is None else nu, plane=plane)
    problem = ContactProblem(u, bulk, load, dirichlet, contacts)
    copies = 2 if symmetry == "half" else 1  # figures for the whole cylinders

    def profiles() -> list[tuple[np.ndarray, np.ndarray]]:
        """(current x, pressure) along the contact for each slave surface, x ascending from the axis."""
        out = []
        for c in pair:
            x, _, p = c.point_values()
            order = np.argsort(x[:, 0], kind="stable")
            out.append((x[order, 0], p[order]))
        return out

    def figures() -> dict:
        prof = profiles()
        forces = [copies * abs(float(c.total_force()[1])) for c in pair]
        P = float(np.mean(forces))
        a_h, p0_h = hertz_two_cylinders(P, R_lower, R_upper, plane, bulk.E, bulk.nu)
        prof = [(x[x >= -1e-12], p[x >= -1e-12]) for x, p in prof]  # full disks: the right half of the profile
        p0 = float(max(q.max() for _, q in prof))
        a = float(np.mean([contact_half_width(xx, q) for xx, q in prof]))
        both = {}
        if len(prof) == 2:  # pressure of one surface against the other's, interpolated at the same x
            (x1, p1), (x2, p2) = prof
            inside = x1 <= 0.9 * min(contact_half_width(x1, p1), contact_half_width(x2, p2))
            both["pressure_mismatch"] = float(np.max(np.abs(p1[inside] - np.interp(x1[inside], x2, p2)))) / p0
        return {**both, "total_force": P, "total_force_surfaces": forces,
                "plate_force": copies * abs(float(upper_plate.total_force()[1])),
                "lower_plate_force": copies * abs(float(lower_plate.total_force()[1])),
                "p0": p0, "a": a, "p0_hertz": p0_h, "a_hertz": a_h, "p0_error": abs(p0 - p0_h) / p0_h,
                "a_error": abs(a - a_h) / a_h,
                "pairing_changes": int(sum(c.pairing_changes for c in pair)),
                **cauchy_peak(p0)}

    def cauchy_peak(p0: float) -> dict:
        """Neo-Hookean, pointwise quadratures: the peak pressure per current area beside the nominal ``p0``."""
        if model != "neohookean" or quadrature == "segment":
            return {}
        return {"p0_nominal": p0, "p0_cauchy": float(max(c.point_values(kind="cauchy")[2].max() for c in pair))}

    lame_constants = (LAMBDA, MU) if E is None and nu is None else (float(bulk.lmbda), float(bulk.mu))
    params = {"R_lower": R_lower, "R_upper": R_upper, "lambda": lame_constants[0], "mu": lame_constants[1],
              "E": bulk.E, "nu": bulk.nu, "h_contact": h_contact,
              "h_far": h_far, "contact_width": contact_width, "grading": grading,
              "quadrature": quadrature, "passes": passes,
              "overlap": overlap,
              "model": f"{'right halves (symmetry x = 0)' if symmetry == 'half' else 'whole disks'}, "
              f"plane {plane}, {'neo-Hookean' if model == 'neohookean' else 'linear elastic'}"}
    if loads is None:
        loads = [T_HERTZ] + np.arange(0.5, T_END + 1e-9, 0.5).tolist()
    for c in contacts:  # one name per field in the XDMF file
        c.gap_out.name, c.pressure_out.name = f"gap_{c.name}", f"contact_pressure_{c.name}"
    setup = Setup("cylinders", problem, contacts, loads, params, figures,
                  [lower_plate.displacement_out] + [f for c in contacts for f in (c.gap_out, c.pressure_out)])
    setup.profiles = profiles
    return setup


# Benchmark (fenics_contact.app.bench): the Hertz step alone (t = T_HERTZ, a/R = 0.1), error of the peak pressure
# against Hertz (two cylinders, plane strain), two-pass with Gauss points as the demo (nodal points on the
# curved P1 chords are the scene docstring's wrong choice).
BENCH = {"error": "p0_error", "value": "p0", "figures": ["a", "a_error", "total_force"], "target": 0.05, "K": DEFAULT_K,
         "mesh": None, "methods": ["penalty", "cross", "auglag"], "quadratures": ["gauss"],
         "demo_args": ["--t-end", repr(T_HERTZ)], "quick_sweep": {"penalty": (-1, 0, 1), "other": (0,)},
         "reduction": True}
