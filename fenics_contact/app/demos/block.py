"""Elastic block pressed on a rigid frictionless foundation (Zavarise et al. 1998, block scene).

    python demos/block.py --method cross --F-hat 100
    mpirun -n 2 python demos/block.py --method auglag --out results/block
    python demos/block.py --model neohookean-mixed --nu 0.4999 --quadrature gauss --method auglag --augment 30

Height 2, E = 1000, nu = 0.3, top moved down by 0.32; the exact pressure
is E/(1-nu^2) * 0.32/2 = 175.8243 (plane strain, linear; ``--plane stress``: 160;
``--model neohookean`` or ``neohookean-mixed`` (nearly incompressible rubber, Taylor-Hood P2-P1): the
closed-form homogeneous state, nominal and Cauchy). Writes block.xdmf, summary.json,
block_deformed.png and block_pressure.png to --out. Check: the contact pressure against the exact
(nominal) one, to 1e-8 with an exact method (or converged augmentation), to 1e-2 with a plain
penalty-type law (its penetration p/K).
"""
from pathlib import Path

import numpy as np
from dolfinx import fem

from fenics_contact import function_space, interpolate_expression
from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, block, scene_arguments

EXACT_METHODS = ("vi", "lagrange", "nitsche", "coulomb", "penalty_multiplier")


def main(argv=None) -> dict:
    # 1. Options: the formulation and its parameters (K = 1e5 as in the paper).
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(1e5, block.build, length="height"))
    p.add_argument("--steps", type=cli.COUNT, default=1, help="load steps")
    p.add_argument("--plane", choices=["strain", "stress"], default="strain", help="2D assumption")
    cli.model_option(p, mixed=True)
    scene = add_scene_options(p, block.build)  # --height, --width, --E, --nu, --displacement
    args = cli.parse(p, argv)
    out = Path(args.out or "results/block")
    cli.refuse_unsupported(args, kind="rigid", dim=2, degree=cli.model_degree(args.model), model=args.model)

    # 2. The scene: mesh, material, Dirichlet data, the rigid foundation and the contact law.
    setup = build("block", law=cli.law_from_args(args), quadrature=args.quadrature, steps=args.steps,
                  plane=args.plane, model=args.model, **scene_arguments(args, scene))
    exact = block.homogeneous_state(args.model, args.plane, args.E, args.nu,
                                    args.displacement / args.height)["p_nominal"]

    # 3. Solve (one load step by default, augmentations as asked), write XDMF and summary.json with the check.
    exact_method = args.method in EXACT_METHODS or args.augment > 0
    summary = run(setup, out, args.method, cli.method_parameters(args), args.augment, args.augment_tol, args.quiet,
                  options=cli.solver_options(args), xdmf=not args.no_xdmf,
                  restart=args.restart, overwrite=args.overwrite, args=args,
                  check=lambda s: reference_check("contact_pressure", s.get("contact_pressure"), exact,
                                        1e-8 if exact_method else 1e-2,
                                        f"closed form, homogeneous state ({args.model}, plane {args.plane})"))

    # 4. Pictures: the compressed block coloured by sigma_yy, and the pressure along the base.
    if not args.no_pictures:
        from fenics_contact.app.plotting import plot_deformed, plot_profile

        u = setup.displacement
        syy = interpolate_expression(fem.Function(function_space(u.function_space.mesh, "Lagrange", 1),
                                                  name="sigma_yy"), setup.problem.material.stress(u)[1, 1])
        # The state is uniform: a fixed colour range keeps round-off from looking like a pattern.
        plot_deformed(u, syy, out / "block_deformed.png", title=f"block, {args.method}",
                      clim=(-2 * exact, 0.0))
        x, g, p = setup.contacts[0].surface_values()
        if setup.problem.comm.rank == 0:
            plot_profile(x[:, 0], p, out / "block_pressure.png", x_ref=np.array([0.0, args.width / 2]),
                         p_ref=np.full(2, exact), xlabel="x", labels=(args.method, f"exact {exact:.7g}"),
                         title=f"block: contact pressure, {args.method}")
    return summary


if __name__ == "__main__":
    cli.main(main)
