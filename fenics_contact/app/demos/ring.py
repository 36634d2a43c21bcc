"""Elastic ring between two rigid plates: the penalty method with augmentation cycles, cross-constraints does not.

    python demos/ring.py
    mpirun -n 2 python demos/ring.py --out results/ring -fc_snes_linesearch_type l2

Zavarise, Wriggers & Schrefler (1998), ring test: R_out = 8, R_in = 6,
E = 1000, nu = 0.3, upper plate down by 1 in one step, K = K^ = 1e5,
F^ = 0, nodal contact points on a coarse mesh (quarter model). Both methods
solve the first step identically; then one augmentation. The penalty
method with augmentation (gap status decides: F = lam + K g closed, 0 open)
opens the edge point at the first iterate, its force jumps to zero, and the
active set cycles for ever; the failure is diagnosed as ``cycling``.
Cross-constraints (exponential branch on the open side) converges in a few
iterations. Plain Newton (``basic`` line search, the paper's) unless told
otherwise. The augmented Lagrangian ``<lam + K g>`` (continuous in g) is
run as a third method for reference.

Writes to --out: summary.json and ring.xdmf (cross-constraints), penalty/
and auglag/ (the same for those), ring_forces.csv|md and ring_forces.png
(contact forces of the active points against the iteration after the first
augmentation), methods.csv|md (method, converged, iterations, time) and
ring_deformed.png, first_step.json (the first step's penetrations, plate force, closed points).
"""
import json
from pathlib import Path

import numpy as np
from dolfinx import fem
from mpi4py import MPI

from fenics_contact import (
    AugmentedLagrangian,
    ConvergenceError,
    CrossConstraints,
    Penalty,
    Solver,
    function_space,
    interpolate_expression,
    write_summary,
)
from fenics_contact.app import build, cli, run, tables
from fenics_contact.app.checks import log_check, reference_check
from fenics_contact.app.scenes import add_scene_options, ring, scene_arguments

# first-step penetration at the centre: 2.02e-4 on this mesh against the paper's 0.19e-3 (its mesh is described,
# not given; the neighbour's 1.28e-4 against 0.13e-3)
TOLERANCE = 1e-1


