"""The strict command line: a misspelt option, a number out of range, an unused or rejected PETSc option end the
demo with a non-zero exit and one line naming the offender, without a traceback (subprocesses, serial lane); so
do a size the memory cannot hold and running out of memory. A failed check exits 3 after the outputs are
written; an exception on one rank of an mpirun job ends the job."""
import json
import logging
import os
import resource
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from mpi4py import MPI

from fenics_contact.app import cli
from fenics_contact.app.checks import reference_check

ROOT = Path(__file__).resolve().parent.parent
NOISE = ("hwloc/linux:", "[")  # hwloc's warning; UCX's "[<time>] [<host>] ... UCX ERROR" lines
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="subprocesses from the serial lane only")


def _env() -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _cap(nbytes: int):
    """A ``preexec_fn`` capping the child's address space (``ulimit -v``)."""
    return lambda: resource.setrlimit(resource.RLIMIT_AS, (nbytes, nbytes))


def demo(name: str, *args: str, out: Path, memory: int | None = None) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(ROOT / "demos" / f"{name}.py"), "--out", str(out), "--no-pictures",
                           "--no-xdmf", "--quiet", *args], capture_output=True, text=True, env=_env(), timeout=300,
                          preexec_fn=None if memory is None else _cap(memory))


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
    with pytest.raises(cli.UsageError, match="--refinement must be an integer >= 0, got -1"):
        cli.parse(p, ["--refinement", "-1"])


def test_check_record():
    c = reference_check("p", 1.01, 1.0, 2e-2, "closed form")
    assert c["passed"] and abs(c["rel_error"] - 0.01) < 1e-12
    assert not reference_check("p", 1.03, 1.0, 2e-2)["passed"]
    assert reference_check("p", None, 1.0, 2e-2) == {"figure": "p", "value": None, "reference": 1.0, "rel_error": None,
                                           "tolerance": 2e-2, "passed": False, "source": "", "flag": None}
    with pytest.raises(ValueError, match="tolerance"):
        reference_check("p", 1.0, 1.0, 0.0)


def test_hertz_reference_beyond_its_range_is_flagged(caplog):
    """Hertz's parabolic profile x^2 / (2R) against the circle R - sqrt(R^2 - x^2): its relative error at the
    contact edge is (a/R)^2 / 4 to leading order, 1 % at the flag's a/R = 0.2; the flag says so and the check's
    line carries it, whether the check passed or not."""
    from fenics_contact.app.checks import HERTZ_RANGE, hertz_range, log_check

    for ratio in (0.05, HERTZ_RANGE):
        circle = 1.0 - (1.0 - ratio**2) ** 0.5
        assert abs(ratio**2 / 2 - circle) / circle == pytest.approx(ratio**2 / 4, rel=0.1)
    assert hertz_range(0.1, 1.0) is None and hertz_range(HERTZ_RANGE * 5.0, 5.0) is None
    assert hertz_range(None, 1.0) is None
    flag = hertz_range(0.35, 1.0)
    assert flag.startswith("a/R = 0.35 > 0.2") and "3.1%" in flag  # 0.35^2 / 4
    assert hertz_range(0.35e-3, 1e-3) == flag  # a ratio: any length unit
    c = reference_check("p0", 1.01, 1.0, 2e-2, "Hertz", flag)
    assert c["passed"] and c["flag"] == flag
    checks_logger = logging.getLogger("fenics_contact.app.checks")
    checks_logger.addHandler(caplog.handler)  # the command line's set-up may have stopped its propagation
    try:
        with caplog.at_level(logging.INFO, logger="fenics_contact.app.checks"):
            log_check(c)
    finally:
        checks_logger.removeHandler(caplog.handler)
    assert caplog.records[-1].levelno == logging.WARNING
    assert caplog.records[-1].getMessage().endswith(f"passed (reference out of its range: {flag})")


def test_error_line_knows_the_user_errors_only():
    class UnsupportedCombination(Exception):
        pass

    from fenics_contact.solver import ConvergenceError

    assert cli.error_line(ValueError("--K must be > 0\nmore")) == "--K must be > 0"
    assert cli.error_line(UnsupportedCombination("nodal two-pass: use gauss")) == "nodal two-pass: use gauss"
    assert cli.error_line(ConvergenceError("step 1 failed", {}, 12)) == \
        "did not converge: step 1 failed (12 Newton iterations spent)"
    assert cli.error_line(TypeError("a bug")) is None  # a bug keeps its traceback


