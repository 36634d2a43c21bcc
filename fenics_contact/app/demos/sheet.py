"""Elastic sheet pulled over a much stiffer cylinder: Papadopoulos & Solberg's collocated element against
the two-pass three-point penalty (surface locking).

    python demos/sheet.py
    mpirun -n 2 python demos/sheet.py --out results/sheet --n-arc 48 --solver iterative

Sheet (thickness 1, lambda = 1e3, mu = 5e2, neo-Hookean, plane strain,
9-node quadrilaterals; Papadopoulos & Solberg 1998) over a hollow cylinder R_in = 1 (fixed), R_out = 3,
deformable and 100 x stiffer (--ratio), both bodies in one mesh with non-matching interface nodes; ends
pulled down by t up to 1 (see fenics_contact/app/scenes/sheet.py). Runs (the paper's Figure 9):
- collocated multipliers (the reference): the paper's element, a pressure on both surfaces, the gap at
  the vertices of both, the middle pressure collocated from the opposite surface;
- two-point penalty, p = eps <g> on the same element, for each --eps;
- three-point penalty, p = eps <g> at all three nodes of the facets of both surfaces (two passes), for each
  --three-point-eps (default: --eps);
- one-pass two-point multipliers (the sheet alone carries the pressure; the cylinder takes the reaction).
--solver: the linear solver of the multiplier runs (direct: MUMPS LU; iterative: FGMRES with the Schur
complement field split, see fenics_contact/multipliers.py); the three-point penalty always direct.
Writes <variant>/sheet.xdmf (displacement) + summary.json per run, sheet_pressure.csv (at t = 0.5 and 1, at
the sheet's contact nodes: the pressure field and the nodal traction = contact nodal force / Simpson weight),
sheet_pressure.png and summary.json (the comparison) to --out. Check: the collocated multipliers' equilibrium
(the ends' pull against the reaction of the cylinder's fixed inner surface, 0.2 %: the element loads each
body by its own pressure) and the two-point penalty at the largest --eps within 0.5 % of the multipliers'
peak at t = 0.5 and 1 (the worse of the two, relative to its tolerance, is ``check``; both in ``checks``).
"""
import csv
from pathlib import Path

import numpy as np
from mpi4py import MPI

from fenics_contact import (
    LINEAR_SOLVERS,
    LagrangeMultiplier,
    Penalty,
    PenaltyMultiplier,
    write_summary,
)
from fenics_contact.app import build, cli, run
from fenics_contact.app.checks import log_check, reference_check
from fenics_contact.app.run import claimed
from fenics_contact.app.scenes import add_scene_options, scene_arguments, sheet

TIMES = (0.5, 1.0)
REFERENCE = "collocated multipliers"
EQUILIBRIUM_TOL = 2e-3  # the collocated element: each body loaded by its own pressure (not exact)
AGREEMENT_TOL = 5e-3  # two-point penalty at the largest eps against the multipliers, over the peak


def sheet_checks(s: dict, comparison: dict, eps: float) -> list[dict]:
    """The collocated multipliers' equilibrium (ends' pull against the fixed inner surface's reaction) and the
    two-point penalty's agreement with them at t = 0.5 and 1 (``peak + max |p - p_mult|`` against the peak)."""
    out = [reference_check("end_force (collocated multipliers)", s.get("end_force"), s.get("cylinder_support_y"),
                 EQUILIBRIUM_TOL, "equilibrium: the reaction of the cylinder's fixed inner surface")]
    for t in TIMES:
        c = comparison[f"t={t:g} pressure"]
        row = c["variants"].get(f"two-point penalty eps={eps:g}")
        value = None if row is None else c["peak_multipliers"] * (1 + row["max_difference_over_peak"])
        out.append(reference_check(f"peak + max |p_penalty - p_mult| at t = {t:g} (two-point penalty eps={eps:g})",
                                   value,
                         c["peak_multipliers"], AGREEMENT_TOL, "the collocated multipliers' peak pressure"))
    return out

# The complementarity parameter and the penalties per unit (shear modulus / thickness), i.e. ~ E / h
C_PER_MU, EPS_PER_MU = 2.0, (20.0, 2000.0)


