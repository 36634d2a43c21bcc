"""Restarts that cannot change the problem or lie: ``--restart`` with another option that shapes the problem or its
load path is refused naming it; a restart checks the files it goes on with (checkpoint, summary, field index, HDF5
files) and refuses a damaged or missing one in one line; a SIGTERM while a step's files are written leaves a summary
of that step, never an older one; an output folder is refused in one line when it is a file, holds a stale lock or a
folder where a file goes."""
import json
import os
import re
import shutil
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import pytest
from mpi4py import MPI

from fenics_contact import Penalty
from fenics_contact.app import cli
from fenics_contact.app.run import run
from fenics_contact.app.scenes import build
from fenics_contact.output import OutputError, hdf5_incomplete

ROOT = Path(__file__).resolve().parent.parent
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="starts its own processes: from the serial lane only")
NOISE = ("hwloc/linux:", "[")  # the MPI stack's own lines (Debian 13 root), not ours


def _env() -> dict:
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    return {**env, "PYTHONPATH": str(ROOT) + os.pathsep + env.get("PYTHONPATH", ""), "OMP_NUM_THREADS": "1",
            "OPENBLAS_NUM_THREADS": "1"}


def _demo(name: str, out: Path, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(ROOT / "demos" / f"{name}.py"), "--out", str(out), "--no-pictures",
                           "--quiet", *args], capture_output=True, text=True, env=_env(), timeout=300,
                          stdin=subprocess.DEVNULL)


def _one_line(proc: subprocess.CompletedProcess, *named: str) -> str:
    assert "Traceback" not in proc.stderr + proc.stdout, proc.stderr
    lines = [line for line in proc.stderr.splitlines() if line.strip() and not line.startswith(NOISE)]
    assert len(lines) == 1, proc.stderr
    for word in named:
        assert word in lines[0], lines[0]
    return lines[0]


def _folder(tmp_path_factory, comm, name: str) -> Path:
    return Path(comm.bcast(str(tmp_path_factory.mktemp(name)) if comm.rank == 0 else None))


def _on_rank0(comm, action) -> None:
    if comm.rank == 0:
        action()
    comm.barrier()


def _summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


# --- options that shape the problem -----------------------------------------------------------------------------

@serial
@pytest.mark.scene
@pytest.mark.parametrize("name,first,changed", [
    ("block", ["--steps", "3"], [["--steps", "2"], ["--method", "penalty"], ["--height", "1"]]),
    ("mindlin", ["--ratios", "0.5", "--press-steps", "2", "--no-xdmf"], [["--press-steps", "3"]]),
    ("wedges", ["--slide-steps", "2", "--no-xdmf"], [["--slide-steps", "4"]]),
    ("compliance3d", ["--mesh", "8", "4", "2", "--press-steps", "2", "--drag-steps", "2", "--no-xdmf"],
     [["--press-steps", "1"], ["--drag-steps", "4"]]),
])
def test_a_restart_with_another_option_is_refused_naming_it(name, first, changed, tmp_path):
    """A run, then ``--restart`` with one option changed (the load steps of a phase, the method, a size): refused in
    one line naming the option with the run's value and the new one, exit 1, the run's files untouched; with the
    run's own options the restart goes on (block)."""
    out = tmp_path / name
    proc = _demo(name, out, *first)
    assert proc.returncode == 0, proc.stderr
    before = _summary(out)
    for change in changed:
        flag = change[0]
        args = list(first)
        if flag in args:  # the option's value replaced
            args[args.index(flag) + 1] = change[1]
        else:
            args += change
        proc = _demo(name, out, *args, "--restart")
        line = _one_line(proc, "--restart: ", "give that run's options")
        said, has = line.split("holds a run with ", 1)[1].split("; this one has ")
        assert proc.returncode == cli.EXIT_ERROR and " ".join(change) in has.split(":")[0].split(", "), line
        if flag in first:
            assert f"{flag} {first[first.index(flag) + 1]}" in said.split(", "), line
        assert _summary(out) == before
    if name == "block":
        proc = _demo(name, out, *first, "--restart")
        assert proc.returncode == 0, proc.stderr
        assert _summary(out)["load_steps"] == before["load_steps"]


def test_a_restart_with_another_load_path_is_refused(tmp_path_factory, comm):
    """Without a command line (the API): the load path itself is compared."""
    out = _folder(tmp_path_factory, comm, "loads")
    setup = build("block", law=Penalty(1e5), comm=comm, steps=3)
    run(setup, out, "penalty", {}, quiet=True)
    with pytest.raises(OutputError, match=r"another load path \(3 load steps to t = 1; this one: 2 load steps to "
                                          r"t = 1\)"):
        run(build("block", law=Penalty(1e5), comm=comm, steps=2), out, "penalty", {}, quiet=True, restart=True)


# --- the files a restart goes on with ---------------------------------------------------------------------------

