"""The benchmark's command line: its scenes one after another, each on its own, and their times in a table.

    python demos/bench.py --quick --main --out results/bench    # make bench: the main scenes, accuracy rows
    python demos/bench.py --quick --out results/bench-all       # make bench-all: every scene and its maps

A scene that fails (a run cannot fail it: a failed run is a row; its report, a chart, a table can) is one line naming
it, its traceback in ``<out>/<scene>_error.txt``; the other scenes still run and write their results, and the
program exits with status 1 at the end. Every output path is absolute from the start (the ``--out`` folder is
resolved once, against the working directory the program was started in). At the end: one row per scene, its
runs, failed runs, wall time and CPU time (this process and its runs; on a shared machine the steadier figure).
"""
from __future__ import annotations

import resource
import sys
import time
import traceback
from pathlib import Path
from typing import Sequence

from mpi4py import MPI

from . import bench
from .cli import EXIT_ERROR

__all__ = ["MAIN_SCENES", "ERROR_FILE", "cpu_seconds", "time_table", "parts_computed", "sweep_scene", "sweep_command",
           "main"]

# make bench: every method's speed against accuracy on the main scenes, in minutes: the rigid plane (hertz: penalty,
# cross, auglag, nitsche, SNES VI), two deformable bodies (hertz_twobody: lagrange, exact coulomb, the three
# quadratures), friction (slab: compliance and the exact coulomb against the penalty), an axisymmetric body
# (axisphere: penalty_multiplier). Together they show every declared method (tests/test_bench.py checks).
MAIN_SCENES = ("hertz", "hertz_twobody", "slab", "axisphere")
ERROR_FILE = "{scene}_error.txt"  # the traceback of a scene that failed, in the output folder


def cpu_seconds() -> float:
    """CPU seconds (user and system) of this process and of its children that have ended (the runs)."""
    return sum(getattr(resource.getrusage(who), f) for who in (resource.RUSAGE_SELF, resource.RUSAGE_CHILDREN)
               for f in ("ru_utime", "ru_stime"))


def time_table(times: Sequence[dict]) -> str:
    """Markdown: per scene (``scene``, ``runs``, ``failed``, ``wall_s``, ``cpu_s``, ``status``) and in total."""
    lines = ["| scene | runs | failed runs | wall time [s] | CPU time [s] | status |", "|---|---|---|---|---|---|"]
    for t in times:
        lines.append(f"| {t['scene']} | {t['runs']} | {t['failed']} | {t['wall_s']:.0f} | {t['cpu_s']:.0f} | "
                     f"{t['status']} |")
    lines.append(f"| total | {sum(t['runs'] for t in times)} | {sum(t['failed'] for t in times)} | "
                 f"{sum(t['wall_s'] for t in times):.0f} | {sum(t['cpu_s'] for t in times):.0f} | "
                 f"{sum(t['status'] != 'done' for t in times)} failed |")
    return "\n".join(lines) + "\n"


def parts_computed(args) -> list[str]:
    """The parts of a scene's results (``run_record.PARTS``) that the command line ``args`` computes, where the
    scene has them (the benchmark pages keep the others from their previous page)."""
    if args.reduction_only:
        return ["reduction"]
    skipped = {"stability": args.no_stability, "locking": args.no_locking, "reduction": args.no_reduction}
    return ["sweep", *(part for part, skip in skipped.items() if not skip)]


def sweep_scene(scene: str, args, out: Path, reduced: dict[str, str]) -> None:
    """Everything the command line ``args`` asks of ``scene`` into the absolute folder ``out``: its sweep, findings
    and charts, stability map, locking map, model reduction (rows into ``reduced``); or, with ``charts_only``, its
    charts and tables again from its CSV files."""
    say, s = bench._say, bench.spec(scene)
    if args.charts_only:
        if (out / f"{scene}_reduction.csv").exists() and scene in bench.REDUCTIONS:
            reduced[scene] = bench.reduction_report(scene, out)
        if not (out / f"{scene}.csv").exists() and scene in reduced:  # the model-reduction rows alone
            return
        say(bench.report(scene, bench.read_rows(out / f"{scene}.csv"), out))
        if s.get("stability") and (out / f"{scene}_stability.csv").exists():
            st = bench.read_rows(out / f"{scene}_stability.csv")
            bench.plot_stability(st, out / f"{scene}_stability.png", title=bench.STABILITY_TITLE.format(scene=scene))
            bench.plot_stability_accuracy(st, out / f"{scene}_stability_accuracy.png",
                                          title=f"{scene}: the K each method needs, and whether it converges there")
        if s.get("locking") and (out / f"{scene}_locking.csv").exists():
            bench.locking_report(scene, bench.read_rows(out / f"{scene}_locking.csv"), out)
        return
    if args.reduction_only:
        reduced[scene] = bench.reduction(scene, out, quiet=args.quiet, timeout=args.timeout)
        say(f"{scene} model reduction:\n" + reduced[scene])
        return
    start = time.perf_counter()
    rows = bench.bench(scene, out, bench.sweep(scene, args.quick, args.main), quiet=args.quiet, timeout=args.timeout)
    charts = f"{scene}_pareto.png, {scene}_dofs.png, " if s["error"] is not None else ""
    failed = sum(not r["converged"] for r in rows)
    say(f"{scene}: {len(rows)} runs ({failed} failed) in {time.perf_counter() - start:.1f} s -> {out / scene}.csv, "
        f"{charts}{scene}_iterations.png")
    say((out / f"{scene}_findings.md").read_text())
    if s.get("stability") and not args.no_stability:
        rows = bench.stability(scene, out, args.quick, quiet=args.quiet)
        say(f"{scene} stability map: {len(rows)} runs, {sum(not r['converged'] for r in rows)} failed -> "
            f"{out / scene}_stability.csv, {scene}_stability.png")
    if s.get("locking") and not args.no_locking:
        rows = bench.locking(scene, out, quiet=args.quiet, timeout=args.timeout)
        say(f"{scene} locking map: {len(rows)} runs, {sum(not r['converged'] for r in rows)} failed -> "
            f"{out / scene}_locking.csv, {scene}_locking.png\n" + (out / f"{scene}_locking.md").read_text())
    if s.get("reduction") and not args.no_reduction and scene in bench.REDUCTIONS:
        reduced[scene] = bench.reduction(scene, out, quiet=args.quiet)
        say(f"{scene} model reduction:\n" + reduced[scene])


