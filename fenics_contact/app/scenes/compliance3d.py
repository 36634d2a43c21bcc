"""``compliance3d``: an elastic box pressed onto a rigid plane, then dragged sideways (formulation 1.5).

The body is a box 1 (x, the drag direction) by 1 (y) by 0.5 (z, height), E = 1000, nu = 0.3, linear
elasticity (strains below 2 %). Its top is glued to a rigid platen that first moves down by
``press = 0.01`` (load t in [0, 1]) and then sideways by ``drag`` along +x (t in [1, 2]); the base
rests on the rigid plane z = 0 with normal compliance ``p = c_n <g>^m_n`` and friction bound
``c_t <g>^m_t`` (or ``mu F(g)``: any normal law with friction). The box spans y in [-0.5, 0.5] and is
symmetric about y = 0 (the drag is along x): we model y in [0, 0.5] with ``u_y = 0`` on y = 0; forces
and areas are reported for the whole box (doubled).

Why these choices: the glued top makes the pressing phase itself frictional (the base wants to expand
laterally by Poisson's effect; friction holds its centre: stick inside, slip at the rim), and the drag
then grows a slip zone from the edges until the whole face slides, when the tangential force reaches
the friction capacity ``int c_t <g>^m_t`` (= ``mu`` times the normal force when ``m_t = m_n``,
``c_t = mu c_n``: Coulomb). Default law: ``m_n = m_t = 1.5`` (inside the paper's range [1, 3.3], a
nonlinear compliance), ``c_n = 5e5`` (the compliant layer takes about a fifth of the approach),
``mu = 0.3``, ``omega_t = 1e5`` (stick slip error ``mu p / omega_t`` about 1 % of the drag). The
default drag 0.006 ends with stick and slip regions side by side; P1 tetrahedra, nodal contact
quadrature (state at the contact vertices). Coarse on purpose: the test mesh solves in seconds.
"""
from __future__ import annotations

import numpy as np
from dolfinx import fem
from dolfinx import mesh as dmesh
from mpi4py import MPI

from ...compat import cell_partitioner, function_space
from ...domain import NamedTags
from ...factory import contact_surface
from ...friction import Friction, FrictionalContact
from ...laws import ContactLaw, ExactCoulomb, NormalCompliance
from ...materials import LinearElastic
from ...obstacles import HalfPlane
from ...problem import ContactProblem, Dirichlet
from . import Option, Setup, SizeError, max_dofs, nonnegative, poisson, positive

__all__ = [
    "LX", "LY", "H", "E", "NU", "PRESS", "DRAG", "C_N", "M_N", "MU", "OMEGA_T",
    "default_law", "half_box", "OPTIONS", "build"
]

LX, LY, H, E, NU = 1.0, 1.0, 0.5, 1000.0, 0.3
PRESS, DRAG = 0.01, 0.006
C_N, M_N, MU, OMEGA_T = 5e5, 1.5, 0.3, 1e5


def default_law(c_n: float = C_N, m_n: float = M_N, mu: float = MU, omega_t: float = OMEGA_T) -> Friction:
    """Coulomb friction (default ``mu = 0.3``) on normal compliance (default ``c_n = 5e5``, ``m_n = 1.5``)."""
    return Friction(NormalCompliance(c_n, m_n), mu=mu, omega_t=omega_t)


def half_box(comm: MPI.Comm, nx: int, ny: int, nz: int, lx: float = LX, ly: float = LY, height: float = H):
    """Tetrahedral box [0, lx] x [0, ly/2] x [0, height] and its named facets
    (:class:`~fenics_contact.domain.NamedTags`) ``base`` (z = 0), ``top`` (z = height), ``symmetry`` (y = 0)."""
    msh = dmesh.create_box(comm, [np.zeros(3), np.array([lx, ly / 2, height])], [nx, ny, nz],
                           dmesh.CellType.tetrahedron, partitioner=cell_partitioner())
    fdim = 2
    found = [(tag, dmesh.locate_entities_boundary(msh, fdim, lambda x, a=a, c=c: np.isclose(x[a], c)))
             for tag, a, c in ((1, 2, 0.0), (2, 2, height), (3, 1, 0.0))]
    idx = np.concatenate([f for _, f in found]).astype(np.int32)
    val = np.concatenate([np.full(len(f), t, dtype=np.int32) for t, f in found])
    idx, first = np.unique(idx, return_index=True)  # an edge facet keeps its first tag (base, top before symmetry)
    return msh, NamedTags(dmesh.meshtags(msh, fdim, idx, val[first]), {"base": 1, "top": 2, "symmetry": 3})


OPTIONS = {
    "lx": Option("box length along x (length)"),
    "ly": Option("box length along y (length)"),
    "height": Option("box height (length)"),
    "E": Option("Young's modulus (stress)"),
    "nu": Option("Poisson's ratio", "poisson"),
    "press": Option("downward platen displacement of the pressing phase (length)"),
    "drag": Option("sideways platen displacement of the drag phase (length)", "nonnegative"),
}


