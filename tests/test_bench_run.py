"""The benchmark's command line: its outputs from any working directory, a failed scene that leaves the others
written, the time of each scene, the main scenes of ``make bench``. The runs are stand-ins (no demo process):
what is tested is everything the sweep does with their rows."""
import math
import os

import pytest
from mpi4py import MPI

from fenics_contact import methods
from fenics_contact.app import bench, bench_pages, bench_run, run_record
from fenics_contact.app.cli import EXIT_ERROR


def _stand_in(scene, cfg, folder, timeout=0.0):
    """A converged run's row, as :func:`bench.run_one` gives it, without running the demo: error and time fall
    with K (so the findings and charts have a front to draw), the scene's figures near 1."""
    folder.mkdir(parents=True, exist_ok=True)
    s, K = bench.spec(scene), cfg["K"] or 1e6
    figures = {k: 1.0 + 1e-3 * math.log10(K) for k in dict.fromkeys([s["value"], *s.get("figures", [])])}
    row = {"scene": scene, **{k: v for k, v in cfg.items() if k != "args"}, "dofs": 100, "wall_time_s": 0.1,
           "newton_iterations": 3, "augmentations": 0, "linear_iterations": 3, "converged": True, "cutbacks": 0,
           "snes_reason": 2, "error": 1.0 / K, "limit_gap": math.nan, "process_time_s": 1.0, "setup_time_s": 0.5,
           "assembly_s": 0.01, "linear_solve_s": 0.01, "augmentation_s": 0.0, "search_s": math.nan,
           "exchange_s": math.nan, "coupling_s": math.nan, "memory_peak_mb": 100.0, "linear_solve_floor_s": 0.01,
           "ratio_to_linear_solve": 10.0, "condition_estimate": math.nan, "stalled_solves": 0,
           "residual_final": 1e-12, "failure_kind": "", **figures}
    return {**row, "status": bench.status(row)}


@pytest.fixture
def elsewhere(tmp_path, monkeypatch):
    """The sweep's runs are stand-ins; the working directory is a fresh folder (each rank its own)."""
    monkeypatch.setattr(bench, "run_one", _stand_in)
    cwd = tmp_path / f"rank{MPI.COMM_WORLD.rank}" / "elsewhere"
    cwd.mkdir(parents=True)
    monkeypatch.chdir(cwd)
    return cwd


def test_locking_report_is_written_from_another_working_directory(elsewhere):
    """The O-ring's sweep and locking map into a relative ``--out`` from another working directory: the locking
    table and chart are where the CSV is, the scene's findings are its accuracy rows' (not the locking rows'), and
    the working directory is the one the program started in."""
    bench_run.main(["--scene", "oring", "--quick", "--no-stability", "--no-reduction", "--quiet", "--out", "rel/bench"])
    out = elsewhere / "rel" / "bench"
    assert os.getcwd() == str(elsewhere)
    for name in ("oring.csv", "oring_findings.md", "oring_locking.csv", "oring_locking.json", "oring_locking.md",
                 "oring_locking.png"):
        assert (out / name).is_file(), name
    lk = bench.spec("oring")["locking"]
    assert all(f"| {label} |" in (out / "oring_locking.md").read_text() for label, _ in lk["variants"])
    findings = (out / "oring_findings.md").read_text()
    assert "| cross |" in findings and "| auglag augmented |" in findings  # the accuracy rows' methods


def test_a_scene_that_fails_is_one_line_and_the_others_are_written(elsewhere, monkeypatch, capsys):
    """A scene whose report raises: one line naming it (its traceback in a file), the other scenes' results and
    pages written, the time table with every scene, exit status 1 at the end."""
    report = bench.report

    def broken(scene, rows, out, pictures=True):
        if scene == "block":
            raise RuntimeError("the chart could not be drawn")
        return report(scene, rows, out, pictures)

    monkeypatch.setattr(bench, "report", broken)
    with pytest.raises(SystemExit) as exit_:
        bench_run.main(["--scene", "block", "--scene", "slab", "--quick", "--out", "results/bench"])
    assert exit_.value.code == EXIT_ERROR
    captured = capsys.readouterr()
    out = elsewhere / "results" / "bench"
    if MPI.COMM_WORLD.rank == 0:
        lines = captured.err.splitlines()
        assert len(lines) == 1 and "scene block failed" in lines[0] and "chart could not be drawn" in lines[0]
        table = captured.out[captured.out.index("| scene | runs |"):].splitlines()
        assert table[2].startswith(f"| block | {len(bench.sweep('block', quick=True))} | 0 |")
        assert table[2].endswith("| failed |")
        assert table[3].startswith(f"| slab | {len(bench.sweep('slab', quick=True))} | 0 |")
        assert table[3].endswith("| done |") and table[4].endswith("| 1 failed |")
    else:
        assert captured.err == ""
    assert "RuntimeError" in (out / "block_error.txt").read_text()
    assert (out / "block.csv").is_file()  # its runs' rows are kept
    for name in ("slab.csv", "slab.json", "slab_findings.md", "slab_pareto.png"):
        assert (out / name).is_file(), name
    pages = bench_pages.write_pages(out, elsewhere / "pages")
    assert [p.name for p in pages] == ["index.md", "slab.md"]
    # a scene that failed after its findings: its page says so, with what it wrote
    (out / "block_findings.md").write_text("| mesh |\n")
    pages = bench_pages.write_pages(out, elsewhere / "pages")
    text = (elsewhere / "pages" / "block.md").read_text()
    assert "run failed** (`RuntimeError: the chart could not be drawn`)" in text and "| mesh |" in text
    assert "failed" not in (elsewhere / "pages" / "slab.md").read_text()


def test_the_main_scenes_show_every_method():
    """``make bench`` (``--main``): the main scenes together sweep every declared method, and refuse nothing."""
    swept = {r["method"] for scene in bench_run.MAIN_SCENES for r in bench.sweep(scene, main=True)}
    assert swept == set(methods.names())
    for scene in bench_run.MAIN_SCENES:  # a part of the quick sweep (make bench-all)
        quick = [bench.run_name(r) for r in bench.sweep(scene, quick=True)]
        assert set(bench.run_name(r) for r in bench.sweep(scene, main=True)) <= set(quick)
    assert set(bench_run.MAIN_SCENES) <= set(bench.bench_scenes())


def test_time_table_adds_up():
    times = [dict(scene="hertz", runs=30, failed=1, wall_s=100.4, cpu_s=90.0, status="done"),
             dict(scene="slab", runs=6, failed=0, wall_s=20.0, cpu_s=18.2, status="failed")]
    lines = bench_run.time_table(times).splitlines()
    assert lines[2] == "| hertz | 30 | 1 | 100 | 90 | done |"
    assert lines[-1] == "| total | 36 | 1 | 120 | 108 | 1 failed |"


def test_the_run_record_names_the_parts_it_computes(elsewhere):
    """``make bench`` (``--main``) records that its scenes' results are the sweep alone (the pages keep the
    stability maps, locking and model reduction of an earlier run); the other command lines their parts."""
    bench_run.main(["--scene", "slab", "--quick", "--main", "--quiet", "--out", "b"])
    [run] = run_record.read_runs(elsewhere / "b")
    assert run["scenes"] == ["slab"] and run["parts"] == ["sweep"]
    parse = bench_run._parser().parse_args
    assert bench_run.parts_computed(parse(["--quick"])) == list(run_record.PARTS)
    assert bench_run.parts_computed(parse(["--no-locking", "--no-reduction"])) == ["sweep", "stability"]
    assert bench_run.parts_computed(parse(["--reduction-only"])) == ["reduction"]
