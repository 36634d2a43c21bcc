"""``ironing``: a stiff punch pressed into a soft neo-Hookean block and dragged along it with Coulomb friction (2D,
plane strain, two deformable bodies, finite strain, large sliding; after the ironing benchmarks of Puso & Laursen
2004 and Yang, Laursen & Meng 2005).

Bodies. The block ``[x0, x1] x [-H, 0]`` (neo-Hookean ``E``, ``nu``; its base clamped) and the punch above it
(neo-Hookean, ``stiffness`` times ``E``): a face made of a flat ``|x - centre| <= a`` and two circular fillets of
radius ``r`` turning up to ``theta`` from the vertical, its top at ``y = height``. Loading by the punch's top
(displacement control, both components): ``t`` in (0, 1] down by ``t * depth``; then ``t`` in (1, 2] along +x by
``(t - 1) * drag``.

Contact. Node-to-segment, one pass: the block's top is the slave (its nodes, ``h`` apart), the punch's face the
master, Coulomb friction ``mu`` on a penalty-type normal law
(:class:`~fenics_contact.twobody.friction.FrictionalTwoBodySurface`). The choices against the oscillating force
ratio of a sharp-cornered punch (slave nodes crossing master vertices):

* the master's flat face is straight (its facets in line: the normal does not jump from facet to facet) and most of
  the load is carried there; the block's surface conforms to it, so the horizontal over vertical force is the
  local tangential over normal one there;
* the fillets turn the normal in small steps (facets ``h_arc = h / 4`` apart along the arc: a jump of ``h_arc /
  r`` = 0.025 rad per vertex), so a block node enters and leaves contact with its gap growing continuously (a sharp
  corner switches a node's normal by 90 degrees at once). The ratio's swing is these jumps: with ``h_arc = h / 2``
  its peak to peak over the drag is 1.4 % of mu, with ``h / 4`` 0.6 %; ``h / 8`` lowers it again but a slave node
  then changes facet several times within a Newton solve (up to 24 iterations);
* the slave is the finer surface, so the master vertices are few and the slave nodes many.

Force ratio. ``F`` the contact force on the punch (minus the force on the block: the two are equal and opposite,
:meth:`~fenics_contact.twobody.TwoBodySurface.add_residual`); its components in the punch's frame (``e_t`` along
the current flat face, the mean of its facets' directions, ``e_n`` its normal, into the punch) give
``ratio = -F . e_t / F . e_n``: the tangential over normal force on the punch, friction opposing the drag. The
fillets' pressure has a horizontal part (the pile-up ahead of the punch, the lighter contact behind): the ratio's
departure from ``mu``. Where every closed point slides with ``|q| = mu p`` against the drag, the force on the punch
is the pressure's resultant turned by ``atan mu``, so ``ratio = (mu + tan psi) / (1 - mu tan psi)`` exactly, with
``psi`` the tilt of the pressure's resultant (``P``, the ``F n`` part alone) from the punch's normal (the wedges
formula): ``ratio - mu`` is the contact zone's shape, the rest is Coulomb's law. Reported over the steady window
(the drag from ``steady_from`` on): the mean, peak to peak and largest relative distance from ``mu`` (the check's
2 % is measured on every step of the window), the mean ``psi`` and the identity's error; also in the global frame
(``-F_x / F_y``).
"""
from __future__ import annotations

import math

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from ...compat import function_space
from ...factory import two_body_surfaces
from ...friction import SLIP, Friction
from ...laws import ContactLaw
from ...materials import Materials, NeoHookean
from ...problem import ContactProblem, Dirichlet
from ...twobody.friction import FrictionalTwoBodySurface
from ..meshes.ironing import punch_on_block
from . import Option, Setup, log_dofs, poisson, positive, refuse_fine

__all__ = ["OPTIONS",
           "E", "NU", "STIFFNESS", "DEFAULT_K", "DEFAULT_OMEGA_T", "PREDICTOR", "IroningSurface", "build", "BENCH"]

E, NU = 1000.0, 0.3  # the block; the punch is STIFFNESS times stiffer
STIFFNESS = 100.0
# Normal penalty 2.5 E / h: the penetration p / K ~ 3e-3 (3 % of the depth). Measured on the demo (70 drag steps, the
# secant predictor): with 5e4, 4.3 Newton iterations per step on average (at most 8) and the farthest window step
# 0.46 % from mu; with 1e5 (5 E / h), 5.0 per step and 0.40 %; with 1e6, up to 27 in a step. A stiffer K gains
# nothing for the checked figure (the force ratio) and costs iterations: at each step the contact zone's edges move
# on by the step under the fillets, where the prediction opens or overloads a few slave nodes, and the stiffer the
# law the more Newton iterations it takes to find them again.
DEFAULT_K = 5e4
# Each step starts from the linear extrapolation of the last two converged states (the solver's secant predictor):
# in steady sliding the punch and the contact zone move on by the step, and Newton starts with nearly the pairing it
# ends with (4-5 iterations per drag step of the demo, 8 in the first, instead of 6-13 from the last state).
PREDICTOR = "secant"
DEFAULT_OMEGA_T = 1e4  # tangential penalty ~ E / (2 h): the elastic slip mu p / omega_t ~ 4e-3 is 1/10 of a drag step


