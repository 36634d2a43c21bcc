"""A sphere pressed on a block of its own material, then sheared below sliding: Cattaneo-Mindlin partial slip (3D).

    python demos/mindlin3d.py
    mpirun -n 2 python demos/mindlin3d.py --ratios 0.5
    python demos/mindlin3d.py --refinement 1
    python demos/mindlin3d.py --solver direct   # MUMPS LU: the same answer, 2.6 x the time at 12k dofs, 7 x at 68k
    python demos/mindlin3d.py --method coulomb  # exact Signorini-Coulomb, condensed (small sliding; MUMPS LU)

The half y >= 0 of a spherical cap (R = 1, height 0.5) on a block, both E = 1000, nu = 0.3, node-to-triangle
Coulomb friction (penalty K = 2e6, mu = 0.3, omega_t = 1e6 at the default mesh, scaled with 1 / h_contact; or
exact with --method coulomb, on the Coulomb disk, pressed with friction in one step). The
top moves down (force P measured), then carries the tangential force Q = r mu P along x for each r of --ratios.
The stick radius c (from the stick area by the vertex rule, sqrt(2 A / pi); also along the +x, -x and +y rays) is
compared with Cattaneo-Mindlin c = a (1 - Q/(mu P))^(1/3) (a: Hertz for P, 1/E* = 2 (1 - nu^2) / E), the
traction along the x axis with Mindlin's q(r). Writes mindlin3d.xdmf, summary.json and mindlin3d.png (the
traction along x against Mindlin, and the stick/slip map of the last step) to --out. The linear solver is
GMRES + GAMG by default (--solver iterative; --method coulomb factors with MUMPS, --solver direct, unless its
condensed system is too large and the run takes the sparse exact method, by default iterative): MUMPS's LU
of this 3D Jacobian grows like dofs^2 (Debian's MUMPS orders with PORD: 4.7 GFlop at 12k dofs), GAMG about
linearly, with the same Newton iterations and figures.
"""
import sys
from pathlib import Path

import numpy as np

from fenics_contact.app import build, cli, run
from fenics_contact.app.scenes import add_scene_options, mindlin, mindlin3d, scene_arguments

TOLERANCE = 0.05  # the stick radius at every ratio, against Cattaneo-Mindlin


