"""Scaling run: 3D Hertz (sphere on a plane) from about 1e4 to 1e6 dofs, serial and mpirun -n 2.

    python demos/scaling.py --out results/scaling                 # levels 0-3, 1 and 2 ranks
    python demos/scaling.py --levels 0 1 --ranks 1                # a quick look

Each run is ``demos/sphere.py --method penalty --solver iterative --level L``
in a fresh process (``mpirun -n 2`` for two ranks). The time per Newton
iteration is (assembly + linear solves) / Newton iterations, from the run's
summary.json; its log-log slope against the dofs is fitted per rank count
and printed (1 = linear cost, the ideal for AMG). Writes scaling.csv,
scaling.json and scaling.png to --out. Heavy: the 1e6-dof mesh takes about
4 minutes of gmsh and ~5 GB per run; check ``free -g`` first.
"""
import argparse
import csv
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

from fenics_contact.bench import child_env, figure
from fenics_contact.scenes import sphere

DEMO = Path(__file__).resolve().parent / "sphere.py"

p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
p.add_argument("--levels", type=int, nargs="+", default=list(range(len(sphere.LEVELS))), help="sphere mesh levels")
p.add_argument("--ranks", type=int, nargs="+", default=[1, 2], help="MPI rank counts")
p.add_argument("--method", default="penalty", help="contact method")
p.add_argument("--out", default="results/scaling", help="output folder")
args = p.parse_args()
out = Path(args.out)
out.mkdir(parents=True, exist_ok=True)

# 1. One fresh process per (ranks, level): the sphere demo with the iterative solver.
rows = []
for n in args.ranks:
    for level in args.levels:
        folder = out / f"n{n}_level{level}"
        cmd = [sys.executable, str(DEMO), "--quiet", "--no-pictures", "--no-xdmf", "--out", str(folder),
               "--method", args.method, "--solver", "iterative", "--level", str(level)]
        env = child_env()  # a fresh job, not a member of ours; mpirun keeps the run-as-root settings
        if n > 1:
            cmd = [shutil.which("mpirun") or "mpirun", "-n", str(n), *cmd]
            env.update({"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
                        "OMPI_MCA_rmaps_base_oversubscribe": "1"})
        folder.mkdir(parents=True, exist_ok=True)
        start = time.perf_counter()
        proc = subprocess.run(cmd, capture_output=True, text=True, env=env)
        (folder / "log.txt").write_text(proc.stdout + proc.stderr)
        s = json.loads((folder / "summary.json").read_text()) if (folder / "summary.json").exists() else {}
        split = s.get("time_split", {})
        iterations = s.get("newton_iterations", 0)
        solve = split.get("assembly_s", np.nan) + split.get("linear_solve_s", np.nan)
        row = {"ranks": n, "level": level, "dofs": s.get("dofs", 0), "converged": proc.returncode == 0 and
               s.get("converged", False), "newton_iterations": iterations,
               "time_per_newton_iteration_s": solve / iterations if iterations else np.nan,
               "assembly_s": split.get("assembly_s", np.nan), "linear_solve_s": split.get("linear_solve_s", np.nan),
               "wall_time_s": s.get("wall_time_s", np.nan), "setup_time_s": s.get("setup_time_s", np.nan),
               "linear_solve_floor_s": s.get("linear_solve_floor_s", np.nan),
               "memory_peak_mb_per_rank": s.get("memory_peak_mb", np.nan), "p0_error": s.get("p0_error", np.nan),
               "process_time_s": time.perf_counter() - start}
        rows.append(row)
        print(f"ranks {n} level {level}: dofs {row['dofs']:8d} converged {row['converged']!s:5s} newton "
              f"{iterations:2d} time/iteration {row['time_per_newton_iteration_s']:.3f} s  memory "
              f"{row['memory_peak_mb_per_rank']:.0f} MB/rank  p0 error {row['p0_error']:.3%}  "
              f"({row['process_time_s']:.0f} s in all)", flush=True)

# 2. Slope of log(time per iteration) against log(dofs), per rank count.
slopes = {}
for n in args.ranks:
    ok = [r for r in rows if r["ranks"] == n and r["converged"]]
    if len(ok) >= 2:
        slopes[n] = float(np.polyfit(np.log([r["dofs"] for r in ok]),
                                     np.log([r["time_per_newton_iteration_s"] for r in ok]), 1)[0])
        print(f"ranks {n}: time per Newton iteration ~ dofs^{slopes[n]:.2f}")

# 3. CSV, JSON and the chart.
with open(out / "scaling.csv", "w", newline="") as f:
    w = csv.DictWriter(f, list(rows[0]))
    w.writeheader()
    w.writerows(rows)
(out / "scaling.json").write_text(json.dumps({"rows": rows, "slopes": slopes}, indent=1, default=float) + "\n")
fig, ax = figure()
for n in args.ranks:
    ok = [r for r in rows if r["ranks"] == n and r["converged"]]
    label = f"{n} rank{'s' * (n > 1)}" + (f" (slope {slopes[n]:.2f})" if n in slopes else "")
    ax.plot([r["dofs"] for r in ok], [r["time_per_newton_iteration_s"] for r in ok], marker="o", label=label)
ax.set_xscale("log")
ax.set_yscale("log")
ax.set_xlabel("dofs")
ax.set_ylabel("time per Newton iteration (assembly + GMRES/GAMG) [s]")
ax.set_title(f"sphere on a plane (3D Hertz), {args.method}, iterative solver")
ax.grid(True, which="both", alpha=0.3)
ax.legend()
fig.savefig(out / "scaling.png", dpi=110)
print(f"-> {out / 'scaling.csv'}, {out / 'scaling.png'}")