def main(argv=None) -> dict:
    # 1. Options: mesh and the paper's data (K = K^ = 1e5, F^ = 0, one augmentation).
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(ring.K, ring.build, length="R_out"))
    p.add_argument("--n-theta", type=cli.COUNT, default=44, help="cells along the quarter circle")
    p.add_argument("--n-r", type=cli.COUNT, default=4, help="cells through the thickness")
    p.set_defaults(augment=1)
    scene = add_scene_options(p, ring.build)  # --R-out, --R-in, --E, --nu, --approach
    args = cli.parse(p, argv)
    out = Path(args.out or "results/ring")
    comm = MPI.COMM_WORLD
    # --solver, and plain Newton as in the paper; -fc_snes_linesearch_type wins
    OPTIONS = {**cli.solver_options(args), "snes_linesearch_type": "basic"}

    METHODS = {"penalty": ("penalty + augmentation", lambda: Penalty(args.K, augmented=True)),
               "cross": ("cross-constraints", lambda: CrossConstraints(args.K, 0.0)),
               "auglag": ("augmented Lagrangian <lam + K g>", lambda: AugmentedLagrangian(args.K))}

    # 2. Each method: the same scene, one load step, `--augment` augmentations; the contact forces of
    #    every Newton iterate are recorded (nodal forces of the full ring: the centre point is on the
    #    symmetry axis, its quarter-model force is doubled).
    summaries, forces = {}, {}
    for method, (label, law) in METHODS.items():
        setup = build("ring", law=law(), n_theta=args.n_theta, n_r=args.n_r, **scene_arguments(args, scene))
        contact = setup.contacts[0]
        history = []  # (solve, iterate, forces sorted from the centre outward)

        def on_iterate(it, contact=contact, history=history):
            x, f = contact.point_forces()
            x, f = (np.concatenate(a) for a in zip(*comm.allgather((x, f))))
            order = np.argsort(np.arctan2(x[:, 1] - args.R_out, x[:, 0]))
            f = f[order] * np.where(np.abs(x[order, 0]) < 1e-9, 2.0, 1.0)
            solve = sum(1 for h in history if h[1] == 0) - (0 if it == 0 else 1)
            history.append((solve, it, f))

        folder = out if method == "cross" else out / method
        try:
            summaries[method] = run(setup, folder, method, {**cli.method_parameters(args), "label": label},
                                    args.augment, args.augment_tol, args.quiet, options=OPTIONS, max_cutbacks=0,
                                    on_iterate=on_iterate, keep=(history,), xdmf=not args.no_xdmf,
                                    restart=args.restart, overwrite=args.overwrite, args=args)
        except ConvergenceError as exc:
            summaries[method] = {**json.load(open(folder / "summary.json")), "exception": str(exc)}
        forces[method] = history

    # The first step alone (identical for the three laws: F^ = 0, lam = 0): penetrations against the paper's.
    first = build("ring", law=Penalty(args.K), n_theta=args.n_theta, n_r=args.n_r, **scene_arguments(args, scene))
    with Solver(first.problem, quiet=True, options=OPTIONS) as solver:
        solver.run(first.loads)
    first_step = {**first.figures(), "paper_penetration_centre": ring.PAPER_PENETRATION[0],
                  "paper_penetration_neighbour": ring.PAPER_PENETRATION[1]}
    if comm.rank == 0:
        cli.say("first step:", {k: round(v, 8) for k, v in first_step.items()})
        (out / "first_step.json").write_text(json.dumps(first_step, indent=1))
    # The check: the first step's centre penetration against the paper's (two digits; 6 % off on this mesh)
    summary = {**summaries["cross"], "check": reference_check("penetration_centre (first step)",
                                                     first_step["penetration_centre"], ring.PAPER_PENETRATION[0],
                                                     TOLERANCE, "Zavarise et al. 1998, 0.19e-3 (two digits)")}
    write_summary(out / "summary.json", {k: v for k, v in summary.items() if k != "exception"}, comm)
    log_check(summary["check"], comm)

    # 3. The forces of the active points (closed at some iterate) after the first augmentation, printed and plotted.
    rows = []
    for method, history in forces.items():
        after = [(it, f) for s, it, f in history if s == 1]
        active = np.flatnonzero(np.max([f for _, f in after], axis=0) > 0) if after else []
        for it, f in after:
            rows.append({"method": method, "iteration": it, **{f"point_{i + 1}": f"{f[i]:.6g}" for i in active}})
    if comm.rank == 0:
        keys = sorted({k for r in rows for k in r if k.startswith("point_")}, key=lambda k: int(k.split("_")[1]))
        cli.say(tables.write_table(rows, out / "ring_forces", ["method", "iteration", *keys]))

    # 4. The comparison table (one row per method; merged with the other demos' under --out's parent).
    if comm.rank == 0:
        cli.say(tables.write_table([tables.method_row(summaries[m], METHODS[m][0]) for m in METHODS], out / "methods",
                                 tables.METHOD_COLUMNS))
        tables.merge_method_tables(out.parent)
        for m, s in summaries.items():
            first = s["steps"][0]["residuals"][0] if s["steps"] else []
            cli.say(f"{m:8s} first solve: {len(first) - 1} iterations, |r| {first[-1]:.2e}; "
                    f"failure: {s.get('failure')}")

    # 5. Pictures: forces against the iteration after the first augmentation; the deformed ring (cross).
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_deformed

        if comm.rank == 0:
            from matplotlib.backends.backend_agg import FigureCanvasAgg
            from matplotlib.figure import Figure

            fig = Figure(figsize=(10, 4.2))
            FigureCanvasAgg(fig)
            for k, method in enumerate(("penalty", "cross")):
                ax = fig.add_subplot(1, 2, k + 1)
                after = [(it, f) for s, it, f in forces[method] if s == 1]
                if after:
                    its = [it for it, _ in after]
                    F = np.array([f for _, f in after])
                    for i in np.flatnonzero(F.max(axis=0) > 0):
                        ax.plot(its, F[:, i], "o-", ms=3, label="centre" if i == 0 else f"neighbour {i}")
                ax.set(xlabel="Newton iteration after the first augmentation", ylabel="nodal contact force",
                       title=METHODS[method][0], yscale="symlog" if method == "penalty" else "linear")
                ax.grid(alpha=0.3)
                ax.legend()
            fig.tight_layout()
            fig.savefig(str(out / "ring_forces.png"), dpi=150)
        setup = build("ring", law=CrossConstraints(args.K, 0.0), n_theta=args.n_theta, n_r=args.n_r,
                      **scene_arguments(args, scene))
        with Solver(setup.problem, augment_max=args.augment, quiet=True, options=OPTIONS) as solver:
            solver.run(setup.loads)
        u = setup.problem.u
        syy = interpolate_expression(fem.Function(function_space(u.function_space.mesh, "Lagrange", 1),
                                                  name="sigma_yy"), setup.problem.material.stress(u)[1, 1])
        plot_deformed(u, syy, out / "ring_deformed.png", title="ring quarter, cross-constraints (displacement x1)")
    return summary


if __name__ == "__main__":
    cli.main(main)
