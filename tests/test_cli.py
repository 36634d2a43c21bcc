"""The strict command line: a misspelt option, a number out of range, an unused or rejected PETSc option end the
demo with a non-zero exit and one line naming the offender, without a traceback (subprocesses, serial lane)."""
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

from fenics_contact.app import cli
from fenics_contact.app.checks import reference_check

ROOT = Path(__file__).resolve().parent.parent
NOISE = ("hwloc/linux:", "[")  # hwloc's warning; UCX's "[<time>] [<host>] ... UCX ERROR" lines
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="subprocesses from the serial lane only")


def demo(name: str, *args: str, out: Path) -> subprocess.CompletedProcess:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return subprocess.run([sys.executable, str(ROOT / "demos" / f"{name}.py"), "--out", str(out), "--no-pictures",
                           "--no-xdmf", "--quiet", *args], capture_output=True, text=True, env=env, timeout=300)


def one_line_error(proc: subprocess.CompletedProcess, *named: str) -> str:
    assert proc.returncode != 0
    assert "Traceback" not in proc.stderr + proc.stdout
    # lines of the MPI stack's own (hwloc and UCX in the Debian 13 root: no /sys there) are not ours
    lines = [line for line in proc.stderr.splitlines() if line.strip() and not line.startswith(NOISE)]
    assert len(lines) == 1, proc.stderr
    for word in named:
        assert word in lines[0], lines[0]
    return lines[0]


@serial
@pytest.mark.parametrize("args,named", [
    (["--refinment", "1"], ["--refinment", "did you mean --refinement"]),
    (["--Mu", "0.8"], ["--Mu", "did you mean --mu"]),
    (["--steps", "-2"], ["--steps", ">= 1", "-2"]),
    (["--refinement", "-1"], ["--refinement", ">= 0"]),
    (["--K", "0"], ["--K", "> 0"]),
    (["--mu", "-0.1"], ["--mu", ">= 0"]),
    (["--a", "1"], ["--a", "[0, 1)"]),
    (["--steps", "two"], ["--steps", "'two'"]),
    (["stray"], ["'stray'"]),
])
def test_bad_command_line_is_one_line_before_any_work(args, named, tmp_path):
    proc = demo("hertz", *args, out=tmp_path)
    one_line_error(proc, *named)
    assert proc.returncode == 2
    assert not (tmp_path / "summary.json").exists()  # refused before any work


@serial
def test_misspelt_petsc_option_is_named_with_its_close_match(tmp_path):
    one_line_error(demo("block", "-fc_snes_max_itt", "1", out=tmp_path), "-fc_snes_max_itt",
                   "did you mean -fc_snes_max_it?")


@serial
def test_petsc_option_without_the_prefix_is_unused(tmp_path):
    one_line_error(demo("block", "-snes_max_it", "1", out=tmp_path), "-snes_max_it")


@serial
def test_rejected_petsc_value_is_one_line(tmp_path):
    line = one_line_error(demo("block", "-fc_snes_linesearch_type", "nonsense", out=tmp_path),
                          "-fc_snes_linesearch_type nonsense")
    assert line.count("\n") == 0


@serial
def test_used_petsc_option_runs(tmp_path):
    proc = demo("block", "-fc_snes_max_it", "20", "-fc_snes_linesearch_type", "basic", out=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert (tmp_path / "summary.json").exists()


@serial
def test_failed_run_is_one_line_with_the_iterations_spent(tmp_path):
    # 2 Newton iterations per attempt cannot solve the hertz step: 5 attempts (4 cutbacks) of 2 iterations each
    proc = demo("hertz", "--steps", "1", "-fc_snes_max_it", "2", out=tmp_path)
    line = one_line_error(proc, "did not converge", "10 Newton iterations spent")
    assert proc.returncode == 1 and line
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert not summary["converged"] and summary["newton_iterations"] == summary["newton_iterations_spent"] == 10
    assert summary["check"]["passed"] is False and summary["check"]["value"] is None


def test_inexact_needs_the_iterative_solver():
    p = cli.parser("test", default_K=1.0)
    with pytest.raises(cli.UsageError, match="--inexact needs --solver iterative, got --solver direct"):
        cli.parse(p, ["--inexact"])
    args = cli.parse(p, ["--inexact", "--solver", "iterative"])
    assert cli.solver_options(args)["snes_ksp_ew"] is True and "snes_ksp_ew" not in cli.solver_options(
        cli.parse(p, ["--solver", "iterative"]))


def test_number_ranges():
    steps = cli.number(int, 1)
    assert steps("3") == 3
    for bad in ("0", "-2", "1.5", "x"):
        with pytest.raises(Exception, match=">= 1"):
            steps(bad)
    a = cli.number(float, 0.0, 1.0, high_open=True)
    assert a("0") == 0.0
    for bad in ("1", "nan", "inf", "-0.1"):
        with pytest.raises(Exception, match=r"\[0, 1\)"):
            a(bad)


def test_unknown_option_in_process_names_the_close_match():
    p = cli.parser("test", default_K=1.0)
    p.add_argument("--refinement", type=cli.LEVEL, default=0)
    with pytest.raises(cli.UsageError, match="unknown option --refinment .did you mean --refinement"):
        cli.parse(p, ["--refinment", "1"])
    with pytest.raises(cli.UsageError, match="--refinement: must be an integer >= 0, got -1"):
        cli.parse(p, ["--refinement", "-1"])


def test_check_record():
    c = reference_check("p", 1.01, 1.0, 2e-2, "closed form")
    assert c["passed"] and abs(c["rel_error"] - 0.01) < 1e-12
    assert not reference_check("p", 1.03, 1.0, 2e-2)["passed"]
    assert reference_check("p", None, 1.0, 2e-2) == {"figure": "p", "value": None, "reference": 1.0, "rel_error": None,
                                           "tolerance": 2e-2, "passed": False, "source": ""}
    with pytest.raises(ValueError, match="tolerance"):
        reference_check("p", 1.0, 1.0, 0.0)


def test_error_line_knows_the_user_errors_only():
    class UnsupportedCombination(Exception):
        pass

    from fenics_contact.solver import ConvergenceError

    assert cli.error_line(ValueError("--K must be > 0\nmore")) == "--K must be > 0"
    assert cli.error_line(UnsupportedCombination("nodal two-pass: use gauss")) == "nodal two-pass: use gauss"
    assert cli.error_line(ConvergenceError("step 1 failed", {}, 12)) == \
        "did not converge: step 1 failed (12 Newton iterations spent)"
    assert cli.error_line(TypeError("a bug")) is None  # a bug keeps its traceback
