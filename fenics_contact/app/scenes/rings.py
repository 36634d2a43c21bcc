"""``rings``: two concentric elastic rings under external pressure, an exact curved two-body interface.

Geometry and data: inner ring ``a <= r <= b``, outer ring ``b <= r <= c``
(``a, b, c = 0.2, 0.6, 1.0``), two bodies of one mesh touching along ``r = b``
without shared nodes (``n`` elements along the inner ring's arc ``r = b``,
``n_outer`` (default ``3 n / 4``) along the outer ring's: non-matching
interface meshes, :func:`~fenics_contact.app.meshes.rings.concentric_rings`);
pressure ``q`` on ``r = c`` (dead load, small strain), ``r = a`` free; linear
elasticity per ring (``E1, nu1`` inside, ``E2, nu2`` outside), plane strain
or plane stress. Quarter model: rollers ``u_x = 0`` on ``x = 0`` and ``u_y =
0`` on ``y = 0`` for both rings (each ring is then held without contact).
The inner ring's arc is the slave surface (one pass), both in two passes.

Lamé. For a ring ``r0 <= r <= r1`` under inner pressure ``p_i`` and outer
pressure ``p_o`` (plane stress)::

    sigma_r = A - B/r^2,   sigma_t = A + B/r^2,
    A = (p_i r0^2 - p_o r1^2) / (r1^2 - r0^2),   B = (p_i - p_o) r0^2 r1^2 / (r1^2 - r0^2),
    u_r = [(1 - nu) A r + (1 + nu) B / r] / E;

plane strain is the same with ``E' = E/(1 - nu^2)``, ``nu' = nu/(1 - nu)``.
Inner ring (``p_i = 0, p_o = p``) and outer ring (``p_i = p, p_o = q``) at ``r = b``::

    u1(b) = -p b [(1 - nu1) b^2 + (1 + nu1) a^2] / (E1 (b^2 - a^2)),
    u2(b) =  b [p ((1 - nu2) b^2 + (1 + nu2) c^2) - 2 q c^2] / (E2 (c^2 - b^2)).

Contact (frictionless, no gap at rest, ``p > 0``) is ``u1(b) = u2(b)``::

    p = 2 q c^2 / (E2 (c^2 - b^2)) / [ ((1 - nu1) b^2 + (1 + nu1) a^2) / (E1 (b^2 - a^2))
                                      + ((1 - nu2) b^2 + (1 + nu2) c^2) / (E2 (c^2 - b^2)) ]

(primes in plane strain). Equal materials: the bracket times ``E (b^2 - a^2)(c^2 - b^2)`` is
``2 b^2 (c^2 - a^2)`` whatever ``nu``, so ``p = q c^2 (1 - a^2/b^2) / (c^2 - a^2)`` in plane strain and
plane stress alike (0.9259 q here: the one-body annulus's ``sigma_r(b)``). Then ``u_r(a) = -2 p a b^2 /
(E1 (b^2 - a^2))`` and ``u_r(c) = c [2 p b^2 - q ((1 - nu2) c^2 + (1 + nu2) b^2)] / (E2 (c^2 - b^2))``.
The solution is radial: circles stay circles, so the current interface is a circle too and the
finite-displacement contact condition of the library is exact for it (the bulk is linear).

Figures: ``p_lame``; over the constrained points of every slave surface (collocated element: every node of
both surfaces) (the vertices for ``nodal``,
the Gauss points for ``gauss``, the sub-segment Gauss points for ``segment``, all three nodes of a
quadratic facet for ``simpson`` with a penalty-type law, the end nodes for ``nodal`` on quadratic
facets and for multipliers) the pressure's ``p_max_deviation = max |p - p_lame| / p_lame`` and
``p_mean_deviation = mean |p - p_lame| / p_lame``; ``p_reaction``: the interface pressure from the
inner ring's roller reaction on ``y = 0`` (the quarter's vertical equilibrium: ``R_y = p b``),
formulation-independent; ``ur_a`` / ``ur_c``: mean radial displacement of the nodes on ``r = a`` /
``r = c``, ``ur_a_deviation`` / ``ur_c_deviation``: max relative deviation from Lamé over them.

Measured (``demos/rings.py``, defaults: ``E = 1000, nu = 0.3`` both rings, ``q = 10`` (strains ~1e-2),
plane strain, ``n = 16``, ``n_outer = 12``; serial; max / mean pointwise deviation, the reaction's
deviation, ``u_r(a)``, ``u_r(c)`` deviations; K in pressure per length)::

    P1 nodal one     penalty 1e5 / 1e8     0.76 / 0.43   0.046   0.019  0.077
                     auglag, lagrange      0.84 / 0.48   0.051   0.024  0.085
    P1 nodal two     penalty 1e8, auglag, lagrange
                                           1.99 / 1.22   0.050   0.022  0.083
    P1 gauss one     penalty 1e8, auglag   2.19 / 1.05   0.041   0.015  0.071
    P1 gauss two     penalty 1e7, auglag   5.4 / 1.6     0.041   0.015  0.071   (1e8: no convergence)
    P1 segment one   penalty 1e8           1.94 / 1.14   0.045   0.018  0.077   (auglag 1.77 / 1.18)
    P1 segment two   penalty 1e8           3.56 / 1.31   0.044   0.018  0.077   (auglag 4.4 / 1.5)
    P2 nodal one     penalty 1e8, auglag, lagrange
                                           0.171 / 0.077 0.022   0.024  0.038
    P2 nodal two     penalty 1e8, auglag, lagrange
                                           1.0 / 0.47    0.014   0.020  0.028   (points open: p = 0)
    P2 simpson one   penalty 1e5           0.027 / 0.010 5.4e-3  6.8e-3 8.6e-3
                     penalty 1e6           0.026 / 0.011 5.1e-4  2.0e-3 8.4e-4
                     penalty 1e8, auglag   0.027 / 0.011 2.6e-5  1.5e-3 5.1e-5
                     lagrange (two-point)  0.024 / 0.019 1.3e-5  1.5e-3 5.7e-5
    P2 simpson two   penalty 1e7, auglag   1.2-1.4 / 0.5-0.6  2e-4 1.5e-3 1e-4   (locking; 1e8 and
                                                                                  lagrange: no convergence)
    P2 collocated    lagrange              6.2e-4 / 3.2e-4  1.7e-4  1.6e-3 1.6e-4
                     p = eps <g>, 1e5      6.0e-3 / 5.5e-3  5.5e-3  6.9e-3 8.6e-3
                     p = eps <g>, 1e6      1.2e-3 / 6.4e-4  7.0e-4  2.2e-3 7.7e-4
                     p = eps <g>, 1e7      6.7e-4 / 3.3e-4  2.3e-4  1.7e-3 7.5e-5
                     p = eps <g>, 1e8      6.2e-4 / 3.2e-4  1.8e-4  1.6e-3 1.5e-4

Since :mod:`~fenics_contact.capabilities`, the ``nodal`` rule on P2 facets (every method) and two-pass
multipliers are refused up front; their rows above were measured before that refusal.

Reading: with P1 facets every option is dominated by the chord sag ``h^2/8b`` (1.3e-3 for the outer
ring's facets) against interface displacements ~6e-3: the two polygons interfere, and the pressure
oscillates by O(1) between the meshes' nodes (first order in ``h`` and proportional to ``E/q``; the
interface force, second order). P2 facets remove the sag (quadratic curves agree with the circle to
``O(h^4)``); the one-pass elements with Simpson's rule then reach ~2.5 % pointwise, an error that does
not decrease with ``h`` (``n = 8, 16, 32``: 2.5, 2.4, 2.4 %; the interface force converges, 2e-4, 1.3e-5,
8e-6): the one-pass node-to-surface element fails the patch test on non-matching meshes. The ``nodal`` rule
on P2 facets (end nodes only) is inconsistent (17 %); two passes over-constrain (locking, open points).
Papadopoulos & Solberg's collocated element (``quadrature="collocated"``, :mod:`~fenics_contact.collocation`:
a pressure on both surfaces, the gap at the vertices of both, the middle pressure collocated from the
opposite surface, each body loaded by its own pressure) is the best of all and converges pointwise: max
deviation 0.32, 0.062, 0.012 % at ``n = 8, 16, 32``. Its pressure is per current length (Cauchy); the
figures use its nominal value (per reference length, Lamé's small-strain convention: the interface
shrinks by 0.7 %), ``point_table(kind="nominal")``.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...compat import collapse, function_space
from ...contact import is_mixed
from ...factory import two_body_multipliers, two_body_surfaces
from ...laws import ContactLaw, LagrangeMultiplier
from ...materials import LinearElastic
from ...multipliers import unknown
from ...problem import ContactProblem, Dirichlet
from ..meshes.rings import concentric_rings
from . import Option, Setup, log_dofs, poisson, positive, refuse_count

__all__ = [
    "A", "B", "C", "E_DEFAULT", "NU_DEFAULT", "Q_DEFAULT", "PLANES", "RADIUS", "lame_pressure", "lame_displacements",
    "RingsElastic", "OPTIONS", "build"
]

A, B, C = 0.2, 0.6, 1.0
E_DEFAULT, NU_DEFAULT, Q_DEFAULT = 1000.0, 0.3, 10.0
PLANES = ("strain", "stress")
RADIUS = 0.1  # two-body search radius over c (the interface moves by ~1e-2 c at most)


def _plane(E: float, nu: float, plane: str) -> tuple[float, float]:
    """``(E, nu)`` of the plane-stress formulas: unchanged in plane stress, ``E/(1-nu^2), nu/(1-nu)`` in plane
    strain."""
    return (E, nu) if plane == "stress" else (E / (1 - nu**2), nu / (1 - nu))


def lame_pressure(q: float, E1: float, nu1: float, E2: float, nu2: float, plane: str = "strain",
                  a: float = A, b: float = B, c: float = C) -> float:
    """Lamé's interface pressure of the two rings (module docstring)."""
    (E1, nu1), (E2, nu2) = _plane(E1, nu1, plane), _plane(E2, nu2, plane)
    inner = ((1 - nu1) * b**2 + (1 + nu1) * a**2) / (E1 * (b**2 - a**2))
    outer = ((1 - nu2) * b**2 + (1 + nu2) * c**2) / (E2 * (c**2 - b**2))
    return 2 * q * c**2 / (E2 * (c**2 - b**2)) / (inner + outer)


