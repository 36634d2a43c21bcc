"""The benchmark pages: written from a small fixture of benchmark results (not a benchmark run) with the run's
machine, date, commit and command; the committed pages in docs/bench/ carry them and no development history."""
import json
import math
import re
from pathlib import Path

import dolfinx
import pytest
from history import HISTORY
from mpi4py import MPI

from fenics_contact.app import bench, bench_pages, run_record

ROOT = Path(__file__).resolve().parent.parent
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="writes files: the serial lane only")



def _fixture(folder: Path) -> None:
    """Two hertz runs and an SNES VI run on one mesh, their findings, a chart, the run's record, a demo summary."""
    rows = [dict(bench.run_config(m, K, 0, "nodal", 0), scene="hertz", dofs=3990, wall_time_s=t,
                 newton_iterations=n, augmentations=0, linear_iterations=0, converged=True, cutbacks=0,
                 snes_reason=3, error=e, limit_gap=math.nan, setup_time_s=0.5, linear_solve_floor_s=0.05,
                 ratio_to_linear_solve=t / 0.05, p0=11.2)
            for m, K, t, n, e in (("penalty", 1e6, 0.12, 4, 2.1e-2), ("penalty", 1e8, 0.2, 5, 3.2e-3),
                                  ("vi", 0.0, 0.4, 9, 3.1e-3))]
    folder.mkdir()
    bench.write_rows(rows, folder / "hertz.csv", folder / "hertz.json")
    (folder / "hertz_findings.md").write_text(bench.findings("hertz", rows))
    bench.plot_pareto(rows, folder / "hertz_pareto.png", title="hertz")
    run_record.record_run(folder, ["--quick", "--scene", "hertz", "--out", str(folder)], ["hertz"])
    demo = folder.parent / "demos" / "hertz"
    demo.mkdir(parents=True)
    (demo / "summary.json").write_text(json.dumps({
        "scene": "hertz", "method": "auglag", "ranks": 2, "dofs": 3990, "wall_time_s": 0.3,
        "check": {"figure": "p0", "value": 11.235, "reference": 11.2, "rel_error": 3.1e-3, "tolerance": 0.01,
                  "passed": True, "source": "Hertz"}}))


@serial
def test_pages_from_a_fixture_carry_the_run_and_its_figures(tmp_path):
    results, out = tmp_path / "bench", tmp_path / "docs"
    _fixture(results)
    pages = bench_pages.write_pages(results, out, demos=tmp_path / "demos")
    assert [p.name for p in pages] == ["index.md", "hertz.md"]
    [run] = json.loads((results / "run.json").read_text())["runs"]
    machine = run_record.machine()
    assert run["machine"] == machine and machine["cores"] >= 1
    for page in pages:
        text = page.read_text()
        assert machine["cpu"] in text and f"{machine['cores']} cores" in text and "GB memory" in text
        assert run["date"] in text and run["commit"] in text
        assert f", dolfinx {dolfinx.__version__} (PETSc " in text  # the dolfinx each figure was measured on
        assert "command `python demos/bench.py --quick --scene hertz" in text and "; scenes hertz." in text
        assert not HISTORY.search(text), HISTORY.search(text)
    scene = (out / "hertz.md").read_text()
    assert "| 0 | 3990 | penalty | K 1e+08 | 0.0032 |" in scene  # the fastest penalty run within the 1 % target
    assert "![hertz: Error against solver time](hertz_pareto.png)" in scene
    assert (out / "hertz_pareto.png").read_bytes() == (results / "hertz_pareto.png").read_bytes()
    index = (out / "index.md").read_text()
    assert "| hertz | auglag | 2 | 3990 | p0 | 11.235 | 11.2 | 3.10e-03 | 0.01 | yes | 0.3 |" in index
    assert "hertz\n```" in index  # the scene page in the toctree


@serial
def test_pages_keep_and_list_the_side_by_side_pages(tmp_path):
    """The side-by-side pages (the peer's of scripts/peer/run.py, which needs the peer's build; FElupe's of
    scripts/felupe/run.py) survive a rewrite of the scene pages and are in the index's toctree; a scene page of an
    earlier run does not survive."""
    results, out = tmp_path / "bench", tmp_path / "docs"
    _fixture(results)
    out.mkdir()
    (out / "peer.md").write_text("# peer\n")
    (out / "peer_hertz2d.png").write_bytes(b"png")
    (out / "felupe.md").write_text("# felupe\n")
    (out / "felupe_strain.png").write_bytes(b"png")
    (out / "versions.md").write_text("# versions\n")
    (out / "sphere.md").write_text("# an earlier run\n")
    bench_pages.write_pages(results, out)
    assert (out / "peer.md").read_text() == "# peer\n" and (out / "peer_hertz2d.png").exists()
    assert (out / "felupe.md").read_text() == "# felupe\n" and (out / "felupe_strain.png").exists()
    assert (out / "versions.md").read_text() == "# versions\n"
    assert not (out / "sphere.md").exists()
    assert "hertz\npeer\nfelupe\nversions\n```" in (out / "index.md").read_text()