class IroningSurface(FrictionalTwoBodySurface):
    """The frictional surface that also logs, at each committed step, the direction of the punch's flat face
    (``face_angle``, rad from +x: the mean of the current flat master facets)."""

    flat_half_width: float = 0.0  # the flat face's facets: |X - centre| <= a (set by build)
    centre: float = 0.0

    def face_angle(self) -> float:
        """Angle (rad) of the punch's flat face: the sum of its current facet vectors, oriented along +x."""
        md = self.master_data
        X = md.X
        x = X + self.u.x.array[md.comp]
        mid = X.mean(axis=1)[:, 0] - self.centre
        sel = md.owned & (np.abs(mid) < self.flat_half_width) if len(X) else np.zeros(0, bool)
        d = x[sel, -1] - x[sel, 0] if np.any(sel) else np.zeros((0, 2))
        d = d * np.sign(d[:, :1] + (d[:, :1] == 0))  # along +x
        t = self.comm.allreduce(d.sum(axis=0) if len(d) else np.zeros(2), op=MPI.SUM)
        return float(math.atan2(t[1], t[0]))

    def commit(self) -> None:
        super().commit()
        if self.log:
            self.log[-1]["face_angle"] = self.face_angle()


OPTIONS = {
    "E": Option("block's Young's modulus (stress)"),
    "nu": Option("block's Poisson's ratio (the punch's too)", "poisson"),
    "stiffness": Option("punch's Young's modulus / the block's (dimensionless)"),
    "depth": Option("punch's descent into the block (length)"),
    "drag": Option("punch's horizontal travel (length)"),
    "H": Option("block height (length)"),
    "half_width": Option("half-width of the punch's flat face (length)"),
    "r": Option("radius of the punch's fillets (length)"),
    "theta": Option("angle the fillets turn from the vertical (degrees, in (0, 90])", (0.0, 90.0, True)),
    "height": Option("height of the punch's top above its flat face (length)"),
    "margin": Option("block length beyond the punch at both ends of the drag (length)"),
    "h": Option("slave node spacing, the block's columns (length)"),
    "h_flat": Option("punch's facet size on the flat face (length; default: 2 --h)"),
    "h_arc": Option("punch's facet size along the fillets (length; default: --h / 4)"),
    "steady_from": Option("drag from which the steady figures are averaged (length; default: half of --drag)",
                          "nonnegative"),
}


