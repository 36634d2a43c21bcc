"""``seal``: flattening of a double-curved seal between two rigid plates (Zavarise et al. 1998, sealing test).

Cross-section: the U-shaped band of :func:`fenics_contact.meshes.seal_section`
(the annular sector between arcs of radii R_out = 10 and R_in = 9, thickness
1; the paper's Figure 17 is not available, the design is documented in the
module docstring of :mod:`fenics_contact.meshes`), plates y = 0 (fixed) and
y = 7 (moving down by ``t``). E = 1000, nu = 0.3, compressible neo-Hookean
(finite strain, large rotations), plane strain. Loads: ``t`` = 0.5, 1.0, ...,
5.5, then 5.6, ..., 6.0 (plates 1 apart = the band's thickness at the end).
Half model: the section and the loading are symmetric about x = 0
(``u_x = 0`` there).

Both plates are analytic half-planes, each with its own contact surface on
the whole free boundary (any part may touch either plate; nodal quadrature).
Nothing else holds the body vertically: at the first iterate the bottom
point touches the lower plate with g = 0 exactly, where a penalty law (and
cross-constraints with F^ = 0) has no stiffness, so the Jacobian is
singular; cross-constraints with ``F^ > 0`` is stiff there (``K^`` at g = 0,
its exponential branch) and needs nothing more. Contact zones are counted
for the whole section: a zone of the half touching x = 0 is one zone, any
other zone has its mirror image.
"""
from __future__ import annotations

from dolfinx import fem
from mpi4py import MPI

from ..compat import function_space
from ..contact import ContactSurface
from ..laws import ContactLaw
from ..materials import NeoHookean
from ..meshes import SEAL_BOUNDARY, SEAL_SYMMETRY, seal_section
from ..obstacles import HalfPlane
from ..problem import ContactProblem, Dirichlet
from . import Setup

E, NU, R_OUT, R_IN, GAP = 1000.0, 0.3, 10.0, 9.0, 7.0
K_HAT = 1e5
F_HAT = 0.1  # far below the contact pressures: a slight penetration, no adhesion; > 0 keeps g = 0 stiff
LOADS = [0.5 * k for k in range(1, 12)] + [5.5 + 0.1 * k for k in range(1, 6)]


def build(law: ContactLaw, quadrature: str = "nodal", h: float = 0.5, loads: list[float] | None = None,
          comm: MPI.Comm = MPI.COMM_WORLD) -> Setup:
    """``h``: cell size (quadrilaterals; the default 0.5 gives 2 cells through the thickness and 30 along
    the half arc, 0.25 gives 4 and 62)."""
    mesh, _, facet_tags = seal_section(comm, h, R_OUT, R_IN, GAP)
    V = function_space(mesh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    sym = fem.locate_dofs_topological(V.sub(0), 1, facet_tags.indices[facet_tags.values == SEAL_SYMMETRY])
    dirichlet = [Dirichlet(V.sub(0), sym)]
    lower = ContactSurface(u, facet_tags, SEAL_BOUNDARY, HalfPlane([0.0, 0.0], [0.0, 1.0]), law, load, quadrature,
                           name="lower plate")
    upper = ContactSurface(u, facet_tags, SEAL_BOUNDARY, HalfPlane([0.0, GAP], [0.0, -1.0], motion=[0.0, -1.0]),
                           _copy(law), load, quadrature, name="upper plate")
    problem = ContactProblem(u, NeoHookean(E, NU), load, dirichlet, [lower, upper])

    def figures() -> dict:
        zl, zu = lower.contact_zones(), upper.contact_zones()
        fl, fu = lower.total_force(), upper.total_force()
        whole = lambda zones: sum(1 if z["X_min"][0] <= 1e-9 else 2 for z in zones)  # noqa: E731
        return {"plate_force_lower": 2 * float(fl[1]), "plate_force_upper": -2 * float(fu[1]),
                "zones_lower": whole(zl), "zones_upper": whole(zu),
                "zones_lower_x": [[z["X_min"][0], z["X_max"][0]] for z in zl],
                "zones_upper_x": [[z["X_min"][0], z["X_max"][0]] for z in zu],
                "max_penetration": max(lower.max_penetration(), upper.max_penetration())}

    params = {"E": E, "nu": NU, "R_out": R_OUT, "R_in": R_IN, "plate_distance": GAP, "h": h,
              "quadrature": quadrature, "material": "neohookean",
              "model": "half of the U-shaped section (symmetry x = 0)"}
    fields = [u, lower.gap_out, lower.pressure_out]
    return Setup("seal", problem, [lower, upper], list(loads or LOADS), params, figures, fields)


def _copy(law: ContactLaw) -> ContactLaw:
    """A second law object with the same parameters (each surface owns its state)."""
    import copy

    return copy.deepcopy(law)
