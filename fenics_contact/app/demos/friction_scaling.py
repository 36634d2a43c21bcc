"""Friction at size: Cattaneo-Mindlin's sphere on a block (mindlin3d) refined, the sparse exact method beside the
penalty and Nitsche friction, GMRES + GAMG, serial or mpirun -n 2.

    python demos/friction_scaling.py --out results/friction_scaling                  # refinements 0-2, 2 ranks
    python demos/friction_scaling.py --methods lagrange --refinements 1 --ranks 1 2  # serial against 2 ranks

Each run is ``demos/mindlin3d.py --method M --refinement R --solver iterative`` in a fresh process (``mpirun -n 2``
for two ranks): ``lagrange`` is the sparse exact Coulomb method (Alart-Curnier, one semismooth Newton on
displacements and tractions, c from the problem), ``penalty`` and ``nitsche`` the penalty-type friction laws at the
demo's defaults (normal penalty and ``omega_t`` growing as 1 / h_contact). Per run: dofs, contact dofs (three per
slave vertex of the contact zone), Newton iterations (failed attempts included), Krylov iterations per Newton
iteration, time per Newton iteration (assembly and linear solves), the whole solve over one linear solve of the same
mesh and solver (``ratio_to_linear_solve``: assembly, preconditioner set-up and Krylov solve of the Jacobian; also
over penalty's linear solve, the elastic one: ``ratio_to_elastic_solve``), peak memory per rank and the stick radius
against Cattaneo-Mindlin at Q / (mu P) = 0.2, 0.5, 0.8. The log-log slopes against the dofs (time per Newton
iteration, one linear solve, peak memory) are fitted per method and rank count. Writes ``friction_scaling.json``
(rows, slopes), ``friction_scaling.csv`` and ``friction_scaling.png`` (the solve over the elastic linear solve, and the
worst stick radius error, against the dofs) to --out. Heavy: refinement 2 (1.6e5 dofs) takes minutes a run.
"""
import sys
from pathlib import Path

import numpy as np

from fenics_contact import methods
from fenics_contact.app import cli
from fenics_contact.app.study import run_demo, slope, write_rows

DEMO = Path(__file__).resolve().parent / "mindlin3d.py"
METHODS = ("lagrange", "penalty", "nitsche")
RATIOS = (0.2, 0.5, 0.8)

p = cli.StrictParser(description=" ".join(__doc__.split("\n\n")[0].split()), epilog=None)
p.add_argument("--methods", nargs="+", choices=METHODS, default=list(METHODS), help="friction methods to run")
p.add_argument("--refinements", type=cli.number(int, 0, 4), nargs="+", default=[0, 1, 2],
               help="the mindlin3d demo's --refinement (the contact mesh size / sqrt(2) each)")
p.add_argument("--ranks", type=cli.COUNT, nargs="+", default=[2], help="MPI rank counts")
p.add_argument("--out", default="results/friction_scaling", help="output folder")
p.add_argument("--existing", action="store_true",
               help="read the runs already in --out (their summary.json) instead of running them; the others are "
                    "left out")
try:
    args = p.parse_args()
except cli.UsageError as exc:
    print(f"{Path(sys.argv[0]).name}: error: {exc}", file=sys.stderr)
    sys.exit(cli.EXIT_USAGE)
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)


def run(method: str, refinement: int, ranks: int) -> dict | None:
    """One run of the mindlin3d demo in a fresh process; its row (None: --existing and not in --out)."""
    folder = out / f"{method}_refinement{refinement}_n{ranks}"
    if args.existing and not (folder / "summary.json").exists():
        return None
    cmd = [sys.executable, str(DEMO), "--quiet", "--no-pictures", "--no-xdmf", "--overwrite", "--out", str(folder),
           "--method", method, "--solver", "iterative", "--refinement", str(refinement)]
    s, status, seconds = run_demo(cmd, folder, ranks, existing=args.existing)
    split = s.get("time_split", {})
    spent = s.get("newton_iterations_spent", 0)  # failed attempts too: their time is in the split
    work = split.get("assembly_s", np.nan) + split.get("linear_solve_s", np.nan)
    return {"method": method, "refinement": refinement, "ranks": ranks, "dofs": s.get("dofs", 0),
            "contact_dofs": 3 * s.get("slave_vertices_in_contact", 0),
            "converged": bool(s.get("converged", False)), "check_passed": bool(s.get("check", {}).get("passed")),
            "newton_iterations": spent, "failed_attempts": len(s.get("warnings", [])),
            "ksp_per_newton": s.get("linear_iterations", 0) / spent if spent else np.nan,
            "time_per_newton_s": work / spent if spent else np.nan, "solve_time_s": s.get("solve_time_s", np.nan),
            "linear_solve_s": s.get("linear_solve_floor_s", np.nan),
            "ratio_to_linear_solve": s.get("ratio_to_linear_solve", np.nan),
            "peak_memory_gb": s.get("memory_peak_mb", np.nan) / 1024.0,
            **{f"c_error_{r:g}": s.get(f"c_error_{r:g}", np.nan) for r in RATIOS},
            "c_error_max": s.get("c_error_max", np.nan), "P": s.get("P", np.nan),
            **{f"Q_{r:g}": s.get(f"Q_{r:g}", np.nan) for r in RATIOS},
            "process_time_s": seconds, "exit_status": status}


