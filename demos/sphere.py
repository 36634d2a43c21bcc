"""Elastic sphere on a rigid plane, against 3D Hertz (linear elasticity); the scaling scene.

    python demos/sphere.py --method penalty --level 0
    mpirun -n 2 python demos/sphere.py --method penalty --level 2 --solver iterative

Octant of a ball (R = 1, E = 1000, nu = 0.3) pressed on the plane z = 0; p0
and a are compared with Hertz for the computed load. Writes sphere.xdmf,
summary.json and sphere_pressure.png to --out.
"""
from pathlib import Path

import numpy as np

from fenics_contact import build, cli, run
from fenics_contact.scenes import sphere

# 1. Options: formulation, mesh level (about 1e4 to 1e6 dofs), linear solver.
p = cli.parser(__doc__.splitlines()[0], default_K=sphere.DEFAULT_K)
p.add_argument("--level", type=int, default=0, choices=range(len(sphere.LEVELS)), help="mesh level")
p.add_argument("--steps", type=int, default=1, help="load steps")
p.set_defaults(augment_tol=1e-10)
args = cli.parse(p)
cli.check(args, kind="rigid", dim=3, degree=1, model="linear")  # refused combinations: one line, before any work
out = Path(args.out or "results/sphere")

# 2. The scene: graded octant mesh, three symmetry planes, prescribed approach, rigid plane.
setup = build("sphere", law=cli.law_from_args(args), quadrature=args.quadrature, level=args.level, steps=args.steps)

# 3. Solve, write XDMF and summary.json.
summary = run(setup, out, args.method, {**cli.method_parameters(args), "steps": args.steps},
              args.augment, args.augment_tol, args.quiet, options=cli.solver_options(args), xdmf=not args.no_xdmf)

# 4. Picture: contact pressure against the distance from the axis, with Hertz.
if not args.no_pictures:
    from fenics_contact.plotting import plot_profile

    x, g, pr = setup.contacts[0].surface_values()
    if setup.problem.comm.rank == 0:
        a, p0 = summary["a_hertz"], summary["p0_hertz"]
        r = np.hypot(x[:, 0], x[:, 1])
        keep = r <= 2 * a
        order = np.argsort(r[keep])
        rr = np.linspace(0, a, 200)
        plot_profile(r[keep][order], pr[keep][order], out / "sphere_pressure.png", x_ref=rr,
                     p_ref=p0 * np.sqrt(1 - (rr / a) ** 2), xlabel="r (distance from the axis)",
                     labels=(args.method, "Hertz"),
                     title=f"sphere: p0 {summary['p0']:.4g} (Hertz {p0:.4g}), a {summary['a']:.4g} (Hertz {a:.4g})")