def lame_displacements(q: float, E1: float, nu1: float, E2: float, nu2: float, plane: str = "strain",
                       a: float = A, b: float = B, c: float = C) -> tuple[float, float]:
    """Lamé's radial displacements ``(u_r(a), u_r(c))``."""
    p = lame_pressure(q, E1, nu1, E2, nu2, plane, a, b, c)
    (E1, nu1), (E2, nu2) = _plane(E1, nu1, plane), _plane(E2, nu2, plane)
    ua = -2 * p * a * b**2 / (E1 * (b**2 - a**2))
    uc = c * (2 * p * b**2 - q * ((1 - nu2) * c**2 + (1 + nu2) * b**2)) / (E2 * (c**2 - b**2))
    return ua, uc


class RingsElastic(LinearElastic):
    """Small-strain elasticity with the Lamé constants of each ring (DG0 fields ``lmbda_field``,
    ``mu_field``); plane stress by ``lambda* = 2 lambda mu / (lambda + 2 mu)``."""

    def __init__(self, mesh, cell_tags, E: tuple[float, float], nu: tuple[float, float], plane: str):
        super().__init__(E[0], nu[0])
        self.plane = plane
        Q = function_space(mesh, "DG", 0)
        self.lmbda_field, self.mu_field = fem.Function(Q, name="lambda"), fem.Function(Q, name="mu")
        for ring, Ei, nui in (("inner_ring", E[0], nu[0]), ("outer_ring", E[1], nu[1])):
            lm, mu = LinearElastic(Ei, nui).lmbda, LinearElastic(Ei, nui).mu
            if plane == "stress":
                lm = 2 * lm * mu / (lm + 2 * mu)
            cells = cell_tags.find(ring)
            dofs = np.array([Q.dofmap.cell_dofs(k)[0] for k in cells], dtype=np.int32)
            self.lmbda_field.x.array[dofs], self.mu_field.x.array[dofs] = lm, mu
        self.rings = {"E": tuple(E), "nu": tuple(nu), "plane": plane}

    def energy(self, u):
        eps = ufl.sym(ufl.grad(u))
        return self.mu_field * ufl.inner(eps, eps) + 0.5 * self.lmbda_field * ufl.tr(eps) ** 2

    def stress(self, u):
        eps = ufl.sym(ufl.grad(u))
        return 2 * self.mu_field * eps + self.lmbda_field * ufl.tr(eps) * ufl.Identity(len(u))

    def describe(self) -> dict:
        return {"model": type(self).__name__, **self.rings}