@pytest.fixture(scope="module")
def stopped(tmp_path_factory):
    """A block run of 3 steps stopped by an error in step 3's writes: the checkpoint and summary of step 2."""
    comm = MPI.COMM_WORLD
    out = _folder(tmp_path_factory, comm, "stopped")

    class Stop(Exception):
        pass

    def stop(t):
        if t > 0.9:
            raise Stop

    with pytest.raises(Stop):
        run(build("block", law=Penalty(1e5), comm=comm, steps=3), out, "penalty", {}, quiet=True, on_step=stop)
    return out


def _damaged(stopped: Path, tmp_path_factory, comm, damage) -> Path:
    """A copy of the stopped run's folder, damaged by ``damage(folder)`` on rank 0."""
    out = _folder(tmp_path_factory, comm, "damaged")

    def copy():
        shutil.rmtree(out)
        shutil.copytree(stopped, out)
        damage(out)

    _on_rank0(comm, copy)
    return out


def _restart(out: Path, comm) -> dict:
    return run(build("block", law=Penalty(1e5), comm=comm, steps=3), out, "penalty", {}, quiet=True, restart=True)


def _truncate(path: Path, keep: float = 0.5) -> None:
    path.write_bytes(path.read_bytes()[:int(path.stat().st_size * keep)])


def _checkpoint(out: Path) -> Path:
    return sorted((out / "checkpoint").glob("step_*.rank0of*.pkl"))[-1]


DAMAGES = {
    "mesh h5 truncated": (lambda out: _truncate(out / "block.h5"), r"the mesh's .*block.h5 is truncated"),
    "step h5 emptied": (lambda out: (out / "block_fields" / "step_000001.h5").write_bytes(b""),
                        r"the fields of step 1: .*step_000001.h5 is empty"),
    "step h5 truncated": (lambda out: _truncate(out / "block_fields" / "step_000002.h5", 0.9),
                          r"the fields of step 2: .*step_000002.h5 is truncated"),
    "step xdmf emptied": (lambda out: (out / "block_fields" / "step_000002.xdmf").write_text(""),
                          r"step_000002.xdmf is not an XDMF file"),
    "index garbage": (lambda out: (out / "block.xdmf").write_text("<Xdmf><Domain>garbage"),
                      r"block.xdmf: not an XDMF index of fields"),
    "checkpoint truncated": (lambda out: _truncate(_checkpoint(out)),
                             r"cannot go on from the checkpoint of step 2: .*rank0of.*\((UnpicklingError|EOFError)"),
    "checkpoint emptied": (lambda out: _checkpoint(out).write_bytes(b""),
                           r"cannot go on from the checkpoint of step 2: .*\(EOFError"),
    "checkpoint random": (lambda out: _checkpoint(out).write_bytes(os.urandom(4096)),
                          r"cannot go on from the checkpoint of step 2: .*rank0of"),
    "checkpoint not one": (lambda out: _checkpoint(out).write_bytes(b"\x80\x04K\x03."),  # the pickle of 3
                           r"cannot go on from the checkpoint of step 2: .*\(not a checkpoint\)"),
    "checkpoint missing": (lambda out: shutil.rmtree(out / "checkpoint"),
                           r"holds a run of 2 completed load steps without their checkpoint .*--overwrite"),
    "summary a list": (lambda out: (out / "summary.json").write_text("[1, 2, 3]"),
                       r"holds a run of \? / \?, unreadable summary.json, not of block / penalty"),
}


@pytest.mark.parametrize("damage", list(DAMAGES))
def test_a_restart_refuses_damaged_files_in_one_line(damage, stopped, tmp_path_factory, comm):
    """Each file a restart goes on with, damaged: refused on every rank, in one line naming the file and what is
    wrong, before any step (the summary as it was)."""
    how, message = DAMAGES[damage]
    out = _damaged(stopped, tmp_path_factory, comm, how)
    before = (out / "summary.json").read_text()
    with pytest.raises(ValueError, match=message) as info:
        _restart(out, comm)
    line = cli.error_line(info.value)
    assert line is not None and "\n" not in line
    comm.barrier()
    assert (out / "summary.json").read_text() == before and not (out / ".lock").exists()


def test_the_undamaged_run_goes_on(stopped, tmp_path_factory, comm):
    out = _damaged(stopped, tmp_path_factory, comm, lambda out: None)
    s = _restart(out, comm)
    assert s["status"] == "converged" and s["restarted_from"]["step"] == 2 and s["load_steps"] == 3


def test_hdf5_incomplete_reads_the_superblock(tmp_path):
    assert hdf5_incomplete(tmp_path / "none.h5") == "missing"
    (tmp_path / "x.h5").write_bytes(b"")
    assert hdf5_incomplete(tmp_path / "x.h5") == "empty"
    (tmp_path / "x.h5").write_bytes(b"not hdf5" * 100)
    assert hdf5_incomplete(tmp_path / "x.h5") == "not an HDF5 file"


# --- the output folder ------------------------------------------------------------------------------------------

def _block(comm):
    return build("block", law=Penalty(1e5), comm=comm)


