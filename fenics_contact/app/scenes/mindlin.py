"""``mindlin``: Cattaneo-Mindlin partial slip between two deformable bodies of the same material (2D, plane strain).

A body with a circular bottom of radius ``R`` (the lower part of a disk, cut flat at ``y = H``: the top) rests
on a block ``[-L, L] x [-D, 0]`` fixed at its base; both ``E``, ``nu``: Dundurs' ``beta = 0``, so the normal and
tangential problems uncouple and the pressure stays Hertz's while the tangential load grows. Two-body contact,
one pass, the arc the slave (node-to-segment, nodal quadrature; ``passes="two"``: each surface slave once, weight
1/2), Coulomb friction ``mu`` on a penalty-type normal
law (:class:`~fenics_contact.twobody.friction.FrictionalTwoBodySurface`), or exact Signorini-Coulomb on the
condensed system (method ``coulomb``: :class:`~fenics_contact.condensed.CondensedTwoBody`, small sliding).

Loading. ``t`` in (0, 1]: the top moves down by ``t * approach`` (displacement control; ``u_x`` free), pressing
the bodies together with the force ``P`` (measured: the contact force at ``t = 1``). Then ``t = 1 + r`` for each
ratio ``r`` of ``ratios`` (increasing): the tangential force ``Q = r mu P`` on the top (a uniform traction, force
control: the body's horizontal position is held by friction alone). The body is placed ``overlap`` into the block
at the start (``1e-9 R``), so that the touching point sticks at the first iterate: without it the first tangent
has no horizontal stiffness for the upper body (an open point has no friction capacity).

Reference (plane strain, two identical bodies: ``E* = E / (2 (1 - nu^2))``): Hertz ``a = sqrt(4 P R / (pi E*))``,
``p0 = 2 P / (pi a)``; Cattaneo-Mindlin: the stick zone ``|x| < c`` with ``c = a sqrt(1 - Q / (mu P))`` and the
tangential traction ``q(x) = mu p0 [sqrt(1 - (x/a)^2) - (c/a) sqrt(1 - (x/c)^2)]`` (the second term only for
``|x| < c``). The measured ``c`` is half the stick length by the contact quadrature rule (the vertices that
sticked at the accepted step, each with its vertex weight): the stick zone's edge at the middle between the last
sticking and the first sliding vertex, so within half a contact element of the discrete edge.

The defaults give ``a / L ~ 0.1`` (the finite bodies approximate half-planes) and about 30 contact elements
across ``a``.
"""
from __future__ import annotations

import argparse
import math
from typing import Callable

import numpy as np
import ufl
from dolfinx import fem
from mpi4py import MPI

from ...factory import two_body_surfaces
from ...friction import Friction
from ...laws import ContactLaw, ExactCoulomb
from ...materials import LinearElastic
from ...multipliers import unknown
from ...problem import ContactProblem, Dirichlet
from ..meshes.mindlin import disk_on_block
from . import Option, Setup, log_dofs, poisson, positive, refuse_refined
from .hertz import contact_half_width

__all__ = ["OPTIONS", "build", "mindlin_c", "mindlin_traction", "check_loading", "stick_figures", "worst_ratio",
           "add_shear_options", "check_ratios_option", "worst_ratio_check", "ShearProblem", "committed_force",
           "DEFAULT_K", "DEFAULT_OMEGA_T", "PRESS_STEPS", "PRESS_STEPS_EXACT", "PRESS_STEPS_NITSCHE", "PREDICTOR",
           "predictor_for", "BENCH"]

R, E, NU = 1.0, 1000.0, 0.3
APPROACH = 3.5e-3  # per unit R (default: APPROACH R): gives a ~ 0.047 R with the default bodies
RATIOS = (0.2, 0.5, 0.8)
DEFAULT_K = 1e7  # normal penalty: p0 / K ~ 1e-6, 1e-3 of the approach
# Tangential penalty: the elastic slip mu p0 / omega_t ~ 4e-6 is 1 % of the slip at the contact edge; 1e7 (= K)
# makes Newton cycle between stick and slip at the stick zone's edge (the 2nd pressing step never converged).
DEFAULT_OMEGA_T = 1e6
# Load steps of the pressing. Dundurs' beta = 0: the pressing slips nowhere, so the exact method (method coulomb)
# presses in one step (the same stick zones to round-off as in 4, 8 semismooth Newton iterations instead of 21).
# The penalty-type laws press in 8 steps, each started from the tangent predictor (PREDICTOR): 50 Newton iterations
# in 11 steps with the penalty defaults (4 steps from the last state: 43 in 7, up to 11 in one step; 4 steps from
# the tangent predictor: 37 in 7; 6: 44 in 9), no failed attempt in any.
PRESS_STEPS, PRESS_STEPS_EXACT = 8, 1
PREDICTOR = "tangent"  # the penalty-type laws' steps (the exact method's steps are the step solver's)
# Nitsche's steps start from the last state and press in 6 steps. From the tangent predictor in 8 steps its active
# set cycles (period 2) at the contact edge in the pressing: 247 Newton iterations with 8 failed attempts on the
# default mesh; from the last state in 8 steps one step still cycles (178, 90 of them in 3 failed attempts; 12
# steps: the same), in 6 steps none (74). The stick zones are the same to 1e-6.
PRESS_STEPS_NITSCHE = 6