def main(argv=None) -> dict:
    # 1. Options: Coulomb friction mu = 0.3 on a penalty normal law unless told otherwise.
    p = cli.parser(__doc__.splitlines()[0], default_K=cli.scene_scaled(mindlin3d.DEFAULT_K, mindlin3d.build),
                   quadratures=("nodal",))
    mindlin.add_shear_options(p, mindlin3d.RATIOS, "divide the contact mesh size by sqrt(2) this many times")
    p.set_defaults(method="penalty", mu=0.3, solver="iterative")
    p.add_argument("--sliding", choices=["finite", "small"], default=None,
                   help="contact kinematics: finite (current configuration, the pointwise methods' default) or "
                        "small (reference pairs and normals, a gap linear in u: Cattaneo-Mindlin's; method coulomb "
                        "is small by construction)")
    scene = add_scene_options(p, mindlin3d.build)  # --R, --E, --nu, --approach, --width, --h-contact, ...
    args = cli.parse(p, argv)
    given = sys.argv[1:] if argv is None else argv
    default_solver = args.method == "coulomb" and not any(a == "--solver" or a.startswith("--solver=") for a in given)
    if default_solver:
        args.solver = "direct"  # the exact method factors the stiffness itself (MUMPS)
    mindlin.check_ratios_option(args.ratios)
    if args.c_t is not None or args.tresca is not None or args.mu <= 0:
        raise ValueError(f"--mu: mindlin3d needs Coulomb friction with mu > 0 (no --c-t, --tresca), got mu={args.mu}")
    if args.omega_t is None:  # the interface layer E* / omega_t a fixed fraction of the contact element
        args.omega_t = mindlin3d.default_omega_t(args.refinement, args.h_contact, args.R, args.E)
    out = Path(args.out or "results/mindlin3d")
    cli.refuse_unsupported(args, kind="two-body", dim=3, degree=1, model="linear")

    # 2. The scene: graded two-body mesh, displacement-controlled press, force-controlled shear.
    setup = build("mindlin3d", law=cli.law_from_args(args), ratios=tuple(args.ratios), refinement=args.refinement,
                  press_steps=args.press_steps, sliding=args.sliding, **scene_arguments(args, scene))
    if default_solver and "solved_by" in setup.parameters:  # too large for the condensed system: the sparse method
        args.solver = p.get_default("solver")  # with the scene's own linear solver
    profiles = []

    def on_step(t: float) -> None:  # the friction profile of the last shear step (collective)
        if t > 1.0:
            profiles[:] = [(t - 1.0, setup.profile())]

    self_check = mindlin.worst_ratio_check(args.ratios, TOLERANCE, "Cattaneo-Mindlin c = a (1 - Q/(mu P))^(1/3) at "
                                           "the worst ratio (stick area's radius)")

    # 3. Solve step by step (history on accepted steps), write XDMF and summary.json.
    options = {**cli.solver_options(args), **(mindlin3d.ITERATIVE if args.solver == "iterative" else {})}
    summary = run(setup, out, args.method, {**cli.method_parameters(args), "ratios": args.ratios}, args.augment,
                  args.augment_tol, args.quiet, options=options, on_step=on_step, keep=(profiles,),
                  xdmf=not args.no_xdmf, restart=args.restart, overwrite=args.overwrite, args=args, check=self_check,
                  predictor=False if setup.problem.step_solver else mindlin3d.PREDICTOR)  # the exact method's own

    # 4. Pictures: the traction along x against Mindlin; the stick/slip map of the last step.
    if not args.no_pictures and setup.problem.comm.rank == 0 and summary.get("P") and profiles:
        _pictures(out, summary, *profiles[-1])
    return summary


def _pictures(out: Path, s: dict, r: float, prof: dict) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    a, p0, mu = s["a_hertz"], s["p0_hertz"], s["mu"]
    c = mindlin3d.mindlin_c(a, r)
    x, q, state = prof["x"], prof["traction"], prof["state"]
    fig = Figure(figsize=(11, 4.4))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(1, 2, 1)
    on = (np.abs(x[:, 1]) < 1e-9) & (np.abs(x[:, 0]) <= 1.3 * a)
    xr = np.linspace(-a, a, 801)
    ax.plot(x[on, 0] / a, -q[on, 0] / (mu * p0), "o", ms=3, label=f"computed, Q/(mu P) = {r:g}")
    ax.plot(xr / a, mindlin3d.mindlin_traction(xr, a, c, mu, p0) / (mu * p0), "k-", lw=1, label="Mindlin")
    ax.set(xlabel="x / a (y = 0)", ylabel="q_x / (mu p0)", title="tangential traction along x")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    ax = fig.add_subplot(1, 2, 2)
    near = np.hypot(x[:, 0], x[:, 1]) <= 1.3 * a
    for value, colour, label in ((2, "tab:blue", "stick"), (1, "tab:red", "slip"), (0, "0.8", "open")):
        k = near & (state == value)
        ax.plot(x[k, 0] / a, x[k, 1] / a, ".", color=colour, ms=4, label=label)
    phi = np.linspace(0, np.pi, 181)
    ax.plot(np.cos(phi), np.sin(phi), "k-", lw=1, label="Hertz a")
    ax.plot(c / a * np.cos(phi), c / a * np.sin(phi), "k--", lw=1, label="Mindlin c")
    ax.set(xlabel="x / a", ylabel="y / a", aspect="equal",
           title=f"stick radius within {s.get(f'c_error_{r:g}', np.nan):.1%} of Cattaneo-Mindlin")
    ax.legend(fontsize=8, loc="upper right")
    fig.tight_layout()
    fig.savefig(out / "mindlin3d.png", dpi=120)


if __name__ == "__main__":
    cli.main(main)
