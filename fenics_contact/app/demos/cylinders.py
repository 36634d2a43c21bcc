"""Two neo-Hookean cylinders pressed together between rigid plates (Papadopoulos & Solberg 1998, 4.1).

    python demos/cylinders.py
    mpirun -n 2 python demos/cylinders.py --t-end 15 --out results/cylinders

Cylinders R = 18 (lower) and R = 8 (upper), lambda = 288, mu = 192, plane strain; the upper plate moves
down by t. Right halves (symmetry x = 0). Two-body contact between the cylinders (two-pass: each
surface slave once), rigid plates as analytic obstacles. Writes cylinders.xdmf, summary.json,
figures_per_step.csv, pressure_t<t>.csv (both surfaces), cylinders_hertz.png (pressure at the Hertz
load against Hertz) and cylinders_pressure.png (t = 5, 10, 15 as the paper's Figure 4) to --out.
"""
import csv
import json
from pathlib import Path

import numpy as np

from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import hertz_range, reference_check
from fenics_contact.app.scenes import add_scene_options, cylinders, scene_arguments
from fenics_contact.twobody import QUADRATURES

# p0 at the Hertz step: 2.0 % from Hertz at h_contact = 0.05 (README, two deformable bodies; Hertz assumes
# half-spaces, here a/R = 0.07 on cylinders between plates)
TOLERANCE = 3e-2


def main(argv=None) -> dict:
    # 1. Options: penalty two-pass with Gauss points by default (see the scene's docstring for why).
    K = cli.scene_scaled(cylinders.DEFAULT_K, cylinders.build, length="R_upper", E0=cylinders.reference_E())
    p = cli.parser(__doc__.splitlines()[0], default_K=K, quadratures=QUADRATURES)
    p.set_defaults(method="penalty", quadrature="gauss")
    p.add_argument("--passes", choices=["one", "two"], default="two", help="one-pass or two-pass two-body contact")
    p.add_argument("--h-contact", type=cli.POSITIVE, default=0.05, help="mesh size at the contacts (length)")
    p.add_argument("--grading", type=cli.POSITIVE, default=0.04,
                   help="mesh size growth per unit distance from the contacts")
    p.add_argument("--t-end", type=cli.POSITIVE, default=cylinders.T_END, help="final plate motion (length)")
    p.add_argument("--dt", type=cli.POSITIVE, default=0.5,
                   help="plate motion per load step after the Hertz step (length)")
    cli.model_option(p, "neohookean", help="bulk material (linear: small t only, the model-reduction check)")
    p.add_argument("--symmetry", choices=["half", "full"], default="half", help="right halves (x >= 0) or whole disks")
    # --R-lower, --R-upper, --E, --nu, --h-far, --contact-width
    scene = add_scene_options(p, cylinders.build, shared=("h_contact", "grading"))
    args = cli.parse(p, argv)
    out = Path(args.out or "results/cylinders")

    # 2. The scene: one mesh with both half cylinders, plates, two-body pair; loads t_hertz, then steps of dt.
    loads = [cylinders.T_HERTZ] + np.arange(args.dt, args.t_end + 1e-9, args.dt).tolist()
    setup = build("cylinders", law_factory=lambda: cli.law_from_args(args), quadrature=args.quadrature,
                  passes=args.passes, h_contact=args.h_contact, grading=args.grading,
                  loads=[t for t in loads if t <= args.t_end + 1e-9], model=args.model, symmetry=args.symmetry,
                  **scene_arguments(args, scene))
    comm = setup.problem.comm

    # 3. Solve with load stepping; after each step keep the figures and both surfaces' pressure profiles.
    history, profiles = [], {}


    def after_step(t: float) -> None:
        history.append({"t": t, **{k: v for k, v in setup.figures().items() if not isinstance(v, list)}})
        profiles[t] = setup.profiles()


    summary = run(setup, out, args.method, {**cli.method_parameters(args), "passes": args.passes},
                  args.augment, args.augment_tol, args.quiet, on_step=after_step, keep=(history, profiles),
                  check=lambda s: reference_check("p0 (Hertz step)", history[0]["p0"] if history else None,
                                        history[0]["p0_hertz"] if history else None, TOLERANCE,
                                        f"Hertz for two cylinders at t = {cylinders.T_HERTZ:g}",
                                        hertz_range(history[0]["a_hertz"] if history else None,
                                                    min(setup.parameters["R_lower"], setup.parameters["R_upper"]))),
                  xdmf=not args.no_xdmf, restart=args.restart, overwrite=args.overwrite, args=args)

    # 4. Tables and pictures (rank 0; every figure is already reduced over ranks).
    if comm.rank == 0:
        keys = list(history[0])
        with open(out / "figures_per_step.csv", "w", newline="") as fh:
            w = csv.DictWriter(fh, fieldnames=keys + ["newton_iterations"])
            w.writeheader()
            for h, step in zip(history, [s for s in summary["steps"] if s["converged"]]):
                w.writerow({**h, "newton_iterations": step["newton_iterations"]})
        for t, prof in profiles.items():
            with open(out / f"pressure_t{t:g}.csv", "w", newline="") as fh:
                w = csv.writer(fh)
                w.writerow(["surface", "x", "pressure"])
                for name, (x, pr) in zip(("upper_on_lower", "lower_on_upper"), prof):
                    w.writerows([name, xi, pi] for xi, pi in zip(x, pr))
        with open(out / "figures_per_step.json", "w") as fh:
            json.dump(history, fh, indent=1)
        if not args.no_pictures:
            from fenics_contact.app.plotting import plot_curves

            h0 = history[0]
            a, p0 = h0["a_hertz"], h0["p0_hertz"]
            xr = np.linspace(0, a, 200)
            (x1, p1), *rest = profiles[h0["t"]]
            curves = [(xr, p0 * np.sqrt(1 - (xr / a) ** 2), "Hertz", "k-"), (x1, p1, "upper cylinder (slave)", "o-")]
            curves += [(x2, p2, "lower cylinder (slave)", "s--") for x2, p2 in rest]
            plot_curves([(x[x <= 2 * a], y[x <= 2 * a], lab, st) if lab != "Hertz" else (x, y, lab, st)
                         for x, y, lab, st in curves], out / "cylinders_hertz.png", xlabel="x",
                        title=f"cylinders, t = {h0['t']:g}: p0 {h0['p0']:.4g} (Hertz {p0:.4g}), "
                              f"a {h0['a']:.3g} (Hertz {a:.3g})")
            shown = [t for t in (5.0, 10.0, 15.0) if t in profiles]
            if shown:
                curves = []
                for t in shown:
                    for (x, pr), st, side in zip(profiles[t], ("-", "--"), ("upper", "lower")):
                        curves.append((x[x <= 12], pr[x <= 12], f"t = {t:g}, {side} surface", st))
                plot_curves(curves, out / "cylinders_pressure.png", xlabel="x (current)",
                            title="cylinders: pressure on both surfaces")
    return summary


if __name__ == "__main__":
    cli.main(main)
