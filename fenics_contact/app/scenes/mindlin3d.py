"""``mindlin3d``: Cattaneo-Mindlin partial slip between a sphere and a block of the same material (3D).

The cap ``z <= H`` of a ball of radius ``R`` rests on the block ``[-L, L] x [0, L] x [-D, 0]`` fixed at its
base; both ``E``, ``nu``: Dundurs' ``beta = 0``, so the normal and tangential problems uncouple and the pressure
stays Hertz's while the tangential load grows. Half model: the plane ``y = 0`` is a symmetry plane of both
bodies (``u_y = 0``; the tangential load is along ``x``). Two-body contact, one pass, the cap's surface the
slave (node-to-triangle, nodal quadrature), Coulomb friction ``mu`` on a penalty-type normal law
(:class:`~fenics_contact.twobody.friction.FrictionalTwoBodySurface`), or exact Signorini-Coulomb on the condensed
system (method ``coulomb``: :class:`~fenics_contact.condensed.CondensedTwoBody`, small sliding; the slave
vertices within ``EXACT_RADIUS`` times the approach of the block paired, each on its Coulomb disk).

Loading. ``t`` in (0, ``T_PRESS``]: the cap's top moves down by ``t / T_PRESS * approach`` (displacement
control; ``u_x`` free) without friction (``mu = 0``; a spring ``k u_x``, ``k = PRESS_SPRING E / R^2``, on the
cap holds its free motion along ``x``). At ``t = 1`` (the top held) friction comes on and the spring goes: for
``beta = 0`` the pressing carries no tangential traction, so pressing with or without friction is the same problem
(Mindlin's), and frictionless pressing avoids Newton cycling at the contact edge, where tiny tractions under
tiny pressures turn the 3D slip direction at every iterate. The exact method presses with friction in one step
to ``t = 1`` (``beta = 0``: the same problem; the contact holds the cap along ``x``, no spring). The force ``P``
is the whole sphere's (twice the half model's contact force at ``t = 1``). Then ``t = 1 + r`` for each ratio
``r`` of ``ratios`` (increasing): the tangential force ``Q = r mu P`` along ``+x`` on the top (a uniform
traction, force control: the cap's position along ``x`` is held by friction alone). The cap is placed
``overlap`` (``1e-9 R``) into the block.

Reference (two identical bodies: ``1/E* = 2 (1 - nu^2) / E``): Hertz ``a^3 = 3 P R / (4 E*)``,
``p0 = 3 P / (2 pi a^2)``; Cattaneo-Mindlin: the stick zone ``r < c`` with ``c = a (1 - Q / (mu P))^(1/3)`` and
the tangential traction (along ``-x`` on the cap) ``q(r) = mu p0 [sqrt(1 - (r/a)^2) - (c/a) sqrt(1 - (r/c)^2)]``
(the second term only for ``r < c``).

Measured stick radius (the committed slip state of the accepted step at the slave vertices, nodal quadrature):
``c_area = sqrt(2 A / pi)`` with ``A`` the stick area by the contact quadrature rule (the vertices that stick,
each with its vertex weight; the half disk's area is ``pi c^2 / 2``), the 3D analogue of ``mindlin``'s half
stick length; and ``c_axes``, the mean over the three rays ``+x``, ``-x`` (the vertices on ``y = 0``) and ``+y``
(on ``x = 0``: the mesh has a line of vertices there) of the radius half-way between the last sticking vertex
and the next vertex outward (each within half a contact element of the discrete edge). ``c`` is ``c_area``.

The tangential penalty ``omega_t`` is a stiffness per unit area and length: its elastic slip ``q / omega_t``
acts as an interface layer of thickness ``E* / omega_t``, which must stay a small part of a contact element;
the demo scales it with ``1 / h_contact``.
"""
from __future__ import annotations

import math

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...compat import function_space
from ...contact import displacement
from ...factory import two_body_surfaces
from ...friction import STICK, Friction
from ...laws import ContactLaw, ExactCoulomb
from ...materials import LinearElastic
from ...multipliers import unknown
from ...problem import Dirichlet
from ...solver import LINEAR_SOLVERS
from ..meshes.mindlin3d import cap_on_block
from . import Option, Setup, log_dofs, poisson, positive, refuse_fine, refuse_refined
from .mindlin import ShearProblem, check_loading, coulomb_mu, exact_friction, stick_figures, worst_ratio
from .sphere import FIT_INNER, hertz_fit

