"""Speed against accuracy: run every method over a parameter sweep, one fresh process per run.

    python -m fenics_contact.app.bench_run --scene hertz --quick --out results/bench
    python demos/bench.py --quick --main                # make bench: the main scenes (bench_run.MAIN_SCENES)
    python demos/bench.py --quick                       # make bench-all: every scene with a BENCH entry

A scene takes part when its module defines ``BENCH`` (figure, reference
target, K scale, mesh option and levels, methods, extra demo options; see
``scenes/hertz.py``): adding a scene to the benchmark is adding that dict.
Each run is ``demos/<scene>.py --quiet --no-pictures --no-xdmf --out
<out>/<scene>/<run>`` in its own serial process; its ``summary.json``
becomes one row of ``<out>/<scene>.csv`` and ``.json``. A run that exits
non-zero (or times out) is recorded with ``converged = False``. A scene whose
demo does not take ``--method`` gives ``build`` (builder keywords) and is run
by :func:`run_scene` instead (``python -m fenics_contact.app.bench --run-scene``).
``error``: a summary key (closed form), ``"limit_gap"`` (distance of ``value``
from the ``reference`` method's on the same mesh) or ``None`` (no error
figure: convergence, iterations and time only; no error charts).

Charts: ``<scene>_pareto.png`` (error against solver wall time, Pareto
front, one linear solve as the cost floor), ``<scene>_dofs.png`` (error
against dofs), ``<scene>_iterations.png`` (Newton iterations against K);
``<scene>_findings.md`` (per method the fastest run within the scene's
target, its ratios to one linear solve and to the scene's reference method -- SNES VI unless ``BENCH['reference']``
names another, e.g. the exact ``coulomb`` of the friction scenes --, Pareto membership). The reference method's run
on each mesh is drawn on the Pareto chart as a line at its error and one at its time.
With ``stability`` in BENCH: ``<scene>_stability.csv|png|md`` (status -- converged, ill-conditioned,
failed with its kind --, Newton and Krylov iterations, condition estimate and distance from the
augmentation limit over parameter x load steps, per method) and ``<scene>_stability_accuracy.png`` (that
distance against K: the K each method needs, and whether it converges there); with ``reduction``:
``<scene>_reduction.csv|md`` and, for all such scenes, ``model_reduction.md`` (one table); with ``locking``:
``<scene>_locking.csv|md|png`` (the bulk models over Poisson's ratio, one contact method: :func:`locking`).
"""
from __future__ import annotations

import csv
import importlib
import json
import math
import os
import subprocess
import sys
import time
from importlib import resources
from pathlib import Path
from typing import Sequence

import numpy as np

from .. import methods
from .cli import EXIT_CHECK

__all__ = [
    "DEMOS", "COLUMNS", "AUGMENT", "ERROR_FLOOR", "PETSC_DTOL", "DTOL", "reference_method", "references",
    "parameter_label",
    "GAMMA0", "spec", "bench_scenes", "run_config", "sweep", "stability_sweep", "status", "run_name", "child_env",
    "command", "run_one", "RUNS", "run_all", "add_limit_gap", "bench", "report", "STABILITY_TITLE", "stability",
    "add_stability_limit", "stability_summary", "REDUCTIONS", "REDUCTION_HEADER", "reduction", "reduction_report",
    "reduction_table",
    "plot_reduction", "locking_runs", "locking_errors", "locking_table", "plot_locking", "locking_report", "locking",
    "write_rows",
    "read_rows", "findings", "convergence_findings", "pareto_front", "MARKERS", "figure",
    "plot_pareto", "plot_dofs", "plot_iterations", "KIND_SHORT", "plot_stability", "plot_stability_accuracy",
    "run_scene"
]

DEMOS = Path(str(resources.files("fenics_contact.app") / "demos"))
COLUMNS = ["scene", "method", "K", "F_hat", "augment", "quadrature", "refinement", "steps", "dofs", "wall_time_s",
           "newton_iterations", "linear_iterations", "augmentations", "converged", "cutbacks", "snes_reason",
           "error", "limit_gap", "process_time_s", "setup_time_s", "assembly_s", "linear_solve_s", "augmentation_s",
           "memory_peak_mb", "linear_solve_floor_s", "ratio_to_linear_solve", "search_s", "exchange_s", "coupling_s"]
AUGMENT = 10  # max augmentations per load step for the augmented variants
ERROR_FLOOR = 1e-16  # errors are drawn at least this large on the log axis (an exact answer is 0)
PETSC_DTOL = ["-fc_snes_convergence_test", "default", "-fc_snes_divergence_tolerance", "1e4"]  # PETSc's own test
DTOL = "penalty, PETSc divergence test on"  # the stability map's control runs (dtol 1e4, PETSc's default)
GAMMA0 = {"quick": (10.0, 100.0), "full": (3.0, 10.0, 30.0, 100.0, 1000.0)}  # nitsche: in the K column


def reference_method(scene: str) -> tuple[str, str]:
    """The method the scene's runs are measured against (``BENCH['reference']``, default SNES VI) and its name in
    the findings."""
    ref = spec(scene).get("reference", "vi")
    if ref == "vi":
        return ref, "SNES VI"
    # a method, or a variant of one such as "auglag augmented" (its name is the method's and "augmented")
    return ref, f"the exact {ref}" if ref in methods.names() and methods.get(ref).sweep.kind == "once" else ref


def references() -> tuple[str, ...]:
    """The methods a user would pick instead of the suite's penalty-type laws (their declarations' ``sweep``)."""
    return tuple(m.name for m in methods.methods() if m.sweep.reference)


def parameter_label(method: str) -> str:
    """The name of the parameter the benchmark sweeps for ``method`` (the K column's meaning), ``-`` if none."""
    return methods.get(method).sweep.parameter or "-"


def _benches() -> dict[str, dict]:
    """Every benchmark by name: a scene module's ``BENCH`` under the scene's name, and each entry of its
    ``BENCHES`` (name -> dict with ``demo``: the scene's demo it runs, e.g. a two-body variant of the scene)."""
    from .scenes import scene_names

    found = {}
    for n in scene_names():
        module = importlib.import_module(f"fenics_contact.app.scenes.{n}")
        if hasattr(module, "BENCH"):
            found[n] = module.BENCH
        found.update(getattr(module, "BENCHES", {}))
    return found


def spec(scene: str) -> dict:
    """The benchmark ``scene``'s dict (``ValueError`` naming the benchmarks if there is none)."""
    benches = _benches()
    if scene not in benches:
        raise ValueError(f"unknown benchmark scene {scene!r}; accepted: {', '.join(benches)}")
    return benches[scene]


def bench_scenes() -> list[str]:
    """Every benchmark: the scenes whose module defines ``BENCH``, and their ``BENCHES`` entries."""
    return list(_benches())


def run_config(method, K, augment=0, quadrature="nodal", refinement=None, F_hat=0.0, steps=None) -> dict:
    """One run of a sweep: the method, its parameter K (or gamma0), augmentations, quadrature, mesh level,
    cross-constraint F_hat and load steps."""
    return dict(method=method, K=float(K), F_hat=F_hat, augment=augment, quadrature=quadrature, refinement=refinement,
                steps=steps)


