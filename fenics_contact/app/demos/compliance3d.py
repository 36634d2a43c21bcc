"""Elastic box pressed onto a rigid plane, then dragged sideways: normal compliance with friction (3D).

    python demos/compliance3d.py
    mpirun -n 2 python demos/compliance3d.py --method compliance --c-n 5e5 --m-n 2 --c-t 1.2e4 --m-t 1.5
    python demos/compliance3d.py --method penalty --K 1e5 --mu 0.3 --drag 0.03

Box 1 x 1 x 0.5 (E = 1000, nu = 0.3; half model by symmetry), top glued to a platen moved down 0.01,
then along +x by --drag; base on the rigid plane z = 0 with p = c_n <g>^m_n and the friction bound
c_t <g>^m_t (or mu p). Writes compliance3d.xdmf, summary.json, compliance3d_face.png (the contact
face coloured by slip state, with the tangential traction) and compliance3d_force.png to --out.
"""
from pathlib import Path

import numpy as np

from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import reference_check
from fenics_contact.app.scenes import add_scene_options, compliance3d, scene_arguments


def main(argv=None) -> dict:
    # 1. Options: Coulomb friction (mu = 0.3) on normal compliance c_n = 5e5, m_n = 1.5 unless told otherwise.
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(1e5, compliance3d.build, length="height"),
                   default_omega_t=cli.scene_scaled(compliance3d.OMEGA_T, compliance3d.build, length="height"))
    p.add_argument("--drag", type=cli.NONNEGATIVE, default=compliance3d.DRAG, help="sideways platen displacement")
    p.add_argument("--mesh", type=cli.COUNT, nargs=3, default=[16, 8, 4], metavar=("NX", "NY", "NZ"),
                   help="cells of the half box")
    p.add_argument("--press-steps", type=cli.COUNT, default=2, help="load steps of the pressing phase")
    p.add_argument("--drag-steps", type=cli.COUNT, default=8, help="load steps of the drag phase")
    p.set_defaults(method="compliance", c_n=compliance3d.C_N, m_n=compliance3d.M_N, mu=None)
    scene = add_scene_options(p, compliance3d.build, shared=("drag",))  # --lx, --ly, --height, --E, --nu, --press
    args = cli.parse(p, argv)
    if args.mu is None:  # mu = 0.3 unless the compliance bound c_t <g>^m_t is asked for
        args.mu = 0.0 if args.c_t is not None else compliance3d.MU
    out = Path(args.out or "results/compliance3d")

    # 2. The scene: half box, glued platen (press, then drag), rigid plane, the law with friction.
    setup = build("compliance3d", law=cli.law_from_args(args), quadrature=args.quadrature, nx=args.mesh[0],
                  ny=args.mesh[1], nz=args.mesh[2], press_steps=args.press_steps, drag_steps=args.drag_steps,
                  drag=args.drag, **scene_arguments(args, scene))

    # 3. Solve step by step (friction history advances on every accepted step), write XDMF and summary.json.
    summary = run(setup, out, args.method, {**cli.method_parameters(args), "drag": args.drag}, args.augment,
                  args.augment_tol, args.quiet,
                  check=lambda s: reference_check("normal_force", s.get("normal_force"),
                                        None if s.get("reaction_top_z") is None else -s["reaction_top_z"], 1e-8,
                                        "equilibrium: the platen's vertical reaction"),
                  xdmf=not args.no_xdmf, restart=args.restart, overwrite=args.overwrite, args=args)

    # 4. Pictures: the contact face (mirrored to the whole face) by slip state; forces against the drag.
    if not args.no_pictures:
        from matplotlib.backends.backend_agg import FigureCanvasAgg
        from matplotlib.figure import Figure

        from fenics_contact.app.plotting import plot_contact_face

        prof = setup.contacts[0].friction_profile()
        if setup.problem.comm.rank == 0:
            x, s, q = prof["x"], prof["state"], prof["traction"]
            mirror = x[:, 1] > 0
            xs = np.concatenate([x[:, :2], x[mirror, :2] * [1, -1]])
            qs = np.concatenate([q[:, :2], q[mirror, :2] * [1, -1]])
            f = summary
            plot_contact_face(xs[:, 0], xs[:, 1], np.concatenate([s, s[mirror]]), out / "compliance3d_face.png",
                              traction=qs, title=f"compliance3d, {args.method}: drag {args.drag:g}, stick "
                              f"{f['stick_fraction']:.0%}, slip {f['slip_fraction']:.0%}, "
                              f"open {f['open_fraction']:.0%}")
            steps = [r for r in f["friction_steps"] if r["load"] >= 1.0]  # the drag phase
            d = [r["drag"] for r in steps]
            fig = Figure(figsize=(6.4, 4.4))
            FigureCanvasAgg(fig)
            ax = fig.add_subplot()
            ax.plot(d, [-r["tangential_force"] / r["capacity"] for r in steps], "o-", label="|F_t| / int b(g)")
            ax.plot(d, [r["slip"] for r in steps], "s--", label="slip fraction")
            ax.plot(d, [r["stick"] for r in steps], "^--", label="stick fraction")
            ax.set(xlabel="platen drag", ylabel="ratio", ylim=(-0.02, 1.05),
                   title="compliance3d: tangential force over friction capacity")
            ax.grid(alpha=0.3)
            ax.legend()
            fig.tight_layout()
            fig.savefig(str(out / "compliance3d_force.png"), dpi=150)
    return summary


if __name__ == "__main__":
    cli.main(main)