def build(law: ContactLaw | None = None, quadrature: str = "nodal", nx: int = 16, ny: int = 8, nz: int = 4,
          press_steps: int = 2, drag_steps: int = 8, drag: float = DRAG, comm: MPI.Comm = MPI.COMM_WORLD,
          lx: float = LX, ly: float = LY, height: float = H, E: float = E, nu: float = NU,
          press: float = PRESS) -> Setup:
    """``law``: a :class:`~fenics_contact.friction.Friction` (default :func:`default_law`); loads: press the
    platen down by ``press`` in ``press_steps`` steps (t to 1), drag it by ``drag`` in ``drag_steps`` steps (t to 2).
    The box ``lx`` x ``ly`` x ``height`` (``E``, ``nu``). Defaults: the module constants."""
    positive(lx=lx, ly=ly, height=height, E=E, press=press)
    nonnegative(drag=drag)
    poisson(nu=nu)
    law = default_law() if law is None else law
    if isinstance(law, ExactCoulomb):  # its figures (slip areas, dissipation) are the friction surface's
        raise ValueError("method coulomb is not offered on compliance3d (its figures are those of a regularised "
                         "friction law); use compliance, penalty, cross or auglag with --mu")
    if not isinstance(law, Friction):
        raise ValueError("compliance3d needs a law with friction (--mu > 0 or --c-t)")
    for name, n in (("nx", nx), ("ny", ny), ("nz", nz), ("press_steps", press_steps), ("drag_steps", drag_steps)):
        if int(n) < 1:
            raise ValueError(f"compliance3d: {name} must be >= 1, got {n!r}")
    dofs = 3.0 * (int(nx) + 1) * (int(ny) + 1) * (int(nz) + 1)
    most, phrase = max_dofs(comm)
    if dofs > most:  # the demos' --mesh NX NY NZ: the cells it asks for and the most that fit
        raise SizeError("mesh", int(nx) * int(ny) * int(nz), f"{nx} x {ny} x {nz} cells, about {dofs:.2g} unknowns "
                        f"(3 per vertex), more than {phrase} holds at 1 kB each",
                        f"NX NY NZ of at most {most / 3:.2g} cells in all")
    msh, tags = half_box(comm, nx, ny, nz, lx, ly, height)
    V = function_space(msh, "Lagrange", 1, (3,))
    u = fem.Function(V, name="displacement")
    load = fem.Constant(msh, 0.0)
    dofs = {(i, t): fem.locate_dofs_topological(V.sub(i), 2, tags.find(t))
            for i, t in ((0, "top"), (1, "top"), (2, "top"), (1, "symmetry"))}
    path = [0.0, 1.0, 2.0]
    dirichlet = [Dirichlet(V.sub(2), dofs[2, "top"], -press, (path, [0.0, 1.0, 1.0])),
                 Dirichlet(V.sub(0), dofs[0, "top"], drag, (path, [0.0, 0.0, 1.0])),
                 Dirichlet(V.sub(1), dofs[1, "top"]), Dirichlet(V.sub(1), dofs[1, "symmetry"])]
    contact: FrictionalContact = contact_surface(u, tags, "base", HalfPlane([0.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
                                                 law, load, quadrature)
    problem = ContactProblem(u, LinearElastic(E, nu), load, dirichlet, [contact])

    def figures() -> dict:
        Fn = 2 * contact.total_force()[2]
        Ft = 2 * contact.tangential_force()  # its y component is the half's only: the mirror cancels it
        capacity = 2 * contact.capacity()
        R = [2 * problem.reaction(dofs[i, "top"]) for i in (0, 2)]  # platen on the body, x and z
        areas = {k: 2 * v for k, v in contact.state_areas().items()}
        total = lx * ly
        c = {k: float(v.value) for k, v in contact.constants.items()}
        coulomb = "mu" in c or (isinstance(law.normal, NormalCompliance) and law.m_t == law.normal.m)
        mu_eff = c["mu"] if "mu" in c else (c["c_t"] / c["c_n"] if coulomb else float("nan"))
        steps = [{"load": s["load"], "drag": float(np.interp(s["load"], path, [0, 0, drag])),
                  "normal_force": 2 * s["normal_force"][2], "tangential_force": 2 * s["tangential_force"][0],
                  "capacity": 2 * s["capacity"], **{k: 2 * s[k] / total for k in ("stick", "slip", "open")}}
                 for s in contact.log]
        return {"normal_force": Fn, "tangential_force": float(Ft[0]),
                "friction_capacity": capacity, "tangential_over_capacity": float(abs(Ft[0]) / capacity),
                "mu_effective": mu_eff,
                "tangential_over_mu_normal": float(abs(Ft[0]) / (mu_eff * Fn)) if coulomb else float("nan"),
                # on the modelled half (whose y-force the mirror half cancels): |int q| <= int |q| <= int b
                "coulomb_limit_holds": bool(np.linalg.norm(Ft) <= capacity * (1 + 1e-10)),
                "reaction_top_x": R[0], "reaction_top_z": R[1],
                "equilibrium_x": abs(R[0] + Ft[0]) / max(abs(R[0]), abs(Fn)),
                "equilibrium_z": abs(R[1] + Fn) / abs(Fn),
                "stick_area": areas["stick"], "slip_area": areas["slip"], "open_area": areas["open"],
                "stick_fraction": areas["stick"] / total, "slip_fraction": areas["slip"] / total,
                "open_fraction": areas["open"] / total, "dissipated": 2 * contact.dissipated,
                "max_penetration": contact.max_penetration(), "friction_steps": steps}

    params = {"E": E, "nu": nu, "size": [lx, ly, height], "press": press, "drag": drag, "nx": nx, "ny": ny, "nz": nz,
              "quadrature": quadrature, "law": law.name,
              "model": "half box (symmetry y = 0), glued top platen pressed then dragged along +x"}
    loads = [*np.linspace(0, 1, press_steps + 1)[1:], *np.linspace(1, 2, drag_steps + 1)[1:]]
    return Setup("compliance3d", problem, [contact], [float(t) for t in loads], params, figures,
                 [u, contact.gap_out, contact.pressure_out, contact.state_out, contact.traction_out])