OPTIONS = {
    "E": Option("inner ring's Young's modulus (stress)"),
    "nu": Option("inner ring's Poisson's ratio", "poisson"),
    "E_outer": Option("outer ring's Young's modulus (stress; default: --E)"),
    "nu_outer": Option("outer ring's Poisson's ratio (default: --nu)", "poisson"),
    "q": Option("external pressure on the outer ring (stress)"),
    "a": Option("inner ring's inner radius (length)", below=("b",)),
    "b": Option("interface radius, between --a and --c (length)", below=("c",)),
    "c": Option("outer ring's outer radius (length)"),
}


def build(law: ContactLaw | None = None, law_factory=None, degree: int = 1, quadrature: str = "nodal",
          passes: str = "one", n: int = 16, n_outer: int | None = None, plane: str = "strain",
          E: float = E_DEFAULT, nu: float = NU_DEFAULT, E_outer: float | None = None, nu_outer: float | None = None,
          q: float = Q_DEFAULT, a: float = A, b: float = B, c: float = C, comm: MPI.Comm = MPI.COMM_WORLD) -> Setup:
    """``degree`` 1 (P1 triangles, flat facets: ``quadrature`` ``nodal``, ``gauss`` or ``segment``) or 2
    (6-node triangles of a quadratic geometry, curved 3-node facets: ``nodal`` or ``simpson``); ``passes``
    ``one`` (the inner ring's arc is the slave) or ``two``. Method ``lagrange`` (``law`` a
    :class:`~fenics_contact.laws.LagrangeMultiplier`): the constraint at the vertices, the work with
    ``quadrature`` (P2: ``simpson`` is the two-point element); ``collocated`` (P2, ``lagrange`` or
    ``penalty_multiplier``): Papadopoulos & Solberg's collocated element (``passes`` not used: both
    surfaces carry a pressure). One load step ``t = 1``. The inner ring's ``E``, ``nu``, the outer ring's
    ``E_outer``, ``nu_outer`` (default: the inner ring's), the external pressure ``q``; the radii ``a < b < c``
    (inner, interface, outer); the two-body search radius ``RADIUS c``."""
    positive(E=E, E_outer=E_outer, a=a, b=b, c=c)
    if not a < b < c:
        raise ValueError(f"the radii must satisfy a < b < c, got a = {a!r}, b = {b!r}, c = {c!r}")
    poisson(nu=nu, nu_outer=nu_outer)
    E = (E, E if E_outer is None else E_outer)
    nu = (nu, nu if nu_outer is None else nu_outer)
    if degree not in (1, 2):
        raise ValueError(f"degree must be 1 or 2, got {degree!r}")
    if plane not in PLANES:
        raise ValueError(f"plane must be one of {PLANES}, got {plane!r}")
    if not (np.isfinite(q) and q > 0):
        raise ValueError(f"pressure q must be a finite number > 0, got {q!r}")
    if int(n) != n or n < 2:
        raise ValueError(f"n must be an integer >= 2, got {n!r}")
    if law_factory is None:
        if law is None:
            raise ValueError("give law (or law_factory)")
        law_factory = lambda: law  # noqa: E731
    first = law_factory()
    multipliers = isinstance(first, LagrangeMultiplier)
    if n_outer is None:
        n_outer = max(3 * int(n) // 4, 2)
    # Triangles of the interface elements' size h = pi b / (2 n) over both quarter rings: at least 1.5 unknowns per
    # h^2 (x 4 at P2)
    per = 1.5 if degree == 1 else 6.0
    for name, count in (("n", n), ("n_outer", n_outer)):
        refuse_count(name, count, log_dofs((per, math.sqrt(math.pi / 4 * (c * c - a * a)) / (math.pi * b / (2 * int(
            count))), 2)), 2, comm, low=2)
    mesh, cell_tags, facet_tags = concentric_rings(comm, a, b, c, int(n), int(n_outer), order=degree)
    u, V = unknown(mesh, degree, first)
    material = RingsElastic(mesh, cell_tags, E, nu, plane)  # validates E and nu
    load = fem.Constant(mesh, 0.0)
    rollers = [Dirichlet.on_facets(V, facet_tags, tag, comp) for tag, comp in
               (("x0_inner", 0), ("y0_inner", 1), ("x0_outer", 0), ("y0_outer", 1))]
    if quadrature == "collocated":
        if degree != 2 or not multipliers:
            raise ValueError("quadrature 'collocated' (Papadopoulos & Solberg's element) needs degree 2 and method "
                             f"'lagrange' or 'penalty_multiplier', got degree {degree!r}, method {first.name!r}")
        from ...collocation import collocated_surfaces

        contacts = collocated_surfaces(u, facet_tags, "inner_surface", "outer_surface", first, load, RADIUS * c,
                                       "interface")
    elif multipliers:
        if quadrature not in (("nodal",) if degree == 1 else ("nodal", "simpson")):
            raise ValueError(f"method {first.name!r} on degree-{degree} facets: quadrature must be 'nodal'"
                             f"{'' if degree == 1 else ' or simpson'}, got {quadrature!r}")
        contacts = two_body_multipliers(u, facet_tags, "inner_surface", "outer_surface", first, load,
                                        RADIUS * c, "interface", passes=passes, work_quadrature=quadrature)
    else:
        contacts = two_body_surfaces(u, facet_tags, "inner_surface", "outer_surface", law_factory, load,
                                     quadrature, passes, RADIUS * c, "interface")
    for cs in contacts:  # one name per field in the XDMF file
        cs.gap_out.name, cs.pressure_out.name = f"gap_{cs.name}", f"contact_pressure_{cs.name}"
    n_ref = ufl.FacetNormal(mesh)
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facet_tags.meshtags)
    problem = ContactProblem(u, material, load, rollers, contacts, tractions=[(-q * n_ref, ds(facet_tags["loaded"]))])

    p_lame = lame_pressure(q, E[0], nu[0], E[1], nu[1], plane, a, b, c)
    ua_lame, uc_lame = lame_displacements(q, E[0], nu[0], E[1], nu[1], plane, a, b, c)
    # Radial displacement at the nodes of r = a and r = c (owned, gathered).
    if is_mixed(u.function_space):
        Vd, to_parent = collapse(u.function_space.sub(0))
        to_parent = np.asarray(to_parent)
    else:
        Vd, to_parent = u.function_space, np.arange(len(u.x.array))
    fdim = mesh.topology.dim - 1
    Xd = Vd.tabulate_dof_coordinates()[:, :2]
    n_own = Vd.dofmap.index_map.size_local
    rim = {}
    for key, region in (("a", "inner_free"), ("c", "loaded")):
        d = fem.locate_dofs_topological(Vd, fdim, facet_tags.find(region))
        rim[key] = d[d < n_own]

    def radial(key: str) -> np.ndarray:
        d = rim[key]
        X = Xd[d]
        U = np.stack([u.x.array[to_parent[2 * d + j]] for j in (0, 1)], axis=1)
        ur = np.einsum("ij,ij->i", U, X) / np.linalg.norm(X, axis=1)
        return np.concatenate(comm.allgather(ur))

    quadratic = degree == 2

    def constrained(cs) -> np.ndarray:
        """Pressure at the constrained points of one slave surface (every rank)."""
        if quadrature == "segment":
            _, g, p = cs.point_values()
            return p[np.isfinite(g)]
        X, _, g, p = cs.point_table()
        if quadrature == "collocated":  # vertices (constrained) and middle nodes (collocated), nominal
            return p
        keep = np.isfinite(g)  # unpaired: left out of a two-pass pair (node on node)
        if quadratic and (multipliers or quadrature == "nodal"):  # the end nodes (mesh vertices) only
            sd = cs.slave_data
            ends = np.concatenate(comm.allgather(sd.X[sd.owned][:, [0, 2]].reshape(-1, 2)))
            keep &= np.isin(_keys(X), _keys(ends))
        return p[keep]

    def figures() -> dict:
        ps = [constrained(cs) for cs in contacts]
        dev = np.abs(np.concatenate(ps) - p_lame) / p_lame
        ura, urc = radial("a"), radial("c")
        p_reaction = problem.reaction(rollers[1].dofs) / b
        return {"p_lame": p_lame, "p_max_deviation": float(dev.max()), "p_mean_deviation": float(dev.mean()),
                "p_min": float(min(p.min() for p in ps)), "p_max": float(max(p.max() for p in ps)),
                "p_reaction": p_reaction, "p_reaction_deviation": abs(p_reaction - p_lame) / p_lame,
                "ur_a": float(ura.mean()), "ur_a_lame": ua_lame,
                "ur_a_deviation": float(np.abs(ura - ua_lame).max() / abs(ua_lame)),
                "ur_c": float(urc.mean()), "ur_c_lame": uc_lame,
                "ur_c_deviation": float(np.abs(urc - uc_lame).max() / abs(uc_lame)),
                "points": int(sum(len(p) for p in ps)),
                "pairing_changes": int(sum(cs.pairing_changes for cs in contacts))}

    params = {"a": a, "b": b, "c": c, "q": q, "E": tuple(E), "nu": tuple(nu), "plane": plane, "degree": degree,
              "n": int(n), "n_outer": int(n_outer), "quadrature": quadrature, "passes": passes,
              "material": "linear elastic per ring"}
    return Setup("rings", problem, contacts, [1.0], params, figures, [contacts[0].displacement_out])


def _keys(X: np.ndarray) -> np.ndarray:
    """Points as hashable rows (rounded to 1e-12) for membership tests."""
    r = np.round(np.asarray(X, dtype=float), 12) + 0.0
    return np.array([f"{x:.12f},{y:.12f}" for x, y in r])
