"""Speed against accuracy: run every method over a parameter sweep, one fresh process per run.

    python -m fenics_contact.bench --scene hertz --quick --out results/bench
    python demos/bench.py --scene block --scene hertz --quick

Each run is ``demos/<scene>.py --quiet --no-pictures --out <out>/<scene>/<run>``
in its own serial process; its ``summary.json`` becomes one row of
``<out>/<scene>.csv`` and ``<out>/<scene>.json``. A run that exits non-zero
(or times out) is recorded with ``converged = False``. Charts:
``<out>/<scene>_pareto.png`` (error against solver wall time, with the
Pareto front) and ``<out>/<scene>_iterations.png`` (Newton iterations
against K).
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
from typing import Sequence

import numpy as np

DEMOS = Path(__file__).resolve().parents[1] / "demos"
SCENES = ("block", "hertz")
DEFAULT_K = {"block": 1e5, "hertz": 1e6}  # the demos' defaults
ERROR = {"block": "pressure_error", "hertz": "p0_error"}
COLUMNS = ["scene", "method", "K", "F_hat", "augment", "quadrature", "refinement", "dofs", "wall_time_s",
           "newton_iterations", "augmentations", "converged", "error", "process_time_s", "setup_time_s",
           "assembly_s", "linear_solve_s", "augmentation_s", "memory_peak_mb", "linear_solve_floor_s",
           "ratio_to_linear_solve"]
AUGMENT = 10  # max augmentations per load step for the augmented variants
ERROR_FLOOR = 1e-16  # errors are drawn at least this large on the log axis (an exact answer is 0)


def sweep(scene: str, quick: bool = False) -> list[dict]:
    """The runs for ``scene``: penalty over a log range of K (no augmentation); cross and auglag,
    each with and without augmentation, over a smaller K range; hertz on refinements 0 and 1 (full: 0-2)."""
    K0 = DEFAULT_K[scene]
    if quick:
        penalty_K = [K0 * 10.0**e for e in ((-2, -1, 0, 1, 2) if scene == "block" else (-1, 0, 1))]
        other_K, quadratures, refinements = [K0, 10 * K0], ["nodal"], [0, 1]
    else:
        penalty_K = [K0 * 10.0**e for e in np.arange(-3, 3.01, 0.5)]
        other_K, quadratures, refinements = [K0 * 10.0**e for e in range(-2, 3)], ["nodal", "gauss"], [0, 1, 2]
    runs = []
    for refinement in refinements if scene == "hertz" else [None]:
        for quadrature in quadratures:
            runs += [dict(method="penalty", K=K, F_hat=0.0, augment=0, quadrature=quadrature,
                          refinement=refinement) for K in penalty_K]
            runs += [dict(method=m, K=K, F_hat=0.0, augment=aug, quadrature=quadrature, refinement=refinement)
                     for m in ("cross", "auglag") for aug in (0, AUGMENT) for K in other_K]
        # the reference: exact nodal enforcement by PETSc SNES VI (no parameter; K = 0 in the rows)
        runs.append(dict(method="vi", K=0.0, F_hat=0.0, augment=0, quadrature="nodal", refinement=refinement))
    return runs


def _say(line: str) -> None:
    """One progress line, from rank 0 only (the tests run the harness on every rank of an mpirun job)."""
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank == 0:
        sys.stdout.write(line + "\n")
        sys.stdout.flush()


def run_name(cfg: dict) -> str:
    ref = "" if cfg.get("refinement") is None else f"_r{cfg['refinement']}"
    return f"{cfg['method']}_K{cfg['K']:.3g}_F{cfg['F_hat']:g}_aug{cfg['augment']}_{cfg['quadrature']}{ref}"


def _child_env() -> dict:
    """The environment without MPI launcher variables: a demo started from a rank of an ``mpirun``
    job (e.g. the tests under ``mpirun -n 2``) must start as its own serial job, not join ours."""
    return {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_", "MPI_LOCALNRANKS"))}


def run_one(scene: str, cfg: dict, folder: Path, timeout: float = 1800.0) -> dict:
    """Run one demo in a fresh process into ``folder``; return its row (never raises on a failed run)."""
    folder.mkdir(parents=True, exist_ok=True)
    cmd = [sys.executable, str(DEMOS / f"{scene}.py"), "--quiet", "--no-pictures", "--out", str(folder),
           "--method", cfg["method"], "--K", repr(cfg["K"]), "--F-hat", repr(cfg["F_hat"]),
           "--augment", str(cfg["augment"]), "--quadrature", cfg["quadrature"]]
    if cfg.get("refinement") is not None:
        cmd += ["--refinement", str(cfg["refinement"])]
    (folder / "summary.json").unlink(missing_ok=True)
    start = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=_child_env())
        ok, log = proc.returncode == 0, proc.stdout + proc.stderr
    except subprocess.TimeoutExpired as exc:
        ok, log = False, f"timeout after {timeout} s\n{exc.stdout or ''}{exc.stderr or ''}"
    (folder / "log.txt").write_text(log if isinstance(log, str) else log.decode(errors="replace"))
    s = json.loads((folder / "summary.json").read_text()) if (folder / "summary.json").exists() else {}
    nan = float("nan")
    return {"scene": scene, **cfg, "dofs": s.get("dofs", 0), "wall_time_s": s.get("wall_time_s", nan),
            "newton_iterations": s.get("newton_iterations", 0), "augmentations": s.get("augmentations", 0),
            "converged": bool(ok and s.get("converged", False)), "error": s.get(ERROR[scene], nan),
            "process_time_s": time.perf_counter() - start, "setup_time_s": s.get("setup_time_s", nan),
            **{k: s.get("time_split", {}).get(k, nan) for k in ("assembly_s", "linear_solve_s", "augmentation_s")},
            **{k: s.get(k, nan) for k in ("memory_peak_mb", "linear_solve_floor_s", "ratio_to_linear_solve")}}


def bench(scene: str, out: str | Path, runs: Sequence[dict], pictures: bool = True, quiet: bool = False,
          timeout: float = 1800.0) -> list[dict]:
    """Run ``runs`` for ``scene`` into ``out/<scene>/``; write ``out/<scene>.csv``, ``.json`` and the charts."""
    out = Path(out)
    rows = []
    for i, cfg in enumerate(runs):
        row = run_one(scene, cfg, out / scene / run_name(cfg), timeout)
        rows.append(row)
        if not quiet:
            _say(f"[{scene} {i + 1}/{len(runs)}] {run_name(cfg):40s} converged {row['converged']!s:5s} "
                  f"newton {row['newton_iterations']:3d} error {row['error']:.3e} "
                  f"time {row['wall_time_s']:.3f} s", flush=True)
    write_rows(rows, out / f"{scene}.csv", out / f"{scene}.json")
    if pictures:
        plot_pareto(rows, out / f"{scene}_pareto.png", title=f"{scene}: error against wall time")
        plot_iterations(rows, out / f"{scene}_iterations.png", title=f"{scene}: Newton iterations against K")
    return rows


def write_rows(rows: Sequence[dict], csv_path: Path, json_path: Path) -> None:
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, COLUMNS)
        w.writeheader()
        w.writerows({k: ("" if r[k] is None else r[k]) for k in COLUMNS} for r in rows)
    # JSON has no NaN: a missing figure is null.
    clean = [{k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()} for r in rows]
    json_path.write_text(json.dumps(clean, indent=1) + "\n")


def read_rows(csv_path: str | Path) -> list[dict]:
    """The rows of a ``<scene>.csv`` with their types back."""
    ints, floats = {"augment", "dofs", "newton_iterations", "augmentations"}, {
        "K", "F_hat", "wall_time_s", "error", "process_time_s", "setup_time_s", "assembly_s", "linear_solve_s",
        "augmentation_s", "memory_peak_mb", "linear_solve_floor_s", "ratio_to_linear_solve"}
    rows = []
    with open(csv_path, newline="") as f:
        for r in csv.DictReader(f):
            r = dict(r)
            for k in ints:
                r[k] = int(r[k])
            for k in floats:
                r[k] = float(r[k]) if r[k] != "" else float("nan")
            r["refinement"] = int(r["refinement"]) if r["refinement"] != "" else None
            r["converged"] = r["converged"] == "True"
            rows.append(r)
    return rows


def pareto_front(times: Sequence[float], errors: Sequence[float]) -> np.ndarray:
    """Indices of the Pareto-optimal points (no other point is at least as fast and at least as
    accurate, and better in one), ordered by increasing time: the minimum error reachable within
    a given time. Points with a NaN time or error are ignored; of exact duplicates the first is kept."""
    t, e = np.asarray(times, dtype=float), np.asarray(errors, dtype=float)
    valid = np.flatnonzero(~(np.isnan(t) | np.isnan(e)))
    order = valid[np.lexsort((e[valid], t[valid]))]  # by time, ties by error (stable: first index first)
    front, best = [], np.inf
    for i in order:
        if e[i] < best:
            front.append(i)
            best = e[i]
    return np.array(front, dtype=int)


# ---------------------------------------------------------------------------------------------- charts

COLOURS = {"penalty": "tab:blue", "cross": "tab:orange", "auglag": "tab:green", "vi": "tab:red"}
MARKERS = {None: "o", 0: "o", 1: "^", 2: "s", 3: "D"}  # by refinement
SIZES = {"penalty": 11.0, "cross": 8.0, "auglag": 5.0, "vi": 7.0}  # coinciding methods stay visible (concentric)


def _variant(r: dict) -> str:
    return r["method"] + (" augmented" if r["augment"] > 0 else "")


def _figure():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.5, 5.2), layout="constrained")
    FigureCanvasAgg(fig)
    return fig, fig.add_subplot()


def _legend_handles(rows: Sequence[dict]):
    from matplotlib.lines import Line2D

    handles = []
    for v in dict.fromkeys(_variant(r) for r in rows):
        m = v.split()[0]
        handles.append(Line2D([], [], ls="", marker="o", ms=7, color=COLOURS[m], mec=COLOURS[m],
                              mfc=COLOURS[m] if "augmented" in v else "none", label=v))
    refinements = sorted({r["refinement"] for r in rows if r["refinement"] is not None})
    if len(refinements) > 1:
        handles += [Line2D([], [], ls="", marker=MARKERS[k], color="grey", mfc="none", label=f"refinement {k}")
                    for k in refinements]
    return handles


def _tick(x: float, _pos=None) -> str:
    mantissa = round(x / 10 ** math.floor(math.log10(x))) if x > 0 else 0
    return f"{x:g}" if mantissa in (1, 2, 5) else ""


def plot_pareto(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """Error against solver wall time (log-log) of the converged runs, and their Pareto front.
    Colour: method; filled marker: augmented; marker shape: refinement."""
    from matplotlib.ticker import FuncFormatter

    fig, ax = _figure()
    ok = [r for r in rows if r["converged"] and not math.isnan(r["error"]) and not math.isnan(r["wall_time_s"])]
    t = np.array([r["wall_time_s"] for r in ok])
    e = np.maximum([r["error"] for r in ok], ERROR_FLOOR)
    for r, ti, ei in zip(ok, t, e):
        c = COLOURS[r["method"]]
        ax.plot(ti, ei, ls="", marker=MARKERS.get(r["refinement"], "o"), ms=7, mec=c,
                mfc=c if r["augment"] > 0 else "none", alpha=0.85)
    front = pareto_front(t, e)
    if len(front):
        ft, fe = np.append(t[front], t.max() * 1.15), np.append(e[front], e[front[-1]])
        ax.step(ft, fe, where="post", color="black", lw=1.2, zorder=0, label="Pareto front")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.xaxis.set_major_formatter(FuncFormatter(_tick))
    ax.xaxis.set_minor_formatter(FuncFormatter(_tick))  # 2 and 5 only: the default minor labels overlap
    ax.set_xlabel("solver wall time [s]")
    ax.set_ylabel(f"relative error of {ERROR[rows[0]['scene']] if rows else 'figure'} [-]"
                  f"  (below {ERROR_FLOOR:g} drawn at {ERROR_FLOOR:g})")
    failed = len(rows) - len(ok)
    ax.set_title(title + (f" ({failed} failed run{'s' * (failed != 1)} not shown)" if failed else ""))
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(handles=_legend_handles(rows) + ax.get_legend_handles_labels()[0], fontsize=8, loc="best")
    fig.savefig(path, dpi=110)


def plot_iterations(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """Total Newton iterations (all load steps and augmentations) against K, one line per method,
    augmentation and refinement; failed runs as crosses."""
    fig, ax = _figure()
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["method"], r["augment"] > 0, r["refinement"]), []).append(r)
    for (method, augmented, refinement), rs in groups.items():
        rs = sorted((r for r in rs if r["K"] > 0), key=lambda r: r["K"])  # vi has no K
        c = COLOURS[method]
        ok = [r for r in rs if r["converged"]]
        ax.plot([r["K"] for r in ok], [r["newton_iterations"] for r in ok], color=c, lw=1.5,
                ls="-" if augmented else "--", marker=MARKERS.get(refinement, "o"), ms=SIZES[method],
                mfc=c if augmented else "none", mec=c, alpha=0.85)
        bad = [r for r in rs if not r["converged"]]
        ax.plot([r["K"] for r in bad], [r["newton_iterations"] for r in bad], ls="", marker="x", color=c, ms=9)
    ax.set_xscale("log")
    ax.set_xlabel("K (penalty, auglag; cross: K_hat) [pressure / length]")
    ax.set_ylabel("Newton iterations, all steps and augmentations [-]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    from matplotlib.lines import Line2D

    extra = [Line2D([], [], ls="", marker="x", color="grey", label="failed")] if any(
        not r["converged"] for r in rows) else []
    ax.legend(handles=_legend_handles(rows) + extra, fontsize=8, loc="best")
    fig.savefig(path, dpi=110)


def main(argv: Sequence[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0],
                                formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--scene", action="append", choices=SCENES, help="scene (repeatable; default: all)")
    p.add_argument("--quick", action="store_true", help="small sweep")
    p.add_argument("--out", default="results/bench", help="output folder")
    p.add_argument("--timeout", type=float, default=1800.0, help="seconds per run before it counts as failed")
    p.add_argument("--charts-only", action="store_true", help="redraw the charts from <out>/<scene>.csv")
    p.add_argument("--quiet", action="store_true", help="no line per run")
    args = p.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    for scene in args.scene or SCENES:
        start = time.perf_counter()
        if args.charts_only:
            rows = read_rows(out / f"{scene}.csv")
            plot_pareto(rows, out / f"{scene}_pareto.png", title=f"{scene}: error against wall time")
            plot_iterations(rows, out / f"{scene}_iterations.png", title=f"{scene}: Newton iterations against K")
            continue
        rows = bench(scene, out, sweep(scene, args.quick), quiet=args.quiet, timeout=args.timeout)
        failed = sum(not r["converged"] for r in rows)
        _say(f"{scene}: {len(rows)} runs ({failed} failed) in {time.perf_counter() - start:.1f} s -> "
              f"{out / scene}.csv, {out / scene}_pareto.png, {out / scene}_iterations.png", flush=True)


if __name__ == "__main__":
    main()
