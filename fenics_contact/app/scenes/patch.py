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
the uniform state is the exact discrete solution); Nitsche with segment integration 2e-13 to 3e-13 (symmetric,
skew-symmetric, incomplete; neo-Hookean at pressure 100: 2e-14). Pointwise: 0.08 (nodal, one-pass, fine slave),
0.15 (nodal, coarse slave), 0.40 (nodal, two-pass), 0.22 / 0.27 / 0.14 (Gauss one-pass fine / coarse
slave, two-pass): pointwise enforcement integrates the master forces at the slave points across the
kinks of the master shape functions, so the uniform state is not the discrete solution. Only a soft
penalty hides it (K = 100: 3.3e-4 with Gauss one-pass, at a penetration of 0.1).

Per-body materials (:class:`~fenics_contact.materials.Materials`): ``E_lower, nu_lower`` and
``E_upper, nu_upper`` may differ. The piecewise-uniform state (each block uniaxial with its own
stretches) is exact only if both blocks expand equally sideways (else the wider block's edge is
unloaded): linear plane strain needs ``nu (1 + nu) / E`` equal (``nu = 0``: any ``E``), neo-Hookean
``nu = 0`` (no lateral stretch) or equal materials; the figure ``lateral_mismatch`` (difference of the
two lateral stretches) says whether it holds. Then ``strain_lower`` and ``strain_upper`` (mean axial
strain of each block) and ``displacement_error`` (every node against the exact piecewise-uniform
field) check each body.

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

from ...compat import function_space
from ...factory import two_body_surfaces
from ...laws import ContactLaw
from ...materials import LinearElastic, Materials
from ...models import MODELS
from ...problem import ContactProblem, Dirichlet
from ..meshes import stacked_blocks
from . import Option, Setup, poisson, positive

__all__ = ["E_LOWER", "E_UPPER", "NU", "PRESSURE", "OVERLAP", "WIDTH", "H_LOWER", "H_UPPER", "uniform_stretches",
           "OPTIONS", "build"]

E_LOWER, E_UPPER, NU, PRESSURE, OVERLAP = 1000.0, 1000.0, 0.3, 10.0, 1e-6
WIDTH, H_LOWER, H_UPPER = 1.0, 1.0, 1.0  # the blocks' width (and depth in 3D) and heights


def uniform_stretches(pressure: float, material: str, dim: int, E: float = E_LOWER,
                      nu: float = NU) -> tuple[float, float]:
    """Lateral and axial stretch ``(a, c)`` of the exact uniform state of a block of ``E``, ``nu``:
    uniaxial nominal stress ``-pressure`` along the stacking axis, zero across (free lateral faces; plane
    strain ``F_zz = 1`` in 2D), for the material (``linear``: ``1 + strain``). The interface stays flat."""
    lam, mu = LinearElastic(E, nu).lmbda, LinearElastic(E, nu).mu
    if material == "linear":
        if dim == 3:
            return 1.0 + nu * pressure / E, 1.0 - pressure / E
        return 1.0 + nu * (1 + nu) * pressure / E, 1.0 - (1 - nu**2) * pressure / E
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


OPTIONS = {
    "pressure": Option("pressure on the upper block's top (stress)"),
    "E_lower": Option("lower block's Young's modulus (stress)"),
    "E_upper": Option("upper block's Young's modulus (stress)"),
    "nu_lower": Option("lower block's Poisson's ratio", "poisson"),
    "nu_upper": Option("upper block's Poisson's ratio", "poisson"),
    "width": Option("blocks' width (and depth in 3D) (length)"),
    "h_lower": Option("lower block's height (length)"),
    "h_upper": Option("upper block's height (length)"),
    "overlap": Option("initial overlap of the upper block into the lower one (length; < 0.1 of the lower height)"),
}