@serial
@pytest.mark.parametrize("name,args,named", [
    # 0.3 R: linear elasticity at 17 % strain, a/R = 0.65: p0 7 % off Hertz, the reference flagged as out of range
    ("hertz", ["--approach", "0.3"], ["rel. error", "> tolerance", "; reference out of its range: a/R = 0.651"]),
    ("hertz", ["--method", "auglag", "--mu", "1e300"], ["rel. error", "> tolerance"]),
    # q = 1e6 on E = 1000: strains ~1000 turn cells over, the run gives no answer to check
    ("rings", ["--main-only", "--n", "8", "--q", "1e6"], ["has no value (the run gave none)"]),
    ("mindlin", ["--method", "auglag", "--press-steps", "4"], ["rel. error", "> tolerance"]),  # the stick zone 9 % off
], ids=["hertz-approach", "hertz-mu", "rings-q", "mindlin-auglag"])
def test_failed_check_exits_3_after_writing_its_outputs(name, args, named, tmp_path):
    start = time.monotonic()
    proc = demo(name, *args, out=tmp_path)
    line = one_line_error(proc, "check failed: ", *named)
    assert proc.returncode == 3 and line.startswith(f"{name}.py: check failed: ")
    assert time.monotonic() - start < 60
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["check"]["passed"] is False


@serial
@pytest.mark.parametrize("name,args,status,named", [
    ("block", ["-fc_snes_max_it", "-5"], 2, ["PETSc rejected -fc_snes_max_it -5:", "must be non-negative"]),
    ("block", ["-fc_ksp_rtol", "2"], 2, ["PETSc rejected -fc_ksp_rtol 2:", "less than 1.0"]),
    ("hertz", ["--steps", "1000000000"], 2, ["--steps", "must be an integer in [1, ", "got '1000000000'"]),
    ("hertz", ["--refinement", "12"], 2, ["--refinement 12: about", "of memory", "accepted: --refinement 0 to "]),
    ("sphere", ["--size", "1e-9"], 2, ["--size 1e-09: about", "accepted: --size >= "]),
    ("oring", ["--h", "1e-7"], 2, ["--h 1e-07: about", "accepted: --h >= "]),
    ("block", ["--method", "penalty", "--augment", "5"], 2, ["--augment 5: method penalty has nothing to augment"]),
    ("hertz", ["-fc_mat_mumps_icntl_14", "100000000"], 1,
     ["error: out of memory: ", "a cutback cannot help", "MUMPS INFOG(1) = -13"]),
    ("mindlin", ["--method", "coulomb", "--sliding", "finite"], 1, ["finite sliding", "use sliding 'small'"]),
    ("mindlin3d", ["--method", "coulomb", "--sliding", "finite"], 1, ["finite sliding", "use sliding 'small'"]),
])
def test_user_errors_are_one_line_within_seconds(name, args, status, named, tmp_path):
    """Values PETSc would take silently or fail on later, absurd sizes, MUMPS out of memory, a sliding the method
    does not do: one line naming the option (or what ran out), the exit status, within seconds; the refusals
    before any work."""
    start = time.monotonic()
    proc = demo(name, *args, out=tmp_path)
    one_line_error(proc, *named)
    assert proc.returncode == status and time.monotonic() - start < 30
    if "out of memory" not in named[0]:
        assert not (tmp_path / "summary.json").exists()  # refused before any work
    else:  # one failed attempt, no cutback
        assert len(json.loads((tmp_path / "summary.json").read_text())["failures"]) == 1


@serial
def test_absurd_refinement_under_a_memory_cap_names_the_cap(tmp_path):
    proc = demo("hertz", "--refinement", "12", out=tmp_path, memory=2 * 10**9)
    line = one_line_error(proc, "--refinement 12:", "(ulimit -v)", "accepted: --refinement 0 to ")
    assert proc.returncode == cli.EXIT_USAGE and "this process may use" in line


def _script(tmp_path: Path, body: str) -> Path:
    path = tmp_path / "script.py"
    path.write_text("import sys\nimport numpy as np\nfrom mpi4py import MPI\nfrom fenics_contact.app import cli\n\n"
                    + textwrap.dedent(body) + "\n\ncli.main(demo)\n")
    return path


@serial
def test_memory_error_is_one_line_naming_what_ran_out(tmp_path):
    script = _script(tmp_path, """
        def demo(argv):
            return np.ones(10**15)  # 8 PB
    """)
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=_env(), timeout=120)
    line = one_line_error(proc, "error: out of memory: Unable to allocate", "(in ", "script.py:", "demo)")
    assert proc.returncode == 1 and "GB" in line


