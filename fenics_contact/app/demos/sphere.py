"""Elastic sphere on a rigid plane, against 3D Hertz (linear elasticity); the scaling scene.

    python demos/sphere.py --method penalty --level 0
    mpirun -n 2 python demos/sphere.py --method penalty --level 2 --solver iterative
    python demos/sphere.py --plate meshed --solver iterative      # on a deformable block (two-body contact)
    python demos/sphere.py --geometry axisymmetric                # the same sphere on its meridian section (r, z)

Octant of a ball (R = 1, E = 1000, nu = 0.3) pressed on the plane z = 0; p0
and a are compared with Hertz for the computed load (check: p0 within 5 %). Writes sphere.xdmf,
summary.json and sphere_pressure.png to --out. ``--geometry axisymmetric`` solves the same sphere (R, E, nu,
approach, contact width, the level's mesh size at the contact) as the ``axisphere`` scene: the model-reduction
table's reduced model (rigid plane, displacement control).
"""
from pathlib import Path

import numpy as np

from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import hertz_range, reference_check
from fenics_contact.app.scenes import add_scene_options, scene_arguments, sphere

# p0 is the nodal maximum on a mesh of h = a/7 at level 0: within 5 % (tests/test_sphere.py); 2.6 % at level 0
# with penalty, 1.6 % on --size 1.0
TOLERANCE = 5e-2


def main(argv=None) -> dict:
    # 1. Options: formulation, mesh level (about 1e4 to 1e6 dofs), linear solver.
    # default K: the scene's, scaled with E / R; on the meshed block E* / h_contact (it follows the mesh)
    p = cli.parser(__doc__.splitlines()[0], default_K=lambda a: sphere.default_K(
        a.E, a.R, a.nu, a.plate, a.level, a.size, a.plate_E, a.plate_nu))
    p.add_argument("--level", type=int, default=0, choices=range(len(sphere.LEVELS)),
                   help="mesh level: 0 to 3, about 1e4 to 1e6 dofs")
    p.add_argument("--steps", type=cli.COUNT, default=None, help="load steps (default: 1, or 2 with --load)")
    cli.model_option(p)
    p.add_argument("--plate", choices=["rigid", "meshed"], default="rigid",
                   help="the plane: rigid, or a meshed block of the sphere's material (two-body contact)")
    p.add_argument("--size", type=cli.POSITIVE, default=None,
                   help="mesh-size factor instead of the level's (level 0: 0.5; 1.0 is a tiny mesh, ~2800 dofs; "
                        "default: the --level's)")
    p.add_argument("--geometry", choices=["3d", "axisymmetric"], default="3d",
                   help="3d: the octant; axisymmetric: the meridian section (r, z) with the same mesh size at the "
                        "contact (scene axisphere; rigid plate, displacement control)")
    # --R, --E, --nu, --approach, --load (force control), ...
    scene = add_scene_options(p, sphere.build, shared=("size",))
    p.set_defaults(augment_tol=1e-10)
    args = cli.parse(p, argv)
    if args.steps is None:
        args.steps = 1 if args.load is None else 2
    out = Path(args.out or "results/sphere")
    # refused combinations: one line, before any work
    axisymmetric = args.geometry == "axisymmetric"
    if axisymmetric and (args.plate != "rigid" or args.load is not None):
        raise ValueError("--geometry axisymmetric takes the rigid plate and displacement control (--approach); "
                         "two spheres: demos/axisphere.py --partner sphere")
    cli.refuse_unsupported(args, kind="two-body" if args.plate == "meshed" else "rigid", dim=2 if axisymmetric else 3,
                           degree=1, model=args.model, geometry="axisymmetric" if axisymmetric else "cartesian")

    # 2. The scene: graded octant mesh, three symmetry planes, prescribed approach, rigid plane (or its meridian
    # section with the same mesh size at the contact).
    law = cli.law_from_args(args)
    if axisymmetric:
        h, h_far = sphere.mesh_sizes(sphere.LEVELS[args.level] if args.size is None else args.size, args.R)
        setup = build("axisphere", law=law, quadrature=args.quadrature, steps=args.steps, model=args.model,
                      R=args.R, E=args.E, nu=args.nu, approach=args.approach, contact_width=args.contact_width,
                      h_contact=h, h_far=h_far)  # the same defaults: approach 0.005 R, contact width 0.15 R
    else:
        setup = build("sphere", law=law, quadrature=args.quadrature, level=args.level, steps=args.steps,
                      size=args.size, model=args.model, plate=args.plate, **scene_arguments(args, scene))

    # 3. Solve, write XDMF and summary.json.
    summary = run(setup, out, args.method, {**cli.method_parameters(args), "steps": args.steps},
                  args.augment, args.augment_tol, args.quiet, options=cli.solver_options(args), xdmf=not args.no_xdmf,
                  restart=args.restart, overwrite=args.overwrite, args=args,
                  check=lambda s: reference_check("p0", s.get("p0"), s.get("p0_hertz"), TOLERANCE,
                                        "Hertz p0 = 3P/(2 pi a^2) for the computed load",
                                        hertz_range(s.get("a_hertz"), setup.parameters["R"])))

    # 4. Picture: contact pressure against the distance from the axis, with Hertz.
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_profile

        c = setup.contacts[0]
        x, g, pr = c.point_values(reference=True) if args.plate == "meshed" else c.surface_values()
        if setup.problem.comm.rank == 0:
            a, p0 = summary["a_hertz"], summary["p0_hertz"]
            r = x[:, 0] if axisymmetric else np.hypot(x[:, 0], x[:, 1])
            keep = r <= 2 * a
            order = np.argsort(r[keep])
            rr = np.linspace(0, a, 200)
            plot_profile(r[keep][order], pr[keep][order], out / "sphere_pressure.png", x_ref=rr,
                         p_ref=p0 * np.sqrt(1 - (rr / a) ** 2), xlabel="r (distance from the axis)",
                         labels=(args.method, "Hertz"),
                         title=f"sphere: p0 {summary['p0']:.4g} (Hertz {p0:.4g}), a {summary['a']:.4g} (Hertz {a:.4g})")
    return summary


if __name__ == "__main__":
    cli.main(main)