__all__ = ["OPTIONS",
           "build", "hertz_a", "mindlin_c", "mindlin_traction", "stick_radii", "contact_size", "default_omega_t",
           "H_CONTACT", "REFINE", "EXACT_RADIUS", "DEFAULT_K", "DEFAULT_OMEGA_T", "PRESS_STEPS", "PREDICTOR", "BENCH",
           "ITERATIVE"]

R, E, NU = 1.0, 1000.0, 0.3
APPROACH = 5e-3  # per unit R (default: APPROACH R): gives a ~ 0.074 R with the default bodies
RATIOS = (0.2, 0.5, 0.8)
# The contact mesh size at refinement 0 (in units of R): about 10 elements across a. R/100 (7 across a) gave the
# stick radius at Q/(mu P) = 0.8 6.5 % below Cattaneo-Mindlin (0.28 elements): within one element, not within 5 %.
H_CONTACT = 0.007
REFINE = 2 ** 0.5  # each refinement divides the contact mesh size by this (3D: about 2.8 times the vertices)
# Normal penalty ~ 20 E / h_contact: p0 / K ~ 1.2e-5, 0.2 % of the approach; 1e7 (100 E / h) made Newton
# cycle between two contact sets at the contact edge in the pressing.
DEFAULT_K = 2e6
# Tangential penalty at refinement 0: the interface layer E* / omega_t ~ 3.8e-4 R is 5.5 % of h_contact.
DEFAULT_OMEGA_T = 1e4 / H_CONTACT
T_PRESS = 0.9  # the pressing ends at this load; friction comes on at t = 1
# Method coulomb pairs the slave vertices within EXACT_RADIUS x the approach of the block (the others stay open, no
# force): two surface points approach each other by less than the cap's top moves (the bodies are compressed), and
# Hertz's contact edge is at a distance of about half the approach, so 1.25 pairs out to 1.5 contact radii. The
# default mesh: 460 paired slave vertices, n_c = 2780 contact dofs (radius 2 x approach: 3332, the same stick
# radii to round-off; the penalty laws' radius 0.1 R would pair 930).
EXACT_RADIUS = 1.25
# Load steps of the pressing and each step's start. The steps are t = T_PRESS (i / n)^2, the approach ~ t^2, so that
# each grows the Hertz contact radius a ~ sqrt(approach) by the same a / n (equal steps grow it most in the first:
# from one closed vertex to a third of a); each starts from the solver's tangent predictor (PREDICTOR), scaled back
# to the energy's minimum along it: it carries the top's increment into both bodies, where from the last state it
# lands on the old contact set alone and Newton wanders over the contact edge. Measured at h_contact = 0.015 R,
# Newton iterations per step: 4 equal steps from the last state 8, 11, 9, 8 and the shear steps 8, 9, 11 (66 in 8
# steps); 8 equal steps from the tangent 11 in the first, 3-5 in the others; 8 graded steps from the tangent 2, 3,
# 4, 4, 6, 3, 4, 8, friction on 2, the shear steps 5, 6, 6 (53 in 12); the same stick radii. At the default mesh:
# 4 equal steps from the last state 62 in 8 steps (10, 10, 6, 5 in the pressing); 8 graded from the tangent 56 in
# 12 (4-5 in the pressing, 5, 7, 8 in the shear steps), the same stick radii to 1e-6.
PRESS_STEPS = 8
PREDICTOR = "tangent"
# k R^2 / E of the spring on the cap's u_x during the frictionless pressing: stiff enough to fix the cap's
# position (1e-2 let the contact set wander); its force k u_x ~ 1e-3 E / R is antisymmetric in x (no net force).
PRESS_SPRING = 1.0


def contact_size(refinement: int = 0, h_contact: float | None = None, R: float = R) -> float:
    """The contact mesh size: ``h_contact`` (default ``H_CONTACT R``) divided by ``REFINE ** refinement``."""
    return (H_CONTACT * R if h_contact is None else h_contact) / REFINE ** int(refinement)


def default_omega_t(refinement: int = 0, h_contact: float | None = None, R: float = R, E: float = E) -> float:
    """The tangential penalty that keeps the interface layer ``E* / omega_t`` the same fraction of the contact
    mesh size as ``DEFAULT_OMEGA_T`` at the default mesh and modulus: ``DEFAULT_OMEGA_T (E / E0) H_CONTACT R / h``
    (pressure per length)."""
    return DEFAULT_OMEGA_T * (E / globals()["E"]) * H_CONTACT * R / contact_size(refinement, h_contact, R)