@serial
def test_pages_refuse_a_folder_without_a_run_record(tmp_path, capsys):
    with pytest.raises(SystemExit) as exit_:
        bench_pages.main([str(tmp_path), str(tmp_path / "out")])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "run.json" in err and str(tmp_path) in err


def test_committed_peer_page_states_its_runs_and_no_history():
    """The side-by-side page with the peer (scripts/peer/run.py): each run's cases, command, date and machine,
    a table and an existing chart per case, no development history."""
    page = ROOT / "docs" / "bench" / f"{bench_pages.PEER_PAGE}.md"
    assert page.exists(), f"{page} is committed and must stay"
    text = page.read_text()
    runs = re.findall(r"^Cases [\w, ]+: `python scripts/peer/run\.py [^`]+` on \d{4}-\d\d-\d\d \d\d:\d\d UTC, .+, "
                      r"\d+ cores, [\d.]+ GB", text, flags=re.M)
    assert runs, text[:400]
    assert not HISTORY.search(text), HISTORY.search(text)
    images = re.findall(r"\]\(([^)]+\.png)\)", text)
    assert images and all((page.parent / image).exists() for image in images)
    assert text.count("| code | method | mesh | dofs | Newton |") == len(images)


def test_committed_pages_state_the_machine_and_date_and_no_history():
    pages = sorted(p for p in (ROOT / "docs" / "bench").glob("*.md") if p.stem not in bench_pages.KEPT_PAGES)
    assert pages and pages[0].name != "index.md" or len(pages) > 1
    for page in pages:
        text = page.read_text()
        first = next(line for line in text.splitlines() if line.startswith("Measured on "))
        assert re.search(r", \d+ cores, [\d.]+ GB memory, .*; \d{4}-\d\d-\d\d \d\d:\d\d UTC; commit `[\w ,]+`; "
                         r"command `python demos/bench.py [^`]*--quick", first), first
        assert not HISTORY.search(text), (page.name, HISTORY.search(text))
        for image in re.findall(r"\]\(([^)]+\.png)\)", text):
            assert (page.parent / image).exists(), image
    explained = (ROOT / "docs" / "benchmarks.md").read_text()
    assert not HISTORY.search(explained), HISTORY.search(explained)


def test_time_split_of_two_body_runs_only():
    """The time split lists the fastest converged run per method variant and quadrature, with its search,
    exchange and coupling times; rigid-obstacle rows (no search time) give no table."""
    base = dict(bench.run_config("penalty", 2.5e4, 0, "nodal", 0), scene="hertz_twobody", dofs=9868, converged=True,
                newton_iterations=20, error=1.7e-3, assembly_s=0.76, linear_solve_s=1.39, exchange_s=0.033,
                coupling_s=0.018, ratio_to_linear_solve=15.9)
    rows = [dict(base, wall_time_s=2.16, search_s=0.233), dict(base, wall_time_s=3.0, search_s=0.3),
            dict(base, wall_time_s=1.0, search_s=0.1, converged=False),
            dict(base, quadrature="segment", wall_time_s=2.04, search_s=0.17)]
    table = bench_pages.time_split(rows).splitlines()
    assert len(table) == 4  # header, rule, nodal's fastest converged run, segment's
    assert table[2] == "| 0 | 9868 | penalty | nodal | K 2.5e+04 | 0.0017 | 20 | 2.16 | 0.233 | 0.033 | 0.018 | " \
                       "0.76 | 1.39 | 15.9 |"
    assert "| segment |" in table[3]
    assert bench_pages.time_split([dict(r, search_s=math.nan) for r in rows]) == ""


@serial
def test_each_page_names_the_run_of_its_scene(tmp_path):
    """Two runs into one folder, the second rerunning one scene of the first: each scene's page carries the run
    that produced its results; the index lists both runs."""
    results = tmp_path / "bench"
    _fixture(results)
    (results / "block_findings.md").write_text("block's findings\n")
    first = run_record.record_run(results, ["--quick", "--scene", "block", "--scene", "hertz"], ["block", "hertz"])
    second = run_record.record_run(results, ["--quick", "--scene", "hertz"], ["hertz"])
    runs = run_record.read_runs(results)
    assert [r["scenes"] for r in runs] == [["block"], ["hertz"]]
    bench_pages.write_pages(results, tmp_path / "docs")
    block, hertz, index = ((tmp_path / "docs" / f"{n}.md").read_text() for n in ("block", "hertz", "index"))
    assert first["command"] in block and second["command"] not in block and "; scenes block." in block
    assert second["command"] in hertz and "; scenes hertz." in hertz
    assert first["command"] in index and second["command"] in index


