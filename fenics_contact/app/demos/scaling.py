"""Scaling run: 3D Hertz (sphere on a rigid plane; on a deformable block) from about 1e4 to 1e6 dofs, serial and
mpirun -n 2.

    python demos/scaling.py --out results/scaling                     # both scenes, levels 0-3, 1 and 2 ranks
    python demos/scaling.py --scenes rigid --levels 0 1 --ranks 1     # a quick look

Each run is ``demos/sphere.py --method penalty --solver iterative --level L`` (``--plate meshed --steps 2
--inexact --size BLOCK_SIZES[L]`` for the two-body scene ``block``: the octant on a block of its own material, one-pass
two-body contact) in a
fresh process (``mpirun -n 2`` for two ranks), the mesh built once per level and kept in ``--out/meshes``
(``$FC_MESH_CACHE``). Per run: the time per Newton iteration, (assembly + linear solves) / Newton iterations
(failed attempts included, their time is in the sums too), the Krylov iterations per Newton iteration
(GMRES + GAMG with the rigid-body near-nullspace: bounded with the size if the preconditioner scales) and the
peak memory (the largest rank's peak resident set, ``ru_maxrss``). The log-log slope of the time per Newton
iteration against the dofs is fitted per scene and rank count (1 = linear cost, the ideal for AMG), the
2-rank speed-up at each scene's largest size is the ratio of the times per Newton iteration. Writes
``scaling.json`` (``rows``: scene, dofs, ranks, peak_memory_gb, time_per_newton_s, the penalty ``K`` (the demo's
default: on the block it grows as 1 / h_contact), ``p0_error`` against Hertz (the block's: of the contact forces'
moments; ``p0_deviation`` the same signed; ``p0_max_error``, signed, of the block's nodal maximum) and the details;
``slopes``; ``speedups``), scaling.csv and scaling.png to --out. Heavy: the 1.2e6-dof rigid run peaks at
3.5 GB and took 13 minutes serial on a shared machine (4 of them gmsh, once per level); check ``free -g``
first.
"""
import sys
from pathlib import Path

import numpy as np

from fenics_contact.app import cli
from fenics_contact.app.bench import figure
from fenics_contact.app.scenes import sphere
from fenics_contact.app.study import run_demo, slope, write_rows

DEMO = Path(__file__).resolve().parent / "sphere.py"
# scene name -> the sphere demo's options (the two-body case takes its approach in two steps: in one, the first
# iterate pushes the undeformed ball 0.005 R into the undeformed block and Newton needs cutbacks; and inexact
# Newton: to 1e-8, GMRES + GAMG fails on such an iterate from 2e4 dofs on, and the step is cut)
SCENES = {"rigid": [], "block": ["--plate", "meshed", "--steps", "2", "--inexact"]}
# The block's graded zone adds ~0.8 times the octant's dofs: its mesh-size factor per level (the demo's --size
# instead of sphere.LEVELS) keeps the largest near 1e6 dofs (about 2.1e4, 1.2e5, 4.1e5, 1.0e6).
BLOCK_SIZES = (0.5, 0.25, 0.16, 0.115)



def relative(value, reference) -> float:
    """(value - reference) / reference; NaN if either is missing."""
    return (value - reference) / reference if value is not None and reference else np.nan


p = cli.StrictParser(description=" ".join(__doc__.split("\n\n")[0].split()), epilog=None)
p.add_argument("--scenes", nargs="+", choices=list(SCENES), default=list(SCENES),
               help="scenes to run: rigid (the sphere on a rigid plane), block (on a deformable block)")
p.add_argument("--levels", type=cli.number(int, 0, len(sphere.LEVELS) - 1), nargs="+",
               default=list(range(len(sphere.LEVELS))), help="the sphere demo's mesh levels (its --level)")
p.add_argument("--ranks", type=cli.COUNT, nargs="+", default=[1, 2], help="MPI rank counts")
p.add_argument("--method", default="penalty", help="contact method (the sphere demo's --method)")
p.add_argument("--out", default="results/scaling", help="output folder")
try:
    args = p.parse_args()
except cli.UsageError as exc:
    print(f"{Path(sys.argv[0]).name}: error: {exc}", file=sys.stderr)
    sys.exit(cli.EXIT_USAGE)
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)