def hertz_a(P: float, R: float, E: float, nu: float) -> float:
    """Hertz contact radius ``(3 P R / (4 E*))^(1/3)`` of a sphere of radius ``R`` on a half-space of the same
    material (``1/E* = 2 (1 - nu^2) / E``) under the load ``P``."""
    Es = E / (2 * (1 - nu**2))
    return (3 * P * R / (4 * Es)) ** (1 / 3)


def mindlin_c(a: float, ratio: float) -> float:
    """Cattaneo-Mindlin stick radius ``a (1 - Q / (mu P))^(1/3)`` (3D)."""
    return a * (1.0 - ratio) ** (1 / 3)


def mindlin_traction(r: np.ndarray, a: float, c: float, mu: float, p0: float) -> np.ndarray:
    """Cattaneo-Mindlin tangential traction magnitude ``mu p0 [sqrt(1 - (r/a)^2) - (c/a) sqrt(1 - (r/c)^2)]``
    (``p0 = 3 P / (2 pi a^2)``)."""
    r = np.abs(np.asarray(r, dtype=float))
    q = np.sqrt(np.clip(1 - (r / a) ** 2, 0.0, None))
    q = q - np.where(r < c, (c / a) * np.sqrt(np.clip(1 - (r / max(c, 1e-300)) ** 2, 0.0, None)), 0.0)
    return mu * p0 * q


def stick_radii(x: np.ndarray, state: np.ndarray, tol: float) -> dict[str, float]:
    """Stick radius along the rays ``+x``, ``-x`` (vertices with ``|y| < tol``) and ``+y`` (``|x| < tol``) of the
    slave vertices ``x`` (reference positions, (n, 3)) and their slip states: half-way between the outermost
    vertex of the ray's inner sticking run and the next vertex outward (0 if the ray's first vertex does not
    stick)."""
    out = {}
    for name, on, along in (("+x", np.abs(x[:, 1]) < tol, x[:, 0]), ("-x", np.abs(x[:, 1]) < tol, -x[:, 0]),
                            ("+y", np.abs(x[:, 0]) < tol, x[:, 1])):
        keep = on & (along > -tol)
        order = np.argsort(along[keep])
        r, s = np.maximum(along[keep][order], 0.0), state[keep][order]
        sticking = s == STICK
        if not sticking.size or not sticking[0]:
            out[name] = 0.0
            continue
        last = len(s) - 1 if sticking.all() else int(np.argmin(sticking)) - 1
        out[name] = float(r[last] if last == len(s) - 1 else 0.5 * (r[last] + r[last + 1]))
    return out


class _Problem(ShearProblem):
    """Force control of ``Q / (mu P)`` from the half model's contact force ``P`` along ``z``
    (:class:`~fenics_contact.app.scenes.mindlin.ShearProblem`); frictionless pressing held along ``x`` by the spring,
    Coulomb from ``t = 1``; each step's start records the stick radii of the step accepted before it
    (``radii[t]``)."""

    scene = "mindlin3d"

    def __init__(self, *args, measure, spring: fem.Constant, k: float, exact: bool, **kw):
        super().__init__(*args, axis=2, **kw)
        self._measure, self._spring, self._k, self._exact = measure, spring, k, exact
        self.radii = {}

    def record(self) -> None:
        """The stick radii of the last accepted step (collective)."""
        log = self.contacts[0].log
        if log and log[-1]["load"] > 1.0 and log[-1]["load"] not in self.radii:
            self.radii[log[-1]["load"]] = self._measure()

    def set_load(self, t: float) -> None:
        if t > 1.0:
            self.record()
        if not self._exact:  # the exact method presses with friction, held along x by it (no spring)
            # Frictionless pressing held along x by the spring (its term is scaled by t: k / t); then Coulomb.
            self.contacts[0].constants["mu"].value = self._mu if t >= 1.0 else 0.0
            self._spring.value = self._k / t if 0.0 < t < 1.0 else 0.0
        super().set_load(t)


OPTIONS = {
    "R": Option("radius of the spherical cap (length)"),
    "E": Option("Young's modulus of both bodies (stress)"),
    "nu": Option("Poisson's ratio of both bodies", "poisson"),
    "approach": Option(f"pressing displacement of the cap (length; default: {APPROACH:g} R)"),
    "cap_height": Option("cap's height (length; default: R / 2)"),
    "width": Option("block's half-width L, y in [0, L] (length; default: R)"),
    "depth": Option("block's depth (length; default: R / 2)"),
    "h_contact": Option(f"mesh size at the contact (length; default: {H_CONTACT:g} R, divided by sqrt(2) per "
                        f"--refinement)"),
    "contact_width": Option("radius of the zone of mesh size --h-contact (length; default: 0.1 R)"),
    "h_far": Option("mesh size far from the contact (length; default: 0.1 R)"),
}