@serial
def test_added_reduction_rows_replace_that_section_and_keep_other_pages(tmp_path):
    """A run of the model-reduction rows alone (``bench --reduction-only``) added to existing pages: the other
    scenes' pages are kept as they are, the rerun scene's page keeps its other sections and gets the new rows
    under the new run's header; the index lists every page and each model-reduction row once."""
    results, out = tmp_path / "bench", tmp_path / "docs"
    results.mkdir()
    out.mkdir()
    old_header = ("Measured on somewhere, 2 cores, 1 GB memory, Linux; 2026-01-01 00:00 UTC; commit `abc`; "
                  "command `x`.\n")
    block = f"# block\n\n{old_header}\n## Fastest run of each method\n\nblock's findings\n"
    (out / "block.md").write_text(block)
    old_rows = "\n".join([*bench.REDUCTION_HEADER, "| hertz: quarter disk (used) | 3990 | old |"])
    (out / "hertz.md").write_text(f"# hertz\n\n{old_header}\n## Fastest run of each method\n\nhertz's findings\n\n"
                                  f"## Model reduction\n\n{old_rows}\n\n## Error against solver time\n\n"
                                  "![hertz: Error against solver time](hertz_pareto.png)\n")
    (out / "hertz_pareto.png").write_bytes(b"png")
    new_rows = "\n".join([*bench.REDUCTION_HEADER, "| hertz: quarter disk (used) | 3990 | new |", ""])
    (results / "hertz_reduction.md").write_text(new_rows)
    (results / "model_reduction.md").write_text(new_rows)  # the run's one table: not a scene's rows
    (results / "hertz_reduction.png").write_bytes(b"chart")
    run = run_record.record_run(results, ["--reduction-only", "--scene", "hertz"], ["hertz"])
    with pytest.raises(ValueError, match="no benchmark results"):
        bench_pages.write_pages(results, tmp_path / "fresh")  # without --add: findings are needed
    bench_pages.write_pages(results, out, add=True)
    assert (out / "block.md").read_text() == block
    hertz = (out / "hertz.md").read_text()
    assert "hertz's findings" in hertz and "| old |" not in hertz and hertz.count("| new |") == 1
    assert hertz.index(run["command"]) > hertz.index("## Model reduction") > hertz.index(old_header)
    assert "](hertz_reduction.png)" in hertz and (out / "hertz_reduction.png").read_bytes() == b"chart"
    assert hertz.index("## Model reduction") < hertz.index("## Error against solver time")
    index = (out / "index.md").read_text()
    assert "block\nhertz\n```" in index and index.count("| new |") == 1 and "| old |" not in index
    assert index.index(old_header) < index.index(run["command"])  # the runs oldest first


@serial
def test_a_rewritten_page_drops_the_charts_its_run_did_not_draw(tmp_path):
    """``--add`` (make bench: the main scenes' pages rewritten, the others kept): a rewritten scene's charts are
    this run's or its previous page's kept sections' (a stability map no page shows is gone); another scene's,
    whose name starts alike, are kept."""
    results, out = tmp_path / "bench", tmp_path / "docs"
    _fixture(results)
    out.mkdir()
    for old in ("hertz_stability.png", "hertz_pareto.png", "hertz_twobody_pareto.png"):
        (out / old).write_bytes(b"old")
    (out / "hertz_twobody.md").write_text("# hertz_twobody\n\n![](hertz_twobody_pareto.png)\n")
    bench_pages.write_pages(results, out, add=True)
    assert not (out / "hertz_stability.png").exists() and "stability" not in (out / "hertz.md").read_text()
    assert (out / "hertz_pareto.png").read_bytes() == (results / "hertz_pareto.png").read_bytes()
    assert (out / "hertz_twobody_pareto.png").read_bytes() == b"old" and (out / "hertz_twobody.md").exists()