def sweep(scene: str, quick: bool = False, main: bool = False) -> list[dict]:
    """The runs for ``scene``: penalty over a log range of K (no augmentation); cross and auglag, each with
    and without augmentation, over a smaller K range; nitsche over ``gamma0`` (in the K column); SNES VI
    once per mesh level. Quick: nodal quadrature, the quick mesh levels; full: nodal and Gauss. ``BENCH``'s
    ``quick_sweep`` may set the quick exponents (``penalty``, ``other``), ``gamma0`` and ``augment`` (the
    augmentation counts of cross and auglag, e.g. ``(0,)``: plain only). Main (``make bench``; a quick sweep):
    ``BENCH``'s ``main`` may keep fewer mesh ``levels`` and ``quadratures`` of the quick sweep."""
    s = spec(scene)
    quick = quick or main
    K0, mode, methods_of_scene, F = s["K"], "quick" if quick else "full", s["methods"], s.get("F_hat", 0.0)
    if quick:
        q = {"penalty": (-1, 0, 1, 2), "other": (0, 1), "gamma0": GAMMA0["quick"], "augment": (0, AUGMENT),
             **s.get("quick_sweep", {})}
        quadratures = s.get("quadratures", ["nodal"])
    else:
        q = {"penalty": tuple(np.arange(-3, 3.01, 0.5)), "other": tuple(range(-2, 3)), "gamma0": GAMMA0["full"],
             "augment": (0, AUGMENT)}
        quadratures = s.get("quadratures", ["nodal", "gauss"])
    levels = [None] if s.get("mesh") is None else s["mesh"][1][mode]
    if main:
        levels, quadratures = s.get("main", {}).get("levels", levels), s.get("main", {}).get("quadratures", quadratures)
    declared = {m: methods.get(m) for m in methods.names() if m in methods_of_scene}
    by_kind = {k: [m for m, d in declared.items() if d.sweep.kind == k] for k in ("wide", "narrow", "gamma0", "once")}
    narrow = [m for m in methods_of_scene if m in by_kind["narrow"]]  # the scene's order
    runs = []
    for level in levels:
        for quad in quadratures:
            runs += [run_config(m, K0 * 10.0**e, 0, quad, level) for m in by_kind["wide"] for e in q["penalty"]]
            runs += [run_config(m, K0 * 10.0**e, aug, quad, level, F if m == "cross" else 0.0)
                     for m in narrow if declared[m].sweep.augmented for aug in q["augment"] for e in q["other"]]
            runs += [run_config(m, g, 0, quad, level) for m in by_kind["gamma0"] for g in q["gamma0"]]
            # further laws of the scene: with a parameter (K / c_n) over the small range
            runs += [run_config(m, K0 * 10.0**e, 0, quad, level) for m in narrow if not declared[m].sweep.augmented
                     for e in q["other"]]
        # methods without a parameter (K = 0 in the rows): once per mesh, nodal
        runs += [run_config(m, 0.0, 0, "nodal", level) for m in by_kind["once"]]
    return [r for r in runs if _offered(s, r)]


def _offered(s: dict, run: dict) -> bool:
    """False if the capability matrix refuses the run (``BENCH``'s ``axes``: the scene's fixed axes, e.g.
    ``kind``, ``dim``): a sweep over quadratures leaves out the method-quadrature pairs the suite refuses."""
    from ..capabilities import supported

    return supported(method=run["method"], quadrature=run["quadrature"], **s.get("axes", {}))


def stability_sweep(scene: str, quick: bool = False) -> list[dict]:
    """Parameter x load steps on the coarsest mesh, the scene's first quadrature: penalty (K), cross and auglag
    augmented (K), nitsche (gamma0); K from the scene's K to 1e8 times it (quick) or 1e-2 to 1e8 times it (full).
    ``BENCH``'s ``quick_stability`` may set the quick grid (``K`` exponents, ``steps``, ``gamma0``, ``variants``:
    (method, augmentations[, F_hat]) tuples, ``dtol``: the control runs with PETSc's divergence test (fewest load steps
    only), ``skip``: (method, K exponent) pairs left out, e.g. a slow failure);
    ``stability_variants``: the full grid's variants; ``stability_args``: demo options of the map's runs (after
    ``demo_args``: they win, e.g. a heavier load than the accuracy rows'). Every run asks for the condition
    estimate of its last Jacobian (direct solvers)."""
    s = spec(scene)
    K0 = s["K"]
    level = None if s.get("mesh") is None else s["mesh"][1]["quick"][0]
    quad = s.get("quadratures", ["nodal"])[0]  # the scene's first (a P2 mixed scene refuses nodal)
    q = s.get("quick_stability", {})
    if quick:
        exps, steps = q.get("K", (0, 2, 4, 6, 8)), q.get("steps", (1, 4))
        gammas = q.get("gamma0", (1.0, 10.0, 1e2, 1e4))
    else:
        exps, steps, gammas = tuple(range(-2, 9)), (1, 2, 4, 8), (0.3, 1.0, 3.0, 10.0, 100.0, 1e3, 1e4, 1e5, 1e6)
    variants = q.get("variants", (("penalty", 0), ("cross", AUGMENT), ("auglag", AUGMENT))) if quick else \
        s.get("stability_variants", (("penalty", 0), ("cross", AUGMENT), ("auglag", AUGMENT)))
    runs = []
    for n in steps:
        for method, aug, *F in variants:
            F_hat = F[0] if F else 0.0
            label = {"label": f"{method} F^ = {F_hat:g}" + (" augmented" if aug else "")} if F_hat else {}
            runs += [dict(run_config(method, K0 * 10.0**e, aug, quad, level, F_hat, steps=n), **label) for e in exps
                     if not quick or (method, e) not in q.get("skip", ())]
        runs += [run_config(m, g, 0, quad, level, steps=n) for m in methods.names()
                 if methods.get(m).sweep.kind == "gamma0" for g in gammas]
        # the control: penalty with PETSc's own divergence test (residual > 1e4 x the first one at any iterate stops
        # SNES; the solver's test also asks for growth), which stops every K-based method at its first iterate
        # when K is very large
        runs += [dict(run_config("penalty", K0 * 10.0**e, 0, quad, level, steps=n), label=DTOL, args=PETSC_DTOL)
                 for e in exps                 if q.get("dtol", True) and n == steps[0]]
    return [dict(r, args=[*s.get("stability_args", []), *r.get("args", []), "-fc_condition_estimate"]) for r in runs
            if r["method"] in s["methods"]]


def status(row: dict) -> str:
    """``converged``, ``ill_conditioned`` (converged, but a solve stalled at the round-off floor
    (:func:`failure.stalled`) or the last Jacobian's condition estimate is above ``failure.ILL_CONDITIONED``)
    or ``failed: <kind>`` (:func:`failure.classify`'s kind; ``exit`` if the run left no diagnosis)."""
    from ..failure import ILL_CONDITIONED

    if not row["converged"]:
        return f"failed: {row.get('failure_kind') or 'exit'}"
    cond = row.get("condition_estimate")
    if row.get("stalled_solves", 0) > 0 or (cond is not None and not math.isnan(cond) and cond > ILL_CONDITIONED):
        return "ill_conditioned"
    return "converged"


def _say(line: str) -> None:
    """One progress line, from rank 0 only (the tests run the harness on every rank of an mpirun job)."""
    from mpi4py import MPI

    if MPI.COMM_WORLD.rank == 0:
        sys.stdout.write(line + "\n")
        sys.stdout.flush()


def run_name(cfg: dict) -> str:
    ref = "" if cfg.get("refinement") is None else f"_r{cfg['refinement']}"
    steps = "" if cfg.get("steps") is None else f"_s{cfg['steps']}"
    label = "" if not cfg.get("label") else "_" + "".join(c if c.isalnum() else "-" for c in cfg["label"])
    return (f"{cfg['method']}_K{cfg['K']:.3g}_F{cfg['F_hat']:g}_aug{cfg['augment']}_{cfg['quadrature']}"
            f"{ref}{steps}{label}")


