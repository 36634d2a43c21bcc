"""Elastic cylinder on a rigid plane, against Hertz (plane strain, linear elasticity).

    python demos/hertz.py --method auglag
    mpirun -n 2 python demos/hertz.py --method cross --refinement 1 -fc_snes_monitor
    python demos/hertz.py --load 0.36 --method auglag          # force control: the disk held by contact alone
    python demos/hertz.py --model neohookean-mixed --nu 0.4999 --quadrature simpson --method auglag  # rubber
    python demos/hertz.py --plate meshed --E 200 --nu 0.3 --R 8 --load 10 --plate-E 200 \
        --method lagrange    # two identical bodies (E* = E / (2 (1 - nu^2))); the plate 10 a wide and deep

Quarter of a disk (R = 1, E = 1000, nu = 0.3) pressed on the plane y = 0;
p0 and a are compared with Hertz for the computed load. Writes hertz.xdmf,
summary.json, hertz_deformed.png and hertz_pressure.png to --out.
"""
from pathlib import Path

import numpy as np
import ufl
from dolfinx import fem

from fenics_contact import function_space, interpolate_expression
from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import hertz_range, reference_check
from fenics_contact.app.scenes import add_scene_options, hertz, scene_arguments

TOLERANCE = 2e-2  # p0 of the nodal maximum on the default mesh (README: within 0.32 % with cross); a (mixed model)


def main(argv=None) -> dict:
    # 1. Options: formulation, parameters, mesh refinement, load steps.
    p = cli.parser(__doc__.splitlines()[0], default_K=lambda a: hertz.default_K(a.E, a.R, a.method, a.plate),
                   quadratures=("nodal", "gauss", "simpson", "segment"))  # segment: the meshed plate
    p.add_argument("--refinement", type=cli.LEVEL, default=0, help="halve the contact mesh size this many times")
    p.add_argument("--steps", type=cli.COUNT, default=2, help="load steps")
    cli.model_option(p, mixed=True)
    p.add_argument("--symmetry", choices=["quarter", "half", "full"], default="quarter",
                   help="modelled part of the disk")
    p.add_argument("--plate", choices=["rigid", "meshed"], default="rigid",
                   help="lower plate: analytic rigid, or meshed (its E: --plate-E; two-body contact; quarter only)")
    p.add_argument("--plane", choices=["strain", "stress"], default="strain",
                   help="2D assumption (Hertz's E* follows)")
    # --R, --E, --nu, --approach, --load (force control: total force per unit length), --plate-E, --plate-nu, ...
    scene = add_scene_options(p, hertz.build)
    p.set_defaults(augment_tol=1e-10)
    args = cli.parse(p, argv)
    out = Path(args.out or "results/hertz")
    # Refused combinations: one line, before any work.
    cli.refuse_unsupported(args, kind="two-body" if args.plate == "meshed" else "rigid", dim=2,
                           degree=cli.model_degree(args.model),
                           model=args.model)

    # 2. The scene: graded quarter-disk mesh, symmetry, prescribed approach, rigid plane.
    setup = build("hertz", law=cli.law_from_args(args), quadrature=args.quadrature, refinement=args.refinement,
                  steps=args.steps, model=args.model, symmetry=args.symmetry, plate=args.plate,
                  plane=args.plane, **scene_arguments(args, scene))

    # The check: p0, or with the mixed model's P2 displacement the half-width a (P2 contact pressures overshoot at
    # the vertices by O(h): p0 2.9 % high at the default mesh, 1.6 % at --refinement 1, nu = 0.4999 or 0.3 alike)
    figure = "a" if cli.model_degree(args.model) == 2 else "p0"

    # 3. Solve with load stepping (and augmentations), write XDMF and summary.json.
    summary = run(setup, out, args.method, {**cli.method_parameters(args), "steps": args.steps},
                  args.augment, args.augment_tol, args.quiet, options=cli.solver_options(args), xdmf=not args.no_xdmf,
                  restart=args.restart, overwrite=args.overwrite, args=args,
                  check=lambda s: reference_check(figure, s.get(figure), s.get(f"{figure}_hertz"), TOLERANCE,
                                                  f"Hertz {figure} for the computed load",
                                                  hertz_range(s.get("a_hertz"), setup.parameters["R"])))

    # 4. Pictures: von Mises stress on the deformed quarter disk; pressure against Hertz.
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_deformed, plot_profile

        u = setup.displacement
        s = setup.problem.material.stress(u)
        dev = s - ufl.tr(s) / 2 * ufl.Identity(2)
        mises = interpolate_expression(fem.Function(function_space(u.function_space.mesh, "Lagrange", 1),
                                                    name="von_Mises_stress_2D"),
                                       (3.0 / 2.0 * (dev[0, 0] ** 2 + dev[1, 1] ** 2 + 2 * dev[0, 1] ** 2)) ** 0.5)
        plot_deformed(u, mises, out / "hertz_deformed.png", title=f"hertz, {args.method} (displacement x50)", scale=50)
        x, g, pr = setup.contacts[0].surface_values()
        if setup.problem.comm.rank == 0:
            a, p0 = summary["a_hertz"], summary["p0_hertz"]
            xr = np.linspace(0, a, 200)
            keep = np.abs(x[:, 0]) <= 2.5 * a
            plot_profile(x[keep, 0], pr[keep], out / "hertz_pressure.png", x_ref=xr,
                         p_ref=p0 * np.sqrt(1 - (xr / a) ** 2),
                         xlabel="x (distance from the contact centre)", labels=(args.method, "Hertz"),
                         title=f"hertz: p0 {summary['p0']:.4g} (Hertz {p0:.4g}), a {summary['a']:.4g} (Hertz {a:.4g})")
    return summary


if __name__ == "__main__":
    cli.main(main)
