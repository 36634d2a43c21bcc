"""``patch``: contact patch test, two stacked elastic blocks with non-matching interface meshes.

Lower block ``[0, 1] x [0, 1]``, upper block ``[0, 1] x [1, 2]``, both E = 1000, nu = 0.3 (the same
material: equal lateral expansion, so no part of the upper block overhangs the lower one and the
uniform state is the exact solution), plane strain, linear elasticity (small uniform strain),
frictionless interface. Rollers: ``u_y = 0`` on the lower block's bottom, ``u_x = 0`` on the left side
of both blocks; uniform pressure ``P = 10`` on the upper block's top. The exact contact pressure is
``P`` everywhere. Meshes: ``n_lower`` and ``n_upper`` cells across differ, so the interface nodes do
not match. The upper block is only held by the contact: it starts with an overlap of ``1e-6`` so that
the penalty-type laws have stiffness at the first Newton iteration.

Figure: ``pressure_deviation = max |p - P| / P`` over the slave quadrature points of every slave
surface (sub-segment Gauss points with ``quadrature="segment"``). Measured (5 x 4 against 7 x 5 cell
pairs, ``demos/patch.py``), with converged multipliers (augmented Lagrangian): segment-to-segment
integration 2e-11 to 4e-11 (one-pass either slave, two-pass; penalty alone: round-off for every K,
the uniform state is the exact discrete solution). Pointwise: 0.08 (nodal, one-pass, fine slave),
0.15 (nodal, coarse slave), 0.40 (nodal, two-pass), 0.22 / 0.27 / 0.14 (Gauss one-pass fine / coarse
slave, two-pass): pointwise enforcement integrates the master forces at the slave points across the
kinks of the master shape functions, so the uniform state is not the discrete solution. Only a soft
penalty hides it (K = 100: 3.3e-4 with Gauss one-pass, at a penetration of 0.1).
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ..compat import function_space
from ..laws import ContactLaw
from ..materials import LinearElastic
from ..meshes import BLOCK_FRONT, BLOCK_LEFT, LOWER_BOTTOM, LOWER_TOP, UPPER, UPPER_BOTTOM, UPPER_TOP, stacked_blocks
from ..problem import ContactProblem, Dirichlet
from ..twobody import two_body_surfaces
from . import Setup

E_LOWER, E_UPPER, NU, PRESSURE, OVERLAP = 1000.0, 1000.0, 0.3, 10.0, 1e-6


class _TwoMaterials(LinearElastic):
    """Linear elasticity with E per block (a DG0 field)."""

    def __init__(self, E_field, nu):
        super().__init__(1.0, nu)
        self.E_field = E_field

    def energy(self, u):
        return self.E_field * super().energy(u)

    def stress(self, u):
        return self.E_field * super().stress(u)

    def describe(self):
        return {"model": "LinearElastic", "E_lower": E_LOWER, "E_upper": E_UPPER, "nu": NU}


def build(law: ContactLaw | None = None, law_factory=None, quadrature: str = "gauss", passes: str = "one",
          slave: str = "upper", n_lower: tuple[int, ...] = (5, 4), n_upper: tuple[int, ...] = (7, 5),
          by_body: bool = False, comm: MPI.Comm = MPI.COMM_WORLD) -> Setup:
    """``slave``: ``upper`` or ``lower`` block's interface is the slave surface (one-pass).
    ``law_factory()`` (or ``law`` for one pass) gives the contact law. Three cell counts make the 3D
    version (unit cubes of tetrahedra stacked along z, rollers also on y = 0)."""
    if slave not in ("upper", "lower"):
        raise ValueError(f"slave must be 'upper' or 'lower', got {slave!r}")
    if law_factory is None:
        if law is None:
            raise ValueError("give law or law_factory")
        if passes == "two":
            raise ValueError("two-pass needs law_factory (one law per surface)")
        law_factory = lambda: law  # noqa: E731
    mesh, cell_tags, facet_tags = stacked_blocks(comm, 1.0, 1.0, 1.0, n_lower, n_upper, OVERLAP, by_body)
    dim = len(n_lower)
    V = function_space(mesh, "Lagrange", 1, (dim,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    D = function_space(mesh, "DG", 0)
    Ef = fem.Function(D)
    Ef.x.array[:] = np.where(cell_tags.values == UPPER, E_UPPER, E_LOWER)
    fdim = mesh.topology.dim - 1
    bottom = fem.locate_dofs_topological(V.sub(dim - 1), fdim,
                                         facet_tags.indices[facet_tags.values == LOWER_BOTTOM])
    left = fem.locate_dofs_topological(V.sub(0), fdim, facet_tags.indices[facet_tags.values == BLOCK_LEFT])
    dirichlet = [Dirichlet(V.sub(dim - 1), bottom), Dirichlet(V.sub(0), left)]
    if dim == 3:
        front = fem.locate_dofs_topological(V.sub(1), fdim, facet_tags.indices[facet_tags.values == BLOCK_FRONT])
        dirichlet.append(Dirichlet(V.sub(1), front))
    tags = (UPPER_BOTTOM, LOWER_TOP) if slave == "upper" else (LOWER_TOP, UPPER_BOTTOM)
    contacts = two_body_surfaces(u, facet_tags, *tags, law_factory, load, quadrature, passes, name="interface")
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags, subdomain_id=UPPER_TOP)
    traction = (ufl.as_vector((0.0,) * (dim - 1) + (-PRESSURE,)), ds)
    problem = ContactProblem(u, _TwoMaterials(Ef, NU), load, dirichlet, contacts, [traction])

    def figures() -> dict:
        dev, forces = 0.0, []
        for c in contacts:
            x, _, p = c.point_values()
            dev = max(dev, float(np.max(np.abs(p - PRESSURE))) / PRESSURE)
            forces.append(float(c.total_force()[dim - 1]))
        return {"pressure_deviation": dev, "contact_force": float(np.mean(np.abs(forces))),
                "applied_force": PRESSURE * 1.0, "reaction_bottom": problem.reaction(bottom)}

    for c in contacts:  # one name per field in the XDMF file
        c.gap_out.name, c.pressure_out.name = f"gap_{c.name}", f"contact_pressure_{c.name}"
    params = {"E_lower": E_LOWER, "E_upper": E_UPPER, "nu": NU, "pressure": PRESSURE, "n_lower": list(n_lower),
              "n_upper": list(n_upper), "quadrature": quadrature, "passes": passes, "slave": slave,
              "overlap": OVERLAP, "model": "two blocks, rollers, plane strain, linear elasticity"}
    return Setup("patch", problem, contacts, [1.0], params, figures, [u] + [f for c in contacts
                                                                         for f in (c.gap_out, c.pressure_out)])