def predictor_for(method: str, problem: ContactProblem) -> bool | str:
    """The predictor of the Newton steps for ``method``: :data:`PREDICTOR` for the penalty-type laws, none for
    ``nitsche`` and for the exact method (whose steps are its step solver's)."""
    return False if problem.step_solver or method == "nitsche" else PREDICTOR


def mindlin_c(a: float, ratio: float) -> float:
    """Cattaneo-Mindlin stick half-width ``a sqrt(1 - Q / (mu P))`` (2D)."""
    return a * math.sqrt(1.0 - ratio)


def mindlin_traction(x: np.ndarray, a: float, c: float, mu: float, p0: float) -> np.ndarray:
    """Cattaneo-Mindlin tangential traction magnitude ``mu p0 [sqrt(1 - (x/a)^2) - (c/a) sqrt(1 - (x/c)^2)]``."""
    x = np.abs(np.asarray(x, dtype=float))
    q = np.sqrt(np.clip(1 - (x / a) ** 2, 0.0, None))
    q = q - np.where(x < c, (c / a) * np.sqrt(np.clip(1 - (x / max(c, 1e-300)) ** 2, 0.0, None)), 0.0)
    return mu * p0 * q


def check_loading(ratios: tuple, refinement: int, press_steps: int) -> tuple[float, ...]:
    """The ratios ``Q / (mu P)`` as floats; ``ValueError`` unless they increase in (0, 1), ``refinement >= 0`` and
    ``press_steps >= 1``."""
    ratios = tuple(float(r) for r in ratios)
    if not ratios or any(not 0 < r < 1 for r in ratios) or list(ratios) != sorted(set(ratios)):
        raise ValueError(f"ratios (Q / (mu P)) must be increasing values in (0, 1), got {ratios!r}")
    if int(refinement) < 0:
        raise ValueError(f"refinement must be >= 0, got {refinement!r}")
    if int(press_steps) < 1:
        raise ValueError(f"press_steps must be >= 1, got {press_steps!r}")
    return ratios


def stick_figures(out: dict, ratio: float, c: float, c_ref: float, h: float) -> float:
    """Write the measured stick size ``c``, Cattaneo-Mindlin's ``c_ref``, the relative error and the error in
    contact elements ``h`` at ``ratio`` into ``out`` (keys ``c_<r>``, ``c_ref_<r>``, ``c_error_<r>``,
    ``c_error_elements_<r>``); return the relative error."""
    out[f"c_{ratio:g}"], out[f"c_ref_{ratio:g}"] = c, c_ref
    out[f"c_error_{ratio:g}"] = abs(c - c_ref) / c_ref
    out[f"c_error_elements_{ratio:g}"] = abs(c - c_ref) / h
    return out[f"c_error_{ratio:g}"]


def worst_ratio(out: dict, errors: list[tuple[float, float]]) -> None:
    """From ``(error, ratio)`` pairs: ``c_error_max``, the ratio that has it (``ratio_worst``) and its stick size
    (``c_worst``) into ``out`` (nothing without a pair)."""
    if errors:
        out["c_error_max"], worst = max(errors)
        out["ratio_worst"], out["c_worst"] = worst, out[f"c_{worst:g}"]


def add_shear_options(parser: argparse.ArgumentParser, ratios: tuple, refinement_help: str) -> None:
    """The Mindlin demos' loading options: ``--ratios`` (default ``ratios``), ``--refinement`` (``refinement_help``)
    and ``--press-steps`` (before :func:`~fenics_contact.app.scenes.add_scene_options`, which then skips them)."""
    from ..cli import COUNT, LEVEL, number

    parser.add_argument("--ratios", type=number(float, 0.0, 1.0, True, True), nargs="+", default=list(ratios),
                        metavar="R",
                        help="Q / (mu P) of the tangential load steps, increasing in (0, 1)")
    parser.add_argument("--refinement", type=LEVEL, default=0, help=refinement_help)
    parser.add_argument("--press-steps", type=COUNT, default=None,
                        help="load steps of the pressing (default: the scene's for the method)")


