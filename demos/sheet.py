"""Elastic sheet pulled over a much stiffer cylinder: two-point against three-point enforcement.

    python demos/sheet.py
    mpirun -n 2 python demos/sheet.py --out results/sheet --n-arc 48

Sheet (thickness 1, lambda = 1e3, mu = 5e2, neo-Hookean, plane strain,
9-node quadrilaterals; Papadopoulos & Solberg 1998) over a hollow cylinder R_in = 1 (fixed), R_out = 3,
deformable and 100 x stiffer (--ratio; --cylinder rigid: its limit), both bodies in one mesh with
non-matching interface nodes; ends pulled down by t up to 1 (see fenics_contact/scenes/sheet.py).
Five runs: Lagrange multipliers and the penalty p = eps <g> of the two-point element (gap at the end nodes
of the sheet's facets, pressure linear on the facet, Simpson's rule), and the three-point penalty (gap at
all three nodes of the facets of both surfaces, two passes), eps in {1e4, 1e6}. Writes
<variant>/sheet.xdmf (displacement) + summary.json per run, sheet_pressure.csv (at t = 0.5 and 1, at the
sheet's contact nodes: the pressure field and the nodal traction = contact nodal force / Simpson weight),
sheet_pressure.png and summary.json (the comparison) to --out.
"""
import csv
from pathlib import Path

import numpy as np
from mpi4py import MPI

from fenics_contact import LagrangeMultiplier, Penalty, PenaltyMultiplier, build, cli, run, write_summary
from fenics_contact.checks import check, log_check
from fenics_contact.scenes import add_scene_options, scene_arguments, sheet

TIMES = (0.5, 1.0)



def sheet_check(s: dict) -> dict:
    """Equilibrium of the multipliers' run: the ends' pull against the cylinder's support reaction (deformable
    cylinder) or the contact force (rigid)."""
    support = s.get("cylinder_support_y", s.get("contact_force_y"))
    return check("end_force (multipliers)", s.get("end_force"), None if support is None else abs(support), 1e-6,
                 "equilibrium: the cylinder's reaction")