def _mpirun(script: Path, *args: str, timeout: float) -> tuple[subprocess.CompletedProcess, float]:
    env = {**_env(), "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1"}
    start = time.monotonic()
    proc = subprocess.run(["mpirun", "-n", "2", sys.executable, str(script), *args], capture_output=True, text=True,
                          env=env, timeout=timeout)
    return proc, time.monotonic() - start


@serial
def test_an_exception_on_one_rank_ends_the_mpi_job(tmp_path):
    """Rank 1 raises (a bug) while rank 0 waits in a collective: the traceback is printed and the whole job ends
    within 10 s, with a non-zero exit, instead of rank 0 waiting for ever."""
    script = _script(tmp_path, """
        def demo(argv):
            if MPI.COMM_WORLD.rank == 1:
                raise RuntimeError("a bug seen by rank 1 only")
            MPI.COMM_WORLD.barrier()
    """)
    proc, elapsed = _mpirun(script, timeout=60)
    assert proc.returncode != 0 and elapsed < 10, (elapsed, proc.stderr)
    assert "Traceback" in proc.stderr and "RuntimeError: a bug seen by rank 1 only" in proc.stderr


@serial
def test_an_expected_error_on_one_rank_ends_the_mpi_job(tmp_path):
    """A one-line error raised by rank 1 alone while rank 0 waits in a collective: rank 1 waits for the others a
    few seconds, says its line and ends the job; raised by every rank: one line from rank 0, every rank exits 1."""
    script = _script(tmp_path, """
        def demo(argv):
            if sys.argv[1] == "every" or MPI.COMM_WORLD.rank == 1:
                raise ValueError(f"a bad value seen by rank {MPI.COMM_WORLD.rank}")
            MPI.COMM_WORLD.barrier()
    """)
    proc, elapsed = _mpirun(script, "one", timeout=60)
    assert proc.returncode != 0 and elapsed < 15, (elapsed, proc.stderr)
    assert "rank 1: error: a bad value seen by rank 1" in proc.stderr and "Traceback" not in proc.stderr
    proc, elapsed = _mpirun(script, "every", timeout=60)
    assert proc.returncode == 1 and elapsed < 10, (elapsed, proc.stderr)
    assert "script.py: error: a bad value seen by rank 0" in proc.stderr and "seen by rank 1" not in proc.stderr


@serial
def test_make_demo_names_the_demos_whose_check_failed(tmp_path):
    runs = tmp_path / "runs.txt"
    runs.write_text("block\nhertz --approach 0.3 --no-pictures --no-xdmf\n")
    env = {**_env(), "QUICK": str(runs), "MPIRUN": "env", "PY": sys.executable}
    proc = subprocess.run(["bash", str(ROOT / "scripts" / "demos.sh"), "quick", str(tmp_path / "out")], cwd=ROOT,
                          capture_output=True, text=True, env=env, timeout=300)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert "demos whose check failed (exit status 3): hertz" in proc.stdout
    assert "checks failed: hertz (p0: rel. error" in proc.stdout and "demos that failed" not in proc.stdout


@serial
def test_gmsh_out_of_memory_is_one_line(tmp_path):
    """gmsh running out of memory (std::bad_alloc in a parallel region aborts its process) in the mesher's child
    process: one line saying so, under a 0.82 GB cap."""
    script = _script(tmp_path, """
        def demo(argv):
            from fenics_contact.app.meshes import hertz_quarter_disk

            hertz_quarter_disk(MPI.COMM_WORLD, 1.0, h_contact=1e-5, h_far=0.1, contact_width=0.1)
    """)
    proc = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, env=_env(), timeout=300,
                          preexec_fn=_cap(820 * 10**6))
    line = one_line_error(proc, "gmsh", "memory", "the quarter disk")
    assert proc.returncode == 1 and "out of memory" in line


def test_counts_are_bounded_by_the_memory():
    steps = cli.count(1)
    assert steps("3") == 3
    with pytest.raises(Exception, match=r"must be an integer in \[1, \d+\] \(a load step or a cell takes at least "
                                        r"1 kB of .*\), got '1000000000000'"):
        steps("1000000000000")
    with pytest.raises(Exception, match=r">= 2"):
        cli.count(2)("1")