@pytest.mark.parametrize("content", ["garbage", "[1, 2, 3]", '{"pid": "x"}', ""])
def test_a_lock_that_is_not_one_is_stale(content, tmp_path_factory, comm):
    """A ``.lock`` whose content is not a lock's (``RunLock`` writes it whole): stale, said so with how to clear it;
    ``--overwrite`` replaces it."""
    out = _folder(tmp_path_factory, comm, "stale")
    _on_rank0(comm, lambda: (out / ".lock").write_text(content))
    with pytest.raises(OutputError, match=r"\.lock is a stale lock \(not a lock's content; no run writes into .*\): "
                                          r"remove it, or give --overwrite"):
        run(_block(comm), out, "penalty", {}, quiet=True)
    assert run(_block(comm), out, "penalty", {}, quiet=True, overwrite=True)["status"] == "converged"


def test_an_output_folder_that_is_a_file_is_said(tmp_path_factory, comm):
    out = _folder(tmp_path_factory, comm, "file") / "results"
    _on_rank0(comm, lambda: out.write_text("a file"))
    with pytest.raises(OutputError, match=r"results is a file, not a folder: give a folder as --out"):
        run(_block(comm), out, "penalty", {}, quiet=True)
    with pytest.raises(OutputError, match=r"cannot make the output folder .*results/run: Not a directory"):
        run(_block(comm), out / "run", "penalty", {}, quiet=True)


def test_a_folder_where_a_picture_goes_is_refused_before_the_run(tmp_path_factory, comm):
    out = _folder(tmp_path_factory, comm, "pictures")
    _on_rank0(comm, lambda: (out / "block_deformed.png").mkdir())
    with pytest.raises(OutputError, match=r"block_deformed.png is a folder where the run writes a file"):
        run(_block(comm), out, "penalty", {}, quiet=True)
    assert not (out / "summary.json").exists()


@serial
def test_a_picture_that_cannot_be_written_is_one_line(tmp_path):
    """A picture's folder is a file: one line naming the picture."""
    pytest.importorskip("matplotlib")
    from fenics_contact.app.plotting import plot_profile

    (tmp_path / "file").write_text("")
    with pytest.raises(OutputError, match=r"could not write the picture .*file/p.png"):
        plot_profile([0.0, 1.0], [1.0, 2.0], tmp_path / "file" / "p.png")


# --- a signal while a step's files are written -----------------------------------------------------------------

INJECT = """
import importlib, os, signal, sys
import fenics_contact.checkpoint
from fenics_contact.app import cli
run_module = importlib.import_module("fenics_contact.app.run")
sys.path.insert(0, {demos!r})
import block

where = sys.argv[1]
original = {{"summary": run_module.write_summary, "checkpoint": fenics_contact.checkpoint.save}}

def summary(path, s, comm):  # SIGTERM once the summary of step 2 is on disk
    original["summary"](path, s, comm)
    if where == "summary" and s.get("load_steps") == 2:
        os.kill(os.getpid(), signal.SIGTERM)

def save(solver, folder, extra=None):  # SIGTERM once the checkpoint of step 2 is complete
    step = original["checkpoint"](solver, folder, extra)
    if where == "checkpoint" and step == 2:
        os.kill(os.getpid(), signal.SIGTERM)
    return step

run_module.write_summary, fenics_contact.checkpoint.save = summary, save
cli.main(block.main, ["--steps", "4", "--out", sys.argv[2], "--no-pictures", "--quiet"])
"""


@serial
@pytest.mark.parametrize("where", ["summary", "checkpoint"])
def test_sigterm_while_a_step_is_written_leaves_that_step(where, tmp_path):
    """SIGTERM right after step 2's summary is on disk, or right after its checkpoint is complete (before the
    summary): the summary says ``interrupted`` after step 2, as the checkpoint and the fields do, and so does the
    line; ``--restart`` goes on from step 2."""
    script = tmp_path / "inject.py"
    script.write_text(textwrap.dedent(INJECT.format(demos=str(ROOT / "demos"))))
    out = tmp_path / "block"
    start = time.monotonic()
    proc = subprocess.run([sys.executable, str(script), where, str(out)], capture_output=True, text=True,
                          env=_env(), timeout=120, stdin=subprocess.DEVNULL)
    assert proc.returncode == 128 + 15 and time.monotonic() - start < 60, proc.stderr
    _one_line(proc, "block: interrupted by SIGTERM after step 2;")
    s = _summary(out)
    assert s["status"] == "interrupted" and s["load_steps"] == 2 and s["checkpoint"] == "checkpoint/step_000002"
    assert sorted(p.name[:11] for p in (out / "checkpoint").glob("*.pkl")) == ["step_000002"]
    times = set(re.findall(r'<Time Value="([^"]+)"', (out / "block.xdmf").read_text()))
    assert len(times) == 2 and not (out / ".lock").exists()
    proc = _demo("block", out, "--steps", "4", "--restart")
    assert proc.returncode == 0, proc.stderr
    assert _summary(out)["restarted_from"]["step"] == 2
