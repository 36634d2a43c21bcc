"""A block pushed up an elastic incline (wedge) with Coulomb friction between the two bodies (2D).

    python demos/wedges.py
    mpirun -n 2 python demos/wedges.py --alpha 10 --mu 0.5

Incline of angle alpha (default 20 deg) and block, both E = 1000, nu = 0.3 (plane strain); node-to-segment
Coulomb friction (penalty K = 1e6, omega_t = 1e4, mu = 0.3). The block carries the vertical force N, then its left
face is pushed horizontally until the whole interface slides: H / N against (mu + tan alpha) / (1 - mu tan alpha).
Writes wedges.xdmf, summary.json and wedges_traction.png (pressure and friction traction along the interface).
"""
from pathlib import Path

import numpy as np

from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, scene_arguments, wedges

TOLERANCE = 0.01  # the force ratio against its closed form


def main(argv=None) -> dict:
    # 1. Options: Coulomb friction mu = 0.3 on a penalty normal law unless told otherwise.
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(wedges.DEFAULT_K, wedges.build, length="length"),
                   default_omega_t=cli.scene_scaled(wedges.DEFAULT_OMEGA_T, wedges.build, length="length"),
                   quadratures=("nodal",))
    p.add_argument("--slide-steps", type=cli.COUNT, default=wedges.SLIDE_STEPS, help="load steps of the push")
    p.set_defaults(method="penalty", mu=0.3)
    scene = add_scene_options(p, wedges.build)  # --alpha, --E, --nu, --load, --push
    args = cli.parse(p, argv)
    if args.c_t is not None or args.mu <= 0:
        raise ValueError(f"--mu: wedges needs Coulomb friction with mu > 0 (no --c-t), got mu={args.mu}")
    out = Path(args.out or "results/wedges")
    cli.refuse_unsupported(args, kind="two-body", dim=2, degree=1, model="linear")

    # 2. The scene: incline and block in one mesh, vertical force, then a horizontal push.
    setup = build("wedges", law=cli.law_from_args(args), slide_steps=args.slide_steps,
                  **scene_arguments(args, scene))

    # 3. Solve step by step (history on accepted steps), write XDMF and summary.json.
    summary = run(setup, out, args.method, cli.method_parameters(args), args.augment, args.augment_tol, args.quiet,
                  options=cli.solver_options(args), xdmf=not args.no_xdmf, predictor=wedges.PREDICTOR,
                  restart=args.restart, overwrite=args.overwrite, args=args,
                  check=lambda s: reference_check("ratio", s.get("ratio"), s.get("ratio_reference"), TOLERANCE,
                                        "(mu + tan alpha) / (1 - mu tan alpha)"))

    # 4. Picture: pressure and friction traction along the interface (slave side, the block's bottom).
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_curves

        prof = setup.contacts[0].friction_profile()
        if setup.problem.comm.rank == 0:
            x = prof["x"]
            s = np.hypot(x[:, 0], x[:, 1]) * np.sign(x[:, 0])  # position along the incline
            mu = summary["parameters"]["mu"]
            plot_curves([(s, prof["pressure"], "pressure p", "o"), (s, np.abs(prof["traction"]), "|q|", "s"),
                         (s, mu * prof["pressure"], "mu p", "k-")], out / "wedges_traction.png",
                        xlabel="position along the incline", ylabel="traction",
                        title=f"wedges: H/N = {summary.get('ratio', float('nan')):.5g}, formula "
                              f"{summary['ratio_reference']:.5g}")
    return summary


if __name__ == "__main__":
    cli.main(main)
