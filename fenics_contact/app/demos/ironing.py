"""Ironing: a stiff punch pressed into a soft neo-Hookean block and dragged along it with Coulomb friction (2D).

    python demos/ironing.py
    mpirun -n 2 python demos/ironing.py --drag 1.5 --steps 35

Block 1 high (neo-Hookean E = 1000, nu = 0.3, plane strain, base clamped); punch 100 times stiffer with a flat
face (width 1) and round corners (radius 0.5), pressed 0.1 into the block, then dragged 3 along it (70 steps:
0.86 of the block's node spacing each, so that the steps sample every position of the punch between two nodes).
Node-to-segment Coulomb friction (mu = 0.3, penalty K = 5e4, omega_t = 1e4), the block's top the slave. The
tangential over normal force on the punch (the punch's frame) against mu over the second half of the drag.
Writes ironing.xdmf, summary.json (with the per-step history: forces, ratio, Newton iterations) and
ironing_forces.png (the forces on the punch and their ratio against the drag).
"""
from pathlib import Path

import numpy as np

from fenics_contact import write_summary
from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, ironing, scene_arguments

TOLERANCE = 0.02  # the steady-sliding ratio within 2 % of mu (every step of the window)


def main(argv=None) -> dict:
    # 1. Options: Coulomb friction mu = 0.3 on a penalty normal law unless told otherwise.
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(ironing.DEFAULT_K, ironing.build, length="H"),
                   default_omega_t=cli.scene_scaled(ironing.DEFAULT_OMEGA_T, ironing.build, length="H"),
                   quadratures=("nodal", "gauss"))
    p.add_argument("--steps", type=cli.COUNT, default=70, help="load steps of the drag")
    p.add_argument("--press-steps", type=cli.COUNT, default=4, help="load steps of the pressing")
    p.set_defaults(method="penalty", mu=0.3)
    scene = add_scene_options(p, ironing.build)  # --E, --nu, --stiffness, --depth, --drag, --h, ...
    args = cli.parse(p, argv)
    if args.c_t is not None or args.tresca is not None or args.mu <= 0:
        raise ValueError(f"--mu: ironing needs Coulomb friction with mu > 0 (no --c-t, --tresca), got mu={args.mu}")
    out = Path(args.out or "results/ironing")
    cli.refuse_unsupported(args, kind="two-body", dim=2, degree=1, model="neohookean")

    # 2. The scene: block and punch in one mesh, the punch's top pressed down, then dragged along +x.
    setup = build("ironing", law=cli.law_from_args(args), drag_steps=args.steps, press_steps=args.press_steps,
                  quadrature=args.quadrature, **scene_arguments(args, scene))

    # 3. Solve step by step (history on accepted steps), write XDMF and summary.json.
    def figures_check(s: dict) -> dict:
        return reference_check("ratio_worst", s.get("ratio_worst"), s["parameters"]["mu"], TOLERANCE,
                     "Coulomb in steady sliding: tangential / normal force on the punch (punch's frame), the window "
                     "step farthest from mu")

    summary = run(setup, out, args.method, cli.method_parameters(args), args.augment, args.augment_tol, args.quiet,
                  options=cli.solver_options(args), xdmf=not args.no_xdmf,
                  restart=args.restart, overwrite=args.overwrite, args=args, check=figures_check,
                  predictor=ironing.PREDICTOR)
    iterations = [s["newton_iterations"] for s in summary["steps"] if s["converged"]]
    summary.update({"history": setup.history(), "newton_per_step": iterations,
                    "max_newton_per_step": max(iterations) if iterations else None})
    write_summary(out / "summary.json", summary, setup.problem.comm)

    # 4. Picture: the forces on the punch and their ratio against the drag.
    if not args.no_pictures and setup.problem.comm.rank == 0:
        plot_history(summary, out / "ironing_forces.png")
    return summary


def plot_history(summary: dict, path: Path) -> None:
    """Two panels against the punch's travel: -F_t and F_n on the punch (its frame), and -F_t / F_n with mu +- 2 %."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    rows = [r for r in summary["history"] if r["load"] > 1.0]
    x = np.array([r["travel"] for r in rows])
    mu = summary["parameters"]["mu"]
    fig = Figure(figsize=(7.0, 6.4))
    FigureCanvasAgg(fig)
    ax1, ax2 = fig.subplots(2, 1, sharex=True)
    ax1.plot(x, [-r["Ft"] for r in rows], "o-", ms=2, lw=1, label="horizontal (tangential) -F_t")
    ax1.plot(x, [r["Fn"] for r in rows], "s-", ms=2, lw=1, label="vertical (normal) F_n")
    ax1.set(ylabel="force on the punch (per unit thickness)", title=f"ironing: mu = {mu:g}, window mean "
            f"{summary.get('ratio_mean', float('nan')):.5f}, peak to peak {summary.get('ratio_peak_to_peak', 0):.1e}")
    ax1.legend()
    ax1.grid(alpha=0.3)
    ax2.plot(x, [r["ratio"] for r in rows], "o-", ms=2, lw=1, label="-F_t / F_n (punch's frame)")
    ax2.plot(x, [r["ratio_global"] for r in rows], "--", lw=1, label="-F_x / F_y")
    ax2.axhline(mu, color="k", lw=0.8, label="mu")
    ax2.axhspan(0.98 * mu, 1.02 * mu, color="0.85", label="mu +- 2 %")
    ax2.axvline(summary.get("window_from", x[-1]), color="0.5", ls=":", label="steady window")
    ax2.set(xlabel="drag (punch travel)", ylabel="force ratio", ylim=(0.94 * mu, 1.06 * mu))
    ax2.legend(fontsize=8)
    ax2.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


if __name__ == "__main__":
    cli.main(main)
