"""FElupe side by side: an O-ring cord squeezed between two rigid frictionless plates (plane strain and
axisymmetric, 5-35 % squeeze), computed by FElupe (scripts/felupe/felupe_case.py, in its own venv) and by this
suite's ``oring`` scene (a gland wide enough that its side walls stay clear: two plates); and the O-ring in its
rigid gland, squeezed, then pressurised (axisymmetric, the scene's default load;
scripts/felupe/felupe_gland.py); over a mesh study of each, in one run; then the page docs/bench/felupe.md with one
table and one chart per case (scripts/felupe/page.py).

    python scripts/felupe/run.py [--quick] [--cases strain axisymmetric gland] [--venv DIR]

FElupe is installed from the package index into ``--venv`` (default ``~/.cache/fenics_contact/felupe-venv``, made
with ``/usr/bin/python3 -m venv`` and ``pip install felupe`` if it is not there). Each job is a fresh serial
process; the figures go to ``--out``/rows.json with the run's record (machine, date, load average, command).
The rows of cases a run does not redo are kept with their own run's record. Exit status: 0 all jobs done, 1 a job
failed, 2 bad command line or no FElupe.
"""
from __future__ import annotations

import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(HERE))

from table import CASES, GLAND, GLAND_T, MATERIAL, SQUEEZES  # noqa: E402

from fenics_contact.app.run_record import machine  # noqa: E402
from fenics_contact.app.scenes.oring import profile_width  # noqa: E402

VENV = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "fenics_contact" / "felupe-venv"
# Mesh studies: FElupe's circle mesh, n points on a 45-degree edge (8 (n - 1) segments round the cord); the suite's
# gmsh mesh size h on the cord's surface (per d; P2-P1 Taylor-Hood).
FELUPE_N = {"quick": [8, 16, 32], "full": [8, 16, 32, 64]}
OURS_H = {"quick": [1 / 16, 1 / 32], "full": [1 / 16, 1 / 32, 1 / 64]}
# The gland case: the whole cord; n - 1 a multiple of 9, so that the ends of the pressurised arc (40 degrees about
# -z) are nodes of FElupe's circle mesh (its rim nodes 45 / (n - 1) degrees apart), as they are vertices of the suite's
FELUPE_N_GLAND = {"quick": [10, 19], "full": [10, 19, 37]}
# The suite's side: augmented Lagrangian to convergence of the gap (the exact contact limit of the penalty), a gland
# three cords wide (the cord at 35 % squeeze is 1.4 d wide: its side walls never touch), no fluid pressure.
OURS_ARGS = ["--method", "auglag", "--augment-tol", "1e-6", "--gland-width", "3", "--pressure", "0"]
# ... the gland case: the scene's gland and load (table.GLAND); penalty, K = OURS_GLAND_K E / h (ten times the scene's
# default): the augmented Lagrangian's Newton cycles between two active sets of the side wall from h = d/32 (the two
# ends of its contact zone in turn, as the spring fades; FElupe's Newton does too, and passes with a longer step),
# the penalty's does not (at h = d/16, where both converge, they differ by less than the mesh study's last
# change)
OURS_GLAND_K = 1000.0
OURS_GLAND_ARGS = ["--method", "penalty", "--gland-width", repr(GLAND["gland_width"] * MATERIAL["d"]),
                   "--pressure", repr(GLAND["pressure"] * MATERIAL["E"]), "--pressure-arc", repr(GLAND["pressure_arc"]),
                   "--squeeze", repr(GLAND["squeeze"]), "--steps", str(GLAND["steps"]),
                   "--pressure-steps", str(GLAND["pressure_steps"])]


def ensure_felupe(venv: Path) -> str | None:
    """Make ``venv`` with FElupe if it has none; None, or a one-line reason it cannot be made."""
    py = venv / "bin" / "python"
    probe = [str(py), "-c", "import felupe"]
    if py.exists() and subprocess.run(probe, capture_output=True).returncode == 0:
        return None
    print(f"felupe: installing FElupe into {venv}", flush=True)
    for cmd in (["/usr/bin/python3", "-m", "venv", str(venv)], [str(py), "-m", "pip", "install", "-q", "felupe"]):
        proc = subprocess.run(cmd, capture_output=True, text=True)
        if proc.returncode != 0:
            return f"{' '.join(cmd)} failed: {(proc.stderr.strip().splitlines() or ['?'])[-1]}"
    return None if subprocess.run(probe, capture_output=True).returncode == 0 else f"no felupe in {venv}"


def _job(cmd: list[str], timeout: float, env: dict | None = None) -> tuple[bool, str, float]:
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, cwd=ROOT,
                              env={**os.environ, **(env or {})})
        # exit 3: the suite's demo ran to the end and its own check (Hertz at the first step) failed: figures kept
        ok, log = proc.returncode in (0, 3), (proc.stdout[-1500:] + proc.stderr[-1500:])
    except subprocess.TimeoutExpired:
        ok, log = False, f"timed out after {timeout:.0f} s"
    return ok, log, time.perf_counter() - t0