@serial
def test_a_rewritten_page_keeps_the_sections_its_run_did_not_compute(tmp_path):
    """``--add`` from a run without the stability map and model reduction (make bench): the previous page's
    stability section and charts and its model-reduction rows are kept, each headed by the run that measured them,
    and the index keeps their rows and headers; a run with the stability map replaces that section, and the index
    drops the header of a run that no page section comes from any more."""
    results, out = tmp_path / "bench", tmp_path / "docs"
    _fixture(results)
    out.mkdir()
    old_run = ("Measured on somewhere, 2 cores, 1 GB memory, Linux; 2026-01-01 00:00 UTC; commit `abc`; "
               "command `python demos/bench.py --quick --scene hertz`.\n")
    reduction_run = old_run.replace("00:00", "01:00").replace("--quick --scene hertz", "--reduction-only")
    old_rows = "\n".join([*bench.REDUCTION_HEADER, "| hertz: quarter disk (used) | 3990 | old |"])
    (out / "hertz.md").write_text(
        f"# hertz\n\n{old_run}\n## Fastest run of each method\n\nold findings\n\n"
        "## Stability over the parameter and the load steps\n\nold stability table\n\n"
        f"## Model reduction\n\n{reduction_run}\n{old_rows}\n\n![hertz: model reduction](hertz_reduction.png)\n\n"
        "## Error against solver time\n\n![hertz: Error against solver time](hertz_pareto.png)\n\n"
        "## Stability map\n\n![hertz: Stability map](hertz_stability.png)\n")
    for chart in ("pareto", "stability", "reduction"):
        (out / f"hertz_{chart}.png").write_bytes(b"old")
    bench_pages.write_pages(results, out, add=True)  # the fixture's run: no stability map, no model reduction
    [run] = run_record.read_runs(results)
    hertz = (out / "hertz.md").read_text()
    titles = re.findall(r"^## (.+)$", hertz, flags=re.M)
    assert titles == ["Fastest run of each method", "Stability over the parameter and the load steps",
                      "Model reduction", "Error against solver time", "Stability map"], titles
    assert "old findings" not in hertz and hertz.index(run["command"]) < hertz.index("## Fastest run")
    stability = hertz[hertz.index("## Stability over"):hertz.index("## Model reduction")]
    assert old_run in stability and "old stability table" in stability
    reduction = hertz[hertz.index("## Model reduction"):hertz.index("## Error against")]
    assert reduction_run in reduction and old_run not in reduction and reduction.count("| old |") == 1
    assert old_run in hertz[hertz.index("## Stability map"):]
    assert (out / "hertz_stability.png").read_bytes() == b"old" == (out / "hertz_reduction.png").read_bytes()
    assert (out / "hertz_pareto.png").read_bytes() == (results / "hertz_pareto.png").read_bytes()
    index = (out / "index.md").read_text()
    assert index.count("| old |") == 1 and all(h in index for h in (old_run, reduction_run, run["command"]))

    (results / "hertz_stability.md").write_text("new stability table\n")  # a run that computed the stability map
    bench_pages.write_pages(results, out, add=True)
    hertz = (out / "hertz.md").read_text()
    assert "new stability table" in hertz and "old stability table" not in hertz
    assert "## Stability map" not in hertz and not (out / "hertz_stability.png").exists()  # this run drew none
    assert old_run not in hertz and reduction_run in hertz  # the model reduction still kept
    index = (out / "index.md").read_text()
    assert old_run not in index and reduction_run in index and index.count("| old |") == 1


@serial
def test_a_run_without_a_part_leaves_an_earlier_runs_results_of_it_off_the_page(tmp_path):
    """Results of an earlier run in the same folder (a stability map, findings) are not the new run's: a sweep
    without the stability map (``parts`` ``sweep``) keeps the previous page's stability section, not the folder's
    older one; a run of the model-reduction rows alone keeps the page's findings under their own run."""
    results, out = tmp_path / "bench", tmp_path / "docs"
    _fixture(results)
    (results / "hertz_stability.md").write_text("earlier stability table\n")
    (results / "hertz_stability.png").write_bytes(b"earlier")
    bench_pages.write_pages(results, out)  # the fixture's run (every part): its stability map
    first = (out / "hertz.md").read_text()
    assert "earlier stability table" in first and (out / "hertz_stability.png").read_bytes() == b"earlier"
    (out / "hertz.md").write_text(first.replace("earlier stability table", "the page's stability table"))
    main = run_record.record_run(results, ["--quick", "--main"], ["hertz"], ["sweep"])
    bench_pages.write_pages(results, out, add=True)
    hertz = (out / "hertz.md").read_text()
    assert "the page's stability table" in hertz and "earlier stability table" not in hertz
    assert hertz.index(main["command"]) < hertz.index("## Fastest run") < hertz.index("## Stability over")
    assert (out / "hertz_stability.png").read_bytes() == b"earlier"  # the kept section's chart
    (results / "hertz_reduction.md").write_text("\n".join([*bench.REDUCTION_HEADER, "| hertz: (used) | 1 | new |"]))
    reduction = run_record.record_run(results, ["--reduction-only", "--scene", "hertz"], ["hertz"], ["reduction"])
    bench_pages.write_pages(results, out, add=True)
    page = (out / "hertz.md").read_text()
    assert page.startswith(hertz.split("## ")[0]) and reduction["command"] not in page.split("## ")[0]
    assert "| new |" in page[page.index(reduction["command"]):] and "the page's stability table" in page
