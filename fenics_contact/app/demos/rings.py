"""Two concentric rings under external pressure: every two-body option against Lamé's interface pressure.

    python demos/rings.py
    mpirun -n 2 python demos/rings.py --out results/rings --n 32

Inner ring 0.2 <= r <= 0.6, outer ring 0.6 <= r <= 1.0 (separate bodies, non-matching meshes at r = 0.6),
pressure q on r = 1, linear elasticity (see fenics_contact/app/scenes/rings.py for Lamé's solution). For P1
facets (nodal, gauss, segment) and P2 facets (nodal, simpson), one and two passes: the penalty at
--K values, the augmented Lagrangian (converged) and Lagrange multipliers (pointwise quadratures); P2
with Papadopoulos & Solberg's collocated element (multipliers and p = eps <g> at --K values).
Writes rings_options.csv|md (one row per option: pressure deviations from Lamé, the pressure from the
roller reaction, u_r at r = a and r = c, Newton iterations, or the error a run raised) and summary.json.
Check: the collocated element on P2 facets (multipliers), its interface pressure farthest from Lamé's,
within 0.5 % (--main-only: that option alone).
"""
import time
from pathlib import Path

from mpi4py import MPI

from fenics_contact import (
    AugmentedLagrangian,
    LagrangeMultiplier,
    Penalty,
    PenaltyMultiplier,
    Solver,
    write_summary,
)
from fenics_contact.app import cli
from fenics_contact.app.checks import log_check, reference_check
from fenics_contact.app.run import claimed
from fenics_contact.app.scenes import SizeError, add_scene_options, build, rings, scene_arguments
from fenics_contact.app.tables import write_table

# Penalty parameters per unit E / c (the mesh is fixed relative to the radii, so K ~ E / h scales as E / c): the
# penalty sweep, the augmented Lagrangian's K and the multipliers' complementarity parameter (it steers Newton only)
K_PER_E, AUGLAG_PER_E, C_PER_E = (1e2, 1e3, 1e4, 1e5), 1e3, 1.0


def main(argv=None) -> dict:
    p = cli.StrictParser(description=__doc__.splitlines()[0])
    p.add_argument("--n", type=cli.COUNT, default=16, help="elements along the inner ring's interface arc")
    p.add_argument("--plane", choices=rings.PLANES, default="strain", help="2D assumption")
    p.add_argument("--K", type=cli.POSITIVE, nargs="+", default=None,
                   help=f"penalty parameters (pressure per length; default: {', '.join(f'{k:g}' for k in K_PER_E)} "
                        f"times --E / --c)")
    scene = add_scene_options(p, rings.build)  # --E, --nu, --E-outer, --nu-outer, --q
    p.add_argument("--main-only", action="store_true", help="only the checked option (P2, collocated, multipliers)")
    cli.output_options(p, out="results/rings")
    args = cli.parse(p, argv)
    if args.K is None:
        args.K = [k * args.E / args.c for k in K_PER_E]
    if args.restart:
        raise cli.UsageError("--restart: rings solves each option in one load step, there is nothing to go on "
                             "with; run it again with --overwrite")
    start = time.perf_counter()
    out = Path(args.out)
    comm = MPI.COMM_WORLD
    with claimed(out, comm, overwrite=args.overwrite):
        return _compare(args, scene_arguments(args, scene), out, comm, start)


def _compare(args, physics: dict, out: Path, comm: MPI.Comm, start: float) -> dict:
    """Every option into the table, the check and summary.json; ``physics``: the builder's physical parameters."""
    OPTIONS = [(1, q) for q in ("nodal", "gauss", "segment")] + [(2, q) for q in ("nodal", "simpson", "collocated")]
    if args.main_only:
        OPTIONS = [(2, "collocated")]
    rows = []
    for degree, quadrature in OPTIONS:
        for passes in (("both",) if quadrature == "collocated" else ("one", "two")):
            laws = [(f"penalty K={K:g}", lambda K=K: Penalty(K), 0) for K in args.K]
            K_auglag = AUGLAG_PER_E * args.E / args.c
            laws.append((f"auglag K={K_auglag:g}", lambda K=K_auglag: AugmentedLagrangian(K), 50))
            if quadrature == "collocated":  # the pressure is an unknown: multipliers and p = eps <g>
                laws = [(f"penalty_multiplier eps={K:g}", lambda K=K: PenaltyMultiplier(K), 0) for K in args.K]
            if quadrature != "segment":
                laws.append(("lagrange", lambda: LagrangeMultiplier(C_PER_E * args.E / args.c), 0))
            if args.main_only:
                laws = laws[-1:]
            for name, law, augment in laws:
                row = {"degree": degree, "quadrature": quadrature, "passes": passes, "method": name}
                try:
                    setup = build("rings", law_factory=law, degree=degree, quadrature=quadrature,
                                  passes="one" if passes == "both" else passes, n=args.n, plane=args.plane,
                                  comm=comm, **physics)
                    with Solver(setup.problem, quiet=True, augment_max=augment, augment_tol=1e-10) as solver:
                        solver.run(setup.loads)
                    f = setup.figures()
                    row.update({k: f[k] for k in ("p_max_deviation", "p_mean_deviation", "p_reaction_deviation",
                                                  "ur_a_deviation", "ur_c_deviation", "points")})
                    row["newton"] = sum(r.newton_iterations for r in solver.records)
                    row["dofs"] = setup.dofs
                except SizeError:  # the same for every option: the run's, not a row's
                    raise
                except Exception as exc:  # noqa: BLE001 (the table records what each option does)
                    row["error"] = f"{type(exc).__name__}: {str(exc).splitlines()[0][:120]}"
                rows.append(row)
                if comm.rank == 0:
                    cli.say(row)

    columns = ["degree", "quadrature", "passes", "method", "p_max_deviation", "p_mean_deviation",
               "p_reaction_deviation", "ur_a_deviation", "ur_c_deviation", "points", "newton", "dofs", "error"]
    if comm.rank == 0:
        write_table([{c: r.get(c, "") for c in columns} for r in rows], out / "rings_options", columns)
    p_lame = rings.lame_pressure(args.q, args.E, args.nu, args.E if args.E_outer is None else args.E_outer,
                                 args.nu if args.nu_outer is None else args.nu_outer, args.plane, args.a, args.b,
                                 args.c)
    best = [r for r in rows if r["quadrature"] == "collocated" and r["method"] == "lagrange" and "error" not in r]
    summary = {"scene": "rings", "method": "compare", "ranks": comm.size,
               **({"dofs": best[0]["dofs"]} if best else {}), "n": args.n, **physics,  # the checked option's
               "plane": args.plane, "p_lame": p_lame, "options": rows,
               "newton_iterations": sum(r.get("newton", 0) for r in rows),
               "wall_time_s": comm.allreduce(time.perf_counter() - start, op=MPI.MAX),
               "check": reference_check("p_interface (P2 collocated, farthest)",
                              p_lame * (1 + best[0]["p_max_deviation"]) if best else None, p_lame, 5e-3,
                              "Lame's interface pressure")}
    write_summary(out / "summary.json", summary, comm)
    log_check(summary["check"], comm)
    return summary


if __name__ == "__main__":
    cli.main(main)
