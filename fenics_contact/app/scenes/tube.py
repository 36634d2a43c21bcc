"""``tube``: a thick-walled rubber tube crushed between two rigid frictionless plates until its inner wall folds onto
itself (plane strain, nearly incompressible neo-Hookean, mixed Taylor-Hood P2-P1; self-contact).

The tube (inner radius ``r_in``, wall ``thickness``, centred at the origin) lies between the plates ``y = +-r_out``
(``r_out = r_in + thickness``), which move toward each other by ``approach / 2`` each over ``0 < t <= 1``. The inner
hole flattens into a slit along ``x``; its upper and lower walls meet at the centre and the contact zone (the fold)
grows along ``x`` with the load. Two models of the same problem:

- full (``half=False``): the whole annulus; the inner wall is one surface in contact with itself
  (:func:`~fenics_contact.factory.self_contact_surfaces`: every point paired with the rest of the wall beyond its
  own neighbourhood, weight 1/2 from each side). The walls are held on the line ``y = 0`` through them, ``u_y =
  0`` (which the symmetric solution satisfies), and ``u_x = 0`` at ``(0, +-r_out)``: this holds the rigid motions
  the frictionless plates leave free, and the antisymmetric mode of the walls where the crease forms (the wall's
  tip may fold up or down: without it, Newton stalls there, at ``t = 0.81`` on the default mesh). The fold itself
  closes by self-contact alone: no constraint acts on the inner wall's points off ``y = 0``.
- half (``half=True``): the half ``y >= 0``, ``u_y = 0`` on its faces on ``y = 0`` (the symmetry plane), ``u_x =
  0`` at ``(0, r_out)``; the inner wall against the symmetry plane ``y = 0`` as a rigid obstacle.

By symmetry the full tube's fold closes on the plane ``y = 0``: the two models are the same problem, their plate
force and fold force equal. The fold forms first at the ends of the slit (a crease of the wall, its tip on the
plane), then the middles of the upper and lower walls meet and the zones grow toward each other. The fold's gap in
the full model is the overlap of the two walls, twice a wall's penetration of the plane; the half model's obstacle
law has twice the stiffness (``K``; ``c_n 2^m_n`` for compliance) so that both models have the same regularised
pressure for the same overlap.

Figures per step (per unit length of tube): ``plate_force`` (the upper plate's), ``fold_force`` (the normal force
the fold carries: on the upper wall from the lower one, or from the plane), ``fold_width`` (the current length of
the upper inner wall in contact, at its vertices), ``fold_p0`` (its peak nominal pressure), ``fold_overlap`` (the
largest overlap of the two walls: full, the largest gap; half, twice the largest penetration of the plane; > 0
interpenetration) and ``plate_penetration``.
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
from ..meshes.tube import tube_section
from . import Option, Setup, poisson, positive
from ._mirror import line_dofs, stiffer, vertex_dofs

__all__ = ["R_IN", "THICKNESS", "E", "NU", "APPROACH", "DEFAULT_K", "N_THETA", "N_R", "STEPS", "FOLD_STEPS",
           "FINE_FROM", "METHODS", "OPTIONS",
           "build", "stiffer"]

R_IN, THICKNESS, E, NU = 1.0, 1.0, 1000.0, 0.4999
APPROACH = 0.6  # of the outer diameter: the hole closes at about 0.5
N_THETA, N_R = 64, 4
# The stepping: 32 equal steps up to t = 0.8, 16 after (where the middles of the walls meet and the zones merge),
# measured on the default mesh to converge with no cutback in both models (uniform 30 to 60 steps each had one
# rescued by a cutback in the full model: where the crease closes, t = 0.65, or where the zones merge, t = 0.84)
STEPS, FOLD_STEPS, FINE_FROM = 32, 16, 0.8
DEFAULT_K = 100.0  # per E / h, h the inner wall's facet length
QUADRATURE_DEGREE = 4  # the bulk's (twice the P2 displacement's), as the oring scene
METHODS = ("penalty", "auglag", "compliance")  # the capability grid's self-contact methods on the mixed P2 model

OPTIONS = {
    "r_in": Option("inner radius of the tube (length)"),
    "thickness": Option("wall thickness of the tube (length; outer radius r_in + thickness)"),
    "E": Option("Young's modulus of the rubber (stress)"),
    "nu": Option("Poisson's ratio of the rubber (0.4999: nearly incompressible)", "poisson"),
    "approach": Option(f"the plates' total approach, a fraction of the outer diameter (default {APPROACH:g})",
                       (0.05, 0.9)),
}


def build(law: ContactLaw, quadrature: str = "simpson", steps: int = STEPS, fold_steps: int = FOLD_STEPS,
          half: bool = False,
          comm: MPI.Comm = MPI.COMM_WORLD, n_theta: int = N_THETA, n_r: int = N_R, r_in: float = R_IN,
          thickness: float = THICKNESS, E: float = E, nu: float = NU, approach: float = APPROACH) -> Setup:
    """The tube (``half``: the half model, else the full one with self-contact): ``steps`` equal load steps up to
    ``t = FINE_FROM``, then ``fold_steps`` up to ``t = 1`` (the whole ``approach``, a fraction of the outer
    diameter); ``n_theta`` cells around the whole circle (a multiple of 4),
    ``n_r`` through the wall. ``OPTIONS`` describes each parameter; the module docstring the model."""
    if law.name not in METHODS:
        raise ValueError(f"tube: method must be one of {', '.join(METHODS)} (self-contact on the mixed P2 model), "
                         f"got {law.name!r}")
    for name, n in (("steps", steps), ("fold_steps", fold_steps)):
        if int(n) != n or n < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {n!r}")
    positive(r_in=r_in, thickness=thickness, E=E)
    poisson(nu=nu)
    if not 0.05 <= approach <= 0.9:
        raise ValueError(f"approach must be in [0.05, 0.9], got {approach!r}")
    r_out = r_in + thickness
    mesh, _, facets = tube_section(comm, r_in, thickness, n_theta, n_r, half)
    u, V = unknown(mesh, 2, law, model="neohookean-mixed")
    t = fem.Constant(mesh, 0.0)
    material = MODELS["neohookean-mixed"](E, nu, "strain")
    material.quadrature_degree = QUADRATURE_DEGREE
    d = approach * 2 * r_out  # the total approach (length)
    tol = 1e-9 * r_out
    top = contact_surface(u, facets, "outer", HalfPlane([0.0, r_out], [0.0, -1.0], motion=[0.0, -0.5 * d]),
                          copy.deepcopy(law), t, quadrature, name="top plate", material=material)
    contacts = [top]
    on_axis = lambda x: (np.abs(x[0]) < tol) & (np.abs(np.abs(x[1]) - r_out) < tol)  # noqa: E731
    if half:
        fold = contact_surface(u, facets, "inner", HalfPlane([0.0, 0.0], [0.0, 1.0]), stiffer(law), t, quadrature,
                               name="symmetry plane", material=material)
        contacts.append(fold)
        dirichlet = [Dirichlet.on_facets(V, facets, "cut", 1), Dirichlet(V.sub(0), vertex_dofs(V, 0, on_axis))]
    else:
        bottom = contact_surface(u, facets, "outer", HalfPlane([0.0, -r_out], [0.0, 1.0], motion=[0.0, 0.5 * d]),
                                 copy.deepcopy(law), t, quadrature, name="bottom plate", material=material)
        (fold,) = self_contact_surfaces(u, facets, "inner", lambda: copy.deepcopy(law), t, quadrature,
                                        name="fold", material=material)
        contacts += [bottom, fold]
        dirichlet = [Dirichlet(V.sub(0), vertex_dofs(V, 0, on_axis)),
                     Dirichlet(V.sub(1), line_dofs(V, 1, lambda x: np.abs(x[1]) < tol))]
    problem = ContactProblem(u, material, t, dirichlet, contacts)
    # The fold's force on the upper wall: the pressure's y-resultant over the inner wall's upper half (reference
    # y > 0); in the full model the lower wall's points carry the mirror image (their reaction on the upper wall).
    X = ufl.SpatialCoordinate(mesh)
    upper = ufl.conditional(ufl.gt(X[1], 0.0), 1.0, 0.0)
    fold_form = fem.form(upper * fold.pressure * fold.normal[1] * fold.ds)

    def profile() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The fold's nominal pressure at the upper inner wall's vertices (the mid-side nodes of the P2 facets are
        left out: a rigid surface recovers none there): their reference angle, current ``x`` and pressure, sorted
        by the angle."""
        Xp, _, _ = fold.point_values(reference=True)
        x, _, p = fold.point_values()
        keep = (Xp[:, 1] > -tol) & (np.abs(np.hypot(Xp[:, 0], Xp[:, 1]) - r_in) < tol)
        angle = np.arctan2(Xp[keep, 1], Xp[keep, 0])
        order = np.argsort(angle)
        return angle[order], x[keep][order], p[keep][order]

    def figures() -> dict:
        _, x, p = profile()
        loaded = (p > 0).astype(float)
        # the current length of the wall in contact: a facet with both ends loaded counts whole, with one half
        lengths = np.linalg.norm(np.diff(x, axis=0), axis=1)
        width = float(np.sum(lengths * 0.5 * (loaded[1:] + loaded[:-1])))
        overlap = fold.max_penetration() * (2.0 if half else 1.0)
        return {"t": float(t.value), "approach": d * float(t.value), "plate_force": float(-top.total_force()[1]),
                "fold_force": comm.allreduce(fem.assemble_scalar(fold_form), op=MPI.SUM),
                "fold_width": width, "fold_p0": float(p.max(initial=0.0)), "fold_overlap": overlap,
                "plate_penetration": top.max_penetration()}

    params = {"r_in": r_in, "thickness": thickness, "E": E, "nu": nu, "approach": approach, "n_theta": n_theta,
              "n_r": n_r, "quadrature": quadrature, "half": half, "material": "neohookean-mixed",
              "h": 2 * np.pi * r_in / n_theta,
              "model": "half tube on its symmetry plane (rigid)" if half else "full tube, inner wall in self-contact"}
    loads = [FINE_FROM * (i + 1) / steps for i in range(int(steps))]
    loads += [FINE_FROM + (1 - FINE_FROM) * (i + 1) / fold_steps for i in range(int(fold_steps))]
    setup = Setup("tube", problem, contacts, loads, params, figures,
                  [top.displacement_out, fold.pressure_out])
    setup.profile = profile
    return setup
