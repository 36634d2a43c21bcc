"""The benchmark pages of the documentation, written from the results of a benchmark run.

    python -m fenics_contact.app.bench_pages results/bench docs/bench [--demos results]

Reads what :mod:`fenics_contact.app.bench` writes into its output folder (``run.json``: the machine, date,
commit and command of the run, :mod:`~fenics_contact.app.run_record`; per scene ``<scene>_findings.md``,
``<scene>_stability.md``, ``<scene>_reduction.md`` and the charts ``<scene>_*.png``) and, with ``--demos``, the
``<demo>/summary.json`` of every demo in that folder (their checks against the scenes' references). Writes
``index.md`` (the run's header, the demos' checks, a page per scene) and ``<scene>.md`` with the charts copied
next to them. Every page starts with the header: machine (CPU model, cores, memory, from /proc), date, commit,
command. The pages hold numbers only; docs/benchmarks.md explains how to read them.
"""
from __future__ import annotations

import json
import math
import shutil
import sys
from pathlib import Path
from typing import Sequence

from . import bench
from .run_record import read_runs

__all__ = ["header", "time_split", "scene_page", "demo_checks", "write_pages", "main"]

CHARTS = ("pareto", "dofs", "iterations", "stability", "stability_accuracy")
CHART_TITLES = {"pareto": "Error against solver time", "dofs": "Error against dofs",
                "iterations": "Newton iterations against K", "stability": "Stability map",
                "stability_accuracy": "The K each method needs"}


def header(run: dict) -> str:
    """The line a page starts with, per run: machine, date, commit, command, load, the scenes it ran."""
    m = run["machine"]
    memory = "unknown memory" if m.get("memory_gb") is None else f"{m['memory_gb']:g} GB memory"
    return (f"Measured on {m['cpu']}, {m['cores']} cores, {memory}, {m['system']}; {run['date']}; "
            f"commit `{run['commit']}`; command `{run['command']}`. Times are wall times of serial runs on this "
            "machine" + ("" if run.get("load_average") is None else
                         f", load average {run['load_average']:g} at the start (other jobs on its cores)") +
            f"; scenes {', '.join(run['scenes'])}.\n")


def _section(title: str, path: Path) -> list[str]:
    return [f"## {title}", "", path.read_text().rstrip(), ""] if path.exists() else []


