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

``material="neohookean"`` with a large ``pressure`` (a dead load) tests finite strain: the exact state
is still uniform (uniaxial nominal stress, :func:`uniform_stretches`), and the figure
``top_displacement_error`` (top face against it, converged contact: gap 0) checks the whole solution.
3D (three cell counts; ``tests/test_twobody.py``): segment integration (clipped triangles) 3.5e-11,
Gauss points 0.33 (neo-Hookean, pressure 100, augmented Lagrangian) with the exact displacement in both.
"""
from __future__ import annotations

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ..compat import function_space
from ..factory import two_body_surfaces
from ..laws import ContactLaw
from ..materials import LinearElastic, NeoHookean
from ..meshes import BLOCK_FRONT, BLOCK_LEFT, LOWER_BOTTOM, LOWER_TOP, UPPER, UPPER_BOTTOM, UPPER_TOP, stacked_blocks
from ..problem import ContactProblem, Dirichlet
from . import Setup

__all__ = ["E_LOWER", "E_UPPER", "NU", "PRESSURE", "OVERLAP", "uniform_stretches", "build"]

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


def uniform_stretches(pressure: float, material: str, dim: int) -> tuple[float, float]:
    """Lateral and axial stretch ``(a, c)`` of the exact uniform state: uniaxial nominal stress ``-pressure``
    along the stacking axis, zero across (free lateral faces; plane strain ``F_zz = 1`` in 2D), for the
    blocks' material (``linear``: ``1 + strain``). Both blocks have it, so the interface stays flat."""
    lam, mu = LinearElastic(E_LOWER, NU).lmbda, LinearElastic(E_LOWER, NU).mu
    if material == "linear":
        if dim == 3:
            return 1.0 + NU * pressure / E_LOWER, 1.0 - pressure / E_LOWER
        return 1.0 + NU * (1 + NU) * pressure / E_LOWER, 1.0 - (1 - NU**2) * pressure / E_LOWER
    # Neo-Hookean first Piola stress P = mu (F - F^-T) + lam/2 (J^2 - 1) F^-T, F = diag(a, .., c): Newton.
    x = np.array([1.0, 1.0])
    for _ in range(50):
        a, c = x
        J = a ** (dim - 1) * c
        r = np.array([mu * (a - 1 / a) + 0.5 * lam * (J * J - 1) / a, mu * (c - 1 / c) + 0.5 * lam * (J * J - 1) / c
                      + pressure])
        dJ = np.array([(dim - 1) * J / a, J / c])
        jac = np.array([[mu * (1 + 1 / a**2) - 0.5 * lam * (J * J - 1) / a**2 + lam * J * dJ[0] / a,
                         lam * J * dJ[1] / a],
                        [lam * J * dJ[0] / c,
                         mu * (1 + 1 / c**2) - 0.5 * lam * (J * J - 1) / c**2 + lam * J * dJ[1] / c]])
        step = np.linalg.solve(jac, r)
        x = x - step
        if np.max(np.abs(step)) < 1e-15:
            break
    return float(x[0]), float(x[1])


def build(law: ContactLaw | None = None, law_factory=None, quadrature: str = "gauss", passes: str = "one",
          slave: str = "upper", n_lower: tuple[int, ...] = (5, 4), n_upper: tuple[int, ...] = (7, 5),
          by_body: bool = False, material: str = "linear", pressure: float = PRESSURE,
          comm: MPI.Comm = MPI.COMM_WORLD) -> Setup:
    """``slave``: ``upper`` or ``lower`` block's interface is the slave surface (one-pass).
    ``law_factory()`` (or ``law`` for one pass) gives the contact law. Three cell counts make the 3D
    version (unit cubes of tetrahedra stacked along z, rollers also on y = 0). ``material``: ``linear``
    or ``neohookean`` (the same E, nu; finite strain for a large ``pressure``, a dead load)."""
    if slave not in ("upper", "lower"):
        raise ValueError(f"slave must be 'upper' or 'lower', got {slave!r}")
    if material not in ("linear", "neohookean"):
        raise ValueError(f"material must be 'linear' or 'neohookean', got {material!r}")
    if not (np.isfinite(pressure) and pressure > 0):
        raise ValueError(f"pressure must be a finite number > 0, got {pressure!r}")
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
    support = Dirichlet.on_facets(V, facet_tags, LOWER_BOTTOM, dim - 1)
    dirichlet = [support, Dirichlet.on_facets(V, facet_tags, BLOCK_LEFT, 0)]
    if dim == 3:
        dirichlet.append(Dirichlet.on_facets(V, facet_tags, BLOCK_FRONT, 1))
    tags = (UPPER_BOTTOM, LOWER_TOP) if slave == "upper" else (LOWER_TOP, UPPER_BOTTOM)
    contacts = two_body_surfaces(u, facet_tags, *tags, law_factory, load, quadrature, passes, name="interface")
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags, subdomain_id=UPPER_TOP)
    traction = (ufl.as_vector((0.0,) * (dim - 1) + (-pressure,)), ds)
    bulk = _TwoMaterials(Ef, NU) if material == "linear" else NeoHookean(E_LOWER, NU)
    problem = ContactProblem(u, bulk, load, dirichlet, contacts, [traction])
    top_dofs = fem.locate_dofs_topological(V, fdim, facet_tags.indices[facet_tags.values == UPPER_TOP])
    a_lat, c_ax = uniform_stretches(pressure, material, dim)
    u_top = 2.0 * c_ax - (2.0 - OVERLAP)  # exact top displacement (bottom fixed, gap 0)

    def figures() -> dict:
        """Pressure deviation, forces, and the top face's displacement against the exact uniform state
        (converged contact: the blocks touch along a flat interface, gap 0)."""
        dev, forces = 0.0, []
        for s in contacts:
            x, _, p = s.point_values()
            dev = max(dev, float(np.max(np.abs(p - pressure))) / pressure)
            forces.append(float(s.total_force()[dim - 1]))
        n_own = V.dofmap.index_map.size_local
        top = top_dofs[top_dofs < n_own]
        X = V.tabulate_dof_coordinates()[top, :dim]
        U = u.x.array.reshape(-1, dim)[top]
        exact = np.concatenate([(a_lat - 1.0) * X[:, : dim - 1], np.full((len(X), 1), u_top)], 1)
        err = comm.allreduce(float(np.max(np.abs(U - exact))) if len(top) else 0.0, op=MPI.MAX)
        return {"pressure_deviation": dev, "contact_force": float(np.mean(np.abs(forces))),
                "applied_force": pressure * 1.0, "reaction_bottom": problem.reaction(support.dofs),
                "top_displacement_exact": u_top, "top_displacement_error": err / abs(u_top)}

    for c in contacts:  # one name per field in the XDMF file
        c.gap_out.name, c.pressure_out.name = f"gap_{c.name}", f"contact_pressure_{c.name}"
    params = {"E_lower": E_LOWER, "E_upper": E_UPPER, "nu": NU, "pressure": pressure, "material": material,
              "n_lower": list(n_lower), "n_upper": list(n_upper), "quadrature": quadrature, "passes": passes,
              "slave": slave,
              "overlap": OVERLAP, "model": f"two blocks, rollers, {'plane strain' if dim == 2 else '3D'}, {material}"}
    return Setup("patch", problem, contacts, [1.0], params, figures, [u] + [f for c in contacts
                                                                         for f in (c.gap_out, c.pressure_out)])