def child_env() -> dict:
    """The environment without MPI launcher variables: a demo started from a rank of an ``mpirun``
    job (e.g. the tests under ``mpirun -n 2``) must start as its own serial job, not join ours."""
    return {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_", "MPI_LOCALNRANKS"))}


def command(scene: str, cfg: dict, folder: Path) -> list[str]:
    """The demo command line of one run (scene options from ``BENCH``; the run's own options last, so they win)."""
    s = spec(scene)
    script = ["-m", "fenics_contact.app.bench_run", "--run-scene", scene] if "build" in s else \
        [str(DEMOS / f"{s.get('demo', scene)}.py")]
    cmd = [sys.executable, *script, "--quiet", "--no-pictures", "--no-xdmf", "--out", str(folder), "--overwrite",
           "--method", cfg["method"], "--augment", str(cfg["augment"]), "--quadrature", cfg["quadrature"],
           *s.get("demo_args", []), *s.get("method_args", {}).get(cfg["method"], [])]
    method = methods.get(cfg["method"])
    if method.sweep.parameter is not None:  # the swept parameter (a method without one: nothing to give)
        cmd += [f"--{method.sweep.parameter.replace('_', '-')}", repr(cfg["K"])]
        if any(p.option == "F_hat" for p in method.parameters):
            cmd += ["--F-hat", repr(cfg["F_hat"])]
    if cfg.get("refinement") is not None:
        cmd += [f"--{s['mesh'][0]}", str(cfg["refinement"])]
    if cfg.get("steps") is not None:
        cmd += ["--steps", str(cfg["steps"])]
    return cmd + list(cfg.get("args", []))


def run_one(scene: str, cfg: dict, folder: Path, timeout: float = 1800.0) -> dict:
    """Run one demo in a fresh process into ``folder``; return its row (never raises on a failed run)."""
    folder.mkdir(parents=True, exist_ok=True)
    (folder / "summary.json").unlink(missing_ok=True)
    start = time.perf_counter()
    try:
        proc = subprocess.run(command(scene, cfg, folder), capture_output=True, text=True, timeout=timeout,
                              env=child_env())
        # a run whose own check failed (EXIT_CHECK) has solved: the sweep measures its error itself
        ok, log = proc.returncode in (0, EXIT_CHECK), proc.stdout + proc.stderr
    except subprocess.TimeoutExpired as exc:
        ok, log = False, f"timeout after {timeout} s\n{exc.stdout or ''}{exc.stderr or ''}"
    (folder / "log.txt").write_text(log if isinstance(log, str) else log.decode(errors="replace"))
    s = json.loads((folder / "summary.json").read_text()) if (folder / "summary.json").exists() else {}
    nan, b = float("nan"), spec(scene)
    steps = s.get("steps", [])
    row = {"scene": scene, **{k: v for k, v in cfg.items() if k != "args"}, "dofs": s.get("dofs", 0),
            "wall_time_s": s.get("wall_time_s", nan), "newton_iterations": s.get("newton_iterations", 0),
            "augmentations": s.get("augmentations", 0), "linear_iterations": s.get("linear_iterations", 0),
            "converged": bool(ok and s.get("converged", False)),
            "cutbacks": sum(not st["converged"] for st in steps),
            "snes_reason": steps[-1]["snes_reason"] if steps else 0,
            "error": s.get(b["error"], nan), "limit_gap": nan,
            "process_time_s": time.perf_counter() - start, "setup_time_s": s.get("setup_time_s", nan),
            **{k: s.get("time_split", {}).get(k, nan) for k in ("assembly_s", "linear_solve_s", "augmentation_s",
                                                                  "search_s", "exchange_s", "coupling_s")},
            **{k: s.get(k, nan) for k in ("memory_peak_mb", "linear_solve_floor_s", "ratio_to_linear_solve")},
            "condition_estimate": nan if s.get("condition_estimate") is None else s["condition_estimate"],
            "stalled_solves": s.get("stalled_solves", 0), "residual_final": s.get("residual_final") or nan,
            "failure_kind": (s.get("failure") or {}).get("kind", "" if s.get("converged") else "exit"),
            **{k: s.get(k, nan) for k in dict.fromkeys([b["value"], *b.get("figures", [])])}}
    return {**row, "status": status(row)}


RUNS = {"runs": 0, "failed": 0}  # the runs of this process so far and those that failed (the sweep's time table)


def _tally(row: dict) -> dict:
    RUNS["runs"] += 1
    RUNS["failed"] += not row["converged"]
    return row


def run_all(scene: str, out: Path, runs: Sequence[dict], quiet: bool, timeout: float, tag: str = "") -> list[dict]:
    rows = []
    for i, cfg in enumerate(runs):
        row = _tally(run_one(scene, cfg, out / scene / run_name(cfg), timeout))
        rows.append(row)
        if not quiet:
            _say(f"[{scene}{tag} {i + 1}/{len(runs)}] {run_name(cfg):44s} converged {row['converged']!s:5s} "
                 f"newton {row['newton_iterations']:3d} error {row['error']:.3e} time {row['wall_time_s']:.3f} s")
    return rows


def add_limit_gap(rows: Sequence[dict], scene: str) -> None:
    """``limit_gap``: relative distance of the scene's figure from SNES VI's (or ``BENCH['reference']``'s) on the
    same mesh (the limit of converged augmentation), where both exist: it tells a truly converged method from a
    lucky one. With ``BENCH['error'] == 'limit_gap'`` it is also the run's error."""
    s = spec(scene)
    value, method = s.get("value"), s.get("reference", "vi")
    vi = {r["refinement"]: r[value] for r in rows if method in (r["method"], _variant(r)) and r["converged"]
          and value in r}  # a method name, or a variant such as "auglag augmented" (then its last converged run)
    for r in rows:
        ref = vi.get(r["refinement"])
        if ref and value in r and not math.isnan(r[value]):
            r["limit_gap"] = abs(r[value] - ref) / abs(ref)
        if s.get("error") == "limit_gap":  # the scene's error is this distance (no closed form)
            r["error"] = r["limit_gap"] if r["converged"] else float("nan")


def bench(scene: str, out: str | Path, runs: Sequence[dict], pictures: bool = True, quiet: bool = False,
          timeout: float = 1800.0) -> list[dict]:
    """Run ``runs`` for ``scene`` into ``out/<scene>/``; write ``out/<scene>.csv``, ``.json``, the charts
    and ``<scene>_findings.md``."""
    out = Path(out)
    rows = run_all(scene, out, runs, quiet, timeout)
    add_limit_gap(rows, scene)
    write_rows(rows, out / f"{scene}.csv", out / f"{scene}.json")
    report(scene, rows, out, pictures)
    return rows


def report(scene: str, rows: Sequence[dict], out: Path, pictures: bool = True) -> str:
    """Charts and the findings table of a scene's rows; returns the findings (Markdown)."""
    text = findings(scene, rows)
    (out / f"{scene}_findings.md").write_text(text)
    if pictures and spec(scene)["error"] is not None:  # no error figure: no error charts
        plot_pareto(rows, out / f"{scene}_pareto.png", title=f"{scene}: error against solver time")
        plot_dofs(rows, out / f"{scene}_dofs.png", title=f"{scene}: error against dofs")
    if pictures:
        plot_iterations(rows, out / f"{scene}_iterations.png", title=f"{scene}: Newton iterations against K")
    return text


STABILITY_TITLE = ("{scene}: Newton iterations (colour); x = failed (kind), ill = ill-conditioned, c = cutbacks, "
                   "(k) Krylov per Newton, e = distance from the augmentation limit")


def stability(scene: str, out: str | Path, quick: bool = False, pictures: bool = True, quiet: bool = False,
              timeout: float = 600.0) -> list[dict]:
    """The stability map: :func:`stability_sweep` into ``<scene>_stability.csv|json|png|md``; each row gets
    its :func:`status` and its ``limit_gap`` (distance of the scene's figure from the augmentation limit:
    the median of the converged ``auglag augmented`` runs)."""
    out = Path(out)
    rows = run_all(scene, out, stability_sweep(scene, quick), quiet, timeout, tag=" stability")
    add_stability_limit(rows, scene)
    write_rows(rows, out / f"{scene}_stability.csv", out / f"{scene}_stability.json")
    (out / f"{scene}_stability.md").write_text(stability_summary(rows))
    if pictures:
        plot_stability(rows, out / f"{scene}_stability.png", title=STABILITY_TITLE.format(scene=scene))
        plot_stability_accuracy(rows, out / f"{scene}_stability_accuracy.png",
                                title=f"{scene}: the K each method needs, and whether it converges there")
    return rows


def add_stability_limit(rows: Sequence[dict], scene: str) -> None:
    """``limit_gap`` of the stability rows: relative distance of the scene's figure from the limit of
    converged augmentation (median over the converged ``auglag augmented`` runs, which agree to their
    augmentation tolerance); NaN without such runs."""
    value = spec(scene)["value"]
    ref = [r[value] for r in rows if _variant(r) == "auglag augmented" and r["converged"]
           and not math.isnan(r.get(value, float("nan")))]
    limit = float(np.median(ref)) if ref else float("nan")
    for r in rows:
        v = r.get(value, float("nan"))
        r["limit_gap"] = abs(v - limit) / abs(limit) if r["converged"] and limit and not math.isnan(v) else \
            float("nan")


def stability_summary(rows: Sequence[dict]) -> str:
    """Markdown: per method variant, the parameters at which it converged for every step count, those at
    which it was ill-conditioned or failed (with the kind), the Newton and Krylov iterations, the condition
    estimate and the distance from the augmentation limit over the parameter (fewest load steps)."""
    lines = ["| method | parameter | converged for all load steps at | ill-conditioned at | failed at (kind) | "
             "Newton iterations (fewest steps) | Krylov per Newton | condition estimate | distance from the "
             "augmentation limit |", "|---|---|---|---|---|---|---|---|---|"]
    for variant in dict.fromkeys(_variant(r) for r in rows):
        rs = [r for r in rows if _variant(r) == variant]
        params = sorted({r["K"] for r in rs})
        st = {p: [status(r) for r in rs if r["K"] == p] for p in params}
        good = [p for p in params if all(x == "converged" for x in st[p])]
        ill = [p for p in params if p not in good and all(x != "failed" and not x.startswith("failed") for x in st[p])]
        bad = {p: next(x for x in st[p] if x.startswith("failed"))[8:] for p in params if p not in good + ill}
        fewest = min(r["steps"] or 1 for r in rs)
        its = [next((r for r in rs if r["K"] == p and (r["steps"] or 1) == fewest), None) for p in params]
        lines.append(
            f"| {variant} | {parameter_label(rs[0]['method'])} | "
            f"{', '.join(f'{p:.0e}' for p in good) or '-'} | {', '.join(f'{p:.0e}' for p in ill) or '-'} | "
            f"{', '.join(f'{p:.0e} ({k})' for p, k in bad.items()) or '-'} | "
            f"{' / '.join(str(r['newton_iterations']) if r and r['converged'] else 'x' for r in its)} | "
            f"{' / '.join(_krylov_per_newton(r) for r in its)} | "
            f"{' / '.join(_short(r.get('condition_estimate') if r else None) for r in its)} | "
            f"{' / '.join(_short(r.get('limit_gap') if r else None) for r in its)} |")
    return "\n".join(lines) + "\n"


def _short(x: float | None) -> str:
    return "-" if x is None or math.isnan(x) else ("0" if x == 0 else f"{x:.0e}")


def _krylov_per_newton(r: dict | None) -> str:
    if not r or not r["converged"] or not r["newton_iterations"]:
        return "-"
    return f"{r['linear_iterations'] / r['newton_iterations']:.0f}"


def _snes_reasons() -> dict:
    from petsc4py import PETSc

    return {k: v for k, v in vars(PETSc.SNES.ConvergedReason).items() if isinstance(v, int)}


# Model-reduction checks: the reduced model (used by the scene, first) against richer ones, same method. Per scene:
# the run (method, augmentations, quadrature, extra demo options), the figures compared, timing repeats, variants.
REDUCTIONS = {
    "hertz": {"method": "auglag", "augment": AUGMENT, "quadrature": "nodal", "args": [], "repeats": 2,
              "figures": ["p0", "a", "total_force"], "variants": [
                  ("hertz: quarter disk, rigid analytic plate, linear elasticity (used)", []),
                  ("hertz: half disk (no mirror about x = 0)", ["--symmetry", "half"]),
                  ("hertz: full disk between two rigid plates (no mirror; rigid modes fixed at 3 points)",
                   ["--symmetry", "full"]),
                  ("hertz: meshed plate, E x 1000, two-body contact (not rigid)", ["--plate", "meshed"]),
                  ("hertz: neo-Hookean (finite strain)", ["--model", "neohookean"])]},
    # the sphere on its meridian section (r, z) against the 3D octant: the same mesh size at the contact (level 0),
    # and the octant's level 1, whose p0 error is the section's at level 0 (2.1 %); the octant with the scene's
    # iterative solver (GMRES + GAMG), the axisymmetric section with LU; the fastest of 2 runs each (their ratio is the
    # acceptance figure: one run of each on a shared machine scatters by a factor of 2 and more)
    "sphere": {"method": "auglag", "augment": AUGMENT, "quadrature": "nodal", "args": [], "repeats": 2,
               "figures": ["p0", "a", "total_force"], "variants": [
                   ("sphere: axisymmetric meridian section (r, z), 2 pi r weights (used)",
                    ["--geometry", "axisymmetric", "--solver", "direct"]),
                   ("sphere: axisymmetric, 1/4 of the mesh size at the contact (h = R/400)",
                    ["--geometry", "axisymmetric", "--solver", "direct", "--size", "0.125"]),
                   ("sphere: 3D octant (symmetry x = 0, y = 0)", []),
                   ("sphere: 3D octant, level 1 (the p0 error of the axisymmetric section)", ["--level", "1"])]},
    # the scene's own method (penalty K 1e4, two-pass, Gauss points) at the Hertz step t = 0.2
    "cylinders": {"method": "penalty", "augment": 0, "quadrature": "gauss", "args": [], "repeats": 1,
                  "figures": ["p0", "a", "total_force"], "variants": [
                      ("cylinders: right halves, neo-Hookean (used)", []),
                      ("cylinders: whole disks (no mirror about x = 0; u_x = 0 at the poles)", ["--symmetry", "full"]),
                      ("cylinders: linear elasticity (small strain) at t = 0.2", ["--model", "linear"])]},
}
REDUCTION_HEADER = ["| variant | dofs | p0 | a | total force | p0 / a error vs Hertz | difference of p0 / a / force "
                    "from the reduced model | solver time [s] | peak memory [MB] | time saved by the reduced model |",
                    "|---|---|---|---|---|---|---|---|---|---|"]


def reduction(scene: str, out: str | Path, quiet: bool = False, timeout: float = 600.0,
              pictures: bool = True) -> str:
    """Model-reduction rows of ``scene`` (``REDUCTIONS[scene]``, the scene's K, coarsest mesh), all in this one
    run: each variant's figures, its ``p0`` and ``a`` errors against Hertz, their differences from the first
    variant (the reduced model the scene uses), the solver time (the fastest of the scene's ``repeats`` runs),
    the run's peak memory (the process's resident set, MB) and the time saved. Writes ``<scene>_reduction.csv``,
    ``.md`` and the chart ``<scene>_reduction.png`` (:func:`plot_reduction`); returns the Markdown rows (without
    the header, :data:`REDUCTION_HEADER`)."""
    out, s, r0 = Path(out), spec(scene), REDUCTIONS[scene]
    level = None if s.get("mesh") is None else s["mesh"][1]["quick"][0]
    keys = r0["figures"]
    rows = []
    for label, args in r0["variants"]:
        cfg = dict(run_config(r0["method"], s["K"], r0["augment"], r0["quadrature"], level), args=[*r0["args"], *args])
        folder = out / scene / ("reduction_" + "".join(c if c.isalnum() else "-" for c in label.split(": ")[1])[:60])
        # the fastest of `repeats` runs: single timings on a shared machine are too noisy to subtract
        row = min((_tally(run_one(scene, cfg, folder, timeout)) for _ in range(r0["repeats"])),
                  key=lambda r: r["wall_time_s"])
        rows.append({"variant": label, **row})
        if not quiet:
            _say(f"[{scene} reduction] {label[:60]:60s} converged {row['converged']!s:5s} error {row['error']:.3e}")
    text, table = reduction_table(rows, keys)
    with open(out / f"{scene}_reduction.csv", "w", newline="") as f:
        w = csv.DictWriter(f, list(table[0]))
        w.writeheader()
        w.writerows(table)
    return reduction_report(scene, out, pictures)


def reduction_report(scene: str, out: str | Path, pictures: bool = True) -> str:
    """``<scene>_reduction.md`` and ``.png`` from ``<scene>_reduction.csv`` (:func:`reduction`'s table); returns
    the Markdown rows."""
    out = Path(out)
    with open(out / f"{scene}_reduction.csv", newline="") as f:
        rows = [{k: v if k == "variant" else v == "True" if k == "converged" else float(v) for k, v in r.items()}
                for r in csv.DictReader(f)]
    text, table = reduction_table([dict(r, dofs=int(r["dofs"]), newton_iterations=int(r["newton_iterations"]))
                                   for r in rows], REDUCTIONS[scene]["figures"])
    (out / f"{scene}_reduction.md").write_text("\n".join(REDUCTION_HEADER) + "\n" + text)
    if pictures:
        plot_reduction(table, out / f"{scene}_reduction.png",
                       title=f"{scene}: model reduction, error against solver time and peak memory")
    return text


def reduction_table(rows: Sequence[dict], keys: Sequence[str]) -> tuple[str, list[dict]]:
    """The Markdown rows (under :data:`REDUCTION_HEADER`) and the table of the variants' ``rows`` (each a
    :func:`run_one` row with its ``variant``; the first is the reduced model): figures ``keys``, ``p0`` and ``a``
    errors against Hertz, differences from the reduced model, solver time, peak memory, time saved (with the
    ratio ``1/n`` where the variant takes at least twice as long)."""
    base = rows[0]
    lines, table = [], []
    for r in rows:
        diff = [abs(r[k] - base[k]) / abs(base[k]) for k in keys]
        ratio = r["wall_time_s"] / base["wall_time_s"]  # this variant's time per the reduced model's
        a_error = r.get("a_error", float("nan"))
        table.append({"variant": r["variant"], "dofs": r["dofs"], **{k: r[k] for k in keys}, "error": r["error"],
                      "a_error": a_error, **{f"diff_{k}": d for k, d in zip(keys, diff)},
                      "wall_time_s": r["wall_time_s"], "memory_peak_mb": r["memory_peak_mb"],
                      "time_saved": 1 - 1 / ratio, "converged": r["converged"],
                      "newton_iterations": r["newton_iterations"]})
        share = 1 - 1 / ratio  # one decimal from 99.5 % on: never a 100 % saved
        saved = "-" if r is base else (f"{share:.{0 if share < 0.995 else 1}%}"
                                       + (f" (1/{ratio:.0f})" if ratio >= 2 else ""))
        lines.append(f"| {r['variant']} | {r['dofs']} | " + " | ".join(f"{r[k]:.5g}" for k in keys)
                     + f" | {r['error']:.3%} / {a_error:.3%} | " + " / ".join(f"{d:.2%}" for d in diff)
                     + f" | {r['wall_time_s']:.3f} | {r['memory_peak_mb']:.0f} | {saved} |"
                     + ("" if r["converged"] else " (did not converge)"))
    return "\n".join(lines) + "\n", table


# Volumetric locking: a scene's BENCH["locking"]: ``method`` (one contact method, its K the scene's), ``quadrature``,
# ``nu`` (the ratios), ``figures`` (summary keys), ``variants`` (label, demo options: the bulk models and degrees
# compared), ``reference`` (label, demo options: the run each variant is measured against at the same ``nu``, e.g.
# the mixed model on a fine mesh), ``args`` (demo options of every run). Each run is a fresh serial demo process.


def locking_runs(scene: str) -> list[dict]:
    """The locking runs of ``scene``: every variant and the reference at every ``nu``, each a
    :func:`run_config` with its ``variant`` (the label of its variant), ``nu``, demo
    options ``args`` and a ``label`` naming both (its run's folder)."""
    s = spec(scene)
    lk = s["locking"]
    out = []
    for nu in lk["nu"]:
        for label, args in (*lk["variants"], lk["reference"]):
            cfg = run_config(lk["method"], s["K"], 0, lk["quadrature"])
            out.append(dict(cfg, label=f"{label}, nu = {nu:g}", variant=label, nu=nu,
                            args=[*lk.get("args", []), *args, "--nu", repr(nu)]))
    return out


def locking_errors(rows: Sequence[dict], scene: str) -> list[dict]:
    """Per run but the references: its figures' relative errors against the reference run at the same ``nu``
    (``<figure>_error``; NaN where either did not converge)."""
    lk = spec(scene)["locking"]
    ref_label = lk["reference"][0]
    refs = {r["nu"]: r for r in rows if r["variant"] == ref_label}
    out = []
    for r in rows:
        if r["variant"] == ref_label:
            continue
        ref = refs.get(r["nu"])
        e = {}
        for f in lk["figures"]:
            ok = r["converged"] and ref is not None and ref["converged"] and ref[f]
            e[f"{f}_error"] = abs(r[f] - ref[f]) / abs(ref[f]) if ok else float("nan")
        out.append({**r, **e})
    return out


def locking_table(rows: Sequence[dict], scene: str) -> str:
    """Markdown: per variant (rows) and ``nu`` (columns) the errors of the figures against the reference, the
    Newton iterations and the solver time; then the reference's figures."""
    lk = spec(scene)["locking"]
    nus = list(lk["nu"])
    figs = lk["figures"]
    head = "| model | " + " | ".join(f"nu = {nu:g}" for nu in nus) + " |"
    lines = [f"Errors of {' / '.join(figs)} against {lk['reference'][0]} at the same nu; Newton iterations, "
             "solver time [s]. Method " + f"{lk['method']}, {lk['quadrature']}.", "", head,
             "|---|" + "---|" * len(nus)]
    err = locking_errors(rows, scene)
    for label, _ in lk["variants"]:
        cells = []
        for nu in nus:
            r = next((x for x in err if x["variant"] == label and x["nu"] == nu), None)
            if r is None:
                cells.append("-")
            elif not r["converged"]:
                cells.append(f"failed ({r.get('failure_kind') or 'exit'})")
            else:
                cells.append(" / ".join(f"{r[f + '_error']:.1%}" for f in figs)
                             + f"; {r['newton_iterations']} it, {r['wall_time_s']:.2g} s")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    refs = {r["nu"]: r for r in rows if r["variant"] == lk["reference"][0]}
    lines.append(f"| {lk['reference'][0]}: " + " / ".join(figs) + " | " + " | ".join(
        " / ".join(f"{refs[nu][f]:.5g}" for f in figs) if nu in refs and refs[nu]["converged"] else "failed"
        for nu in nus) + " |")
    return "\n".join(lines) + "\n"


def plot_locking(rows: Sequence[dict], scene: str, path: str | Path) -> None:
    """The errors of each variant's figures against ``1 - 2 nu`` (log-log; one colour per variant, a marker per
    figure); failed runs as red crosses at the top."""
    lk = spec(scene)["locking"]
    fig, ax = figure()
    err = locking_errors(rows, scene)
    finite = [r[f + "_error"] for r in err for f in lk["figures"] if not math.isnan(r[f + "_error"])]
    top = max(finite, default=1.0) * 2
    for k, (label, _) in enumerate(lk["variants"]):
        rs = sorted((r for r in err if r["variant"] == label), key=lambda r: -r["nu"])
        for f, m in zip(lk["figures"], "os^D"):
            ok = [r for r in rs if not math.isnan(r[f + "_error"])]
            ax.plot([1 - 2 * r["nu"] for r in ok], [max(r[f + "_error"], ERROR_FLOOR) for r in ok],
                    color=f"C{k}", marker=m, ls="-", label=f"{label}: {f}")
        bad = [r for r in rs if not r["converged"]]
        ax.plot([1 - 2 * r["nu"] for r in bad], [top] * len(bad), ls="", marker="x", color="red", ms=10, mew=2)
    if any(not r["converged"] for r in err):
        ax.plot([], [], ls="", marker="x", color="red", ms=10, mew=2, label="failed (drawn at the top)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.invert_xaxis()  # toward incompressibility to the right
    ax.set_xlabel("1 - 2 nu [-] (0: incompressible)")
    ax.set_ylabel(f"relative error against {lk['reference'][0]} [-]")
    ax.set_title(f"{scene}: locking of the displacement-only models", fontsize=10)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7, loc="best")
    fig.savefig(path, dpi=100)


def locking_report(scene: str, rows: Sequence[dict], out: str | Path, pictures: bool = True) -> str:
    """``<scene>_locking.md`` (and ``.png``) from ``rows``; returns the table."""
    out = Path(out)
    text = locking_table(rows, scene)
    (out / f"{scene}_locking.md").write_text(text)
    if pictures:
        plot_locking(rows, scene, out / f"{scene}_locking.png")
    return text


def locking(scene: str, out: str | Path, quiet: bool = False, timeout: float = 600.0,
            pictures: bool = True) -> list[dict]:
    """Run :func:`locking_runs` into ``out/<scene>/``; write ``<scene>_locking.csv``, ``.json``, ``.md`` and ``.png``
    (:func:`read_rows` reads the ``.csv`` back)."""
    out = Path(out)
    rows = run_all(scene, out, locking_runs(scene), quiet, timeout, tag=" locking")
    write_rows(rows, out / f"{scene}_locking.csv", out / f"{scene}_locking.json")
    locking_report(scene, rows, out, pictures)
    return rows


def write_rows(rows: Sequence[dict], csv_path: Path, json_path: Path) -> None:
    columns = COLUMNS + [k for k in dict.fromkeys(k for r in rows for k in r) if k not in COLUMNS]
    with open(csv_path, "w", newline="") as f:
        w = csv.DictWriter(f, columns)
        w.writeheader()
        w.writerows({k: ("" if r.get(k) is None else r.get(k, "")) for k in columns} for r in rows)
    # JSON has no NaN: a missing figure is null.
    clean = [{k: (None if isinstance(v, float) and math.isnan(v) else v) for k, v in r.items()} for r in rows]
    json_path.write_text(json.dumps(clean, indent=1) + "\n")


def read_rows(csv_path: str | Path) -> list[dict]:
    """The rows of a ``<scene>.csv`` with their types back."""
    ints = {"augment", "dofs", "newton_iterations", "linear_iterations", "augmentations", "cutbacks", "snes_reason",
            "stalled_solves"}
    texts = {"scene", "method", "quadrature", "label", "variant", "failure_kind", "status"}
    rows = []
    with open(csv_path, newline="") as f:
        for r in csv.DictReader(f):
            r = dict(r)
            for k, v in r.items():
                if k in texts:
                    continue
                if k in ("refinement", "steps"):  # a mesh level, or a mesh size (e.g. --h-contact)
                    r[k] = None if v == "" else int(v) if v.lstrip("-").isdigit() else float(v)
                elif k == "converged":
                    r[k] = v == "True"
                elif k in ints:
                    r[k] = int(v)
                else:
                    r[k] = float(v) if v != "" else float("nan")
            rows.append(r)
    return rows


def findings(scene: str, rows: Sequence[dict]) -> str:
    """Markdown: per mesh level and method variant, the fastest converged run within the scene's target
    error (else its most accurate run), with its ratios to one linear solve and to the reference method
    (:func:`reference_method`), and whether it is on the Pareto front; then the headline (the fastest method within
    the target against the reference)."""
    s = spec(scene)
    if s["error"] is None:
        return convergence_findings(rows)
    target = s.get("target", 0.01)
    ok = [r for r in rows if r["converged"] and not math.isnan(r["error"])]
    front = {id(ok[i]) for i in pareto_front([r["wall_time_s"] for r in ok], [r["error"] for r in ok])}
    ref, ref_name = reference_method(scene)
    short = "VI" if ref == "vi" else ref
    lines = [f"Target: {s['error']} <= {target:g}. Time: solver wall time (no output), set-up excluded; "
             f"ratios to one linear solve (assembly + factorisation + solve) and to {ref_name} on the same mesh.", "",
             f"| mesh | dofs | method | parameter | error | gap to {short} | Newton | aug | "
             f"time [s] | /linear | /{short} | Pareto |", "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    headline = []
    for level in dict.fromkeys(r["refinement"] for r in rows):
        here = [r for r in ok if r["refinement"] == level]
        vi = next((r for r in here if ref in (r["method"], _variant(r))), None)
        for variant in dict.fromkeys(_variant(r) for r in here):
            runs = [r for r in here if _variant(r) == variant]
            within = [r for r in runs if r["error"] <= target]
            best = min(within, key=lambda r: r["wall_time_s"]) if within else min(runs, key=lambda r: r["error"])
            label = parameter_label(best["method"])
            par = "-" if label == "-" else f"{label} {best['K']:.3g}"
            lines.append(
                f"| {'-' if level is None else level} | {best['dofs']} | {variant} | {par} | {best['error']:.3g}"
                f"{'' if within else ' (target not reached)'} | {best.get('limit_gap', float('nan')):.2g} | "
                f"{best['newton_iterations']} | {best['augmentations']} | {best['wall_time_s']:.3f} | "
                f"{best['ratio_to_linear_solve']:.1f} | "
                f"{'-' if vi is None else format(best['wall_time_s'] / vi['wall_time_s'], '.2f')} | "
                f"{'yes' if id(best) in front else 'no'} |")
        for who, keep in (("the suite's methods", lambda m: m not in references()),
                          ("the references", references().__contains__)):
            cands = [r for r in here if keep(r["method"]) and r["error"] <= target]
            if not cands:
                headline.append(f"- mesh {'-' if level is None else level}: none of {who} reaches the target.")
                continue
            b = min(cands, key=lambda r: r["wall_time_s"])
            vs = (f"; {ref_name} {vi['wall_time_s']:.3f} s (error {vi['error']:.3g}): "
                  f"{b['wall_time_s'] / vi['wall_time_s']:.2f} x its time") if vi and b is not vi else ""
            headline.append(f"- mesh {'-' if level is None else level} ({b['dofs']} dofs): fastest of {who} within "
                            f"the target: {_variant(b)} ({parameter_label(b['method'])} {b['K']:.3g}),"
                            f" {b['wall_time_s']:.3f} s (+ set-up {b['setup_time_s']:.2f} s), error {b['error']:.3g} "
                            f"(gap to {short} {b['limit_gap']:.2g}), {b['ratio_to_linear_solve']:.1f} x one linear "
                            f"solve ({b['linear_solve_floor_s']:.3f} s){vs}.")
    on_front = [r for r in ok if id(r) in front]
    lines += ["", *headline, "- Pareto front (fastest first): " + ", ".join(
        f"{_variant(r)} {r['K']:.3g} r{r['refinement']} ({r['wall_time_s']:.3f} s, {r['error']:.2g})"
        for r in sorted(on_front, key=lambda r: r["wall_time_s"]))]
    return "\n".join(lines) + "\n"


def convergence_findings(rows: Sequence[dict]) -> str:
    """Markdown for a scene without an error figure (``BENCH['error'] is None``): per method variant, the runs
    that converged, the parameters that failed, and the fastest converged run (Newton iterations, time)."""
    names = {v: k for k, v in _snes_reasons().items()}
    lines = ["No error figure for this scene: convergence, Newton iterations and solver time only.", "",
             "| method | converged | failed at parameter (SNES reason) | fastest: parameter | Newton | aug | "
             "time [s] |", "|---|---|---|---|---|---|---|"]
    for variant in dict.fromkeys(_variant(r) for r in rows):
        rs = [r for r in rows if _variant(r) == variant]
        ok = [r for r in rs if r["converged"]]
        bad = ", ".join(f"{r['K']:.3g} ({names.get(r['snes_reason'], r['snes_reason'])})" for r in rs
                        if not r["converged"]) or "-"
        b = min(ok, key=lambda r: r["wall_time_s"]) if ok else None
        lines.append(f"| {variant} | {len(ok)}/{len(rs)} | {bad} | " + (
            f"{b['K']:.3g} | {b['newton_iterations']} | {b['augmentations']} | {b['wall_time_s']:.3f} |" if b
            else "- | - | - | - |"))
    return "\n".join(lines) + "\n"


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

MARKERS = {None: "o", 0: "o", 1: "^", 2: "s", 3: "D"}  # by refinement


def _markers(rows: Sequence[dict]) -> dict:
    """Marker per mesh of ``rows``: ``MARKERS`` for levels, else (a mesh size, e.g. ``--h-contact``) by size,
    coarsest first."""
    levels = {r["refinement"] for r in rows}
    if all(k is None or isinstance(k, int) for k in levels):
        return {k: MARKERS.get(k, "o") for k in levels}
    sizes = sorted((k for k in levels if k is not None), reverse=True)
    return {None: "o", **{k: "o^sDv<>"[i % 7] for i, k in enumerate(sizes)}}


def _variant(r: dict) -> str:
    return r.get("label") or r["method"] + (" augmented" if r["augment"] > 0 else "")


def _colour(method: str) -> str:
    return methods.get(method).sweep.colour if method in methods.names() else "tab:gray"


def _size(method: str) -> float:
    """Marker size: methods that coincide on a chart stay visible."""
    return methods.get(method).sweep.size if method in methods.names() else 7.0


def figure(ncols: int = 1, width: float = 7.5):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(width, 5.2), layout="constrained")
    FigureCanvasAgg(fig)
    if ncols == 1:
        return fig, fig.add_subplot()
    return fig, fig.subplots(1, ncols, sharey=True)


def _legend_handles(rows: Sequence[dict]):
    from matplotlib.lines import Line2D

    handles = []
    for v in dict.fromkeys(_variant(r) for r in rows):
        m = v.split()[0]
        handles.append(Line2D([], [], ls="", marker="o", ms=7, color=_colour(m), mec=_colour(m),
                              mfc=_colour(m) if "augmented" in v else "none", label=v))
    refinements = sorted({r["refinement"] for r in rows if r["refinement"] is not None})
    if len(refinements) > 1:
        markers = _markers(rows)
        handles += [Line2D([], [], ls="", marker=markers[k], color="grey", mfc="none", label=f"mesh {k}")
                    for k in refinements]
    return handles


def _tick(x: float, _pos=None) -> str:
    mantissa = round(x / 10 ** math.floor(math.log10(x))) if x > 0 else 0
    return f"{x:g}" if mantissa in (1, 2, 5) else ""


def _error_label(rows: Sequence[dict]) -> str:
    name = spec(rows[0]["scene"])["error"] if rows else "figure"
    return f"relative error of {name} [-]  (below {ERROR_FLOOR:g} drawn at {ERROR_FLOOR:g})"


def plot_pareto(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """Error against solver wall time (log-log) of the converged runs, and their Pareto front.
    Colour: method; filled marker: augmented; marker shape: mesh level; dotted verticals: one linear
    solve on each mesh (the cost floor)."""
    from matplotlib.lines import Line2D
    from matplotlib.ticker import FuncFormatter

    fig, ax = figure()
    ok = [r for r in rows if r["converged"] and not math.isnan(r["error"]) and not math.isnan(r["wall_time_s"])]
    t = np.array([r["wall_time_s"] for r in ok])
    e = np.maximum([r["error"] for r in ok], ERROR_FLOOR)
    markers = _markers(rows)
    for r, ti, ei in zip(ok, t, e):
        c = _colour(r["method"])
        ax.plot(ti, ei, ls="", marker=markers[r["refinement"]], ms=7, mec=c,
                mfc=c if r["augment"] > 0 else "none", alpha=0.85)
    front = pareto_front(t, e)
    if ok and "reference" in spec(ok[0]["scene"]):  # the scene's exact method: its error and time on each mesh
        ref, ref_name = reference_method(ok[0]["scene"])
        for r, ti, ei in zip(ok, t, e):
            if ref in (r["method"], _variant(r)):
                mesh = "" if r["refinement"] is None else f", mesh {r['refinement']}"
                ax.axhline(ei, color=_colour(ref), ls="--", lw=1.0, zorder=0,
                           label=f"{ref_name}{mesh}: error {r['error']:.2g} in {ti:.3g} s")
                ax.axvline(ti, color=_colour(ref), ls="--", lw=1.0, zorder=0)
    if len(front):
        ft, fe = np.append(t[front], t.max() * 1.15), np.append(e[front], e[front[-1]])
        ax.step(ft, fe, where="post", color="black", lw=1.2, zorder=0, label="Pareto front")
    for level in dict.fromkeys(r["refinement"] for r in ok):
        floor = np.nanmedian([r["linear_solve_floor_s"] for r in ok if r["refinement"] == level])
        if np.isfinite(floor):
            ax.axvline(floor, color="grey", ls=":", lw=1.2)
            ax.annotate(f"1 linear solve{'' if level is None else f' (mesh {level})'}", (floor, 0.02),
                        xycoords=("data", "axes fraction"), rotation=90, fontsize=7, color="grey", ha="right")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.xaxis.set_major_formatter(FuncFormatter(_tick))
    ax.xaxis.set_minor_formatter(FuncFormatter(_tick))  # 2 and 5 only: the default minor labels overlap
    ax.set_xlabel("solver wall time [s]")
    ax.set_ylabel(_error_label(rows))
    failed = len(rows) - len(ok)
    ax.set_title(title + (f" ({failed} failed run{'s' * (failed != 1)} not shown)" if failed else ""))
    ax.grid(True, which="both", alpha=0.3)
    extra = [Line2D([], [], color="grey", ls=":", label="one linear solve")]
    ax.legend(handles=_legend_handles(rows) + ax.get_legend_handles_labels()[0] + extra, fontsize=8, loc="best")
    fig.savefig(path, dpi=100)


def plot_dofs(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """Error against dofs: per method variant, its most accurate converged run on each mesh."""
    fig, ax = figure()
    ok = [r for r in rows if r["converged"] and not math.isnan(r["error"])]
    for variant in dict.fromkeys(_variant(r) for r in ok):
        best = {}
        for r in ok:
            if _variant(r) == variant and (r["dofs"] not in best or r["error"] < best[r["dofs"]]["error"]):
                best[r["dofs"]] = r
        d = sorted(best)
        m = variant.split()[0]
        ax.plot(d, [max(best[k]["error"], ERROR_FLOOR) for k in d], color=_colour(m), marker="o", ms=_size(m),
                mfc=_colour(m) if "augmented" in variant else "none", ls="-" if "augmented" in variant else "--",
                label=variant)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("dofs")
    ax.set_ylabel(_error_label(rows))
    ax.set_title(title + " (most accurate run of each method per mesh)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.savefig(path, dpi=100)


def plot_reduction(table: Sequence[dict], path: str | Path, title: str = "") -> None:
    """The model-reduction rows (:func:`reduction`'s table): the ``p0`` error (filled) and the ``a`` error
    (open) against Hertz of each variant, against its solver wall time (left) and its peak memory (right), log
    axes; one colour per variant, the reduced model first. Runs that did not converge are left out."""
    from matplotlib.lines import Line2D

    fig, axes = figure(2, width=11.0)
    ok = [r for r in table if r["converged"]]
    colours = [f"C{i % 10}" for i in range(len(ok))]
    for ax, x, label in ((axes[0], "wall_time_s", "solver wall time [s]"),
                         (axes[1], "memory_peak_mb", "peak memory of the run [MB]")):
        for r, c in zip(ok, colours):
            ax.plot(r[x], max(r["error"], ERROR_FLOOR), ls="", marker="o", ms=8, color=c)
            if not math.isnan(r.get("a_error", math.nan)):
                ax.plot(r[x], max(r["a_error"], ERROR_FLOOR), ls="", marker="s", ms=8, mec=c, mfc="none")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel(label)
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("relative error against Hertz [-]")
    handles = [Line2D([], [], ls="", marker="o", ms=8, color=c, label=r["variant"].split(": ", 1)[-1][:70])
               for r, c in zip(ok, colours)]
    handles += [Line2D([], [], ls="", marker="o", color="grey", label="p0 error"),
                Line2D([], [], ls="", marker="s", mec="grey", mfc="none", label="a error")]
    fig.legend(handles=handles, fontsize=7, loc="outside lower center", ncols=2)
    fig.suptitle(title, fontsize=10)
    fig.savefig(path, dpi=100)


def plot_iterations(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """Total Newton iterations (all load steps and augmentations) against K, one line per method,
    augmentation and refinement; failed runs as crosses. (Nitsche's gamma0 is on the stability map.)"""
    from matplotlib.lines import Line2D

    fig, ax = figure()
    rows = [r for r in rows if parameter_label(r["method"]) == "K"]
    markers = _markers(rows)
    groups: dict[tuple, list[dict]] = {}
    for r in rows:
        groups.setdefault((r["method"], r["augment"] > 0, r["refinement"]), []).append(r)
    for (method, augmented, refinement), rs in groups.items():
        rs = sorted(rs, key=lambda r: r["K"])
        c = _colour(method)
        ok = [r for r in rs if r["converged"]]
        ax.plot([r["K"] for r in ok], [r["newton_iterations"] for r in ok], color=c, lw=1.5,
                ls="-" if augmented else "--", marker=markers[refinement], ms=_size(method),
                mfc=c if augmented else "none", mec=c, alpha=0.85)
        bad = [r for r in rs if not r["converged"]]
        ax.plot([r["K"] for r in bad], [r["newton_iterations"] for r in bad], ls="", marker="x", color=c, ms=9)
    ax.set_xscale("log")
    ax.set_xlabel("K (penalty, auglag; cross: K_hat) [pressure / length]")
    ax.set_ylabel("Newton iterations, all steps and augmentations [-]")
    ax.set_title(title)
    ax.grid(True, which="both", alpha=0.3)
    extra = [Line2D([], [], ls="", marker="x", color="grey", label="failed")] if any(
        not r["converged"] for r in rows) else []
    ax.legend(handles=_legend_handles(rows) + extra, fontsize=8, loc="best")
    fig.savefig(path, dpi=100)


KIND_SHORT = {"linear_solve": "lin", "ill_conditioning": "ill", "divergence": "div", "cycling": "cyc",
              "stagnation": "stag", "max_iterations": "maxit", "exit": "exit"}


def plot_stability(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """Heat map per method variant: Newton iterations (colour) over (parameter, load steps). A failed run is a
    red ``x`` with its kind (``cyc`` cycling, ``ill`` ill-conditioning, ``lin`` linear solve, ``stag``, ``div``,
    ``maxit``); ``ill`` in orange on a converged cell: ill-conditioned (a solve stalled at round-off, or the
    condition estimate above 1e12); ``c<n>``: step cutbacks; ``(k)``: Krylov iterations per Newton iteration
    (iterative solver: grows with the conditioning); ``k<x>``: log10 of the condition estimate (direct
    solver); ``e<x>``: log10 of the distance from the augmentation limit (``limit_gap``)."""
    from matplotlib.colors import LogNorm

    variants = list(dict.fromkeys(_variant(r) for r in rows))
    fig, axes = figure(len(variants), width=3.0 * len(variants) + 1.0)
    fig.set_figheight(5.8)
    axes = np.atleast_1d(axes)
    its = [r["newton_iterations"] for r in rows if r["newton_iterations"] > 0]
    norm = LogNorm(vmin=max(min(its, default=1), 1), vmax=max(its, default=10))
    image = None
    steps = sorted({r["steps"] for r in rows}, key=lambda n: n or 1)  # the same rows in every panel (shared y)
    for ax, variant in zip(axes, variants):
        rs = [r for r in rows if _variant(r) == variant]
        params = sorted({r["K"] for r in rs})
        grid = np.full((len(steps), len(params)), np.nan)
        for r in rs:
            i, j = steps.index(r["steps"]), params.index(r["K"])
            st = status(r)
            if r["converged"]:
                grid[i, j] = r["newton_iterations"]
                label = [f"{r['newton_iterations']}"] + (["ill"] if st == "ill_conditioned" else [])
                label += [f"c{r['cutbacks']}"] if r["cutbacks"] else []
                if r.get("linear_iterations", 0) > r["newton_iterations"] > 0:  # iterative: Krylov per Newton
                    label.append(f"({r['linear_iterations'] / r['newton_iterations']:.0f})")
                cond = r.get("condition_estimate", float("nan"))
                if cond and not math.isnan(cond):
                    label.append(f"k{math.log10(cond):.0f}")
                gap = r.get("limit_gap", float("nan"))
                if not math.isnan(gap):
                    label.append("e0" if gap == 0 else f"e{math.floor(math.log10(gap))}")
                colour = "darkorange" if st == "ill_conditioned" else "black"
            else:
                label, colour = ["x", KIND_SHORT.get(st[8:], st[8:])], "red"
            ax.text(j, i, "\n".join(label), ha="center", va="center", fontsize=6.5, color=colour,
                    fontweight="bold" if colour != "black" else "normal")
        image = ax.imshow(np.ma.masked_invalid(grid), cmap="viridis", norm=norm, origin="lower", aspect="auto",
                          alpha=0.75)
        ax.set_xticks(range(len(params)), [f"{p:.0e}" if p >= 1e3 else f"{p:g}" for p in params], rotation=45,
                      fontsize=7)
        ax.set_yticks(range(len(steps)), [str(n) for n in steps])
        ax.set_xlabel("K [pressure / length]" if parameter_label(rs[0]["method"]) == "K" else
                      f"{parameter_label(rs[0]['method'])} [-]")
        ax.set_title(variant.replace(", ", ",\n"), fontsize=9)
    axes[0].set_ylabel("load steps")
    if image is not None:
        fig.colorbar(image, ax=list(axes), label="Newton iterations")
    fig.suptitle(title, fontsize=9)
    fig.savefig(path, dpi=100)


def plot_stability_accuracy(rows: Sequence[dict], path: str | Path, title: str = "") -> None:
    """The stability map's runs with the fewest load steps: distance from the augmentation limit against K,
    one line per K-based method variant (Nitsche and the divergence-test control left out). Filled: converged;
    orange ring: ill-conditioned (stalled at round-off or condition estimate > 1e12); red x at the top:
    failed. It shows which K each method needs for an accuracy, and whether it still converges there."""
    fig, ax = figure()
    rows = [r for r in rows if parameter_label(r["method"]) == "K" and r.get("label") != DTOL]
    fewest = min((r["steps"] or 1 for r in rows), default=1)
    rows = [r for r in rows if (r["steps"] or 1) == fewest]
    gaps = [r["limit_gap"] for r in rows if r["converged"] and not math.isnan(r.get("limit_gap", float("nan")))]
    top = max(gaps, default=1.0) * 10
    for k, variant in enumerate(dict.fromkeys(_variant(r) for r in rows)):
        rs = sorted((r for r in rows if _variant(r) == variant), key=lambda r: r["K"])
        c, m = _colour(variant.split()[0]), "os^Dv"[k % 5]
        ok = [r for r in rs if r["converged"] and not math.isnan(r.get("limit_gap", float("nan")))]
        ax.plot([r["K"] for r in ok], [max(r["limit_gap"], ERROR_FLOOR) for r in ok], color=c, marker=m, ms=7,
                ls="-" if "augmented" in variant else "--", label=variant, alpha=0.85)
        ill = [r for r in ok if status(r) == "ill_conditioned"]
        ax.plot([r["K"] for r in ill], [max(r["limit_gap"], ERROR_FLOOR) for r in ill], ls="", marker="o", ms=14,
                mfc="none", mec="darkorange", mew=2)
        bad = [r for r in rs if not r["converged"]]
        ax.plot([r["K"] for r in bad], [top * 3.0**k] * len(bad), ls="", marker="x", color=c, ms=10, mew=2)
    ax.plot([], [], ls="", marker="o", ms=14, mfc="none", mec="darkorange", mew=2, label="ill-conditioned")
    ax.plot([], [], ls="", marker="x", color="grey", ms=10, mew=2, label="failed (drawn at the top)")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("K (penalty, auglag; cross: K_hat) [pressure / length]")
    ax.set_ylabel(f"distance from the augmentation limit [-] (below {ERROR_FLOOR:g} drawn at {ERROR_FLOOR:g})")
    ax.set_title(title + f" ({fewest} load step{'s' * (fewest > 1)})", fontsize=9)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="best")
    fig.savefig(path, dpi=100)


def run_scene(scene: str, argv: Sequence[str]) -> None:
    """One run of a scene whose demo does not take ``--method`` (its ``BENCH`` has ``build``: the builder's
    keyword arguments; ``options``: PETSc options; ``predictor``, ``max_cutbacks``): the demos' command line,
    ``scenes.build``, :func:`run.run` into ``--out``. ``--steps n``: n equal steps to the scene's last load.
    Method ``penalty`` with ``--augment`` > 0 is the penalty method *with augmentation* (``Penalty(K,
    augmented=True)``: the gap status decides, Zavarise et al. 1998)."""
    from ..laws import Penalty
    from . import cli
    from .run import run
    from .scenes import build

    s = spec(scene)
    p = cli.parser(f"benchmark run of {scene}", default_K=s["K"])
    p.add_argument("--steps", type=cli.COUNT, default=None, help="equal load steps to the scene's last load")
    mesh = s["mesh"][0] if s.get("mesh") else None
    if mesh:
        p.add_argument(f"--{mesh}", type=cli.LEVEL, default=None, help="mesh level (the scene's builder)")
    args = cli.parse(p, list(argv))
    law = Penalty(args.K, augmented=True) if args.method == "penalty" and args.augment else cli.law_from_args(args)
    level = {} if mesh is None or getattr(args, mesh) is None else {mesh: getattr(args, mesh)}
    setup = build(scene, law=law, quadrature=args.quadrature, **s["build"], **level)
    if args.steps is not None:
        if args.steps < 1:
            raise ValueError(f"--steps must be >= 1, got {args.steps}")
        setup.loads = [setup.loads[-1] * (k + 1) / args.steps for k in range(args.steps)]
    run(setup, args.out, args.method, cli.method_parameters(args), args.augment or 0, args.augment_tol, args.quiet,
        options={**cli.solver_options(args), **(s.get("options") or {})}, max_cutbacks=s.get("max_cutbacks", 4),
        predictor=s.get("predictor", False),
        xdmf=not args.no_xdmf, restart=args.restart, overwrite=args.overwrite, args=args)
