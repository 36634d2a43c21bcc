"""Elastic slab pressed and pushed on a rigid plate with Coulomb friction (Renaud & Feng 2003).

    python demos/slab.py --method coulomb --mu 0.4
    mpirun -n 2 python demos/slab.py --method coulomb --mu 1.0 --refinement 1
    python demos/slab.py --method coulomb --sweep

Half slab 40 x 40 (E = 13000, nu = 0.2), pressure 5 on the top, 10 on the
free side, symmetry u_x = 0 on x = 0, rigid frictional base; Q1 mesh 32 x 16
times 2**refinement. Writes slab.xdmf, summary.json, slab_base.csv (pressure and
tangential traction along the base), slab_base.png and slab_deformed.png to
--out; --sweep does it for mu in 0, 0.4, 0.8, 1.0, 1.3 (one folder each) and
draws the zone lengths against mu (slab_zones.png, slab_sweep.csv).
"""
from pathlib import Path

import numpy as np
from dolfinx import fem

from fenics_contact import function_space, interpolate_expression
from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, scene_arguments, slab

SWEEP = (0.0, 0.4, 0.8, 1.0, 1.3)
# Converged references of ux_A with the exact condensed Coulomb method (README, slab): mu -> value on the default
# mesh (refinement 0), and mu = 1 on refinements 0-3. mu = 0 has the closed form slab.UX_A_FRICTIONLESS.
UX_A = {(0.4, 0): -1.912145e-02, (0.8, 0): -1.557435e-02, (1.0, 0): -1.459668e-02, (1.3, 0): -1.364191e-02,
        (1.4, 0): -1.341721e-02, (1.5, 0): -1.320241e-02, (1.0, 1): -1.463393e-02, (1.0, 2): -1.464506e-02,
        (1.0, 3): -1.464727e-02}


def slab_check(s: dict, mu: float, refinement: int, method: str, top_load: float, default_scene: bool) -> dict:
    """ux_A against the closed form (mu = 0) or the converged exact-Coulomb table; else the normal equilibrium."""
    # the exact method reproduces its own table to its 7 digits; a penalty-type friction law is off by its penalty
    tol = 1e-6 if method == "coulomb" else 1e-2
    if mu == 0.0:
        return reference_check("ux_A", s.get("ux_A"), s.get("ux_A_frictionless"), tol, "closed form, frictionless")
    if (mu, refinement) in UX_A and default_scene:
        return reference_check("ux_A", s.get("ux_A"), UX_A[(mu, refinement)], tol,
                     f"exact Coulomb, mu = {mu:g}, refinement {refinement} (README)")
    return reference_check("normal_force", s.get("normal_force"), top_load, 1e-6, "equilibrium: the top load")



