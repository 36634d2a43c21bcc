"""``lipseal``: a lip seal with two lips (a U-cup) squeezed between the rod and the groove bottom until its lips
close the slot between them and press on each other (plane strain, nearly incompressible neo-Hookean, mixed
Taylor-Hood P2-P1; self-contact).

The seal's section (:func:`~..meshes.lipseal.lipseal_section`; ``x`` radial, ``y`` axial): a heel ``width`` wide and
``heel`` long on the groove's side wall (``y = 0``, frictionless: ``u_y = 0``), and two lips of length ``lip`` whose
outer faces flare out by ``flare`` past the heel's, with a V-shaped slot between them (width ``slot`` at the tips).
The rod and the groove bottom are rigid frictionless plates ``x = +-(width / 2 + flare)``, touching the lips' tips
at ``t = 0``, which approach each other by ``squeeze`` of the seal's free radial span ``width + 2 flare`` over ``0 <
t <= 1``. The plates push the tips in and the lips bend: their tips meet (at about 13 % squeeze with the defaults),
then the closed part of the slot grows toward its root while the lips' outer faces come flat against the plates,
until the lips press on each other over their whole length (the lip collapse of a U-cup in a too tight groove).
Two models of the same problem:

- full (``half=False``): the whole section; the slot's faces are one surface in contact with itself
  (:func:`~fenics_contact.factory.self_contact_surfaces`). The heel is held on its middle line ``x = 0`` (``u_x =
  0``, which the symmetric solution satisfies; it holds the radial rigid motion the frictionless plates leave free).
- half (``half=True``): the half ``x >= 0``, ``u_x = 0`` on the heel's face on ``x = 0``; the lip's inner face
  against the symmetry plane ``x = 0`` as a rigid obstacle, with the law's penalty doubled (the full model's gap is
  the overlap of both lips).

By symmetry the full seal's lips meet on the plane ``x = 0``: the two models are the same problem, their plate force
and slot force equal. Without self-contact the lips would pass through each other.

Figures per step (per unit length of seal): ``plate_force`` (the rod's radial force on the seal), ``slot_force``
(the normal force the closed slot carries: on the ``x > 0`` lip from the other one, or from the plane),
``slot_width`` (the current length of that lip's inner face in contact, at its vertices), ``slot_p0`` (its peak
nominal pressure), ``slot_overlap`` (the largest overlap of the two lips: full, the largest gap; half, twice the
largest penetration of the plane; > 0 interpenetration) and ``plate_penetration``.
"""
from __future__ import annotations

import copy

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...factory import contact_surface, self_contact_surfaces
from ...laws import ContactLaw
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes.lipseal import lipseal_section
from . import Option, Setup, poisson, positive
from ._mirror import line_dofs, stiffer

__all__ = ["WIDTH", "HEEL", "LIP", "FLARE", "SLOT", "E", "NU", "SQUEEZE", "DEFAULT_K", "NX", "NY_HEEL", "NY_LIP",
           "STEPS", "METHODS", "OPTIONS", "build"]

WIDTH, HEEL, LIP, FLARE, SLOT = 4.0, 2.0, 4.0, 0.6, 0.6
E, NU = 1000.0, 0.4999
SQUEEZE = 0.2  # of the free radial span width + 2 flare
NX, NY_HEEL, NY_LIP = 8, 6, 16
STEPS = 20  # converges with no cutback in both models on the default mesh and on a coarser one (6, 4, 12)
DEFAULT_K = 100.0  # per E / h, h the slot face's facet length
QUADRATURE_DEGREE = 4  # the bulk's (twice the P2 displacement's), as the tube and oring scenes
METHODS = ("penalty", "auglag", "compliance")  # the capability grid's self-contact methods on the mixed P2 model

OPTIONS = {
    "width": Option("radial width of the seal's heel (length)"),
    "heel": Option("axial length of the heel (length)"),
    "lip": Option("axial length of the lips (length)"),
    "flare": Option("how far each lip's tip stands out radially past the heel (length; the interference per side)",
                    "nonnegative"),
    "slot": Option("width of the V-shaped slot between the lips at their tips (length; 0 at its root)"),
    "E": Option("Young's modulus of the rubber (stress)"),
    "nu": Option("Poisson's ratio of the rubber (0.4999: nearly incompressible)", "poisson"),
    "squeeze": Option(f"the plates' total approach, a fraction of the seal's free radial span width + 2 flare "
                      f"(default {SQUEEZE:g})", (0.01, 0.4)),
}