def build(law: ContactLaw, ratios: tuple = RATIOS, refinement: int = 0, comm: MPI.Comm = MPI.COMM_WORLD,
          R: float = R, E: float = E, nu: float = NU, approach: float | None = None, press_steps: int | None = None,
          cap_height: float | None = None, width: float | None = None, depth: float | None = None,
          h_contact: float | None = None, contact_width: float | None = None, h_far: float | None = None,
          sliding: str | None = None) -> Setup:
    """``law``: a :class:`~fenics_contact.friction.Friction` with a Coulomb bound (``mu > 0``), or the exact
    :class:`~fenics_contact.laws.ExactCoulomb` (method ``coulomb``, ``mu > 0``). ``ratios``: the
    values of ``Q / (mu P)`` in (0, 1), increasing; ``refinement`` divides the contact mesh size (default
    ``h_contact = H_CONTACT R``) by ``REFINE = sqrt(2)`` that many times; ``press_steps`` load steps for the
    pressing, at ``t = T_PRESS (i / press_steps)^2`` (default :data:`PRESS_STEPS`, frictionless, solved with the
    predictor :data:`PREDICTOR`; method ``coulomb``: 1 step with friction to ``t = 1``).
    Bodies: the cap's height ``cap_height`` (default ``R / 2``), the block's half ``width`` ``L`` (default
    ``R``; it spans ``y`` in ``[0, L]``) and ``depth`` (default ``R / 2``); the mesh: size ``h_contact`` within
    ``contact_width`` (default ``0.1 R``) of the contact point, growing to ``h_far`` (default ``0.1 R``).
    ``sliding``: the contact kinematics (:func:`~fenics_contact.two_body_surfaces`; None: the method's own)."""
    approach = APPROACH * R if approach is None else approach
    positive(R=R, E=E, approach=approach, cap_height=cap_height, width=width, depth=depth, h_contact=h_contact,
             contact_width=contact_width, h_far=h_far)
    poisson(nu=nu)
    exact = exact_friction(law)
    if not (exact and coulomb_mu(law) > 0) and not (isinstance(law, Friction) and law.scalars.get("mu", 0) > 0):
        raise ValueError(f"mindlin3d needs a Coulomb friction law with mu > 0 (e.g. --mu 0.3), got {law!r}")
    press_steps = (1 if exact else PRESS_STEPS) if press_steps is None else press_steps
    ratios = check_loading(ratios, refinement, press_steps)
    H = 0.5 * R if cap_height is None else cap_height
    if not H < R:
        raise ValueError(f"cap_height must be in (0, R), got {H!r}")
    mu = coulomb_mu(law)
    if exact and sliding is None:  # the exact methods' kinematics, Cattaneo-Mindlin's
        sliding = None if isinstance(law, ExactCoulomb) else "small"
    L = R if width is None else width
    D = 0.5 * R if depth is None else depth
    h = contact_size(refinement, h_contact, R)
    cw = 0.1 * R if contact_width is None else contact_width
    hf = max(0.1 * R if h_far is None else h_far, h)
    # At least 1.5 (cw / h)^3 unknowns in the refined zone (both bodies) and 0.5 L^2 D / hf^3 in the block
    refuse_refined("h_contact", contact_size(0, h_contact, R), refinement, log_dofs((1.5, cw / h, 3)), 3,
                   1.5 * math.log10(2.0), comm)
    refuse_fine("h_far", hf, log_dofs((0.5, (L * L * D) ** (1 / 3) / hf, 3)), 3, comm)
    mesh, cells, facets = cap_on_block(comm, R, H, L, D, h, hf, cw, overlap=1e-9 * R)
    u, V = unknown(mesh, 1, law)  # the displacement, or (displacement, traction) for method lagrange
    t = fem.Constant(mesh, 0.0)
    fdim = 2
    dirichlet = [Dirichlet.on_facets(V, facets, "block_bottom", i) for i in range(3)]
    dirichlet += [Dirichlet.on_facets(V, facets, "symmetry", 1),
                  Dirichlet(V.sub(2), fem.locate_dofs_topological(V.sub(2), fdim, facets.find("cap_top")), 1.0,
                            ([0.0, T_PRESS], [0.0, -approach]))]
    material = LinearElastic(E, nu)
    contact = two_body_surfaces(u, facets, "cap_surface", "block_top", lambda: law, t, "nodal",
                                radius=EXACT_RADIUS * approach if exact else 0.1 * R, name="interface",
                                material=material, sliding=sliding)[0]
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags)
    area = comm.allreduce(fem.assemble_scalar(fem.form(fem.Constant(mesh, 1.0) * ds(facets["cap_top"]))),
                          op=MPI.SUM)
    amplitude = fem.Constant(mesh, 0.0)
    # ContactProblem scales tractions by t: this vector times t is (r mu P_half / A_top, 0, 0) at t = 1 + r.
    traction = ufl.as_vector((amplitude * ufl.max_value(t - 1.0, 0.0) / t, 0.0, 0.0))

    def profile() -> dict:
        return contact.friction_profile()

    def measure() -> dict:
        prof = profile()
        area_stick = contact.log[-1]["stick"]
        return {"area": math.sqrt(2 * area_stick / math.pi),
                **stick_radii(prof["x"], prof["state"], 1e-9 * R)}

    spring = fem.Constant(mesh, 0.0)
    # The spring acts on the cap only: a DG0 indicator on the plain dx (dolfinx 0.9 wants every dx integral of a form
    # to share one subdomain_data, and the bulk's dx has none).
    cap = fem.Function(function_space(mesh, "DG", 0), name="cap_indicator")
    cap.x.array[[cap.function_space.dofmap.cell_dofs(c)[0] for c in cells.find("cap")]] = 1.0
    cap.x.scatter_forward()
    # The exact method has no spring (it presses with friction): without the term its stiffness is the same at
    # every load (a term scaled by t, even at zero spring, makes the condensed method re-assemble K every step).
    held = [] if exact else [(ufl.as_vector((-spring * cap * displacement(u)[0], 0.0, 0.0)), ufl.dx(domain=mesh))]
    problem = _Problem(u, material, t, dirichlet, [contact], [(traction, ds(facets["cap_top"]))] + held,
                       amplitude=amplitude, mu=mu, area=area, measure=measure, spring=spring,
                       k=PRESS_SPRING * E / R**2, exact=exact)
    if exact:  # pressed with friction to t = 1
        loads = [(i + 1) / press_steps for i in range(press_steps)] + [1.0 + r for r in ratios]
    else:
        # The pressing's steps grow the Hertz contact radius a ~ sqrt(approach) by the same amount: approach ~ t^2.
        loads = [T_PRESS * ((i + 1) / press_steps) ** 2 for i in range(press_steps)] + [1.0] + [1.0 + r for r in ratios]

    def figures() -> dict:
        problem.record()
        P_half = problem.P if problem.P is not None else float(contact.total_force()[2])
        P = 2 * P_half
        a_h = hertz_a(P, R, E, nu)
        p0_h = 3 * P / (2 * math.pi * a_h**2)
        prof = profile()
        x, p = prof["x"], prof["pressure"]
        loaded = p > 1e-8 * max(p.max(), 1e-300)
        out = {"P": P, "a_hertz": a_h, "p0_hertz": p0_h, "h_contact": h, "mu": mu,
               "a": float(np.hypot(x[loaded, 0], x[loaded, 1]).max()) if loaded.any() else 0.0, "p0": float(p.max())}
        out["a_error"] = abs(out["a"] - a_h) / a_h
        out["p0_error"] = abs(out["p0"] - p0_h) / p0_h
        # the nodal pressures of node-to-triangle contact on non-matching meshes scatter about the profile: their
        # maximum is no peak to trust; the Hertz profile fitted to them is (the sphere scene's p0_fit)
        out["p0_fit"] = hertz_fit(x, p, a_h)
        out["p0_fit_error"] = abs(out["p0_fit"] - p0_h) / p0_h
        out["notes"] = {"p0": "the largest nodal pressure at the slave vertices; the nodal pressures of two-body "
                              "contact on non-matching meshes scatter about the Hertz profile (by 10-20 % in 3D), "
                              "so p0_error is no measure of accuracy",
                        "p0_fit": f"the peak of the Hertz profile fitted to the nodal pressures within {FIT_INNER:g} "
                                  "a of the axis: the peak to compare with Hertz (p0_fit_error)"}
        out["slave_vertices_in_contact"] = int(np.count_nonzero(loaded))
        errors = []
        for r in ratios:
            entry = [e for e in contact.log if abs(e["load"] - (1.0 + r)) < 1e-12]
            radii = problem.radii.get(1.0 + r)
            if not entry or radii is None:
                continue
            c_ref = mindlin_c(a_h, r)
            error = stick_figures(out, r, radii["area"], c_ref, h)
            for ray in ("+x", "-x", "+y"):
                out[f"c_{ray}_{r:g}"] = radii[ray]
            c_axes = float(np.mean([radii[k] for k in ("+x", "-x", "+y")]))
            out[f"c_axes_{r:g}"] = c_axes
            out[f"c_axes_error_{r:g}"] = abs(c_axes - c_ref) / c_ref
            out[f"c_axes_error_elements_{r:g}"] = max(abs(radii[k] - c_ref) for k in ("+x", "-x", "+y")) / h
            out[f"Q_{r:g}"] = -2 * (entry[-1]["tangential_force"][0] + entry[-1]["normal_force"][0])
            errors.append((error, r))
        worst_ratio(out, errors)  # the benchmark's error and value
        # The last step's traction along the x axis (the vertices on y = 0) against Cattaneo-Mindlin over r < a:
        # RMS and largest difference per mu p0.
        if ratios and problem.P is not None and float(t.value) > 1.0:
            c_ref = mindlin_c(a_h, float(t.value) - 1.0)
            on = (np.abs(x[:, 1]) < 1e-9 * R) & (np.abs(x[:, 0]) < a_h)
            q = -prof["traction"][on, 0]  # the block's traction on the cap is along -x: its magnitude
            diff = np.abs(q - mindlin_traction(x[on, 0], a_h, c_ref, mu, p0_h)) / (mu * p0_h)
            out["traction_rms_error"] = float(np.sqrt(np.mean(diff**2)))
            out["traction_max_error"] = float(diff.max())
        return out

    params = {"E": E, "nu": nu, "R": R, "approach": approach, "cap_height": H, "width": L, "depth": D,
              "h_contact": h, "contact_width": cw, "h_far": hf, "refinement": refinement, "ratios": list(ratios),
              "mu": mu, "quadrature": "nodal", "sliding": "small" if exact else sliding or "finite",
              "model": "half spherical cap on a block (symmetry y = 0), same material, node-to-triangle Coulomb "
                       "friction", "pairing_radius": contact.radius if exact else 0.1 * R}
    setup = Setup("mindlin3d", problem, [contact], loads, params, figures,
                  [contact.displacement_out, contact.gap_out, contact.pressure_out, contact.traction_out,
                   contact.state_out])
    setup.profile = profile  # the friction profile at the current state (the demo's pictures)
    return setup