def felupe_rows(case: str, n: int, py: Path, out: Path, timeout: float) -> list[dict]:
    """FElupe's rows of ``case`` on its mesh ``n``: one per squeeze."""
    path = out / f"felupe-{case}-{n}.json"
    m = MATERIAL
    cmd = [str(py), str(HERE / "felupe_case.py"), str(path), "--plane", CASES[case]["plane"], "--n", str(n),
           "--squeeze", *map(str, SQUEEZES), "--d", str(m["d"]), "--r-in", str(m["r_in"]), "--E", str(m["E"]),
           "--nu", str(m["nu"])]
    ok, log, elapsed = _job(cmd, timeout)
    base = {"code": "FElupe", "case": case, "mesh": f"n {n}", "level": n, "command": " ".join(cmd[1:])}
    if not ok:
        print(f"felupe: FElupe {case} n {n}: failed", flush=True)
        return [dict(base, status="failed", log=log)]
    res = json.loads(path.read_text())
    rows = []
    for r in res["rows"]:
        width = profile_width(np.asarray(r["along"]), np.asarray(r["pressure_nominal"]))
        rows.append(dict(base, status="done" if r["converged"] else "failed", squeeze=r["squeeze"],
                         force=r["force_bore"], p0=max(r["pressure"]), width=width, dofs=res["dofs"],
                         time_s=res["wall_time_s"], total_s=elapsed, newton=r["newton_iterations"],
                         version=res["version"]))
    print(f"felupe: FElupe {case} n {n}: done ({res['dofs']} dofs, {res['wall_time_s']:.3g} s)", flush=True)
    return rows


def felupe_gland_rows(case: str, n: int, py: Path, out: Path, timeout: float) -> list[dict]:
    """FElupe's rows of the gland ``case`` on its mesh ``n``: one per load step of ``GLAND_T``."""
    path = out / f"felupe-{case}-{n}.json"
    m, g = MATERIAL, GLAND
    cmd = [str(py), str(HERE / "felupe_gland.py"), str(path), "--plane", CASES[case]["plane"], "--n", str(n),
           "--d", str(m["d"]), "--r-in", str(m["r_in"]), "--E", str(m["E"]), "--nu", str(m["nu"]),
           "--squeeze", str(g["squeeze"]), "--squeeze-steps", str(g["steps"]),
           "--gland-width", str(g["gland_width"] * m["d"]), "--pressure", str(g["pressure"] * m["E"]),
           "--pressure-arc", str(g["pressure_arc"])]
    ok, log, elapsed = _job(cmd, timeout)
    base = {"code": "FElupe", "case": case, "mesh": f"n {n}", "level": n, "command": " ".join(cmd[1:])}
    res = json.loads(path.read_text()) if ok else None
    if res is None or not all(r["converged"] for r in res["rows"]):
        print(f"felupe: FElupe {case} n {n}: failed", flush=True)
        error = (res["rows"][-1].get("error", "") if res and res["rows"] else "") or log
        return [dict(base, status="failed", log=error)]
    rows = []
    for r in res["rows"]:
        rows.append(dict(base, status="done", t=r["t"], squeeze=r["squeeze"], pressure=r["pressure"],
                         force=r["force_bore"], force_side=r["force_side"], p0=r["p0_bore"], p0_side=r["p0_side"],
                         width=profile_width(np.asarray(r["along_bore"]), np.asarray(r["nominal_bore"])),
                         width_side=profile_width(np.asarray(r["along_side"]), np.asarray(r["nominal_side"])),
                         fluid_axial=r["fluid_axial_force"], walls_axial=r["walls_axial_force"], dofs=res["dofs"],
                         time_s=res["wall_time_s"], total_s=elapsed, newton=res["rows"][-1]["newton_iterations"],
                         version=res["version"]))
    print(f"felupe: FElupe {case} n {n}: done ({res['dofs']} dofs, {res['wall_time_s']:.3g} s)", flush=True)
    return rows


