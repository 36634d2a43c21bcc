"""The benchmark pages of the documentation, written from the results of a benchmark run.

    python -m fenics_contact.app.bench_pages results/bench docs/bench [--demos results]

    python -m fenics_contact.app.bench_pages results/bench docs/bench --add   # a run of some scenes only

Reads what :mod:`fenics_contact.app.bench` writes into its output folder (``run.json``: the machine, date,
commit and command of each run and the parts of its scenes' results it computed,
:mod:`~fenics_contact.app.run_record`; per scene ``<scene>_findings.md``,
``<scene>_stability.md``, ``<scene>_locking.md``, ``<scene>_reduction.md`` and the charts ``<scene>_*.png``)
and, with ``--demos``, the ``<demo>/summary.json`` of every demo in that folder (their checks against the scenes'
references). Writes ``<scene>.md`` with the charts copied next to them and ``index.md`` (the runs' headers, a
page per scene, the model-reduction rows of every page, the demos' checks). Every page starts with the header:
machine (CPU model, cores, memory, from /proc), date, commit, command. ``--add``: the pages of scenes the results do
not hold are kept; a rewritten page keeps the sections of its previous page that the run did not compute (stability
map, locking, model reduction: ``bench --main`` computes none of them), with their charts and the index's rows, each
headed by the run that measured it; a scene whose model-reduction rows alone were rerun (``bench --reduction-only``)
keeps its page with that section replaced (headed by its own run). The pages hold numbers only; docs/benchmarks.md
explains how to read them.
"""
from __future__ import annotations

import json
import math
import re
import shutil
import sys
from pathlib import Path
from typing import Sequence

from . import bench
from .run_record import PARTS, read_runs

__all__ = ["run_parts", "header", "time_split", "reduction_section", "scene_page", "OPTIONAL", "kept_sections",
           "add_sections", "demo_checks", "write_index", "write_pages", "main"]

CHARTS = ("pareto", "dofs", "iterations", "stability", "stability_accuracy", "locking")
CHART_TITLES = {"pareto": "Error against solver time", "dofs": "Error against dofs",
                "iterations": "Newton iterations against K", "stability": "Stability map",
                "stability_accuracy": "The K each method needs", "locking": "Locking against Poisson's ratio"}
STABILITY, LOCKING, REDUCTION = ("Stability over the parameter and the load steps",
                                 "Locking: the bulk models over Poisson's ratio", "Model reduction")
# The sections a run computes only when asked (bench-all does, bench --main does not), by the file of its results
# (``<scene>_<key>.md``): its section and its charts' sections.
OPTIONAL = {"stability": (STABILITY, CHART_TITLES["stability"], CHART_TITLES["stability_accuracy"]),
            "locking": (LOCKING, CHART_TITLES["locking"]), "reduction": (REDUCTION,)}
CHART_PARTS = {"pareto": "sweep", "dofs": "sweep", "iterations": "sweep", "stability": "stability",
               "stability_accuracy": "stability", "locking": "locking"}  # the part of a run that draws each chart
# The order of a page's sections (scene_page's)
ORDER = ("Fastest run of each method", "Where the time goes", STABILITY, LOCKING, REDUCTION,
         *(CHART_TITLES[c] for c in CHARTS))


def run_parts(run: dict) -> list[str]:
    """The parts of its scenes' results (of ``PARTS``) that ``run`` computed (a run recorded without them: every
    part)."""
    return list(run.get("parts", PARTS))