def main(argv=None) -> dict:
    # 1. Options: the formulation (default: the exact condensed Signorini-Coulomb), mu, mesh, load steps.
    # The slab rests on the plate (g = 0 everywhere at t = 0), where penalty-type laws are open: methods penalty and
    # nitsche (no normal stiffness at g = 0 and zero stress: a singular first Jacobian) are not offered (compliance
    # is the penalty closed at g = 0); auglag and cross start from lam0 = F_hat = the mean contact pressure
    # (scenes/slab.py: K_DEMO, OMEGA_T, LAM0). vi, lagrange, penalty_multiplier: frictionless only (--mu 0).
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(slab.K_DEMO, slab.build, length="width"),
                   default_omega_t=cli.scene_scaled(slab.OMEGA_T, slab.build, length="width"))
    p.add_argument("--refinement", type=cli.LEVEL, default=0, help="halve the cells this many times (32 x 16 at 0)")
    p.add_argument("--steps", type=cli.COUNT, default=1, help="proportional load steps (friction is path dependent)")
    p.add_argument("--sweep", action="store_true", help=f"run mu in {SWEEP} and plot the zones against mu")
    cli.model_option(p, help="bulk material (coulomb: linear only)")
    scene = add_scene_options(p, slab.build)  # --width, --height, --E, --nu, --top-pressure, --side-pressure
    # auglag's lam0 > 0: the resting slab's first Jacobian needs it
    p.set_defaults(method="coulomb", F_hat=slab.LAM0, lam0=slab.LAM0)
    for action in p._actions:
        if action.dest == "method":
            action.choices = [m for m in action.choices if m not in ("penalty", "nitsche")]
    args = cli.parse(p, argv)
    defaults = {n: a.default for a in p._actions for n in scene if a.dest == n}
    default_scene = all(getattr(args, n) == d for n, d in defaults.items()) and args.model == "linear"
    out = Path(args.out or "results/slab")
    rows = []

    for mu in SWEEP if args.sweep else (args.mu,):
        args.mu = mu
        folder = out / f"mu_{mu:g}" if args.sweep else out

        # 2. The scene: half slab, tractions on top and free side, symmetry, rigid frictional base.
        setup = build("slab", law=cli.law_from_args(args), quadrature=args.quadrature, refinement=args.refinement,
                      steps=args.steps, model=args.model, **scene_arguments(args, scene))
        comm = setup.problem.comm

        # 3. Solve (one proportional step by default), write XDMF and summary.json.
        summary = run(setup, folder, args.method, {**cli.method_parameters(args), "steps": args.steps},
                      args.augment, args.augment_tol, args.quiet,
                      options={**cli.solver_options(args), **slab.SOLVER_OPTIONS},
                      check=lambda s, mu=mu: slab_check(s, mu, args.refinement, args.method,
                                                        args.top_pressure * args.width, default_scene),
                      xdmf=not args.no_xdmf, restart=args.restart, overwrite=args.overwrite, args=args)
        z = summary["zones"]
        rows.append((mu, summary["ux_A"], summary["uy_A"], z["separated"], z["sliding"], z["sticking"],
                     summary["newton_iterations"]))

        # 4. The base: CSV of gap, pressure, tangential traction and state along x; its plot.
        base = summary["base"]
        x = np.asarray(base["x"])[:, 0]
        if comm.rank == 0:
            columns = [x, setup.parameters["width"] - x, base["gap"], base["pressure"], base["traction"], base["state"]]
            np.savetxt(folder / "slab_base.csv", np.column_stack(columns), delimiter=",", comments="",
                       header="x,distance_from_A,gap,pressure,tangential_traction,state (0 open 1 slip 2 stick)")
        if args.no_pictures:
            continue
        from fenics_contact.app.plotting import plot_curves, plot_deformed

        if comm.rank == 0:
            pr, tr = np.asarray(base["pressure"]), np.asarray(base["traction"])
            plot_curves([(x, pr, "contact pressure p", "o-"), (x, tr, "tangential traction t (along +x)", "o-"),
                         (x, mu * pr, "mu p", "o-")], folder / "slab_base.png", xlabel="x (free corner A at x = 40)",
                        ylabel="traction", title=f"slab, {args.method}, mu = {mu:g}: separated {z['separated']:.3g}, "
                        f"sliding {z['sliding']:.3g}, sticking {z['sticking']:.3g}")
        u = setup.problem.u
        sxy = interpolate_expression(fem.Function(function_space(u.function_space.mesh, "Lagrange", 1),
                                                  name="sigma_xy"), setup.problem.material.stress(u)[0, 1])
        plot_deformed(u, sxy, folder / "slab_deformed.png",
                      title=f"slab, {args.method}, mu = {mu:g} (displacement x500)", scale=500)

    # 5. Sweep: zone lengths (from the free corner inward) against mu.
    if args.sweep and comm.rank == 0:
        table = np.array(rows)
        np.savetxt(out / "slab_sweep.csv", table, delimiter=",", comments="",
                   header="mu,ux_A,uy_A,separated,sliding,sticking,newton_iterations")
        if not args.no_pictures:
            plot_curves([(table[:, 0], table[:, 3 + i], name, "o-") for i, name in enumerate(slab.STATES)],
                        out / "slab_zones.png", xlabel="friction coefficient mu", ylabel="length along the base",
                        title=f"slab zones against mu ({args.method})")
        for r in rows:
            cli.say(f"mu {r[0]:4.2f}  ux_A {r[1]: .6e}  uy_A {r[2]: .6e}  separated {r[3]:6.3f}  sliding {r[4]:6.3f}  "
                  f"sticking {r[5]:6.3f}  newton {r[6]}")
    return summary


if __name__ == "__main__":
    cli.main(main)