# Speed against accuracy (fenics_contact.app.bench): the stick radius at the worst ratio against Cattaneo-Mindlin, on
# the tests' coarse contact mesh (h_contact = 0.015 R, about 4.5 elements across a) and one ratio, Q / (mu P) = 0.5
# (the demo scales omega_t with 1 / h_contact): 29-87 Newton iterations, a minute or more a run. The quick sweep
# leaves out the augmented variants (2.5-2.8 x the iterations for the same stick radius; 24.5 min with them on the
# loaded machine): six plain runs. Method nitsche is not swept: 70-79 Newton iterations at the demo's meshes
# (demos/friction_scaling.py), about 97 x one linear solve.
# The iterative linear solver of this scene (the demo's default): GMRES + GAMG with a longer Krylov space. The
# generic 30-vector restart and 500 iterations were not enough for the first solve of a press step from the
# committed contact at h = 0.007 (two cutbacks) and 0.0035 (six); with 100 / 1000 the default mesh runs the
# direct solver's 62 Newton iterations with no cutback and its figures (docs/scenes.md).
ITERATIVE = {**LINEAR_SOLVERS["iterative"], "ksp_gmres_restart": 100, "ksp_max_it": 1000}

BENCH = {"error": "c_error_max", "value": "c_worst", "figures": ["ratio_worst", "a_error", "traction_rms_error", "P"],
         "target": 0.05, "K": DEFAULT_K, "mesh": ("refinement", {"quick": [0], "full": [0, 1]}),
         "methods": ["penalty", "cross", "auglag", "compliance", "coulomb"], "reference": "coulomb",
         "axes": {"kind": "two-body", "dim": 3, "friction": True},
         "demo_args": ["--h-contact", "0.015", "--ratios", "0.5", "--solver", "direct"],  # as docs/benchmarks.md
         "quick_sweep": {"penalty": (-1, 0, 1), "other": (0,), "augment": (0,)}, "quadratures": ["nodal"]}