def build(law: ContactLaw | None = None, law_factory=None, quadrature: str = "gauss", passes: str = "one",
          slave: str = "upper", n_lower: tuple[int, ...] = (5, 4), n_upper: tuple[int, ...] = (7, 5),
          by_body: bool = False, material: str = "linear", pressure: float = PRESSURE,
          comm: MPI.Comm = MPI.COMM_WORLD, E_lower: float = E_LOWER, E_upper: float = E_UPPER,
          nu_lower: float = NU, nu_upper: float = NU, width: float = WIDTH, h_lower: float = H_LOWER,
          h_upper: float = H_UPPER, overlap: float = OVERLAP, sliding: str | None = None) -> Setup:
    """``slave``: ``upper`` or ``lower`` block's interface is the slave surface (one-pass).
    ``law_factory()`` (or ``law`` for one pass) gives the contact law. Three cell counts make the 3D
    version (unit cubes of tetrahedra stacked along z, rollers also on y = 0). ``material``: ``linear``
    or ``neohookean`` (finite strain for a large ``pressure``, a dead load), with ``E`` and ``nu`` per block
    (:class:`~fenics_contact.materials.Materials`). The blocks ``width`` wide (and deep in 3D), ``h_lower`` and
    ``h_upper`` high, the upper one starting ``overlap`` into the lower one (module docstring); defaults: the
    module constants. ``sliding``: the two-body kinematics (:func:`~fenics_contact.two_body_surfaces`)."""
    if slave not in ("upper", "lower"):
        raise ValueError(f"slave must be 'upper' or 'lower', got {slave!r}")
    if material not in ("linear", "neohookean"):
        raise ValueError(f"material must be 'linear' or 'neohookean', got {material!r}")
    positive(pressure=pressure, E_lower=E_lower, E_upper=E_upper, width=width, h_lower=h_lower, h_upper=h_upper,
             overlap=overlap)
    poisson(nu_lower=nu_lower, nu_upper=nu_upper)
    if not overlap < 0.1 * min(h_lower, h_upper):
        raise ValueError(f"overlap must be < 0.1 min(h_lower, h_upper) = {0.1 * min(h_lower, h_upper)!r} (a start "
                         f"that gives the penalty-type laws stiffness, not a geometry), got {overlap!r}")
    if law_factory is None:
        if law is None:
            raise ValueError("give law or law_factory")
        if passes == "two":
            raise ValueError("two-pass needs law_factory (one law per surface)")
        law_factory = lambda: law  # noqa: E731
    mesh, cell_tags, facet_tags = stacked_blocks(comm, width, h_lower, h_upper, n_lower, n_upper, overlap, by_body)
    dim = len(n_lower)
    V = function_space(mesh, "Lagrange", 1, (dim,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(mesh, 0.0)
    fdim = mesh.topology.dim - 1
    support = Dirichlet.on_facets(V, facet_tags, "lower_bottom", dim - 1)
    dirichlet = [support, Dirichlet.on_facets(V, facet_tags, "left", 0)]
    if dim == 3:
        dirichlet.append(Dirichlet.on_facets(V, facet_tags, "front", 1))
    tags = ("upper_bottom", "lower_top") if slave == "upper" else ("lower_top", "upper_bottom")
    bulk = Materials(mesh, cell_tags, {"lower": MODELS[material](E_lower, nu_lower),
                                       "upper": MODELS[material](E_upper, nu_upper)})
    contacts = two_body_surfaces(u, facet_tags, *tags, law_factory, load, quadrature, passes, name="interface",
                                 material=bulk, sliding=sliding)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags, subdomain_id=facet_tags["upper_top"])
    traction = (ufl.as_vector((0.0,) * (dim - 1) + (-pressure,)), ds)
    problem = ContactProblem(u, bulk, load, dirichlet, contacts, [traction])
    top_dofs = fem.locate_dofs_topological(V, fdim, facet_tags.find("upper_top"))
    (a_lo, c_lo), (a_up, c_up) = (uniform_stretches(pressure, material, dim, E, nu)
                                  for E, nu in ((E_lower, nu_lower), (E_upper, nu_upper)))
    u_top = c_lo * h_lower + c_up * h_upper - (h_lower - overlap + h_upper)  # exact (bottom fixed, gap 0)
    body_dofs = {tag: np.unique(np.concatenate([V.dofmap.cell_dofs(c) for c in cell_tags.find(tag)]
                                               + [np.zeros(0, np.int32)])) for tag in ("lower", "upper")}
    dx = ufl.Measure("dx", domain=mesh, subdomain_data=cell_tags.meshtags)
    one = fem.Constant(mesh, 1.0)
    strain_forms = {tag: (fem.form(ufl.grad(u)[dim - 1, dim - 1] * dx(cell_tags[tag])),
                          fem.form(one * dx(cell_tags[tag]))) for tag in ("lower", "upper")}

    def exact_displacement(tag: str, X: np.ndarray) -> np.ndarray:
        """The exact piecewise-uniform displacement at reference points ``X`` of block ``tag``."""
        a, c = (a_lo, c_lo) if tag == "lower" else (a_up, c_up)
        Y = X[:, dim - 1]
        axial = (c - 1.0) * Y if tag == "lower" else c_lo * h_lower + c_up * (Y - h_lower + overlap) - Y
        return np.concatenate([(a - 1.0) * X[:, : dim - 1], axial[:, None]], 1)

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
        exact = np.concatenate([(a_up - 1.0) * X[:, : dim - 1], np.full((len(X), 1), u_top)], 1)
        err = comm.allreduce(float(np.max(np.abs(U - exact))) if len(top) else 0.0, op=MPI.MAX)
        body_err, strains = 0.0, {}
        for tag in ("lower", "upper"):
            d = body_dofs[tag][body_dofs[tag] < n_own]
            if len(d):
                Xd = V.tabulate_dof_coordinates()[d, :dim]
                body_err = max(body_err, float(np.max(np.abs(u.x.array.reshape(-1, dim)[d] - exact_displacement(
                    tag, Xd)))))
            integral, volume = (comm.allreduce(fem.assemble_scalar(f), op=MPI.SUM) for f in strain_forms[tag])
            strains[f"strain_{tag}"] = integral / volume
        body_err = comm.allreduce(body_err, op=MPI.MAX)
        return {"pressure_deviation": dev, "contact_force": float(np.mean(np.abs(forces))),
                "applied_force": pressure * width ** (dim - 1), "reaction_bottom": problem.reaction(support.dofs),
                "top_displacement_exact": u_top, "top_displacement_error": err / abs(u_top),
                "displacement_error": body_err / abs(u_top), **strains, "lateral_mismatch": abs(a_lo - a_up),
                "strain_lower_exact": c_lo - 1.0, "strain_upper_exact": c_up - 1.0}

    for c in contacts:  # one name per field in the XDMF file
        c.gap_out.name, c.pressure_out.name = f"gap_{c.name}", f"contact_pressure_{c.name}"
    params = {"E_lower": E_lower, "E_upper": E_upper, "nu_lower": nu_lower, "nu_upper": nu_upper,
              "width": width, "h_lower": h_lower, "h_upper": h_upper,
              "pressure": pressure, "material": material,
              "n_lower": list(n_lower), "n_upper": list(n_upper), "quadrature": quadrature, "passes": passes,
              "slave": slave, "sliding": sliding,
              "overlap": overlap, "model": f"two blocks, rollers, {'plane strain' if dim == 2 else '3D'}, {material}"}
    return Setup("patch", problem, contacts, [1.0], params, figures, [u] + [f for c in contacts
                                                                         for f in (c.gap_out, c.pressure_out)])