def test_error_line_of_the_new_kinds():
    from fenics_contact.app.meshes.gmshutil import MeshingError
    from fenics_contact.app.scenes import SizeError
    from fenics_contact.solver import ConvergenceError

    oom = ConvergenceError("load step 1 did not converge (a cutback cannot help): MUMPS ...",
                           {"kind": "out_of_memory"}, 3)
    assert cli.error_line(oom).startswith("out of memory: load step 1")
    assert cli.error_line(SizeError("h_contact", 1e-9, "about 1e12 unknowns", ">= 0.01")) == \
        "--h-contact 1e-09: about 1e12 unknowns; accepted: --h-contact >= 0.01"
    assert cli.error_line(MeshingError("gmsh failed to mesh the seal: ...")) == "gmsh failed to mesh the seal: ..."
    try:
        raise MemoryError()
    except MemoryError as exc:
        line = cli.error_line(exc)
    assert line.startswith("out of memory: Python could not allocate memory (in ") and "test_cli.py" in line
    assert cli._failed_check({"check": {"figure": "p0", "value": 2.0, "reference": 1.0, "rel_error": 1.0,
                                        "tolerance": 0.02, "passed": False, "source": "Hertz"}}) == \
        "check failed: p0 = 2, reference 1 (Hertz), rel. error 1.00e+00 > tolerance 2e-02"
    assert cli._failed_check({"check": {"passed": True}}) is None and cli._failed_check(None) is None


def test_petsc_values_checked_alone_and_named(monkeypatch):
    """A value PETSc takes without a word (-fc_snes_max_it -5: the solve later fails with "Internal error") is
    checked on its own before any work, with PETSc's complaint; an option PETSc accepts passes, and the probe
    leaves nothing in PETSc's database. A PETSc error naming no option lists those given."""
    from petsc4py import PETSc

    with pytest.raises(cli.UsageError, match=r"^PETSc rejected -fc_snes_max_it -5: Maximum number of iterations -5 "
                                             r"must be non-negative$"):
        cli.check_petsc_values([("fc_snes_max_it", "-5")])
    cli.check_petsc_values([("fc_snes_monitor", ""), ("fc_snes_max_it", "5"), ("other_prefix_ksp_rtol", "2")])

    class Internal(PETSc.Error):
        def __str__(self):
            return "error code 77\n[0] SNESSolve() at snes.c:4694\n[0] Internal error, solver returned without " \
                   "setting converged reason"

    monkeypatch.setattr(cli, "_PETSC_OPTIONS", [("fc_snes_max_it", "-5"), ("fc_snes_monitor", "")])
    assert cli.error_line(Internal(77)) == "PETSc error 77: Internal error, solver returned without setting " \
        "converged reason (PETSc options given: -fc_snes_max_it -5, -fc_snes_monitor)"


@serial
@pytest.mark.parametrize("leave,status,said", [
    ("sys.exit(4)", 4, "exit status 4"),
    ("sys.exit('a message of rank 1')", 1, "a message of rank 1"),
    ("raise KeyboardInterrupt", cli.EXIT_INTERRUPTED, "interrupted by SIGINT"),
    ("os.kill(os.getpid(), signal.SIGINT); time.sleep(60)", cli.EXIT_INTERRUPTED, "interrupted by SIGINT"),
], ids=["exit-code", "exit-message", "KeyboardInterrupt", "SIGINT"])
def test_a_rank_that_leaves_ends_the_mpi_job(leave, status, said, tmp_path):
    """Rank 1 leaves (sys.exit, KeyboardInterrupt, SIGINT of that rank alone) while rank 0 waits in a collective:
    the whole job ends within seconds, with one line saying why from rank 1 and no traceback, instead of rank 0
    waiting for ever; left by every rank, the job ends with that status."""
    script = _script(tmp_path, f"""
        import os, signal, time

        def demo(argv):
            if sys.argv[1] == "every" or MPI.COMM_WORLD.rank == 1:
                {leave}
            MPI.COMM_WORLD.barrier()
    """)
    proc, elapsed = _mpirun(script, "one", timeout=60)
    assert proc.returncode != 0 and elapsed < 20, (elapsed, proc.stderr)
    assert f"rank 1: {said}" in proc.stderr and "Traceback" not in proc.stderr, proc.stderr
    proc, elapsed = _mpirun(script, "every", timeout=60)
    assert proc.returncode == status and elapsed < 20, (elapsed, proc.returncode, proc.stderr)
    assert "Traceback" not in proc.stderr and ("script.py: " + said in proc.stderr or said.startswith("exit")), \
        proc.stderr