# 1. One fresh process per (method, refinement, ranks).
rows = []
for method in args.methods:
    for refinement in args.refinements:
        for n in args.ranks:
            row = run(method, refinement, n)
            if row is None:
                print(f"{method:8s} refinement {refinement} ranks {n}: not in {out}, left out", flush=True)
                continue
            rows.append(row)
            print(f"{method:8s} refinement {refinement} ranks {n}: dofs {row['dofs']:7d} contact dofs "
                  f"{row['contact_dofs']:6d} converged {row['converged']!s:5s} newton {row['newton_iterations']:3d} "
                  f"ksp/newton {row['ksp_per_newton']:6.1f} time/newton {row['time_per_newton_s']:6.2f} s, "
                  f"{row['ratio_to_linear_solve']:6.1f} x one linear solve ({row['linear_solve_s']:.2f} s), peak "
                  f"{row['peak_memory_gb']:.2f} GB/rank, stick radius error "
                  + ", ".join(f"{row[f'c_error_{r:g}']:.2%}" for r in RATIOS)
                  + (f" ({row['process_time_s']:.0f} s in all)" if row["exit_status"] != -1 else " (read)"), flush=True)


# The multipliers' linear solve is a saddle point (field split); penalty's is the elastic one (GAMG): every method's
# whole solve also over penalty's linear solve at the same size and ranks (the elastic solve's cost floor).
for row in rows:
    elastic = [r["linear_solve_s"] for r in rows if r["method"] == "penalty" and r["converged"]
               and (r["refinement"], r["ranks"]) == (row["refinement"], row["ranks"])]
    row["ratio_to_elastic_solve"] = row["solve_time_s"] / elastic[0] if elastic else np.nan


# 2. Slopes against the dofs per method and rank count; serial against 2 ranks where both ran.
def ok(method: str, n: int) -> list[dict]:
    return sorted((r for r in rows if r["method"] == method and r["ranks"] == n and r["converged"]),
                  key=lambda r: r["dofs"])


slopes = {}
for method in args.methods:
    for n in args.ranks:
        runs = ok(method, n)
        if len(runs) >= 2:
            slopes[f"{method}/{n}"] = {k: slope([r["dofs"] for r in runs], [r[k] for r in runs])
                                       for k in ("time_per_newton_s", "linear_solve_s", "peak_memory_gb")}
            fit = slopes[f"{method}/{n}"]
            print(f"{method} ranks {n}: time per Newton iteration ~ dofs^{fit['time_per_newton_s']:.2f}, one linear "
                  f"solve ~ dofs^{fit['linear_solve_s']:.2f}, peak memory ~ dofs^{fit['peak_memory_gb']:.2f}")
agreement = []
for method in args.methods:
    for refinement in args.refinements:
        same = [r for r in rows if r["method"] == method and r["refinement"] == refinement and r["converged"]]
        if len(same) >= 2:
            keys = ["P", *(f"Q_{r:g}" for r in RATIOS), *(f"c_error_{r:g}" for r in RATIOS)]
            worst = max(abs(a[k] - b[k]) / max(abs(a[k]), 1e-300) if "error" not in k else abs(a[k] - b[k])
                        for a in same for b in same for k in keys)
            agreement.append({"method": method, "refinement": refinement, "ranks": [r["ranks"] for r in same],
                              "largest_difference": worst})
            print(f"{method} refinement {refinement}: ranks {[r['ranks'] for r in same]} agree to {worst:.1e}")

# 3. CSV, JSON and the chart.
if not rows:
    sys.exit("friction_scaling.py: no run")
write_rows(out, "friction_scaling", rows, slopes=slopes, agreement=agreement)
if not any(r["converged"] for r in rows):  # nothing to chart (a log axis of no data fails)
    sys.exit(f"friction_scaling.py: no run converged: see each run's log.txt under {out}")
from matplotlib.backends.backend_agg import FigureCanvasAgg  # noqa: E402
from matplotlib.figure import Figure  # noqa: E402

fig = Figure(figsize=(12, 4.8), layout="constrained")
FigureCanvasAgg(fig)
ax, bx = fig.subplots(1, 2)
# the elastic solve's ratio where penalty ran at the same size, else the method's own
elastic = any(np.isfinite(r["ratio_to_elastic_solve"]) for r in rows if r["converged"])
ratio = "ratio_to_elastic_solve" if elastic else "ratio_to_linear_solve"
for method in args.methods:
    for n in args.ranks:
        runs = ok(method, n)
        if not runs:  # a legend entry only for what was run
            continue
        style = {"label": f"{method}, {n} rank{'s' * (n > 1)}", "color": methods.get(method).sweep.colour,
                 "marker": "o" if n > 1 else "s", "linestyle": "-" if n > 1 else "--", "fillstyle": "full" if n > 1
                 else "none"}  # the method's colour in both panels
        cost = [(r["dofs"], r[ratio]) for r in runs if np.isfinite(r[ratio])]  # no elastic solve at every size
        if cost:
            ax.plot(*zip(*cost), **style)
        bx.plot([r["dofs"] for r in runs], [r["c_error_max"] for r in runs], **style)
ax.set(xscale="log", yscale="log", xlabel="dofs",
       ylabel=f"whole load path / one {'elastic' if elastic else 'own'} linear solve",
       title=f"cost: solve time over {'penalty' if elastic else 'its own'}'s linear solve (GMRES + GAMG)")
bx.set(xscale="log", yscale="log", xlabel="dofs", ylabel="stick radius error, worst of Q/(mu P) = 0.2, 0.5, 0.8",
       title="accuracy against Cattaneo-Mindlin")
for a in (ax, bx):
    a.grid(True, which="both", alpha=0.3)
    a.legend(fontsize=8)
fig.savefig(out / "friction_scaling.png", dpi=110)
print(f"-> {out / 'friction_scaling.json'}, {out / 'friction_scaling.csv'}, {out / 'friction_scaling.png'}")