def _parser():
    from . import cli

    p = cli.StrictParser(description=bench.__doc__.splitlines()[0], epilog=None)
    p.add_argument("--scene", action="append", help="scene (repeatable; default: every scene with BENCH)")
    p.add_argument("--main", action="store_true",
                   help=f"the main scenes ({', '.join(MAIN_SCENES)}), their accuracy rows only (no stability maps, "
                        "locking, model reduction): make bench")
    p.add_argument("--quick", action="store_true", help="small sweep")
    p.add_argument("--out", default="results/bench", help="output folder")
    p.add_argument("--timeout", type=cli.POSITIVE, default=1800.0, help="seconds per run before it counts as failed")
    p.add_argument("--charts-only", action="store_true", help="redraw charts and findings from <out>/<scene>.csv")
    p.add_argument("--no-stability", action="store_true", help="skip the stability maps")
    p.add_argument("--no-reduction", action="store_true", help="skip the model-reduction tables")
    p.add_argument("--no-locking", action="store_true", help="skip the locking maps (bulk models over nu)")
    p.add_argument("--reduction-only", action="store_true",
                   help="the model-reduction tables alone (no sweep, no stability map)")
    p.add_argument("--quiet", action="store_true", help="no line per run")
    return p


def sweep_command(argv: Sequence[str]) -> None:
    """The sweep's command line (run by :func:`main` under :func:`cli.main`: bad input is one line, exit 2);
    exits with status 1 after the time table if a scene failed."""
    args = _parser().parse_args(argv)
    if args.main and args.reduction_only:
        raise ValueError("--main with --reduction-only: the main scenes' sweep has no model-reduction rows; give one "
                         "of the two")
    if args.main:
        args.no_stability = args.no_locking = args.no_reduction = True
    default = list(bench.REDUCTIONS) if args.reduction_only else list(MAIN_SCENES) if args.main else \
        bench.bench_scenes()
    scenes = args.scene or default
    for scene in scenes:
        bench.spec(scene)  # a clear error before anything runs
        if args.reduction_only and scene not in bench.REDUCTIONS:
            raise ValueError(f"--reduction-only: scene {scene!r} has no model-reduction rows; accepted: "
                             f"{', '.join(bench.REDUCTIONS)}")
    out = Path(args.out).resolve()  # every output path from here on is absolute
    out.mkdir(parents=True, exist_ok=True)
    if not args.charts_only:  # the machine, date, commit and command of the results (the benchmark pages' header)
        from .run_record import record_run

        record_run(out, argv, scenes, parts_computed(args))
    reduced: dict[str, str] = {}  # model-reduction rows per scene, one table at the end
    times = []
    for scene in scenes:
        start, cpu, runs = time.perf_counter(), cpu_seconds(), dict(bench.RUNS)
        error = out / ERROR_FILE.format(scene=scene)
        error.unlink(missing_ok=True)
        try:
            sweep_scene(scene, args, out, reduced)
            status = "done"
        except Exception as exc:  # noqa: BLE001 - one scene's failure is one line; the other scenes still run
            error.write_text(traceback.format_exc())
            what = type(exc).__name__ + (f": {str(exc).splitlines()[0]}" if str(exc).strip() else "")
            line = f"bench: scene {scene} failed: {what} (traceback: {error})"
            if MPI.COMM_WORLD.rank == 0:
                sys.stderr.write(line + "\n")
                sys.stderr.flush()
            status = "failed"
        times.append({"scene": scene, **{k: bench.RUNS[k] - runs[k] for k in runs},
                      "wall_s": time.perf_counter() - start, "cpu_s": cpu_seconds() - cpu, "status": status})
        bench._say(f"{scene}: {status} in {times[-1]['wall_s']:.1f} s")
    if reduced:
        (out / "model_reduction.md").write_text("\n".join(bench.REDUCTION_HEADER) + "\n" + "".join(reduced.values()))
        bench._say(f"model reduction -> {out / 'model_reduction.md'}")
    bench._say(f"Time of each scene ({out}):\n" + time_table(times))
    if any(t["status"] != "done" for t in times):
        raise SystemExit(EXIT_ERROR)


def main(argv: Sequence[str] | None = None) -> None:
    """The benchmark's command line (strict: :mod:`cli`; bad input ends in one line, exit status 2): the sweep, or
    with ``--run-scene SCENE`` one run of a scene (the sweep's child process)."""
    from . import cli

    argv = sys.argv[1:] if argv is None else list(argv)
    if argv[:1] == ["--run-scene"]:  # one run: bad input and failed solves end in one line (cli.main)
        return cli.main(lambda rest: bench.run_scene(argv[1], rest), argv[2:])
    return cli.main(sweep_command, argv)


if __name__ == "__main__":
    main()