def check_ratios_option(ratios: list) -> None:
    """:class:`~fenics_contact.app.cli.UsageError` naming ``--ratios`` unless its values increase in (0, 1) (the
    demos, before any work)."""
    from ..cli import UsageError

    if not all(0 < r < 1 for r in ratios) or ratios != sorted(set(ratios)):
        raise UsageError(f"--ratios must be increasing values in (0, 1), got {ratios}")


def worst_ratio_check(ratios: list, tolerance: float, source: str) -> Callable[[dict], dict]:
    """The demos' self-check of a summary: the stick size ``c_<r>`` at the ratio with the largest ``c_error_<r>``
    (a ratio without one counts as the worst) against ``c_ref_<r>`` within ``tolerance`` (relative); flagged when
    the Hertz contact it stands on is out of its range (:func:`~fenics_contact.app.checks.hertz_range`)."""
    from ..checks import hertz_range, reference_check

    def self_check(s: dict) -> dict:
        worst = max(ratios, key=lambda r: s.get(f"c_error_{r:g}", np.inf))
        return reference_check(f"c_{worst:g}", s.get(f"c_{worst:g}"), s.get(f"c_ref_{worst:g}"), tolerance, source,
                               hertz_range(s.get("a_hertz"), s["parameters"]["R"]))

    return self_check


def committed_force(contacts: list, load: float) -> np.ndarray | None:
    """The contact force on the first pass's slave body at the committed step ``load`` (normal and tangential, from
    the surfaces' logs): the first pass's force, or with two passes (unbiased, weight 1/2 each) the weighted mean of
    the first pass's and the reaction of the second's (one pass alone is not in equilibrium); None before that
    step is committed."""
    force = 0.0
    for sign, c in zip((1.0, -1.0), contacts):
        entry = [e for e in c.log if abs(e["load"] - load) < 1e-12]
        if not entry:
            return None
        weight = float(c.weight.value) if len(contacts) > 1 else 1.0
        force = force + sign * weight * (np.array(entry[-1]["normal_force"]) + entry[-1]["tangential_force"])
    return force


class ShearProblem(ContactProblem):
    """Force control of ``Q / (mu P)``: the tangential traction's amplitude ``mu P / area`` is fixed from the
    contact force ``P`` along ``axis`` (the pressing direction; the model's force, e.g. a half model's) of the
    accepted step ``t = 1`` when the first step beyond it starts. ``area``: the loaded face's measure (a length
    in 2D)."""

    scene = "mindlin"  # the error's prefix

    def __init__(self, *args, amplitude: fem.Constant, mu: float, area: float, axis: int, **kw):
        super().__init__(*args, **kw)
        self._amplitude, self._mu, self._area, self._axis, self.P = amplitude, mu, area, axis, None

    def set_load(self, t: float) -> None:
        if t > 1.0 and self.P is None:
            force = committed_force(self.contacts, 1.0)
            if force is None:
                raise RuntimeError(f"{self.scene}: the tangential load needs the accepted step t = 1 first")
            self.P = force[self._axis]
            self._amplitude.value = self._mu * self.P / self._area
        super().set_load(t)


OPTIONS = {
    "R": Option("radius of the upper body's cylindrical face (length)"),
    "E": Option("Young's modulus of both bodies (stress)"),
    "nu": Option("Poisson's ratio of both bodies", "poisson"),
    "approach": Option(f"pressing displacement of the upper body (length; default: {APPROACH:g} R)"),
    "width": Option("width 2 L of both bodies (length; default: R)"),
    "height": Option("upper body's height (length; default: R / 2)"),
    "depth": Option("lower block's depth (length; default: R / 2)"),
    "h_contact": Option("mesh size at the contact (length; default: R / 600, halved per --refinement)"),
}


def exact_friction(law: ContactLaw) -> bool:
    """Exact Coulomb friction (no regularisation, small sliding): method ``coulomb`` (the condensed system), or
    method ``lagrange`` with friction (the sparse system)."""
    return isinstance(law, ExactCoulomb) or (isinstance(law, Friction) and law.method == "lagrange")


def coulomb_mu(law: ContactLaw) -> float:
    """The friction coefficient of a Coulomb law (0 without one)."""
    return float(law.mu if isinstance(law, ExactCoulomb) else law.scalars.get("mu", 0.0))