def main(argv=None) -> dict:
    # 1. Options: mesh, load steps, the complementarity parameter and the penalties.
    p = cli.StrictParser(description=__doc__.splitlines()[0])
    p.add_argument("--n-arc", type=cli.COUNT, default=24, help="elements along the quarter arc (the leg gets n_arc/3)")
    p.add_argument("--steps", type=cli.number(int, 2), default=4, help="load steps (even, so that t = 0.5 is one)")
    p.add_argument("--cylinder", choices=sheet.CYLINDERS, default="deformable", help="the cylinder's model")
    p.add_argument("--ratio", type=cli.POSITIVE, default=sheet.RATIO, help="cylinder's Lame constants / sheet's")
    p.add_argument("--c", type=cli.POSITIVE, default=1e3, help="multipliers: complementarity parameter, ~E/h")
    p.add_argument("--eps", type=cli.POSITIVE, nargs="+", default=[1e4, 1e6], help="penalty parameters")
    cli.output_options(p, out="results/sheet")
    scene = add_scene_options(p, sheet.build)  # --R, --thickness, --leg, --R-in, --lmbda, --mu, --radius
    args = cli.parse(p, argv)
    if args.steps % 2:
        raise cli.UsageError(f"argument --steps: must be even (t = 0.5 must be a load step), got {args.steps}")
    out = Path(args.out)
    variants = [("multipliers", None, LagrangeMultiplier(args.c))]
    variants += [(f"two-point penalty eps={e:g}", e, PenaltyMultiplier(e)) for e in args.eps]
    variants += [(f"three-point penalty eps={e:g}", e, Penalty(e)) for e in args.eps]

    # 2. Each variant: build the scene, solve to t = 1, keep the interface pressure at t = 0.5 and 1.
    profiles, summaries = {}, {}
    for name, eps, law in variants:
        setup = build("sheet", law=law, quadrature="simpson", n_arc=args.n_arc, n_leg=max(args.n_arc // 3, 1),
                      steps=args.steps, cylinder=args.cylinder, ratio=args.ratio, **scene_arguments(args, scene))
        kept = {}

        def after_step(t, setup=setup, kept=kept):
            if any(np.isclose(t, T) for T in TIMES):
                kept[round(t, 6)] = {"pressure": setup.profile(), "traction": setup.traction()}

        params = {"c": args.c} if eps is None else {"eps": eps}
        summaries[name] = run(setup, out / name.replace(" ", "_").replace("=", ""), law.name, params, quiet=args.quiet,
                              on_step=after_step, xdmf=not args.no_xdmf)
        profiles[name] = kept

    # 3. Compare with the multipliers, for the sheet's pressure field and its nodal traction: largest difference
    #    over the contact nodes (relative to the multipliers' peak), total variation along the interface and
    #    node-to-node oscillation (total variation over all nodes minus that over the vertices).
    MEASURES = ("pressure", "traction")
    comparison = {}
    for t in TIMES:
        for m in MEASURES:
            ref = profiles["multipliers"][t][m]["p"]
            peak = float(ref.max())
            rows = {}
            for name, _, _ in variants:
                pr = profiles[name][t][m]["p"]
                rows[name] = {"max_difference_over_peak": float(np.abs(pr - ref).max() / peak),
                              "p_max": float(pr.max()),
                              "total_variation": sheet.total_variation(pr), "oscillation": sheet.oscillation(pr)}
            comparison[f"t={t:g} {m}"] = {"peak_multipliers": peak, "variants": rows}
    keys = ("end_force", "p_max", "belt_T_over_R", "max_penetration", "newton_iterations", "load_steps", "wall_time_s",
            "cylinder_support_y", "contact_force_y")
    figures = {name: {k: s[k] for k in keys if k in s} for name, s in summaries.items()}
    totals = {k: sum(s[k] for s in summaries.values()) for k in ("newton_iterations", "augmentations", "wall_time_s")}
    summary = {"scene": "sheet", "method": "compare", "ranks": MPI.COMM_WORLD.size,
               "dofs": summaries["multipliers"]["dofs"], **totals, "converged": True, "comparison": comparison,
               "runs": figures, "parameters": summaries["multipliers"]["parameters"], "c": args.c, "eps": args.eps,
               "check": sheet_check(summaries["multipliers"])}
    write_summary(out / "summary.json", summary, MPI.COMM_WORLD)
    log_check(summary["check"], MPI.COMM_WORLD)

    # 4. CSV of every profile and the paper-like picture (pressure against the arc length from the top).
    if MPI.COMM_WORLD.rank == 0:
        with open(out / "sheet_pressure.csv", "w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["variant", "t", "measure", "arc_length", "x", "y", "value"])
            for name, kept in profiles.items():
                for t, both in kept.items():
                    for m, pr in both.items():
                        for row in zip(pr["s"], pr["x"], pr["y"], pr["p"]):
                            w.writerow([name, t, m, *(f"{v:.10g}" for v in row)])
        for t, c in comparison.items():
            cli.say(f"{t}: multipliers' peak {c['peak_multipliers']:.4g}")
            for name, r in c["variants"].items():
                cli.say(f"  {name:30s} max |p - p_mult| / peak {r['max_difference_over_peak']:.4f}  "
                      f"total variation {r['total_variation']:.4g}  oscillation {r['oscillation']:.4g}")
        if not args.no_pictures:
            from fenics_contact.plotting import plot_curves

            styles = {"multipliers": "k:"}
            for i, e in enumerate(args.eps):
                styles[f"two-point penalty eps={e:g}"] = f"-C{i}"
                styles[f"three-point penalty eps={e:g}"] = f"-.C{i + len(args.eps)}"
            prs = {n: {t: profiles[n][t]["pressure"] for t in TIMES} for n, _, _ in variants}
            near = {n: {t: prs[n][t]["s"] <= 5.5 for t in TIMES} for n, _, _ in variants}  # the leg is free below
            curves = [(prs[n][t]["s"][near[n][t]], prs[n][t]["p"][near[n][t]], n if t == 1.0 else f"_{n}",
                       styles[n]) for t in TIMES for n, _, _ in variants]  # one legend entry per variant
            plot_curves(curves, out / "sheet_pressure.png", xlabel="arc length from the top (reference)",
                        title=f"sheet on a {args.cylinder} cylinder: pressure on the sheet, t = 0.5, 1")
    return summary


if __name__ == "__main__":
    cli.main(main)