# 1. One fresh process per (scene, level, ranks): the sphere demo with the iterative solver.
rows = []
for scene in args.scenes:
    for level in args.levels:
        for n in args.ranks:
            folder = out / f"{scene}_level{level}_n{n}"
            cmd = [sys.executable, str(DEMO), "--quiet", "--no-pictures", "--no-xdmf", "--out", str(folder),
                   "--method", args.method, "--solver", "iterative", "--level", str(level), *SCENES[scene],
                   *(["--size", str(BLOCK_SIZES[level])] if scene == "block" else [])]
            # gmsh once per mesh, not per rank count
            s, status, seconds = run_demo(cmd, folder, n, env={"FC_MESH_CACHE": str((out / "meshes").resolve())})
            split = s.get("time_split", {})
            spent = s.get("newton_iterations_spent", 0)  # failed attempts too: their time is in the split
            work = split.get("assembly_s", np.nan) + split.get("linear_solve_s", np.nan)
            row = {"scene": scene, "dofs": s.get("dofs", 0), "ranks": n,
                   "peak_memory_gb": s.get("memory_peak_mb", np.nan) / 1024.0,
                   "time_per_newton_s": work / spent if spent else np.nan,
                   "level": level, "converged": bool(s.get("converged", False)),
                   "check_passed": bool(s.get("check", {}).get("passed", False)),
                   "newton_iterations": s.get("newton_iterations", 0), "newton_iterations_spent": spent,
                   "ksp_iterations_per_newton": s.get("linear_iterations", 0) / spent if spent else np.nan,
                   "assembly_s": split.get("assembly_s", np.nan), "linear_solve_s": split.get("linear_solve_s", np.nan),
                   "wall_time_s": s.get("wall_time_s", np.nan), "setup_time_s": s.get("setup_time_s", np.nan),
                   "linear_solve_floor_s": s.get("linear_solve_floor_s", np.nan),
                   # p0: the rigid plate's nodal maximum; the block's Hertz peak of the contact forces' moments
                   # (the nodal maximum of its one-pass pressure scatters: p0_max_error)
                   "p0": s.get("p0", np.nan), "p0_hertz": s.get("p0_hertz", np.nan),
                   "p0_error": s.get("p0_error", np.nan), "p0_deviation": relative(s.get("p0"), s.get("p0_hertz")),
                   "p0_max_error": relative(s.get("p0_max"), s.get("p0_hertz")),
                   "K": s.get("parameters", {}).get("K", np.nan), "process_time_s": seconds,
                   "exit_status": status}
            rows.append(row)
            print(f"{scene:5s} level {level} ranks {n}: dofs {row['dofs']:8d} converged {row['converged']!s:5s} "
                  f"newton {spent:2d} ksp/newton {row['ksp_iterations_per_newton']:5.1f} time/newton "
                  f"{row['time_per_newton_s']:.3f} s  peak {row['peak_memory_gb']:.2f} GB/rank  p0 error "
                  f"{row['p0_error']:.2%}" + (f" (nodal max {row['p0_max_error']:+.2%})" if scene == "block" else "")
                  + f"  ({row['process_time_s']:.0f} s in all)", flush=True)


# 2. Slope of log(time per iteration) against log(dofs) per scene and rank count; 2-rank speed-up at the largest.
def ok(scene, n):
    return sorted((r for r in rows if r["scene"] == scene and r["ranks"] == n and r["converged"]),
                  key=lambda r: r["dofs"])


slopes, speedups = {}, {}
for scene in args.scenes:
    for n in args.ranks:
        runs = ok(scene, n)
        if len(runs) >= 2:
            slopes[f"{scene}/{n}"] = slope([r["dofs"] for r in runs], [r["time_per_newton_s"] for r in runs])
            print(f"{scene} ranks {n}: time per Newton iteration ~ dofs^{slopes[f'{scene}/{n}']:.2f}")
    serial = {r["level"]: r for r in ok(scene, 1)}
    for n in (m for m in args.ranks if m > 1):
        both = [r for r in ok(scene, n) if r["level"] in serial]
        if both:
            r = both[-1]
            speedups[f"{scene}/{n}"] = {"dofs": r["dofs"], "level": r["level"],
                                        "speedup": serial[r["level"]]["time_per_newton_s"] / r["time_per_newton_s"]}
            print(f"{scene} ranks {n}: speed-up {speedups[f'{scene}/{n}']['speedup']:.2f} at {r['dofs']} dofs")

# 3. CSV, JSON and the chart.
if not rows:
    sys.exit("scaling.py: no run")
write_rows(out, "scaling", rows, slopes=slopes, speedups=speedups)
failed = [f"{r['scene']} level {r['level']} ranks {r['ranks']}" for r in rows if not r["converged"]]
if len(failed) == len(rows):  # nothing to chart (a log axis of no data fails)
    sys.exit(f"scaling.py: no run converged ({', '.join(failed)}): see each run's log.txt under {out}")
fig, ax = figure()
for scene in args.scenes:
    for n in args.ranks:
        runs = ok(scene, n)
        key = f"{scene}/{n}"
        label = f"{scene}, {n} rank{'s' * (n > 1)}" + (f" (slope {slopes[key]:.2f})" if key in slopes else "")
        ax.plot([r["dofs"] for r in runs], [r["time_per_newton_s"] for r in runs], marker="o", label=label)
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("dofs")
ax.set_ylabel("time per Newton iteration (assembly + GMRES/GAMG) [s]")
ax.set_title(f"sphere on a plane / on a block (3D Hertz), {args.method}, iterative solver")
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.savefig(out / "scaling.png", dpi=110)
print(f"-> {out / 'scaling.json'}, {out / 'scaling.csv'}, {out / 'scaling.png'}")