def ours_rows(case: str, h: float, out: Path, timeout: float) -> list[dict]:
    """This suite's rows of ``case`` on its mesh ``h`` (per d): one per squeeze."""
    run = out / f"ours-{case}-{1 / h:.0f}"
    m = MATERIAL
    gland = CASES[case].get("gland", False)
    load = [*OURS_GLAND_ARGS, "--K", repr(OURS_GLAND_K * m["E"] / (h * m["d"]))] if gland else [
        *OURS_ARGS, "--squeeze", str(max(SQUEEZES)), "--steps", str(len(SQUEEZES))]
    cmd = [sys.executable, "demos/oring.py", *load, "--plane", CASES[case]["plane"],
           "--d", str(m["d"]), "--r-in", str(m["r_in"]), "--E", str(m["E"]), "--nu", str(m["nu"]),
           "--h", repr(h * m["d"]), "--out", str(run), "--overwrite", "--no-xdmf", "--no-pictures", "--quiet"]
    ok, log, elapsed = _job(cmd, timeout)
    base = {"code": "fenics_contact", "case": case, "mesh": f"h d/{1 / h:.0f}", "level": h,
            "command": " ".join(cmd[1:])}
    if not ok:
        print(f"felupe: fenics_contact {case} h d/{1 / h:.0f}: failed", flush=True)
        return [dict(base, status="failed", log=log)]
    summary = json.loads((run / "summary.json").read_text())
    with open(run / "oring_figures.csv") as fh:
        steps = list(csv.DictReader(fh))
    rows = []
    if gland:  # the load steps of GLAND_T (cut-back steps between them are left out)
        for t in GLAND_T:
            hit = [r for r in steps if math.isclose(float(r["t"]), t, rel_tol=1e-9)]
            if not hit:
                rows.append(dict(base, status="failed", t=t, log="no converged step at this time"))
                continue
            r = {k: float(v) for k, v in hit[-1].items() if k in (
                "t", "squeeze", "pressure", "force_bore", "force_side", "p0_cauchy_bore", "p0_cauchy_side",
                "width_bore", "width_side", "fluid_axial_force", "walls_axial_force")}
            rows.append(dict(base, status="done", t=t, squeeze=r["squeeze"], pressure=r["pressure"],
                             force=r["force_bore"], force_side=r["force_side"], p0=r["p0_cauchy_bore"],
                             p0_side=r["p0_cauchy_side"], width=r["width_bore"], width_side=r["width_side"],
                             fluid_axial=r["fluid_axial_force"], walls_axial=r["walls_axial_force"],
                             dofs=summary["dofs"], time_s=summary["wall_time_s"], total_s=elapsed,
                             newton=summary["newton_iterations_spent"]))
    for s in ([] if gland else SQUEEZES):  # the steps at the squeezes asked for (cut-back steps between them left out)
        hit = [r for r in steps if math.isclose(float(r["squeeze"]), s, rel_tol=1e-9)]
        if not hit:
            rows.append(dict(base, status="failed", squeeze=s, log="no converged step at this squeeze"))
            continue
        r = hit[-1]
        rows.append(dict(base, status="done", squeeze=s, force=float(r["force_bore"]),
                         p0=float(r["p0_cauchy_bore"]), width=float(r["width_bore"]), dofs=summary["dofs"],
                         time_s=summary["wall_time_s"], total_s=elapsed,
                         newton=summary["newton_iterations_spent"]))
    print(f"felupe: fenics_contact {case} h d/{1 / h:.0f}: done ({summary['dofs']} dofs, "
          f"{summary['wall_time_s']:.3g} s)", flush=True)
    return rows


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--venv", default=str(VENV), help=f"FElupe's venv (default: {VENV})")
    parser.add_argument("--out", default=str(ROOT / "results" / "felupe"), help="output folder")
    parser.add_argument("--docs", default=str(ROOT / "docs" / "bench"), help="folder of the page")
    parser.add_argument("--cases", nargs="+", choices=list(CASES), default=list(CASES))
    parser.add_argument("--quick", action="store_true", help="the coarser meshes only")
    parser.add_argument("--timeout", type=float, default=1800.0, help="seconds per job (default: 1800)")
    args = parser.parse_args(argv)
    reason = ensure_felupe(Path(args.venv))
    if reason:
        print(f"felupe: cannot run: {reason}", file=sys.stderr)
        return 2
    out = Path(args.out).resolve()
    out.mkdir(parents=True, exist_ok=True)
    py = Path(args.venv) / "bin" / "python"
    version = subprocess.run([str(py), "-c", "import felupe; print(felupe.__version__)"], capture_output=True,
                             text=True).stdout.strip()
    size = "quick" if args.quick else "full"
    record = {"date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()), "machine": machine(),
              "load_average": round(os.getloadavg()[0], 1),
              "command": " ".join(["python scripts/felupe/run.py", *(argv if argv is not None else sys.argv[1:])]),
              "felupe": version, "cases": list(args.cases)}
    # Rows of cases this run does not redo are kept, with the record of the run that measured them.
    earlier = json.loads((out / "rows.json").read_text()) if (out / "rows.json").exists() else {"runs": [], "rows": []}
    runs = [dict(r, cases=[c for c in r["cases"] if c not in args.cases]) for r in earlier["runs"]]
    runs = [r for r in runs if r["cases"]] + [record]
    kept = [r for r in earlier["rows"] if r["case"] not in args.cases]
    rows = []
    for case in args.cases:
        gland = CASES[case].get("gland", False)
        for n in (FELUPE_N_GLAND if gland else FELUPE_N)[size]:
            rows += (felupe_gland_rows if gland else felupe_rows)(case, n, py, out, args.timeout)
        for h in OURS_H[size]:
            rows += ours_rows(case, h, out, args.timeout)
        (out / "rows.json").write_text(json.dumps({"runs": runs, "rows": kept + rows}, indent=1) + "\n")
    from page import write_page  # scripts/felupe/page.py

    write_page(out / "rows.json", Path(args.docs))
    return 0 if all(r["status"] == "done" for r in rows) else 1


if __name__ == "__main__":
    sys.exit(main())