def build(law: ContactLaw, ratios: tuple = RATIOS, refinement: int = 0, comm: MPI.Comm = MPI.COMM_WORLD,
          R: float = R, E: float = E, nu: float = NU, approach: float | None = None, press_steps: int | None = None,
          width: float | None = None, height: float | None = None, depth: float | None = None,
          h_contact: float | None = None, passes: str | None = None, sliding: str | None = None) -> Setup:
    """``law``: a :class:`~fenics_contact.friction.Friction` with a Coulomb bound (``mu > 0``), or the exact
    :class:`~fenics_contact.laws.ExactCoulomb` (method ``coulomb``, ``mu > 0``). ``ratios``: the
    values of ``Q / (mu P)`` in (0, 1), increasing; ``refinement`` halves the contact mesh size (default
    ``h_contact = R / 600``) that many times; ``press_steps`` load steps for the pressing (default
    :data:`PRESS_STEPS`, :data:`PRESS_STEPS_EXACT` for method ``coulomb``, :data:`PRESS_STEPS_NITSCHE` for
    ``nitsche``). ``passes``: ``one`` (default: the arc the slave) or ``two`` (each surface slave once, weight
    1/2; ``P`` and ``Q`` the weighted mean of the arc's pass and the reaction of the block's, the stick zone the
    arc's pass's). ``sliding``: the contact kinematics (:func:`~fenics_contact.two_body_surfaces`; None: the
    method's own, ``finite`` for the pointwise surfaces; ``small`` is that of Cattaneo-Mindlin's linear theory).
    Bodies: ``width``
    ``2 L`` (default ``R``), the upper body's ``height`` (default ``R / 2``), the block's ``depth`` (default
    ``R / 2``)."""
    approach = APPROACH * R if approach is None else approach
    positive(R=R, E=E, approach=approach, width=width, height=height, depth=depth, h_contact=h_contact)
    poisson(nu=nu)
    exact = exact_friction(law)
    if not (exact and coulomb_mu(law) > 0) and not (isinstance(law, Friction) and law.scalars.get("mu", 0) > 0):
        raise ValueError(f"mindlin needs a Coulomb friction law with mu > 0 (e.g. --mu 0.3), got {law!r}")
    if press_steps is None:
        press_steps = PRESS_STEPS_EXACT if exact else PRESS_STEPS_NITSCHE if law.method == "nitsche" else PRESS_STEPS
    ratios = check_loading(ratios, refinement, press_steps)
    mu = coulomb_mu(law)
    if exact and sliding is None:  # the exact methods' kinematics, Cattaneo-Mindlin's
        sliding = None if isinstance(law, ExactCoulomb) else "small"
    L = 0.5 * (R if width is None else width)
    H = 0.5 * R if height is None else height
    D = 0.5 * R if depth is None else depth
    h = (R / 600 if h_contact is None else h_contact) / 2 ** int(refinement)
    # At least the refined zone's columns (0.18 R / h) times its rows (24 per refinement), 2 unknowns each
    refuse_refined("h_contact", R / 600 if h_contact is None else h_contact, refinement,
                   log_dofs((2.0 * 24 * 2 ** int(refinement), 0.18 * R / h, 1)), 1, 2 * math.log10(2.0), comm)
    mesh, cells, facets = disk_on_block(comm, R, L, H, D, h, w=0.09 * R, n_coarse=20, ny=24 * 2 ** int(refinement),
                                        overlap=1e-9 * R)
    u, V = unknown(mesh, 1, law)  # the displacement, or (displacement, traction) for method lagrange
    t = fem.Constant(mesh, 0.0)
    dirichlet = [Dirichlet.on_facets(V, facets, "lower_bottom", 0), Dirichlet.on_facets(V, facets, "lower_bottom", 1),
                 Dirichlet(V.sub(1), fem.locate_dofs_topological(V.sub(1), 1, facets.find("upper_top")), 1.0,
                           ([0.0, 1.0], [0.0, -approach]))]
    material = LinearElastic(E, nu)
    passes = "one" if passes is None else passes
    contacts = two_body_surfaces(u, facets, "upper_bottom", "lower_top", lambda: law, t, "nodal", passes,
                                 name="interface", material=material, sliding=sliding)
    contact = contacts[0]
    ds = ufl.Measure("ds", domain=mesh, subdomain_data=facets.meshtags)
    amplitude = fem.Constant(mesh, 0.0)
    # ContactProblem scales tractions by t: this vector times t is (r mu P / (2 L), 0) at t = 1 + r.
    traction = ufl.as_vector((amplitude * ufl.max_value(t - 1.0, 0.0) / t, 0.0))
    problem = ShearProblem(u, material, t, dirichlet, contacts, [(traction, ds(facets["upper_top"]))],
                           amplitude=amplitude, mu=mu, area=2 * L, axis=1)
    Es = E / (2 * (1 - nu**2))
    loads = [(i + 1) / press_steps for i in range(press_steps)] + [1.0 + r for r in ratios]

    def profile() -> dict:
        return contact.friction_profile()

    def figures() -> dict:
        P = problem.P if problem.P is not None else float(sum(
            s * (float(c.weight.value) if len(contacts) > 1 else 1.0) * c.total_force()[1]
            for s, c in zip((1.0, -1.0), contacts)))
        if P <= 0:  # nothing pressed yet (a run stopped in its first steps): no Hertz figures
            return {"P": P, "h_contact": h, "mu": mu}
        a_h = math.sqrt(4 * P * R / (math.pi * Es))
        p0_h = 2 * P / (math.pi * a_h)
        prof = profile()
        x, p = prof["x"][:, 0], prof["pressure"]
        right = x >= 0
        out = {"P": P, "a_hertz": a_h, "p0_hertz": p0_h, "a": contact_half_width(x[right], p[right]),
               "p0": float(p.max()), "h_contact": h, "mu": mu}
        out["a_error"] = abs(out["a"] - a_h) / a_h
        errors = []
        for r in ratios:
            entry = [e for e in contact.log if abs(e["load"] - (1.0 + r)) < 1e-12]
            if not entry:
                continue
            errors.append((stick_figures(out, r, 0.5 * entry[-1]["stick"], mindlin_c(a_h, r), h), r))
            out[f"Q_{r:g}"] = -committed_force(contacts, 1.0 + r)[0]
        worst_ratio(out, errors)  # the benchmark's error and value
        # The last step's traction profile against Cattaneo-Mindlin over |x| < a: RMS and largest difference per
        # mu p0, the largest away from the reference's two kinks (more than 1.5 elements from |x| = c and = a).
        if ratios and problem.P is not None and float(t.value) > 1.0:
            c_ref = mindlin_c(a_h, float(t.value) - 1.0)
            inside = np.abs(x) < a_h
            q = -prof["traction"][inside]  # the block's traction on the upper body is along -x: its magnitude
            diff = np.abs(q - mindlin_traction(x[inside], a_h, c_ref, mu, p0_h)) / (mu * p0_h)
            smooth = (np.abs(np.abs(x[inside]) - c_ref) > 1.5 * h) & (np.abs(np.abs(x[inside]) - a_h) > 1.5 * h)
            out["traction_rms_error"] = float(np.sqrt(np.mean(diff**2)))
            out["traction_max_error"] = float(diff.max())
            out["traction_max_error_smooth"] = float(diff[smooth].max())
        return out

    params = {"E": E, "nu": nu, "R": R, "approach": approach, "width": 2 * L, "height": H, "depth": D,
              "h_contact": h, "refinement": refinement, "ratios": list(ratios), "mu": mu, "quadrature": "nodal",
              "passes": passes, "sliding": "small" if exact else sliding or "finite",
              "model": "disk segment on a block, same material, node-to-segment Coulomb friction"}
    setup = Setup("mindlin", problem, [contact], loads, params, figures,
                  [contact.displacement_out, contact.gap_out, contact.pressure_out, contact.traction_out,
                   contact.state_out])
    setup.profile = profile  # the friction profile at the current state (the demo's per-step pictures)
    return setup


# Speed against accuracy (fenics_contact.app.bench): the stick half-width at the worst ratio against Cattaneo-Mindlin;
# the exact condensed Coulomb law (method coulomb, no K) once per mesh, the reference (the gap of each run's stick
# half-width to its, the line on the Pareto chart). The error is a mesh figure (the edge of the discrete stick zone is
# known to half a contact element): the sweep shows how little the normal K moves it.
BENCH = {"error": "c_error_max", "value": "c_worst", "figures": ["ratio_worst", "a_error", "traction_rms_error", "P"],
         "target": 0.05, "K": DEFAULT_K, "mesh": ("refinement", {"quick": [0], "full": [0, 1]}),
         "methods": ["penalty", "cross", "auglag", "compliance", "coulomb", "nitsche"], "reference": "coulomb",
         "axes": {"kind": "two-body", "dim": 2, "friction": True},
         "demo_args": [], "quick_sweep": {"penalty": (-2, -1, 0, 1), "other": (-1, 0)}, "quadratures": ["nodal"]}
