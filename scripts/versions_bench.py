"""The same scenes on dolfinx 0.5.2 (Debian 12, this machine's ``.venv``) and 0.11 (the PyPI wheel in the Debian 13
root's venv, set up by ``scripts/wheel011.sh``), in one run on one machine: each demo run ``--repeat`` times per
version, alternating, serially; the fastest of each is compared. Prints the table and writes it as a page.

    python scripts/versions_bench.py [--repeat 3] [--page docs/bench/versions.md]

Needs root (chroot) and the Debian 13 root (``DEB13``, as the lanes).
"""
from __future__ import annotations

import argparse
import json
import os
import shlex
import subprocess
import sys
import time
from datetime import datetime, timezone
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from fenics_contact.app.run_record import machine, versions  # noqa: E402

DEB13 = Path(os.environ.get("DEB13") or Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache")
             / "fenics_contact" / "debian13")
PROJECT = "versions-bench"  # the project's folder in the root
VENV = "/opt/fc-wheel"  # the wheel's venv in the root (scripts/wheel011.sh)
ENV = [f"PATH={VENV}/bin:/usr/bin:/bin", "OPENBLAS_NUM_THREADS=1", "OMP_NUM_THREADS=1", "MPLBACKEND=Agg"]
# (name, demo, options): a 2D scene with an exact method and a 3D one
CASES = [("hertz, lagrange (2D)", "hertz", ["--method", "lagrange"]),
         ("sphere (3D), its default method", "sphere", ["--size", "1.0"])]


def run_052(demo: str, options: list[str], out: Path) -> dict:
    subprocess.run([str(ROOT / ".venv" / "bin" / "python"), f"demos/{demo}.py", *options, "--out", str(out),
                    "--overwrite", "--quiet", "--no-pictures"], cwd=ROOT, check=True, stdout=subprocess.DEVNULL)
    return json.loads((out / "summary.json").read_text())


def run_011(demo: str, options: list[str], out: str) -> dict:
    cmd = " ".join(shlex.quote(a) for a in ["python", f"demos/{demo}.py", *options, "--out", out, "--overwrite",
                                            "--quiet", "--no-pictures"])
    subprocess.run(["bash", "-c", '. scripts/lane_root.sh && lane_mounted "$@"', "sh", cmd, PROJECT, *ENV],
                   cwd=ROOT, check=True, stdout=subprocess.DEVNULL, env={**os.environ, "LANE": "versions"})
    return json.loads((DEB13 / PROJECT / out / "summary.json").read_text())


def in_root(cmd: str) -> str:
    return subprocess.run(["bash", "-c", '. scripts/lane_root.sh && lane_mounted "$@"', "sh", cmd, PROJECT, *ENV],
                          cwd=ROOT, check=True, capture_output=True, text=True, env={**os.environ, "LANE": "v"}
                          ).stdout.strip()


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3, help="runs per scene and version (default 3)")
    ap.add_argument("--page", default=None, help="write the table as this Markdown page")
    args = ap.parse_args(argv)
    if args.repeat < 1:
        print(f"versions_bench: --repeat must be >= 1, got {args.repeat}", file=sys.stderr)
        return 2
    # the wheel's venv and the project installed in it, as the wheel lane makes them
    subprocess.run(["bash", "scripts/wheel011.sh"], cwd=ROOT, check=True, stdout=subprocess.DEVNULL,
                   env={**os.environ, "WHEEL_PARTS": "setup", "WHEEL_PROJECT": PROJECT})
    new = {"dolfinx": in_root("python -c 'import dolfinx; print(dolfinx.__version__)'"),
           "petsc": in_root("python -c 'from petsc4py import PETSc; print(*PETSc.Sys.getVersion(), sep=\".\")'"),
           "python": in_root("python -c 'import platform; print(platform.python_version())'"),
           "gmsh": in_root("python -c 'import gmsh; print(gmsh.__version__)'")}
    import gmsh

    old = {**versions(), "python": ".".join(map(str, sys.version_info[:3])), "gmsh": gmsh.__version__}
    start = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    load = round(os.getloadavg()[0], 1)
    rows = []
    for name, demo, options in CASES:
        best = {"old": None, "new": None}
        for i in range(args.repeat):
            for side in ("old", "new"):
                t0 = time.perf_counter()
                s = (run_052(demo, options, ROOT / "results" / "versions" / f"{demo}-{i}") if side == "old"
                     else run_011(demo, options, f"results/versions/{demo}-{i}"))
                s["process_s"] = time.perf_counter() - t0
                if not s.get("converged"):
                    print(f"versions_bench: {demo} {' '.join(options)} did not converge on the {side} dolfinx",
                          file=sys.stderr)
                    return 1
                if best[side] is None or s["wall_time_s"] < best[side]["wall_time_s"]:
                    best[side] = s
        rows.append((name, " ".join([demo, *options]), best["old"], best["new"]))
    head = (f"Measured on {machine()['cpu']}, {machine()['cores']} cores, {machine()['system']}; {start}; "
            f"load average {load:g} at the start (other jobs on its cores); fastest of {args.repeat} serial runs "
            f"each, alternating. dolfinx {old['dolfinx']} (PETSc {old['petsc']}, Python {old['python']}, gmsh "
            f"{old['gmsh']}, Debian 12's packages) against dolfinx {new['dolfinx']} (PETSc {new['petsc']}, Python "
            f"{new['python']}, gmsh {new['gmsh']}, the PyPI wheels dolfinx-solver-real and gmsh in a Debian 13 root "
            "on the same machine). Command: `python "
            f"scripts/versions_bench.py --repeat {args.repeat}`.")
    table = ["| scene, method | demo | dofs 0.5.2 / 0.11 | Newton iterations | set-up [s] 0.5.2 / 0.11 | "
             "solve [s] 0.5.2 / 0.11 | solve ratio 0.11 / 0.5.2 | p0 or figure equal |",
             "|---|---|---|---|---|---|---|---|"]
    for name, cmd, a, b in rows:
        same = all(abs(a[k] - b[k]) <= 1e-8 * max(abs(a[k]), abs(b[k]), 1e-30)
                   for k in ("p0", "total_force") if isinstance(a.get(k), float) and isinstance(b.get(k), float))
        table.append(f"| {name} | `{cmd}` | {a['dofs']} / {b['dofs']} | {a['newton_iterations']} / "
                     f"{b['newton_iterations']} | "
                     f"{a['setup_time_s']:.2f} / {b['setup_time_s']:.2f} | {a['solve_time_s']:.2f} / "
                     f"{b['solve_time_s']:.2f} | {b['solve_time_s'] / a['solve_time_s']:.2f} | "
                     f"{'yes' if same else 'no'} (1e-8) |")
    print(head, "", *table, sep="\n")
    if args.page:
        Path(args.page).write_text("\n".join([
            "# dolfinx 0.5.2 against 0.11", "", head, "",
            "The same demo, options and mesh on both (pictures off); set-up is mesh, spaces and forms (their "
            "compilation included when not cached), solve the load steps. The last column compares the scene's "
            "figures (`p0`, `total_force`) between the two versions, 1e-8 relative: equal where the mesh is (the "
            "2D quarter disk); gmsh's 3D meshes of the sphere differ between its versions (the dofs), and with them "
            "the figures.", "", *table, ""]))
    return 0


if __name__ == "__main__":
    sys.exit(main())
