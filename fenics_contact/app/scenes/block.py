"""``block``: elastic block pressed on a rigid frictionless foundation (Zavarise et al. 1998).

Height 2, E = 1000, nu = 0.3, linear elasticity, plane strain; the top is
moved down by 0.32 (vertical displacement imposed, horizontal free), the
base rests on the rigid half-plane y = 0. The paper's figure with the
block's width is missing: the state is uniform for any width, so we model
the right half of a block 2 wide (symmetry u_x = 0 on x = 0). Exact
pressure ``E/(1-nu^2) * 0.32/2 = 175.8243``; with a penetration ``d`` the
pressure is ``175.8243 (1 - d/0.32)``.

Options: ``plane="stress"`` (``sigma_zz = 0``: exact pressure ``E * 0.32/2 = 160``) and
``model="neohookean"`` (finite strain, same E and nu), whose exact state is the homogeneous
``F = diag(a, c, l3)`` of :func:`homogeneous_state`, and ``model="neohookean-mixed"`` (nearly
incompressible rubber, plane strain: the mixed displacement-pressure model on Taylor-Hood P2-P1, contact
quadrature ``gauss`` or ``simpson``; ``linear-mixed``: Herrmann's small-strain form, the linear state), whose
exact state is homogeneous too. Pressures are nominal (per reference area);
neo-Hookean runs also report the Cauchy (true) pressure, per current area. The constants are keyword
arguments of :func:`build` (``height``, ``width``, ``E``, ``nu``, ``displacement``), their defaults the
paper's; the exact state is then :func:`homogeneous_state` of ``strain = displacement / height``.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ...factory import contact_surface
from ...laws import ContactLaw
from ...materials import PLANES, lame
from ...models import MODELS
from ...multipliers import unknown
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from ..meshes import rectangle
from . import Option, Setup, poisson, positive

__all__ = ["OPTIONS",
           "HEIGHT", "HALF_WIDTH", "E", "NU", "DISPLACEMENT", "EXACT_PRESSURE", "BENCH", "build", "reference"]

HEIGHT, HALF_WIDTH, E, NU, DISPLACEMENT = 2.0, 1.0, 1000.0, 0.3, 0.32
EXACT_PRESSURE = E / (1 - NU**2) * DISPLACEMENT / HEIGHT
# The benchmark's view of this scene (fenics_contact.app.bench): figure, sweep, demo options.
BENCH = {"error": "pressure_error", "value": "contact_pressure", "figures": ["max_penetration"], "target": 1e-3,
         "K": 1e5, "mesh": None, "methods": ["penalty", "cross", "auglag", "nitsche", "vi"], "demo_args": []}


def homogeneous_state(model: str = "linear", plane: str = "strain", E: float = E, nu: float = NU,
                      strain: float = DISPLACEMENT / HEIGHT) -> dict:
    """The exact state of the block pressed by ``strain = 0.32/2`` onto the frictionless plane (contact
    closed with gap 0, lateral faces free): ``F = diag(a, c, l3)`` with ``c = 1 - strain``, the nominal
    pressure ``-P_yy`` (force per reference area) and the Cauchy one ``-sigma_yy`` (per current area).

    ``linear``: small strain, ``p = E* strain`` with ``E* = E/(1 - nu^2)`` (plane strain) or ``E`` (plane
    stress); the two pressures are one. ``neohookean``:
    ``P = mu (F - F^-T) + lambda/2 (J^2 - 1) F^-T``, ``J = a c l3``; ``P_xx = 0`` (free sides) and, in
    plane stress, ``P_zz = 0`` give ``mu (a^2 - 1) + lambda/2 (J^2 - 1) = 0`` (the same for ``l3``):

    - plane strain (``l3 = 1``): ``a^2 = (mu + lambda/2) / (mu + lambda c^2/2)``;
    - plane stress (``l3 = a``): ``s = a^2`` solves ``lambda c^2/2 s^2 + mu s - (mu + lambda/2) = 0``.

    Then ``p_nominal = -(mu (c - 1/c) + lambda/2 (J^2 - 1)/c)``, and ``da/dA = J |F^-T N| = a l3`` for the
    base (``N = -e_y``): ``p_cauchy = p_nominal / (a l3)``.

    ``neohookean-mixed`` (plane strain, ``l3 = 1``): ``P_xx(a, c) = 0`` of
    :meth:`~fenics_contact.materials.MixedNeoHookean.uniaxial` solved for ``a`` (Brent's method), then
    ``p_nominal = -P_yy``, ``p_cauchy = p_nominal / a``."""
    if model not in MODELS:
        raise ValueError(f"model must be one of {sorted(MODELS)}, got {model!r}")
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    if MODELS[model].mixed and plane != "strain":
        raise ValueError(f"model {model!r} is plane strain, got plane {plane!r}")
    lam, mu = lame(E, nu)
    c = 1.0 - strain
    if MODELS[model].linear:  # linear-mixed: the same state (its eliminated energy is LinearElastic's)
        p = (E if plane == "stress" else E / (1 - nu**2)) * strain
        return {"a": 1.0, "c": c, "l3": 1.0, "p_nominal": p, "p_cauchy": p}
    if model == "neohookean-mixed":
        from scipy.optimize import brentq

        m = MODELS[model](E, nu)
        a = brentq(lambda s: m.uniaxial(s, c, 2)[0], 1.0, 2.0 / c)  # P_xx < 0 at a = 1, > 0 at J = 2
        p = -m.uniaxial(a, c, 2)[1]
        return {"a": float(a), "c": c, "l3": 1.0, "p_nominal": float(p), "p_cauchy": float(p / a)}
    if plane == "strain":
        a = np.sqrt((mu + lam / 2) / (mu + lam * c**2 / 2))
        l3 = 1.0
    else:
        qa, qb, qc = lam * c**2 / 2, mu, -(mu + lam / 2)
        a = np.sqrt((-qb + np.sqrt(qb**2 - 4 * qa * qc)) / (2 * qa))
        l3 = a
    J = a * c * l3
    p = -(mu * (c - 1 / c) + lam / 2 * (J**2 - 1) / c)
    return {"a": float(a), "c": c, "l3": float(l3), "p_nominal": float(p), "p_cauchy": float(p / (a * l3))}


OPTIONS = {
    "height": Option("block height (length)"),
    "width": Option("block width, the right half modelled (length)"),
    "E": Option("Young's modulus (stress)"),
    "nu": Option("Poisson's ratio", "poisson"),
    "displacement": Option("downward displacement of the block's top at the end (length)"),
}


def build(law: ContactLaw, quadrature: str = "nodal", nx: int = 4, ny: int = 8,
          comm: MPI.Comm = MPI.COMM_WORLD, quadrilateral: bool = False, model: str = "linear",
          steps: int = 1, plane: str = "strain", height: float = HEIGHT, width: float = 2 * HALF_WIDTH, E: float = E,
          nu: float = NU, displacement: float = DISPLACEMENT) -> Setup:
    """``model``: ``linear`` (the paper's), ``neohookean`` (finite strain, same E and nu) or
    ``neohookean-mixed`` or ``linear-mixed`` (P2-P1, quadrature ``gauss`` or ``simpson``); ``plane``:
    ``strain`` (the paper's) or ``stress``; the block ``width`` x ``height`` (the right half modelled), its top
    moved down by ``displacement``."""
    positive(height=height, width=width, E=E, displacement=displacement)
    poisson(nu=nu)
    homogeneous_state(model, plane)  # checks model and plane before any work
    mesh, _, facet_tags = rectangle(comm, width / 2, height, nx, ny, quadrilateral)
    mixed = MODELS[model].mixed
    u, V = unknown(mesh, 2 if mixed else 1, law, model=model)  # (displacement, pressure): lagrange, or mixed model
    load = fem.Constant(mesh, 0.0)
    fdim = mesh.topology.dim - 1
    top = facet_tags.find("top")
    left = facet_tags.find("left")
    top_y = fem.locate_dofs_topological(V.sub(1), fdim, top)
    dirichlet = [Dirichlet(V.sub(1), top_y, -displacement),
                 Dirichlet(V.sub(0), fem.locate_dofs_topological(V.sub(0), fdim, left))]
    material = MODELS[model](E, nu, plane=plane)
    exact = homogeneous_state(model, plane, E, nu, displacement / height)
    contact = contact_surface(u, facet_tags, "bottom", HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                              material=material)
    problem = ContactProblem(u, material, load, dirichlet, [contact])

    def figures() -> dict:
        """``contact_pressure`` is nominal (per reference area); neo-Hookean: also ``contact_pressure_cauchy``
        (per current area) and the exact values of both."""
        force = contact.total_force()
        p = contact.mean_pressure()
        out = {"contact_pressure": p,
               "max_penetration": contact.max_penetration(),
               "total_force": 2 * force[1],
               "reaction_top": -2 * problem.reaction(top_y),
               "exact_pressure": exact["p_nominal"],
               "pressure_error": abs(p - exact["p_nominal"]) / exact["p_nominal"]}
        if model != "linear":
            out.update({"contact_pressure_nominal": p, "contact_pressure_cauchy": contact.mean_pressure("cauchy"),
                        "exact_pressure_cauchy": exact["p_cauchy"]})
        return out

    params = {"E": E, "nu": nu, "height": height, "width": width, "displacement": displacement,
              "nx": nx, "ny": ny, "quadrature": quadrature, "material": model, "plane": plane,
              "model": "half (symmetry x = 0)" + (", plane stress" if plane == "stress" else "")}
    return Setup("block", problem, [contact], [(i + 1) / steps for i in range(steps)], params, figures,
                 [contact.displacement_out, contact.gap_out, contact.pressure_out])


def reference() -> dict:
    return {"contact_pressure": EXACT_PRESSURE}