def header(run: dict) -> str:
    """The line a page starts with, per run: machine, dolfinx and PETSc, date, commit, command, load, the scenes it
    ran."""
    m = run["machine"]
    memory = "unknown memory" if m.get("memory_gb") is None else f"{m['memory_gb']:g} GB memory"
    software = f", dolfinx {run['dolfinx']} (PETSc {run.get('petsc', 'unknown')})" if "dolfinx" in run else ""
    return (f"Measured on {m['cpu']}, {m['cores']} cores, {memory}, {m['system']}{software}; {run['date']}; "
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


def reduction_section(scene: str, results: Path, out: Path, run: dict | None = None) -> list[str]:
    """The model-reduction section of ``scene``'s page: its rows and chart (copied into ``out``), headed by
    ``run``'s header when the page's other sections come from another run; empty without rows."""
    rows = results / f"{scene}_reduction.md"
    if not rows.exists():
        return []
    lines = [f"## {REDUCTION}", "", *([header(run)] if run is not None else []), rows.read_text().rstrip(), ""]
    png = results / f"{scene}_reduction.png"
    if png.exists():
        shutil.copyfile(png, out / png.name)
        lines += [f"![{scene}: model reduction, error against solver time and peak memory]({png.name})", ""]
    return lines


def scene_page(scene: str, results: Path, run: dict, out: Path) -> str:
    """The page of one scene: findings, time split (two bodies), stability summary, locking, model reduction and charts
    (copied into ``out``)."""
    lines = [f"# {scene}", "", header(run)]  # the run that produced this scene's results
    error = results / f"{scene}_error.txt"  # bench_run: the traceback of a scene that failed
    if error.exists():
        last = error.read_text().strip().splitlines()[-1:] or ["(no message)"]
        lines += [f"**This scene's run failed** (`{last[0]}`): the sections below are what it wrote before.", ""]
    parts = run_parts(run)  # the results of an earlier run in the folder are not this page's
    if "sweep" in parts:
        lines += _section("Fastest run of each method", results / f"{scene}_findings.md")
        csv = results / f"{scene}.csv"
        split = time_split(bench.read_rows(csv)) if csv.exists() else ""
        if split:
            lines += ["## Where the time goes", "",
                      "The fastest converged run of each method and quadrature; times in s.", "", split]
    if "stability" in parts:
        lines += _section(STABILITY, results / f"{scene}_stability.md")
    if "locking" in parts:
        lines += _section(LOCKING, results / f"{scene}_locking.md")
    if "reduction" in parts:
        lines += reduction_section(scene, results, out)
    for chart in CHARTS:
        png = results / f"{scene}_{chart}.png"
        if png.exists() and CHART_PARTS[chart] in parts:
            shutil.copyfile(png, out / png.name)
            lines += [f"## {CHART_TITLES[chart]}", "", f"![{scene}: {CHART_TITLES[chart]}]({png.name})", ""]
    return "\n".join(lines).rstrip() + "\n"


def _split(page: str) -> tuple[list[str], dict[str, list[str]]]:
    """``page``'s lines before its first section, and each section's lines (after its ``## title`` line) by title."""
    head: list[str] = []
    sections: dict[str, list[str]] = {}
    current = head
    for line in page.rstrip().splitlines():
        if line.startswith("## "):
            current = sections.setdefault(line[3:], [])
        else:
            current.append(line)
    return head, sections


def _images(lines: Sequence[str]) -> list[str]:
    """The charts (file names) that ``lines`` show."""
    return re.findall(r"\]\(([^)]+\.png)\)", "\n".join(lines))


def kept_sections(previous: str, computed: Sequence[str]) -> dict[str, list[str]]:
    """The sections of ``previous`` (a scene's page) that a run which computed only the ``OPTIONAL`` parts
    ``computed`` does not replace, by title, each headed by the run that measured it (its own header, else the
    page's)."""
    head, sections = _split(previous)
    run = next((line for line in head if line.startswith("Measured on ")), None)
    kept = {}
    for key, titles in OPTIONAL.items():
        for title in titles if key not in computed else ():
            if title not in sections:
                continue
            body = _strip(sections[title])
            if run is not None and not (body and body[0].startswith("Measured on ")):
                body = [run, "", *body]
            kept[title] = body
    return kept


def _strip(lines: Sequence[str]) -> list[str]:
    """``lines`` without the blank lines they start and end with."""
    lines = list(lines)
    while lines and not lines[0].strip():
        lines.pop(0)
    while lines and not lines[-1].strip():
        lines.pop()
    return lines


def add_sections(page: str, kept: dict[str, list[str]], replace: bool = False) -> str:
    """``page`` with the sections ``kept`` (by title, their lines after the title; :func:`kept_sections`) put in
    their place in ``ORDER``; a section ``page`` has already is its own, or with ``replace`` ``kept``'s."""
    head, sections = _split(page)
    rank = {title: i for i, title in enumerate(ORDER)}
    merged = dict(sections)
    for title, body in kept.items():
        if title in merged:
            if replace:
                merged[title] = body
            continue
        titles = list(merged)
        at = next((i for i, t in enumerate(titles) if rank.get(t, -1) > rank[title]), len(titles))
        merged = {t: merged[t] for t in titles[:at]} | {title: body} | {t: merged[t] for t in titles[at:]}
    lines = [*_strip(head), ""]
    for title, body in merged.items():
        lines += [f"## {title}", "", *_strip(body), ""]
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


def _table_rows(page: str, title: str) -> list[str]:
    """The rows of the table under ``## title`` in ``page`` (without its header and rule)."""
    lines = page.splitlines()
    if f"## {title}" not in lines:
        return []
    rows = []
    for line in lines[lines.index(f"## {title}") + 1:]:
        if line.startswith("## "):
            break
        if line.startswith("|"):
            rows.append(line)
    return rows[2:]


def _date(header_line: str) -> str:
    """The date and time of a page's header line (``YYYY-MM-DD HH:MM``; empty if it has none)."""
    found = re.search(r"\d{4}-\d\d-\d\d \d\d:\d\d", header_line)
    return found.group() if found else ""


# The pages written by their own scripts (not by a benchmark run), kept and listed here: the side-by-side pages
# with the peer (dolfinx_contact, scripts/peer/run.py) and FElupe (scripts/felupe/run.py), and the page of the same
# scenes on two dolfinx versions (scripts/versions_bench.py).
PEER_PAGE = "peer"
FELUPE_PAGE = "felupe"
VERSIONS_PAGE = "versions"
KEPT_PAGES = (PEER_PAGE, FELUPE_PAGE, VERSIONS_PAGE)


def write_pages(results: str | Path, out: str | Path, demos: str | Path | None = None,
                add: bool = False) -> list[Path]:
    """Write a page per scene with results in ``results`` and ``out/index.md``; returns the pages written.
    Pages and charts of an earlier run in ``out`` are removed first, unless ``add`` (see the module), except the
    pages written by their own scripts (:data:`KEPT_PAGES`: ``peer.md``, ``peer_*.png`` of scripts/peer/run.py, which
    needs the peer's build; ``felupe.md``, ``felupe_*.png`` of scripts/felupe/run.py; ``versions.md`` of
    scripts/versions_bench.py, which needs the wheel lane's root), which the index lists when present."""
    results, out = Path(results).resolve(), Path(out).resolve()  # absolute from the start
    runs = read_runs(results)
    by_scene = {scene: run for run in runs for scene in run["scenes"]}

    def held(suffix: str) -> list[str]:
        return sorted(n for n in (p.name[: -len(suffix)] for p in results.glob(f"*{suffix}")) if n in by_scene)

    scenes = [n for n in held("_findings.md") if "sweep" in run_parts(by_scene[n])]
    reduced = [n for n in held("_reduction.md") if "reduction" in run_parts(by_scene[n])]
    if not scenes and not (add and reduced):
        raise ValueError(f"{results} holds no <scene>_findings.md of a recorded run: no benchmark results")
    out.mkdir(parents=True, exist_ok=True)
    if not add:
        for old in [*out.glob("*.md"), *out.glob("*.png")]:
            if not old.name.startswith(KEPT_PAGES):
                old.unlink()
    pages = []
    for scene in scenes:
        page = out / f"{scene}.md"
        computed = [key for key in OPTIONAL if key in run_parts(by_scene[scene])
                    and (results / f"{scene}_{key}.md").exists()]
        kept = kept_sections(page.read_text(), computed) if add and page.exists() else {}
        shown = set(_images([line for body in kept.values() for line in body]))
        for chart in (*CHARTS, "reduction"):  # an earlier page's charts that this run may not draw, unless kept
            if f"{scene}_{chart}.png" not in shown:
                (out / f"{scene}_{chart}.png").unlink(missing_ok=True)
        page.write_text(add_sections(scene_page(scene, results, by_scene[scene], out), kept))
        pages.append(page)
    for scene in (n for n in reduced if n not in scenes):  # the model-reduction rows alone were rerun
        page = out / f"{scene}.md"
        if page.exists():
            section = reduction_section(scene, results, out, by_scene[scene])  # "## Model reduction", its lines
            page.write_text(add_sections(page.read_text(), {REDUCTION: section[1:]}, replace=True))
        else:
            page.write_text(scene_page(scene, results, by_scene[scene], out))
        pages.append(page)
    return [write_index(out, demos), *pages]


def write_index(out: str | Path, demos: str | Path | None = None) -> Path:
    """Write ``out/index.md``: the header of every run that measured a section of a page in ``out`` (oldest
    first), the pages, their model-reduction rows and, with ``demos``, the demos' checks; returns its path."""
    out = Path(out)
    texts = {p.stem: p.read_text() for p in sorted(out.glob("*.md")) if p.stem not in ("index", *KEPT_PAGES)}
    headers = sorted(dict.fromkeys(line + "\n" for t in texts.values() for line in t.splitlines()
                                   if line.startswith("Measured on ")), key=_date)
    index = ["# Benchmark results", "", *headers,
             "One page per scene; [the benchmark page](../benchmarks.md) says what the columns and charts mean.", "",
             "```{toctree}", ":maxdepth: 1", "", *texts, *(p for p in KEPT_PAGES if (out / f"{p}.md").exists()),
             "```", ""]
    rows = [row for t in texts.values() for row in _table_rows(t, REDUCTION)]
    if rows:  # one table: each scene's rows under the common header
        index += [f"## {REDUCTION}", "", *bench.REDUCTION_HEADER, *rows, ""]
    checks = demo_checks(demos) if demos is not None else ""
    if checks:
        index += ["## Demo checks", "", "Each demo's figure against its scene's reference.", "", checks]
    (out / "index.md").write_text("\n".join(index).rstrip() + "\n")
    return out / "index.md"


def main(argv: Sequence[str] | None = None) -> None:
    """Command line: ``results out [--demos folder]``; bad input ends in one line, exit status 2."""
    import argparse

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("results", help="the benchmark's output folder (make bench: results/bench)")
    p.add_argument("out", help="the folder of the pages (docs/bench)")
    p.add_argument("--demos", default=None, help="a folder of demo results (summary.json) to tabulate")
    p.add_argument("--add", action="store_true",
                   help="keep the pages of scenes these results do not hold and the sections of a rewritten page "
                        "that the run did not compute (a run of some scenes or parts only: make bench)")
    args = p.parse_args(argv)
    try:
        pages = write_pages(args.results, args.out, args.demos, add=args.add)
    except ValueError as exc:
        sys.stderr.write(f"error: {exc}\n")
        raise SystemExit(2) from None
    print(f"{len(pages)} pages -> {args.out}")


if __name__ == "__main__":
    main()
