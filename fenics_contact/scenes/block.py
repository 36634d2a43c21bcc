"""``block``: elastic block pressed on a rigid frictionless foundation (Zavarise et al. 1998).

Height 2, E = 1000, nu = 0.3, linear elasticity, plane strain; the top is
moved down by 0.32 (vertical displacement imposed, horizontal free), the
base rests on the rigid half-plane y = 0. The paper's figure with the
block's width is missing: the state is uniform for any width, so we model
the right half of a block 2 wide (symmetry u_x = 0 on x = 0). Exact
pressure ``E/(1-nu^2) * 0.32/2 = 175.8243``; with a penetration ``d`` the
pressure is ``175.8243 (1 - d/0.32)``. The constants are keyword arguments of
:func:`build` (``height``, ``width``, ``E``, ``nu``, ``displacement``), their
defaults the paper's; the exact pressure is then ``E/(1-nu^2) displacement/height``.
"""
from __future__ import annotations

from dolfinx import fem
from mpi4py import MPI

from ..bounds import contact_surface
from ..laws import ContactLaw
from ..materials import MODELS
from ..meshes import BOTTOM, LEFT, rectangle
from ..meshes import RECT_TOP as TOP
from ..multipliers import unknown
from ..obstacles import HalfPlane
from ..problem import ContactProblem, Dirichlet
from . import Setup, poisson, positive

HEIGHT, HALF_WIDTH, E, NU, DISPLACEMENT = 2.0, 1.0, 1000.0, 0.3, 0.32
EXACT_PRESSURE = E / (1 - NU**2) * DISPLACEMENT / HEIGHT
# The benchmark's view of this scene (fenics_contact.bench): figure, sweep, demo options.
BENCH = {"error": "pressure_error", "value": "contact_pressure", "figures": ["max_penetration"], "target": 1e-3,
         "K": 1e5, "mesh": None, "methods": ["penalty", "cross", "auglag", "nitsche", "vi"], "demo_args": []}


def build(law: ContactLaw, quadrature: str = "nodal", nx: int = 4, ny: int = 8,
          comm: MPI.Comm = MPI.COMM_WORLD, quadrilateral: bool = False, model: str = "linear",
          steps: int = 1, height: float = HEIGHT, width: float = 2 * HALF_WIDTH, E: float = E, nu: float = NU,
          displacement: float = DISPLACEMENT) -> Setup:
    """``model``: ``linear`` (the paper's) or ``neohookean`` (finite strain, same E and nu); the block
    ``width`` x ``height`` (the right half modelled), its top moved down by ``displacement``."""
    positive(height=height, width=width, E=E, displacement=displacement)
    poisson(nu=nu)
    exact = E / (1 - nu**2) * displacement / height
    mesh, _, facet_tags = rectangle(comm, width / 2, height, nx, ny, quadrilateral)
    u, V = unknown(mesh, 1, law)  # displacement, or (displacement, pressure) for method lagrange
    load = fem.Constant(mesh, 0.0)
    fdim = mesh.topology.dim - 1
    top = facet_tags.indices[facet_tags.values == TOP]
    left = facet_tags.indices[facet_tags.values == LEFT]
    top_y = fem.locate_dofs_topological(V.sub(1), fdim, top)
    dirichlet = [Dirichlet(V.sub(1), top_y, -displacement),
                 Dirichlet(V.sub(0), fem.locate_dofs_topological(V.sub(0), fdim, left))]
    material = MODELS[model](E, nu)
    contact = contact_surface(u, facet_tags, BOTTOM, HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                              material=material)
    problem = ContactProblem(u, material, load, dirichlet, [contact])

    def figures() -> dict:
        force = contact.total_force()
        return {"contact_pressure": contact.mean_pressure(),
                "max_penetration": contact.max_penetration(),
                "total_force": 2 * force[1],
                "reaction_top": -2 * problem.reaction(top_y),
                "exact_pressure": exact,
                "pressure_error": abs(contact.mean_pressure() - exact) / exact}

    params = {"E": E, "nu": nu, "height": height, "width": width, "displacement": displacement,
              "nx": nx, "ny": ny, "quadrature": quadrature, "material": model, "model": "half (symmetry x = 0)"}
    return Setup("block", problem, [contact], [(i + 1) / steps for i in range(steps)], params, figures,
                 [contact.displacement_out, contact.gap_out, contact.pressure_out])


def reference() -> dict:
    return {"contact_pressure": EXACT_PRESSURE}