def build(law: ContactLaw, E: float = E, nu: float = NU, stiffness: float = STIFFNESS, depth: float = 0.1,
          drag: float = 3.0, H: float = 1.0, half_width: float = 0.5, r: float = 0.5, theta: float = 70.0,
          height: float = 0.5, margin: float = 1.5, h: float = 0.05, h_flat: float | None = None,
          h_arc: float | None = None, quadrature: str = "nodal", press_steps: int = 4, drag_steps: int = 70,
          steady_from: float | None = None, comm: MPI.Comm = MPI.COMM_WORLD) -> Setup:
    """``law``: a Coulomb :class:`~fenics_contact.friction.Friction` (``mu > 0``). Block ``H`` high (``E``,
    ``nu``); punch flat half-width ``half_width`` (``a``), fillet radius ``r`` turning ``theta`` degrees from the
    vertical (in (0, 90]), top at ``height``, ``stiffness`` times the block's ``E``; ``depth`` the punch's descent,
    ``drag`` its horizontal travel; the block reaches ``margin`` beyond the punch at both ends of the drag. Slave
    node spacing ``h`` (the block's columns), the punch's master facets ``h_flat`` on the flat face (default ``2 h``)
    and ``h_arc`` along the fillets (default ``h / 4``); ``quadrature`` ``nodal`` or ``gauss`` (slave points);
    ``press_steps``, ``drag_steps`` load steps (default 70: a step of 0.86 h, so that the steps sample every
    position of the punch between two slave nodes; a step of exactly ``h`` would see one). ``steady_from``: the
    drag from which the window of the steady figures starts (default: half the drag)."""
    positive(E=E, stiffness=stiffness, depth=depth, drag=drag, H=H, half_width=half_width, r=r, theta=theta,
             height=height, margin=margin, h=h, h_flat=h_flat, h_arc=h_arc)
    if quadrature not in ("nodal", "gauss"):
        raise ValueError(f"quadrature must be 'nodal' or 'gauss', got {quadrature!r}")
    poisson(nu=nu)
    if not isinstance(law, Friction) or "mu" not in law.scalars or not law.scalars["mu"] > 0:
        raise ValueError(f"ironing needs a Coulomb friction law with mu > 0 (e.g. --mu 0.3), got {law!r}")
    if getattr(law.normal, "name", "") == "nitsche":
        raise ValueError("method nitsche is refused on ironing: the scene's surface (the punch face's angle) is the "
                         "penalty-type friction surface; use penalty, auglag, cross or compliance")
    if not 0 < theta <= 90:
        raise ValueError(f"theta must be in (0, 90] degrees, got {theta!r}")
    if not depth < 0.5 * H:
        raise ValueError(f"depth must be below H / 2 = {0.5 * H:g}, got {depth!r}")
    if not depth < r * (1 - math.cos(math.radians(theta))):
        raise ValueError(f"depth must be below the fillets' rise r (1 - cos theta) = "
                         f"{r * (1 - math.cos(math.radians(theta))):g}, got {depth!r}")
    a = half_width
    if not h < a:
        raise ValueError(f"h must be below the flat half-width half_width = {a:g}, got {h!r}")
    for name, n in (("press_steps", press_steps), ("drag_steps", drag_steps)):
        if int(n) != n or int(n) < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {n!r}")
    steady = 0.5 * drag if steady_from is None else float(steady_from)
    if not 0 <= steady < drag:
        raise ValueError(f"steady_from must be in [0, drag = {drag:g}), got {steady_from!r}")
    mu = float(law.scalars["mu"])
    th = math.radians(theta)
    half = a + r * math.sin(th)
    x0, x1 = -half - margin, drag + half + margin
    ny = max(6, int(round(4 * math.log2(H / h))))  # graded layers: the top one about h thick
    h_flat = 2 * h if h_flat is None else h_flat
    h_arc = 0.25 * h if h_arc is None else h_arc
    # At least 2 unknowns per block column and layer, per punch facet along its face (8 layers)
    refuse_fine("h", h, log_dofs((2.0 * ny, (x1 - x0) / h, 1)), 1, comm)
    refuse_fine("h_flat", h_flat, log_dofs((16.0, 2 * a / h_flat, 1)), 1, comm)
    refuse_fine("h_arc", h_arc, log_dofs((16.0, 2 * r * th / h_arc, 1)), 1, comm)
    msh, cells, facets = punch_on_block(comm, x0, x1, H, h, ny, a, r, th, height, h_flat, h_arc, 8, 0.0,
                                        overlap=1e-9 * H)
    V = function_space(msh, "Lagrange", 1, (2,))
    u = fem.Function(V, name="displacement")
    t = fem.Constant(msh, 0.0)
    top = facets.find("punch_top")
    dirichlet = [Dirichlet.on_facets(V, facets, "block_bottom", 0), Dirichlet.on_facets(V, facets, "block_bottom", 1),
                 Dirichlet(V.sub(0), fem.locate_dofs_topological(V.sub(0), 1, top), 1.0, ([0.0, 1.0, 2.0],
                                                                                           [0.0, 0.0, drag])),
                 Dirichlet(V.sub(1), fem.locate_dofs_topological(V.sub(1), 1, top), 1.0, ([0.0, 1.0, 2.0],
                                                                                           [0.0, -depth, -depth]))]
    contact = two_body_surfaces(u, facets, "block_top", "punch_face", lambda: law, t, quadrature, name="ironing",
                                cls=IroningSurface)[0]
    contact.flat_half_width, contact.centre = a, 0.0
    material = Materials(msh, cells, {"block": NeoHookean(E, nu), "punch": NeoHookean(stiffness * E, nu)})
    problem = ContactProblem(u, material, t, dirichlet, [contact])
    loads = [(i + 1) / press_steps for i in range(press_steps)] + \
        [1.0 + (i + 1) / drag_steps for i in range(drag_steps)]

    def history() -> list[dict]:
        """Per committed step: the load, the punch's travel, the contact force on the punch (global), its
        tangential and normal components in the punch's frame, both ratios, the tilt of the pressure's resultant
        from the punch's normal (``tilt``, rad) and the ratio it implies with Coulomb at every point
        (``ratio_coulomb``), and the dissipated work."""
        rows = []
        for e in contact.log:
            F = -(np.asarray(e["normal_force"]) + np.asarray(e["tangential_force"]))  # on the punch
            phi = e.get("face_angle", 0.0)
            et, en = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
            Ft, Fn = float(F @ et), float(F @ en)
            P = -np.asarray(e["normal_force"])  # the pressure's part alone, on the punch
            tilt = math.atan2(-float(P @ et), float(P @ en))  # > 0: it leans against the drag (pile-up ahead)
            rows.append({"load": e["load"], "travel": max(e["load"] - 1.0, 0.0) * drag, "Fx": float(F[0]),
                         "Fy": float(F[1]), "Ft": Ft, "Fn": Fn, "ratio": -Ft / Fn if Fn > 0 else float("nan"),
                         "ratio_global": -float(F[0]) / float(F[1]) if F[1] > 0 else float("nan"),
                         "tilt": tilt, "ratio_coulomb": (mu + math.tan(tilt)) / (1 - mu * math.tan(tilt)),
                         "face_angle": phi, "dissipated": e["dissipated"], "slip": e["slip"], "stick": e["stick"]})
        return rows

    def figures() -> dict:
        rows = history()
        out = {"mu": mu, "steps_committed": len(rows)}
        window = [r for r in rows if r["load"] > 1.0 and r["travel"] >= steady - 1e-12]
        if window:
            ratio = np.array([r["ratio"] for r in window])
            glob = np.array([r["ratio_global"] for r in window])
            out.update({"ratio_mean": float(ratio.mean()), "ratio_peak_to_peak": float(ratio.max() - ratio.min()),
                        "ratio_mean_error": abs(float(ratio.mean()) - mu) / mu,
                        "ratio_max_error": float(np.max(np.abs(ratio - mu))) / mu,
                        "ratio_worst": float(ratio[np.argmax(np.abs(ratio - mu))]),
                        "ratio_global_mean": float(glob.mean()),
                        "ratio_global_peak_to_peak": float(glob.max() - glob.min()),
                        "window_steps": len(window), "window_from": steady,
                        "tilt_mean": float(np.mean([r["tilt"] for r in window])),
                        "coulomb_identity_error": max(abs(r["ratio"] - r["ratio_coulomb"]) for r in window) / mu,
                        "Fn_mean": float(np.mean([r["Fn"] for r in window])),
                        "face_angle_max": float(np.max(np.abs([r["face_angle"] for r in window])))})
        if rows:
            d = np.array([r["dissipated"] for r in rows])
            out["dissipated"] = float(d[-1])
            out["dissipation_min_increment"] = float(np.min(np.diff(d, prepend=0.0)))
            last = rows[-1]
            out.update({"Fx": last["Fx"], "Fy": last["Fy"], "ratio_last": last["ratio"]})
            prof = contact.friction_profile()
            closed = prof["state"] > 0
            out["slip_fraction"] = float(np.mean(prof["state"][closed] == SLIP)) if closed.any() else 0.0
        jmin = problem.min_jacobian()
        out["min_jacobian"] = jmin
        return out

    params = {"E": E, "nu": nu, "stiffness": stiffness, "E_punch": stiffness * E, "depth": depth, "drag": drag,
              "H": H, "half_width": a, "r": r, "theta": theta, "height": height, "margin": margin, "h": h,
              "h_flat": h_flat, "h_arc": h_arc, "mu": mu,
              "press_steps": press_steps, "drag_steps": drag_steps, "steady_from": steady, "quadrature": quadrature,
              "block": [x0, x1], "model": "stiff round-cornered punch dragged on a neo-Hookean block, node-to-segment "
                                          "Coulomb friction (block slave)"}
    setup = Setup("ironing", problem, [contact], loads, params, figures,
                  [u, contact.gap_out, contact.pressure_out, contact.traction_out, contact.state_out])
    setup.history = history
    return setup