def build(law: ContactLaw, quadrature: str = "simpson", steps: int = STEPS, half: bool = False,
          comm: MPI.Comm = MPI.COMM_WORLD, nx: int = NX, ny_heel: int = NY_HEEL, ny_lip: int = NY_LIP,
          width: float = WIDTH, heel: float = HEEL, lip: float = LIP, flare: float = FLARE, slot: float = SLOT,
          E: float = E, nu: float = NU, squeeze: float = SQUEEZE) -> Setup:
    """The lip seal (``half``: the half model, else the full one with self-contact) in ``steps`` equal load steps up
    to the whole ``squeeze``; ``nx`` cells across a half, ``ny_heel`` along the heel, ``ny_lip`` along a lip.
    ``OPTIONS`` describes each parameter; the module docstring the model."""
    if law.name not in METHODS:
        raise ValueError(f"lipseal: method must be one of {', '.join(METHODS)} (self-contact on the mixed P2 model), "
                         f"got {law.name!r}")
    if int(steps) != steps or steps < 1:
        raise ValueError(f"steps must be an integer >= 1, got {steps!r}")
    positive(width=width, heel=heel, lip=lip, slot=slot, E=E)
    poisson(nu=nu)
    if not (np.isfinite(flare) and flare >= 0):
        raise ValueError(f"flare must be a finite number >= 0, got {flare!r}")
    if not 0.01 <= squeeze <= 0.4:
        raise ValueError(f"squeeze must be in [0.01, 0.4], got {squeeze!r}")
    span = width + 2 * flare
    mesh, _, facets = lipseal_section(comm, width, heel, lip, flare, slot, nx, ny_heel, ny_lip, half)
    u, V = unknown(mesh, 2, law, model="neohookean-mixed")
    t = fem.Constant(mesh, 0.0)
    material = MODELS["neohookean-mixed"](E, nu, "strain")
    material.quadrature_degree = QUADRATURE_DEGREE
    d = squeeze * span  # the plates' total approach (length)
    tol = 1e-9 * (heel + lip)
    rod = contact_surface(u, facets, "outer", HalfPlane([0.5 * span, 0.0], [-1.0, 0.0], motion=[-0.5 * d, 0.0]),
                          copy.deepcopy(law), t, quadrature, name="rod", material=material)
    contacts = [rod]
    bottom = Dirichlet.on_facets(V, facets, "bottom", 1)
    if half:
        slot_contact = contact_surface(u, facets, "slot", HalfPlane([0.0, 0.0], [1.0, 0.0]), stiffer(law), t,
                                       quadrature, name="symmetry plane", material=material)
        contacts.append(slot_contact)
        dirichlet = [bottom, Dirichlet.on_facets(V, facets, "cut", 0)]
    else:
        groove = contact_surface(u, facets, "outer", HalfPlane([-0.5 * span, 0.0], [1.0, 0.0],
                                                               motion=[0.5 * d, 0.0]),
                                 copy.deepcopy(law), t, quadrature, name="groove bottom", material=material)
        (slot_contact,) = self_contact_surfaces(u, facets, "slot", lambda: copy.deepcopy(law), t, quadrature,
                                                name="slot", material=material)
        contacts += [groove, slot_contact]
        dirichlet = [bottom, Dirichlet(V.sub(0), line_dofs(V, 0, lambda x: (np.abs(x[0]) < tol) &
                                                            (x[1] < heel + tol)))]
    problem = ContactProblem(u, material, t, dirichlet, contacts)
    # The slot's force on the x > 0 lip: the pressure's x-resultant over that lip's inner face (reference x > 0); in
    # the full model the other lip's points carry the mirror image (their reaction on this lip).
    X = ufl.SpatialCoordinate(mesh)
    right = ufl.conditional(ufl.gt(X[0], 0.0), 1.0, 0.0)
    slot_form = fem.form(right * slot_contact.pressure * slot_contact.normal[0] * slot_contact.ds)

    def profile() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The slot's nominal pressure at the x > 0 lip's inner-face vertices (the mid-side nodes of the P2 facets
        are left out: a rigid surface recovers none there): their reference height ``y``, current position and
        pressure, sorted by the height."""
        Xp, _, _ = slot_contact.point_values(reference=True)
        x, _, p = slot_contact.point_values()
        h = lip / ny_lip
        keep = (Xp[:, 0] > -tol) & (np.abs(np.round((Xp[:, 1] - heel) / h) * h - (Xp[:, 1] - heel)) < 1e-6 * h)
        order = np.argsort(Xp[keep, 1])
        return Xp[keep, 1][order], x[keep][order], p[keep][order]

    def figures() -> dict:
        _, x, p = profile()
        loaded = (p > 0).astype(float)
        # the current length of the face in contact: a facet with both ends loaded counts whole, with one half
        lengths = np.linalg.norm(np.diff(x, axis=0), axis=1)
        width_in_contact = float(np.sum(lengths * 0.5 * (loaded[1:] + loaded[:-1])))
        overlap = slot_contact.max_penetration() * (2.0 if half else 1.0)
        return {"t": float(t.value), "squeeze": squeeze * float(t.value), "approach": d * float(t.value),
                "plate_force": float(-rod.total_force()[0]),
                "slot_force": comm.allreduce(fem.assemble_scalar(slot_form), op=MPI.SUM),
                "slot_width": width_in_contact, "slot_p0": float(p.max(initial=0.0)), "slot_overlap": overlap,
                "plate_penetration": rod.max_penetration()}

    params = {"width": width, "heel": heel, "lip": lip, "flare": flare, "slot": slot, "E": E, "nu": nu,
              "squeeze": squeeze, "nx": nx, "ny_heel": ny_heel, "ny_lip": ny_lip, "quadrature": quadrature,
              "half": half, "material": "neohookean-mixed", "h": float(np.hypot(lip, 0.5 * slot)) / ny_lip,
              "model": "half seal on its symmetry plane (rigid)" if half else "full seal, the slot in self-contact"}
    loads = [(i + 1) / steps for i in range(int(steps))]
    setup = Setup("lipseal", problem, contacts, loads, params, figures,
                  [rod.displacement_out, slot_contact.pressure_out])
    setup.profile = profile
    return setup
