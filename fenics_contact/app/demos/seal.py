"""Flattening of a double-curved seal between two rigid plates (Zavarise et al. 1998, sealing test).

    python demos/seal.py
    mpirun -n 2 python demos/seal.py --out results/seal

Wave-shaped band (arcs R_out = 10, R_in = 9; half model; --shape S or U
for the other designs, see the scene), neo-Hookean (E = 1000, nu = 0.3),
plates 7 apart, upper plate down by 0.5 per step to 5.5, then by 0.1 to
6.0; cross-constraints K^ = 1e5 (F^ = 1e-3, see the scene), full Newton
steps; each step starts from the tangent predictor. The penalty method
(K = 1e5) is run on the same scene for the comparison table.

Writes to --out: seal.xdmf (every step), summary.json, seal_residuals.csv|md
(Newton residual norm, step x iteration, like the paper's Table I),
seal_zones.csv|md (contact zones per plate over the history),
seal_<t>.png (deformed section coloured by the vertical Cauchy stress at
t = 0.5, 2.0, 5.5, 6.0), methods.csv|md (method, converged, iterations,
time; merged with the other demos' into --out's parent) and penalty/.
"""
import json
from pathlib import Path

from dolfinx import fem
from mpi4py import MPI

from fenics_contact import (
    ConvergenceError,
    CrossConstraints,
    Penalty,
    function_space,
    interpolate_expression,
)
from fenics_contact.app import build, cli, run, tables
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, scene_arguments, seal


def main(argv=None) -> dict:
    # 1. Options: mesh size, contact data (K^ = 1e5 as in the paper).
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(seal.K_HAT, seal.build, length="R_out"))
    p.add_argument("--h", type=cli.POSITIVE, default=0.5, help="cell size (0.5: 2 cells through the thickness)")
    p.add_argument("--shape", choices=list(seal.SHAPES), default="wave", help="seal cross-section (see the scene)")
    p.set_defaults(F_hat=seal.F_HAT)
    scene = add_scene_options(p, seal.build, shared=("h",))  # --E, --nu, --R-out, --R-in, --plate-distance
    args = cli.parse(p, argv)
    out = Path(args.out or "results/seal")
    comm = MPI.COMM_WORLD
    PICTURES = (0.5, 2.0, 5.5, 6.0)

    # 2. The scene and the step hook: contact zones per plate after every step, pictures at PICTURES.
    setup = build("seal", law=CrossConstraints(args.K, args.F_hat), h=args.h, shape=args.shape,
                  **scene_arguments(args, scene))
    u = setup.problem.u
    syy = fem.Function(function_space(u.function_space.mesh, "Lagrange", 1), name="sigma_yy")
    zones, states = [], {}


    def on_step(t: float) -> None:
        f = setup.figures()
        zones.append({"t": round(t, 6), "zones_lower": f["zones_lower"], "zones_upper": f["zones_upper"],
                      "lower_x": "; ".join(f"{a:.2f}-{b:.2f}" for a, b in f["zones_lower_x"]),
                      "upper_x": "; ".join(f"{a:.2f}-{b:.2f}" for a, b in f["zones_upper_x"]),
                      "force": round(f["plate_force_lower"], 6)})
        if any(abs(t - s) < 1e-9 for s in PICTURES):  # pictured after the run (rendering is not solver time)
            states[t] = u.x.array.copy()


    # 3. Solve every load step (cross-constraints), write XDMF, summary.json and the tables.
    options = {**cli.solver_options(args), **seal.SOLVER_OPTIONS}  # --solver; full Newton steps
    summary = run(setup, out, args.method if args.method == "cross" else "cross", cli.method_parameters(args), 0,
                  quiet=args.quiet, options=options, predictor=seal.PREDICTOR[args.shape], on_step=on_step,
                  keep=(zones, states),
                  check=lambda s: reference_check("plate_force_upper", s.get("plate_force_upper"),
                                                  s.get("plate_force_lower"),
                                        1e-6, "equilibrium: the lower plate's force"),
                  xdmf=not args.no_xdmf, restart=args.restart, overwrite=args.overwrite, args=args)
    if comm.rank == 0:
        cli.say(tables.residual_table(summary["steps"], out / "seal_residuals"))
        cli.say(tables.write_table(zones, out / "seal_zones"))
        with open(out / "summary.json") as fh:  # the zones history into summary.json too
            full = json.load(fh)
        full["zones_history"] = zones
        with open(out / "summary.json", "w") as fh:
            json.dump(full, fh, indent=1)

    # 4. Pictures: the deformed section (the modelled part) coloured by the vertical Cauchy stress at PICTURES.
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_deformed

        for t, state in states.items():
            u.x.array[:] = state
            interpolate_expression(syy, setup.problem.material.stress(u)[1, 1])
            plot_deformed(u, syy, out / f"seal_{t:.1f}.png", title=f"seal ({args.shape}), t = {t:.1f}")

    # 5. The penalty method on the same scene, for the comparison table.
    penalty = build("seal", law=Penalty(args.K), h=args.h, shape=args.shape, **scene_arguments(args, scene))
    try:
        penalty_summary = run(penalty, out / "penalty", "penalty", {"K": args.K}, 0, quiet=args.quiet,
                              options=options, predictor=seal.PREDICTOR[args.shape], xdmf=not args.no_xdmf,
                              restart=args.restart, overwrite=args.overwrite, args=args)
    except ConvergenceError:
        penalty_summary = json.load(open(out / "penalty" / "summary.json")) if comm.rank == 0 else None
    if comm.rank == 0:
        rows = [tables.method_row(summary, f"cross-constraints (K^ {args.K:g}, F^ {args.F_hat:g})"),
                tables.method_row(penalty_summary, f"penalty (K {args.K:g})")]
        cli.say(tables.write_table(rows, out / "methods", tables.METHOD_COLUMNS))
        tables.merge_method_tables(out.parent)
        its = [s["newton_iterations"] for s in summary["steps"]]
        cli.say(f"seal: {len(its)} steps, Newton iterations per step {its} (max {max(its)}), "
              f"{summary['wall_time_s']:.2f} s, {summary['dofs']} dofs, {comm.size} ranks")
        cli.say("contact zones (lower, upper):", [(z["t"], z["zones_lower"], z["zones_upper"]) for z in zones])
    return summary


if __name__ == "__main__":
    cli.main(main)