def main(argv=None) -> dict:
    # 1. Options: mesh, load steps, the complementarity parameter and the penalties.
    p = cli.StrictParser(description=__doc__.splitlines()[0])
    p.add_argument("--n-arc", type=cli.COUNT, default=24, help="elements along the quarter arc (the leg gets n_arc/3)")
    p.add_argument("--steps", type=cli.number(int, 2), default=4, help="load steps (even, so that t = 0.5 is one)")
    p.add_argument("--ratio", type=cli.POSITIVE, default=sheet.RATIO, help="cylinder's Lame constants / sheet's")
    p.add_argument("--c", type=cli.POSITIVE, default=None,
                   help=f"multipliers: complementarity parameter, ~E/h (pressure per length; default: {C_PER_MU:g} "
                        f"--mu / --thickness)")
    p.add_argument("--eps", type=cli.POSITIVE, nargs="+", default=None,
                   help=f"penalty parameters (pressure per length; default: "
                        f"{', '.join(f'{e:g}' for e in EPS_PER_MU)} times --mu / --thickness)")
    p.add_argument("--three-point-eps", type=cli.POSITIVE, nargs="+", default=None,
                   help="the three-point penalty's parameters (default: --eps)")
    p.add_argument("--solver", choices=list(LINEAR_SOLVERS), default="direct",
                   help="linear solver of the multiplier runs: direct (MUMPS LU) or iterative (FGMRES, Schur "
                        "complement field split)")
    p.add_argument("--no-one-pass", action="store_true", help="leave out the one-pass two-point multipliers")
    cli.output_options(p, out="results/sheet")
    # --R, --thickness, --leg, --R-in, --lmbda, --mu, --radius
    scene = add_scene_options(p, sheet.build, shared=("ratio",))
    args = cli.parse(p, argv)
    if args.steps % 2:
        raise cli.UsageError(f"--steps must be even (t = 0.5 must be a load step), got {args.steps}")
    stiffness = args.mu / args.thickness  # ~ E / h: the mesh is fixed relative to the thickness
    args.c = C_PER_MU * stiffness if args.c is None else args.c
    args.eps = [e * stiffness for e in EPS_PER_MU] if args.eps is None else args.eps
    with claimed(Path(args.out), MPI.COMM_WORLD, overwrite=args.overwrite, restart=args.restart) as out:
        return _compare(args, scene, out)


