"""Elastic sphere on a rigid plane, or two elastic spheres, axisymmetric, against 3D Hertz.

    python demos/axisphere.py --method auglag
    python demos/axisphere.py --partner sphere --R2 2 --E2 1000          # two elastic spheres (two-body contact)
    mpirun -n 2 python demos/axisphere.py --method penalty --h-contact 0.005

The meridian section (r, z) of the sphere (R = 1, E = 1000, nu = 0.3) below its equator, every integral over the
whole ring (2 pi r); p0 and a against Hertz for the computed load (check: p0 and a within 1 %). Writes
axisphere.xdmf, summary.json and axisphere_pressure.png to --out.
"""
from pathlib import Path

import numpy as np

from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, axisphere, scene_arguments

# p0 and a within 1 % of Hertz on the default mesh (h = a / 28): measured 0.42 % / 0.20 % (plane), 0.39 % /
# 0.71 % (two spheres), auglag, nodal
TOLERANCE = 1e-2


def main(argv=None) -> dict:
    # 1. Options: formulation, partner (rigid plane or a second sphere), the sphere(s) and the mesh.
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(axisphere.DEFAULT_K, axisphere.build))
    p.add_argument("--partner", choices=list(axisphere.PARTNERS), default="plane",
                   help="what the sphere is pressed on: the rigid plane, or a second elastic sphere (two-body)")
    p.add_argument("--steps", type=cli.COUNT, default=1, help="load steps")
    p.add_argument("--model", choices=["linear", "neohookean"], default="linear", help="bulk material")
    p.add_argument("--degree", type=int, choices=(1, 2), default=1, help="degree of the displacement")
    scene = add_scene_options(p, axisphere.build)  # --R, --E, --nu, --approach, --R2, ..., --h-contact
    p.set_defaults(augment_tol=1e-10)
    args = cli.parse(p, argv)
    out = Path(args.out or "results/axisphere")
    # refused combinations: one line, before any work
    cli.refuse_unsupported(args, kind="two-body" if args.partner == "sphere" else "rigid", dim=2,
                           degree=args.degree, model=args.model, geometry="axisymmetric")

    # 2. The scene: graded meridian section(s), u_r = 0 on the axis, the equator moved down.
    setup = build("axisphere", law=cli.law_from_args(args), quadrature=args.quadrature, steps=args.steps,
                  model=args.model, partner=args.partner, degree=args.degree, **scene_arguments(args, scene))

    # 3. Solve, write XDMF and summary.json; the check: p0 and a against Hertz for the computed load (the one
    # farther from it, relative to the tolerance, is recorded).
    def check(s: dict) -> dict:
        checks = [reference_check("p0", s.get("p0"), s.get("p0_hertz"), TOLERANCE,
                                  "Hertz p0 = 3P/(2 pi a^2) for the computed load"),
                  reference_check("a", s.get("a"), s.get("a_hertz"), TOLERANCE,
                                  "Hertz a = (3 P R*/(4 E*))^(1/3) for the computed load")]
        failed = [c for c in checks if not c["passed"]]
        return failed[0] if failed else max(checks, key=lambda c: c["rel_error"])

    summary = run(setup, out, args.method, {**cli.method_parameters(args), "steps": args.steps},
                  args.augment, args.augment_tol, args.quiet, options=cli.solver_options(args), xdmf=not args.no_xdmf,
                  restart=args.restart, overwrite=args.overwrite, args=args, check=check)

    # 4. Picture: contact pressure against r, with Hertz.
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_profile

        c = setup.contacts[0]
        x, _, pr = c.point_values(reference=True) if args.partner == "sphere" else c.surface_values()
        if setup.problem.comm.rank == 0:
            a, p0 = summary["a_hertz"], summary["p0_hertz"]
            keep = x[:, 0] <= 2 * a
            order = np.argsort(x[keep, 0])
            rr = np.linspace(0, a, 200)
            plot_profile(x[keep, 0][order], pr[keep][order], out / "axisphere_pressure.png", x_ref=rr,
                         p_ref=p0 * np.sqrt(1 - (rr / a) ** 2), xlabel="r", labels=(args.method, "Hertz"),
                         title=f"axisphere ({args.partner}): p0 {summary['p0']:.4g} (Hertz {p0:.4g}), "
                               f"a {summary['a']:.4g} (Hertz {a:.4g})")
    return summary


if __name__ == "__main__":
    cli.main(main)