def time_split(rows: Sequence[dict]) -> str:
    """Markdown: per mesh, method variant and quadrature the fastest converged run and where its solver time
    went (two-body search, exchange and coupling; assembly; linear solves), in s; empty without a search time
    (rigid obstacles)."""
    rows = [r for r in rows if r["converged"] and not math.isnan(r.get("search_s", math.nan))]
    if not rows:
        return ""
    best: dict[tuple, dict] = {}
    for r in rows:
        key = (r["refinement"], bench._variant(r), r["quadrature"])
        if key not in best or r["wall_time_s"] < best[key]["wall_time_s"]:
            best[key] = r
    lines = ["| mesh | dofs | method | quadrature | parameter | error | Newton | wall | search | exchange | coupling | "
             "assembly | linear solves | /linear |", "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for (level, variant, quadrature), r in best.items():
        label = bench.parameter_label(r["method"])
        parameter = "-" if label == "-" else f"{label} {r['K']:.3g}"
        lines.append(f"| {'-' if level is None else level} | {r['dofs']} | {variant} | {quadrature} | "
                     f"{parameter} | {r['error']:.2g} | "
                     f"{r['newton_iterations']} | {r['wall_time_s']:.3g} | {r['search_s']:.3g} | "
                     f"{r['exchange_s']:.3g} | {r['coupling_s']:.3g} | {r['assembly_s']:.3g} | "
                     f"{r['linear_solve_s']:.3g} | {r['ratio_to_linear_solve']:.1f} |")
    return "\n".join(lines) + "\n"


def scene_page(scene: str, results: Path, run: dict, out: Path) -> str:
    """The page of one scene: findings, time split (two bodies), stability summary, model reduction and charts
    (copied into ``out``)."""
    lines = [f"# {scene}", "", header(run)]  # the run that produced this scene's results
    lines += _section("Fastest run of each method", results / f"{scene}_findings.md")
    split = time_split(bench.read_rows(results / f"{scene}.csv")) if (results / f"{scene}.csv").exists() else ""
    if split:
        lines += ["## Where the time goes", "", "The fastest converged run of each method and quadrature; times in s.",
                  "", split]
    lines += _section("Stability over the parameter and the load steps", results / f"{scene}_stability.md")
    lines += _section("Model reduction", results / f"{scene}_reduction.md")
    for chart in CHARTS:
        png = results / f"{scene}_{chart}.png"
        if png.exists():
            shutil.copyfile(png, out / png.name)
            lines += [f"## {CHART_TITLES[chart]}", "", f"![{scene}: {CHART_TITLES[chart]}]({png.name})", ""]
    return "\n".join(lines).rstrip() + "\n"


def _fmt(v, spec: str = ".6g") -> str:
    return "-" if v is None else format(v, spec)


def demo_checks(folder: str | Path) -> str:
    """Markdown table of the checks in ``folder/<demo>/summary.json`` (the layout of ``make demo``: figure, value,
    reference, relative error, tolerance, passed), one row per demo; empty if there is none."""
    rows = []
    for path in sorted(Path(folder).glob("*/summary.json")):
        s = json.loads(path.read_text())
        c = s.get("check")
        if not c:
            continue
        fmt = _fmt
        rows.append(f"| {s.get('scene', path.parent.name)} | {s.get('method', '-')} | {s.get('ranks', '-')} | "
                    f"{s.get('dofs', '-')} | {c['figure']} | {fmt(c.get('value'))} | {fmt(c.get('reference'))} | "
                    f"{fmt(c.get('rel_error'), '.2e')} | {fmt(c.get('tolerance'), 'g')} | "
                    f"{'yes' if c.get('passed') else 'no'} | {fmt(s.get('wall_time_s'), '.3g')} |")
    if not rows:
        return ""
    return "\n".join(["| scene | method | ranks | dofs | figure | value | reference | error | tolerance | passed | "
                      "wall time [s] |", "|---|---|---|---|---|---|---|---|---|---|---|", *rows]) + "\n"


# The side-by-side page with the peer (dolfinx_contact), written by scripts/peer/run.py: kept and listed here.
PEER_PAGE = "peer"


def write_pages(results: str | Path, out: str | Path, demos: str | Path | None = None) -> list[Path]:
    """Write ``out/index.md`` and a page per scene with results in ``results``; returns the pages written.
    Pages and charts of an earlier run in ``out`` are removed first, except the side-by-side page with the peer
    (``peer.md``, ``peer_*.png``: written by scripts/peer/run.py, which needs the peer's build), which the index
    lists when present."""
    results, out = Path(results), Path(out)
    runs = read_runs(results)
    by_scene = {scene: run for run in runs for scene in run["scenes"]}
    scenes = sorted(p.name[: -len("_findings.md")] for p in results.glob("*_findings.md")
                    if p.name[: -len("_findings.md")] in by_scene)
    if not scenes:
        raise ValueError(f"{results} holds no <scene>_findings.md of a recorded run: no benchmark results")
    out.mkdir(parents=True, exist_ok=True)
    for old in [*out.glob("*.md"), *out.glob("*.png")]:
        if not old.name.startswith(PEER_PAGE):
            old.unlink()
    pages = []
    for scene in scenes:
        page = out / f"{scene}.md"
        page.write_text(scene_page(scene, results, by_scene[scene], out))
        pages.append(page)
    used = [run for run in runs if any(scene in scenes for scene in run["scenes"])]
    index = ["# Benchmark results", "", *(header(run) for run in used),
             "One page per scene; [the benchmark page](../benchmarks.md) says what the columns and charts mean.", "",
             "```{toctree}", ":maxdepth: 1", "", *scenes, *([PEER_PAGE] if (out / f"{PEER_PAGE}.md").exists() else []),
             "```", ""]
    reductions = sorted(results.glob("*_reduction.md"))
    if reductions:  # one table: each scene's rows under the common header
        rows = [line for path in reductions for line in path.read_text().splitlines()[2:] if line.strip()]
        index += ["## Model reduction", "", *bench.REDUCTION_HEADER, *rows, ""]
    checks = demo_checks(demos) if demos is not None else ""
    if checks:
        index += ["## Demo checks", "", "Each demo's figure against its scene's reference.", "", checks]
    (out / "index.md").write_text("\n".join(index).rstrip() + "\n")
    return [out / "index.md", *pages]


def main(argv: Sequence[str] | None = None) -> None:
    """Command line: ``results out [--demos folder]``; bad input ends in one line, exit status 2."""
    import argparse

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("results", help="the benchmark's output folder (make bench: results/bench)")
    p.add_argument("out", help="the folder of the pages (docs/bench)")
    p.add_argument("--demos", default=None, help="a folder of demo results (summary.json) to tabulate")
    args = p.parse_args(argv)
    try:
        pages = write_pages(args.results, args.out, args.demos)
    except ValueError as exc:
        sys.stderr.write(f"error: {exc}\n")
        raise SystemExit(2) from None
    print(f"{len(pages)} pages -> {args.out}")


if __name__ == "__main__":
    main()