def _compare(args, scene: list[str], out: Path) -> dict:
    """2.-4. Every variant into its subfolder of ``out``, their comparison, summary.json, the CSV and picture."""
    three = args.eps if args.three_point_eps is None else args.three_point_eps
    # (name, law, quadrature, eps or None, multiplier method: the --solver applies)
    variants = [(REFERENCE, LagrangeMultiplier(args.c), "collocated", None, True)]
    variants += [(f"two-point penalty eps={e:g}", PenaltyMultiplier(e), "collocated", e, True) for e in args.eps]
    variants += [(f"three-point penalty eps={e:g}", Penalty(e), "simpson", e, False) for e in three]
    if not args.no_one_pass:
        variants.append(("one-pass two-point multipliers", LagrangeMultiplier(args.c), "simpson", None, True))

    # 2. Each variant: build the scene, solve to t = 1, keep the interface pressure at t = 0.5 and 1.
    profiles, summaries = {}, {}
    for name, law, quadrature, eps, multipliers in variants:
        setup = build("sheet", law=law, quadrature=quadrature, n_arc=args.n_arc, n_leg=max(args.n_arc // 3, 1),
                      steps=args.steps, ratio=args.ratio, **scene_arguments(args, scene))
        kept = {}

        def after_step(t, setup=setup, kept=kept):
            if any(np.isclose(t, T) for T in TIMES):
                kept[round(t, 6)] = {"pressure": setup.profile(), "traction": setup.traction()}

        solver = args.solver if multipliers else "direct"
        params = {**({"c": args.c} if eps is None else {"eps": eps}), "solver": solver}
        # The collocated penalty: the active set of p = eps <g> flips with penetrations ~p/eps (1e6: cycling and
        # exploding iterates from the last state at n_arc = 24); the load path's tangent and more cutbacks get it
        # through (27 load steps instead of 4).
        stiff = quadrature == "collocated" and eps is not None
        summaries[name] = run(setup, out / name.replace(" ", "_").replace("=", ""), law.name, params, quiet=args.quiet,
                              on_step=after_step, keep=(kept,), xdmf=not args.no_xdmf,
                              restart=args.restart, overwrite=args.overwrite, args=args,
                              options=dict(LINEAR_SOLVERS[solver]),
                              predictor="tangent" if stiff else False, max_cutbacks=8 if stiff else 4)
        profiles[name] = kept

    # 3. Compare with the multipliers, for the sheet's pressure field and its nodal traction: largest difference
    #    over the contact nodes (relative to the multipliers' peak), total variation along the interface and
    #    node-to-node oscillation (total variation over all nodes minus that over the vertices).
    MEASURES = ("pressure", "traction")
    comparison = {}
    for t in TIMES:
        for m in MEASURES:
            ref = profiles[REFERENCE][t][m]["p"]
            peak = float(ref.max())
            rows = {}
            for name, *_ in variants:
                pr = profiles[name][t][m]["p"]
                # the one-pass element's nodes are the sheet's too (the same mesh): node by node
                rows[name] = {"max_difference_over_peak": float(np.abs(pr - ref).max() / peak),
                              "p_max": float(pr.max()),
                              "total_variation": sheet.total_variation(pr), "oscillation": sheet.oscillation(pr)}
            comparison[f"t={t:g} {m}"] = {"peak_multipliers": peak, "variants": rows}
    keys = ("end_force", "p_max", "belt_T_over_R", "max_penetration", "newton_iterations", "linear_iterations",
            "load_steps", "wall_time_s", "cylinder_support_y", "contact_force_y", "dofs")
    figures = {name: {k: s[k] for k in keys if k in s} for name, s in summaries.items()}
    for name, s in summaries.items():
        figures[name]["linear_solve_s"] = s["time_split"]["linear_solve_s"]
        figures[name]["solver"] = s["parameters"]["solver"]
    totals = {k: sum(s[k] for s in summaries.values()) for k in ("newton_iterations", "augmentations", "wall_time_s")}
    checks = sheet_checks(summaries[REFERENCE], comparison, max(args.eps))
    worst = max(checks, key=lambda c: np.inf if c["rel_error"] is None else c["rel_error"] / c["tolerance"])
    summary = {"scene": "sheet", "method": "compare", "ranks": MPI.COMM_WORLD.size,
               "dofs": summaries[REFERENCE]["dofs"], **totals, "converged": True, "comparison": comparison,
               "runs": figures, "parameters": summaries[REFERENCE]["parameters"], "c": args.c, "eps": args.eps,
               "three_point_eps": three, "solver": args.solver, "check": worst, "checks": checks}
    write_summary(out / "summary.json", summary, MPI.COMM_WORLD)
    for c in checks:
        log_check(c, MPI.COMM_WORLD)

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
            cli.say(f"{t}: collocated multipliers' peak {c['peak_multipliers']:.4g}")
            for name, r in c["variants"].items():
                cli.say(f"  {name:32s} max |p - p_mult| / peak {r['max_difference_over_peak']:.4f}  "
                      f"total variation {r['total_variation']:.4g}  oscillation {r['oscillation']:.4g}")
        if not args.no_pictures:
            from fenics_contact.app.plotting import plot_curves

            styles = {REFERENCE: "k-", "one-pass two-point multipliers": "k:"}
            for i, e in enumerate(args.eps):
                styles[f"two-point penalty eps={e:g}"] = f"--C{i}"
            for i, e in enumerate(three):
                styles[f"three-point penalty eps={e:g}"] = f"-.C{i + len(args.eps)}"
            names = [n for n, *_ in variants]
            prs = {n: {t: profiles[n][t]["pressure"] for t in TIMES} for n in names}
            near = {n: {t: prs[n][t]["s"] <= 5.5 for t in TIMES} for n in names}  # the leg is free below
            curves = [(prs[n][t]["s"][near[n][t]], prs[n][t]["p"][near[n][t]], n if t == 1.0 else f"_{n}",
                       styles[n]) for t in TIMES for n in names]  # one legend entry per variant
            plot_curves(curves, out / "sheet_pressure.png", xlabel="arc length from the top (reference)",
                        title="sheet on a deformable cylinder: pressure on the sheet, t = 0.5, 1")
    return summary


if __name__ == "__main__":
    cli.main(main)