@serial
def test_an_exception_outside_main_on_one_rank_ends_the_mpi_job(tmp_path):
    """An exception escaping on rank 1 outside cli.main (a script's own code, a late import) while rank 0 waits in
    a collective: its traceback, and the job ends within seconds."""
    script = tmp_path / "script.py"
    script.write_text(textwrap.dedent("""
        from mpi4py import MPI
        from fenics_contact.app import cli

        if MPI.COMM_WORLD.rank == 1:
            raise KeyboardInterrupt
        MPI.COMM_WORLD.barrier()
    """))
    proc, elapsed = _mpirun(script, timeout=60)
    assert proc.returncode != 0 and elapsed < 20, (elapsed, proc.stderr)
    assert "KeyboardInterrupt" in proc.stderr


def _ranks_of(marker: str) -> list[int]:
    """The pids of the processes whose command line holds ``marker`` (a job's ranks), lowest first."""
    found = []
    for cmdline in Path("/proc").glob("[0-9]*/cmdline"):
        try:
            words = cmdline.read_bytes().split(b"\0")
        except OSError:
            continue
        if b"python" in words[0] and marker.encode() in b" ".join(words):
            found.append(int(cmdline.parent.name))
    return sorted(found)


@serial
@pytest.mark.scene
def test_sigint_to_one_rank_during_form_compilation_ends_the_job(tmp_path):
    """SIGINT to one rank of ``mpirun -n 2 block.py`` while the forms are being compiled (an empty JIT cache, the
    signal sent as its first files appear): the job ends within seconds, with a non-zero status."""
    if not Path("/proc/self").exists():
        pytest.skip("no /proc: the ranks cannot be found")
    out, cache = tmp_path / "out", tmp_path / "cache"
    env = {**_env(), "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1", "XDG_CACHE_HOME": str(cache)}
    proc = subprocess.Popen(["mpirun", "-n", "2", sys.executable, str(ROOT / "demos" / "block.py"), "--out", str(out),
                             "--no-pictures", "--no-xdmf", "--quiet"], env=env, stdin=subprocess.DEVNULL,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.monotonic() + 120
        while not any(cache.rglob("*")) and time.monotonic() < deadline:
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.01)
        ranks = _ranks_of(str(out))
        assert len(ranks) == 2, ranks
        os.kill(ranks[-1], signal.SIGINT)
        start = time.monotonic()
        _, err = proc.communicate(timeout=60)
        assert proc.returncode != 0 and time.monotonic() - start < 30, err
        assert "interrupted by SIGINT" in err, err
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.communicate()


def test_augment_is_refused_for_a_method_with_nothing_to_augment():
    """``--augment N`` with a method whose law has nothing to augment (penalty, compliance, nitsche, ...) is a
    bad command line naming it and the methods that augment (from their declarations), not a run that records
    augmentations that never happen; the augmented methods and any method with friction take it."""
    p = cli.parser("test", 1e5)
    for argv in (["--method", "penalty", "--augment", "5"], ["--method", "nitsche", "--augment", "1"],
                 ["--method", "compliance", "--augment", "2"]):
        with pytest.raises(cli.UsageError, match=r"^--augment [0-9]+: method \w+ has nothing to augment; accepted: "
                                                 r"--augment 0 \(augmented: methods cross, auglag"):
            cli.law_from_args(cli.parse(p, argv))
    for argv in (["--method", "auglag", "--augment", "5"], ["--method", "cross", "--augment", "5"],
                 ["--method", "penalty", "--mu", "0.3", "--augment", "5"], ["--method", "penalty", "--augment", "0"],
                 ["--method", "penalty"]):
        cli.law_from_args(cli.parse(p, argv))


def test_command_line_petsc_values_checked_as_the_solvers_are():
    """The command line's PETSc options get the checks of ``Solver(options=...)``: a number that is not finite that
    PETSc would take (-fc_snes_linesearch_damping nan), no value for an option that takes one (-fc_snes_rtol, which
    PETSc ignores), each a bad command line naming it; a flag and a finite number pass."""
    with pytest.raises(cli.UsageError, match=r"^PETSc rejected -fc_snes_linesearch_damping nan: accepted: a finite "
                                             r"number$"):
        cli.check_petsc_values([("fc_snes_linesearch_damping", "nan")])
    with pytest.raises(cli.UsageError, match=r"^PETSc rejected -fc_snes_rtol: this option takes a value"):
        cli.check_petsc_values([("fc_snes_rtol", "")])
    cli.check_petsc_values([("fc_snes_converged_reason", ""), ("fc_snes_linesearch_damping", "0.5")])
