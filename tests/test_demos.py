"""Smoke test: every demo's main(argv) on a tiny size passes its own check (serial and under mpirun -n 2).

In process (not as a subprocess): under ``mpirun`` every rank runs the test, so every rank calls ``main``.
"""
import importlib.util
import json
from pathlib import Path

import pytest

from fenics_contact.app.__main__ import DRIVERS, demo_names

DEMOS = Path(__file__).resolve().parent.parent / "fenics_contact" / "app" / "demos"
# demo name -> its small-size options: demos/quick.txt, the list make demo runs
TINY = {line.split()[0]: line.split()[1:] for line in (DEMOS / "quick.txt").read_text().splitlines()
        if line.strip() and not line.startswith("#")}
# Not in the smoke test: the drivers, and mindlin3d (3D two-body friction: its smallest size that meets its own
# check takes minutes; tests/test_mindlin3d.py runs the scene on a coarse mesh).
SCRIPTS = sorted(n for n in demo_names() if n not in (*DRIVERS, "mindlin3d"))


def load(name: str):
    spec = importlib.util.spec_from_file_location(f"demo_{name}", DEMOS / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_every_demo_is_in_the_smoke_test():
    assert sorted(TINY) == SCRIPTS


@pytest.mark.parametrize("name", sorted(TINY))
def test_demo_passes_its_check(name, tmp_path_factory, comm):
    out = comm.bcast(str(tmp_path_factory.mktemp(name)) if comm.rank == 0 else None)
    summary = load(name).main([*TINY[name], "--out", out, "--no-pictures", "--no-xdmf", "--quiet"])
    on_disk = json.loads((Path(out) / "summary.json").read_text())
    check = on_disk["check"]
    assert set(check) >= {"figure", "value", "reference", "rel_error", "tolerance", "passed"}
    assert check["passed"], check
    assert check["rel_error"] <= check["tolerance"]
    assert summary["check"] == check and on_disk["ranks"] == comm.size


def test_table_needs_a_passed_check_in_every_row():
    table = load("table")
    ok_row = {"scene": "block", "method": "cross", "ranks": 1, "dofs": 90, "newton_iterations": 8, "wall_time_s": 0.1,
              "check": {"figure": "contact_pressure", "value": 1.0, "reference": 1.0, "rel_error": 0.0,
                        "tolerance": 1e-8, "passed": True}}
    text, ok = table.table([ok_row])
    assert ok and "contact_pressure" in text and "True" in text
    failed = {**ok_row, "check": {**ok_row["check"], "value": None, "rel_error": None, "passed": False}}
    assert not table.table([ok_row, failed])[1]
    assert not table.table([ok_row, {k: v for k, v in ok_row.items() if k != "check"}])[1]  # no check: a failure
    off = {**ok_row, "scene": "hertz", "check": {**ok_row["check"], "figure": "p0", "rel_error": 0.3, "tolerance": 0.02,
                                                 "passed": False}}
    assert table.failed_checks([ok_row, off, failed, {"scene": "pin"}]) == [
        "hertz (p0: rel. error 3.00e-01 > 2e-02)", "block (contact_pressure: no value)", "pin (check: no check)"]


@pytest.mark.parametrize("method", ["penalty", "nitsche"])
def test_hertz_demo_at_its_defaults_passes_its_check(method, tmp_path_factory, comm):
    """The demo's default K (penalty: 10 x the augmented methods' scale on the rigid plate, where p / K is the
    whole error: p0 2.1 % low at 1e6) and gamma0 meet its own 2 % check on the default mesh."""
    out = comm.bcast(str(tmp_path_factory.mktemp(method)) if comm.rank == 0 else None)
    summary = load("hertz").main(["--method", method, "--out", out, "--no-pictures", "--no-xdmf", "--quiet"])
    assert summary["check"]["passed"], summary["check"]
    assert summary["warnings"] == [] and summary["check"]["flag"] is None  # small strain, a/R ~ 0.09


def test_hertz_two_body_exact_in_one_step_from_the_demo(tmp_path_factory, comm):
    """The two-body Hertz case of two identical bodies (the benchmark's options, hertz.TWO_BODY: force 10 from
    rest) by the exact condensed method in one load step (no vanishing spring): p0 within 0.5 % of Hertz, the load
    carried by the contact alone."""
    from fenics_contact.app.scenes.hertz import TWO_BODY

    out = comm.bcast(str(tmp_path_factory.mktemp("hertz_twobody")) if comm.rank == 0 else None)
    summary = load("hertz").main([*TWO_BODY, "--method", "coulomb", "--steps", "1", "--out", out, "--no-pictures",
                                  "--no-xdmf", "--quiet"])
    assert summary["converged"] and summary["load_steps"] == 1
    assert summary["p0_error"] < 5e-3 and summary["load_error"] < 1e-10, (summary["p0_error"], summary["load_error"])


def test_block_demo_with_the_mixed_model_meets_the_closed_form(tmp_path_factory, comm):
    """``--model neohookean-mixed`` (rubber, nu = 0.4999): the demo's own check, the closed-form pressure to 1e-8
    with converged augmentation."""
    out = comm.bcast(str(tmp_path_factory.mktemp("block_mixed")) if comm.rank == 0 else None)
    summary = load("block").main(["--model", "neohookean-mixed", "--nu", "0.4999", "--quadrature", "gauss",
                                  "--method", "auglag", "--augment", "30", "--out", out, "--no-pictures",
                                  "--no-xdmf", "--quiet"])
    assert summary["check"]["passed"] and summary["check"]["tolerance"] == 1e-8, summary["check"]