# Benchmark (fenics_contact.app.bench): no closed form; the figure is the steady-window force ratio (punch's frame), the
# error the largest relative distance of a window step's ratio from mu. The test's short drag (0.35 in 8 steps on the
# demo's contact mesh); the stability map: K x drag steps, penalty and augmented Lagrangian (Uzawa on the normal and
# the tangential multiplier: its converged runs are the augmentation limit the map's distances refer to). Method
# nitsche is refused by build; method coulomb by the capability matrix (finite strain).
BENCH = {"error": "ratio_max_error", "value": "ratio_mean", "figures": ["ratio_peak_to_peak", "ratio_worst"],
         "target": 0.02, "K": DEFAULT_K, "mesh": None, "methods": ["penalty", "cross", "auglag", "compliance"],
         "axes": {"kind": "two-body", "dim": 2, "friction": True},
         "demo_args": ["--drag", "0.35", "--steps", "8", "--margin", "0.5", "--steady-from", "0.15"],
         "quick_sweep": {"penalty": (-1, 0, 1), "other": (0,)}, "quadratures": ["nodal"], "stability": True,
         "quick_stability": {"K": (-1, 0, 1, 2), "steps": (4, 8), "variants": (("penalty", 0), ("auglag", 10)),
                             "dtol": False},
         "stability_variants": (("penalty", 0), ("cross", 0), ("auglag", 10))}
