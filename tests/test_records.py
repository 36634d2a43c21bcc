"""Records that survive a killed run and cannot lie: the fields of every completed step stay readable (h5py,
dolfinx), ``summary.json`` is never torn and says the run's status, an output folder is not shared or silently
overwritten, and ``--restart`` finishes a killed demo with the figures of an uninterrupted run."""
import dataclasses
import errno
import json
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import numpy as np
import pytest
from dolfinx import fem, io
from dolfinx import mesh as dmesh
from mpi4py import MPI

from fenics_contact import Penalty, compat
from fenics_contact.app import cli
from fenics_contact.app.run import run
from fenics_contact.app.scenes import build
from fenics_contact.output import OutputError, RunLock, XDMFWriter, process_alive
from fenics_contact.solver import ConvergenceError

ROOT = Path(__file__).resolve().parent.parent
serial = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="starts its own processes: from the serial lane only")
# A fast demo of several load steps (demos/quick.txt): 4 pressing and 8 dragging steps of ~0.2 s each
IRONING = ["--drag", "0.35", "--steps", "8", "--margin", "0.5", "--steady-from", "0.15"]
TIMES = ("wall_time_s", "output_time_s", "solve_time_s", "time_split", "linear_solve_floor_s", "ratio_to_linear_solve",
         "memory_peak_mb", "setup_time_s", "residual", "constraint_change")  # of this process, or round-off
# Reads the index as a user's script would (h5py, without dolfinx): every dataset it names, and its times.
READER = """import json, sys, xml.etree.ElementTree as ET
from pathlib import Path
import h5py, numpy as np
index = Path(sys.argv[1])
root = ET.parse(index).getroot()
for item in root.iter("DataItem"):
    name, dataset = item.text.strip().split(":")
    with h5py.File(index.parent / name, "r") as f:
        shape = [int(n) for n in item.get("Dimensions").split()]
        assert list(f[dataset].shape) == shape and np.all(np.isfinite(f[dataset][...])), item.text
print(json.dumps({"times": sorted({float(t.get("Value")) for t in root.iter("Time")}),
                  "mesh": root.find("Domain/Grid").get("Name")}))
"""


def _folder(tmp_path_factory, comm, name: str) -> Path:
    return Path(comm.bcast(str(tmp_path_factory.mktemp(name)) if comm.rank == 0 else None))


def _env() -> dict:
    """This environment without an MPI job's own variables (the user's ``OMPI_MCA_`` choices stay)."""
    # An MPI singleton (this process, or the test runner's controller whose environment a worker inherits) sets
    # OMPI_MCA_ess, OMPI_MCA_orte_*, OMPI_MCA_pmix and ORTE_*: a child mpirun given them starts its ranks as
    # singletons. The user's transport choices (OMPI_MCA_btl, OMPI_MCA_pml, ...) stay.
    singleton = ("OMPI_MCA_ess", "OMPI_MCA_orte_", "OMPI_MCA_pmix", "ORTE_")
    env = {k: v for k, v in os.environ.items()
           if (not k.startswith(("OMPI_", "PMIX_", "PMI_", "ORTE_")) or k.startswith(("OMPI_MCA_", "OMPI_ALLOW")))
           and not k.startswith(singleton)}
    return {**env, "PYTHONPATH": str(ROOT) + os.pathsep + env.get("PYTHONPATH", ""), "OMP_NUM_THREADS": "1",
            "OPENBLAS_NUM_THREADS": "1", "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
            "OMPI_MCA_rmaps_base_oversubscribe": "1"}


def read_fields(index: Path, comm: MPI.Comm) -> list[float]:
    """The times of the steps in the XDMF ``index``, each of its datasets read by h5py in a process of its own;
    and its mesh read by dolfinx."""
    pytest.importorskip("h5py")
    found = None
    if comm.rank == 0:
        proc = subprocess.run([sys.executable, "-c", READER, str(index)], capture_output=True, text=True,
                              env=_env(), timeout=120)
        assert proc.returncode == 0, proc.stderr
        found = json.loads(proc.stdout.strip().splitlines()[-1])
    found = comm.bcast(found)
    with io.XDMFFile(comm, str(index), "r") as f:
        mesh = f.read_mesh(name=found["mesh"])
    assert mesh.topology.index_map(mesh.topology.dim).size_global > 0
    return found["times"]


def summary(out: Path) -> dict:
    return json.loads((out / "summary.json").read_text())


# --- the field output -------------------------------------------------------------------------------------------

def test_fields_of_each_step_are_listed_once_complete_and_resumed(tmp_path_factory, comm):
    out = _folder(tmp_path_factory, comm, "fields")
    mesh = dmesh.create_unit_square(comm, 4, 4)
    u = fem.Function(compat.function_space(mesh, "Lagrange", 1, (2,)), name="displacement")
    p = fem.Function(compat.function_space(mesh, "Lagrange", 1), name="pressure")
    writer = XDMFWriter(out / "x.xdmf", mesh, [u, p])
    assert read_fields(out / "x.xdmf", comm) == []  # the mesh alone, before any step
    for t in (0.25, 0.5, 1e-16):
        u.x.array[:], p.x.array[:] = t, 2 * t
        writer.write(t)
    assert read_fields(out / "x.xdmf", comm) == [1e-16, 0.25, 0.5]
    # killed while step 4's file was being written: a partial file that the index does not list
    if comm.rank == 0:
        (out / "x_fields" / "step_000004.h5").write_bytes(b"\x89HDF partial")
    comm.barrier()
    assert read_fields(out / "x.xdmf", comm) == [1e-16, 0.25, 0.5]
    # a restart from step 2: step 3 and the partial step 4 are dropped, the steps go on from 3
    writer = XDMFWriter(out / "x.xdmf", mesh, [u, p], resume=2)
    writer.write(0.75)
    assert read_fields(out / "x.xdmf", comm) == [0.25, 0.5, 0.75]
    assert not (out / "x_fields" / "step_000004.h5").exists()
    assert sorted(f.name for f in out.iterdir()) == ["x.h5", "x.xdmf", "x_fields"]  # no temporary file left


def test_higher_degree_and_cell_fields_are_written_at_vertices_and_cells(tmp_path_factory, comm):
    h5py = pytest.importorskip("h5py")
    out = _folder(tmp_path_factory, comm, "degrees")
    mesh = dmesh.create_unit_square(comm, 3, 4)
    u = fem.Function(compat.function_space(mesh, "Lagrange", 2, (2,)), name="u")
    u.interpolate(lambda x: np.vstack([x[0] ** 2 - x[1], 3 * x[0] * x[1]]))
    c = fem.Function(compat.function_space(mesh, "DG", 0), name="c")
    c.interpolate(lambda x: 2 * x[0] + x[1])
    XDMFWriter(out / "x.xdmf", mesh, [u, c]).write(1.0)
    if comm.rank == 0:
        with h5py.File(out / "x.h5", "r") as f:
            x, cells = f["Mesh/mesh/geometry"][...], f["Mesh/mesh/topology"][...]
        with h5py.File(out / "x_fields" / "step_000001.h5", "r") as f:
            values = {name: f[f"Function/{name}"][next(iter(f[f"Function/{name}"]))][...] for name in ("u", "c")}
        exact = np.column_stack([x[:, 0] ** 2 - x[:, 1], 3 * x[:, 0] * x[:, 1]])
        assert np.allclose(values["u"][:, :2], exact, rtol=0, atol=1e-14)  # P2 exact at the vertices
        mid = x[cells].mean(axis=1)
        assert np.allclose(values["c"].ravel(), 2 * mid[:, 0] + mid[:, 1], rtol=0, atol=1e-14)


def test_a_field_xdmf_cannot_take_is_refused_by_name(tmp_path_factory, comm):
    mesh = dmesh.create_unit_square(comm, 2, 2)
    try:  # dolfinx >= 0.7
        import basix.ufl
        space = fem.functionspace(mesh, basix.ufl.quadrature_element(mesh.basix_cell(), value_shape=(), degree=2))
    except ImportError:
        import ufl
        space = fem.FunctionSpace(mesh, ufl.FiniteElement("Quadrature", mesh.ufl_cell(), 2, quad_scheme="default"))
    q = fem.Function(space, name="stress")
    with pytest.raises(ValueError, match="function 'stress' is of the 'quadrature' family"):
        XDMFWriter(_folder(tmp_path_factory, comm, "refused") / "x.xdmf", mesh, [q])


def test_a_2d_tensor_reads_back_as_written(tmp_path_factory, comm):
    """A 2 x 2 tensor (not symmetric) written by XDMFWriter reads back the same, whichever way the dolfinx pads it
    to XDMF's 9 components."""
    from fenics_contact import read_xdmf

    mesh = dmesh.create_unit_square(comm, 2, 2)
    f = fem.Function(compat.function_space(mesh, "DG", 0, (2, 2)), name="tensor")
    f.x.array[:] = np.tile([1.0, 2.0, 3.0, 4.0], f.x.array.size // 4)
    path = _folder(tmp_path_factory, comm, "tensor") / "t.xdmf"
    with XDMFWriter(path, mesh, [f]) as writer:
        writer.write(1.0)
    if comm.rank == 0:
        values = read_xdmf(path).at("tensor")
        assert values.shape == (8, 2, 2) and np.all(values == [[1.0, 2.0], [3.0, 4.0]])


# --- the output folder -------------------------------------------------------------------------------------------

def _block(comm, **kw):
    return build("block", law=Penalty(1e5), comm=comm, **kw)


def test_a_folder_with_another_runs_files_is_refused_unless_overwritten(tmp_path_factory, comm):
    out = _folder(tmp_path_factory, comm, "twice")
    first = run(_block(comm), out, "penalty", {}, quiet=True)
    assert first["status"] == "converged" and not (out / ".lock").exists()
    with pytest.raises(OutputError, match=r"holds the files of another run \(block / penalty, converged\).*"
                                          r"--overwrite"):
        run(_block(comm), out, "penalty", {}, quiet=True)
    assert summary(out) == json.loads(json.dumps(first, default=float))  # untouched
    if comm.rank == 0:
        (out / "stale.png").write_text("a picture of the first run")
    comm.barrier()
    again = run(_block(comm), out, "penalty", {}, quiet=True, overwrite=True)
    assert not (out / "stale.png").exists() and again["contact_pressure"] == first["contact_pressure"]
    with pytest.raises(OutputError, match="give one of them"):
        run(_block(comm), out, "penalty", {}, quiet=True, overwrite=True, restart=True)
    with pytest.raises(OutputError, match=r"--restart: .* holds a run of block / penalty, converged, not of "
                                          r"block / cross"):
        run(_block(comm), out, "cross", {}, quiet=True, restart=True)
    # --restart of a run that has ended: its last step solved again (a run of one step: all of it)
    restarted = run(_block(comm), out, "penalty", {}, quiet=True, restart=True)
    assert "restarted_from" not in restarted and restarted["contact_pressure"] == first["contact_pressure"]
    two = _folder(tmp_path_factory, comm, "two_steps")
    first = run(dataclasses.replace(_block(comm), loads=[0.5, 1.0]), two, "penalty", {}, quiet=True)
    restarted = run(dataclasses.replace(_block(comm), loads=[0.5, 1.0]), two, "penalty", {}, quiet=True,
                    restart=True)
    assert restarted["restarted_from"] == {"step": 1, "load": 0.5} and restarted["contact_pressure"] == \
        first["contact_pressure"] and restarted["newton_iterations"] == first["newton_iterations"]


def test_a_folder_in_use_by_a_live_run_is_refused(tmp_path_factory, comm):
    out = _folder(tmp_path_factory, comm, "busy")
    other = subprocess.Popen([sys.executable, "-c", "import time; time.sleep(60)"]) if comm.rank == 0 else None
    try:
        if comm.rank == 0:  # the lock of another live process (as RunLock writes it)
            lock = RunLock(out)
            held = {**lock.mine, "pid": other.pid, "start": None}
            (out / ".lock").write_text(json.dumps(held))
        comm.barrier()
        with pytest.raises(OutputError, match=r"in use by another run \(pid \d+ on .*--out"):
            run(_block(comm), out, "penalty", {}, quiet=True, overwrite=True)
        assert not (out / "summary.json").exists()
        if comm.rank == 0:
            other.kill()
            other.wait()
            assert process_alive(other.pid, lock.mine["host"]) is False
        comm.barrier()
        # its holder dead, the lock is a dead run's: refused, then taken over with --overwrite
        with pytest.raises(OutputError, match=r"holds the files of another run \(a lock of pid \d+ .*ended\)"):
            run(_block(comm), out, "penalty", {}, quiet=True)
        assert run(_block(comm), out, "penalty", {}, quiet=True, overwrite=True)["status"] == "converged"
        if comm.rank == 0:  # a lock of another machine cannot be judged from here
            (out / ".lock").write_text(json.dumps({"pid": 1, "host": "elsewhere", "start": None}))
        comm.barrier()
        with pytest.raises(OutputError, match=r"locked by a run on elsewhere \(pid 1\): if it has ended, remove"):
            run(_block(comm), out, "penalty", {}, quiet=True, overwrite=True)
    finally:
        if other is not None and other.poll() is None:
            other.kill()
            other.wait()


def test_a_full_disk_leaves_the_last_complete_summary(tmp_path_factory, comm, monkeypatch):
    out = _folder(tmp_path_factory, comm, "full")
    setup = _block(comm)
    setup = dataclasses.replace(setup, loads=[0.25, 0.5, 0.75, 1.0])
    opened, write, temporary, summaries = os.open, os.write, set(), []

    def track(path, *args, **kw):
        fd = opened(path, *args, **kw)
        if Path(path).name.startswith(".summary.json."):  # write_atomically's temporary file
            temporary.add(fd)
        else:
            temporary.discard(fd)
        return fd

    def full_disk(fd, data):  # the third summary (after step 2) finds the disk full half-way through
        if fd in temporary:
            temporary.discard(fd)
            summaries.append(fd)
            if len(summaries) >= 3:
                write(fd, bytes(data)[:len(data) // 2])
                raise OSError(errno.ENOSPC, os.strerror(errno.ENOSPC))
        return write(fd, data)

    monkeypatch.setattr(os, "open", track)
    monkeypatch.setattr(os, "write", full_disk)
    with pytest.raises(OutputError, match="could not write .*summary.json: No space left on device") as info:
        run(setup, out, "penalty", {}, quiet=True)
    monkeypatch.undo()
    comm.barrier()  # rank 0 frees the folder on its own when a run ends on an error
    line = cli.error_line(info.value)
    assert line is not None and "\n" not in line  # the command line reports it in one line
    s = summary(out)  # whole JSON: the summary of step 1
    assert s["status"] == "running" and s["load_steps"] == 1 and s["pid"] == comm.bcast(os.getpid())
    assert sorted(p.name for p in out.iterdir()) == ["block.h5", "block.xdmf", "block_fields", "checkpoint",
                                                     "summary.json"]


def test_a_failed_run_says_written_only_when_a_step_was(tmp_path_factory, comm):
    out = _folder(tmp_path_factory, comm, "failed")
    setup = dataclasses.replace(_block(comm), loads=[1.0])
    with pytest.raises(ConvergenceError) as info:
        run(setup, out, "penalty", {}, quiet=True, options={"snes_max_it": 0}, max_cutbacks=0)
    assert "written" not in str(info.value) and "no step converged" in str(info.value)
    s = summary(out)
    assert s["status"] == "failed" and s["load_steps"] == 0 and not (out / ".lock").exists()
    out = _folder(tmp_path_factory, comm, "failed_later")
    setup = dataclasses.replace(_block(comm), loads=[1e-16, 1.0])  # t = 1e-16 converges at iteration 0
    with pytest.raises(ConvergenceError, match=r"step 1 written to .*block.xdmf"):
        run(setup, out, "penalty", {}, quiet=True, options={"snes_max_it": 0}, max_cutbacks=0)
    assert read_fields(out / "block.xdmf", comm) == [1e-16]


def test_rings_summary_has_no_placeholder_figures(tmp_path_factory, comm):
    import importlib.util

    out = _folder(tmp_path_factory, comm, "rings")
    spec = importlib.util.spec_from_file_location("demo_rings", ROOT / "demos" / "rings.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    s = module.main(["--main-only", "--n", "8", "--out", str(out), "--no-pictures", "--quiet"])
    assert s["dofs"] == s["options"][0]["dofs"] > 0 and s["wall_time_s"] > 0
    with pytest.raises(OutputError, match="holds the files of another run"):
        module.main(["--main-only", "--n", "8", "--out", str(out), "--no-pictures", "--quiet"])


# --- killed demos ---------------------------------------------------------------------------------------------------

def _demo(np_: int, out: Path, *args: str) -> list[str]:
    command = [sys.executable, str(ROOT / "demos" / "ironing.py"), *IRONING, "--out", str(out), "--no-pictures",
               "--quiet", *args]
    return command if np_ == 1 else ["mpirun", "-n", str(np_), *command]


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    """The summary of the uninterrupted demo, per number of ranks."""
    done = {}

    def get(np_: int) -> dict:
        if np_ not in done:
            out = tmp_path_factory.mktemp(f"uninterrupted{np_}")
            proc = subprocess.run(_demo(np_, out), capture_output=True, text=True, env=_env(), timeout=300,
                                  stdin=subprocess.DEVNULL)
            assert proc.returncode == 0, proc.stderr
            done[np_] = summary(out)
        return done[np_]

    return get


def _processes(pid: int) -> list[int]:
    """``pid`` and every process under it."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            parent = int(stat.read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, IndexError, ValueError):
            continue
        children.setdefault(parent, []).append(int(stat.parent.name))
    found, todo = [], [pid]
    while todo:
        found.append(todo.pop())
        todo += children.get(found[-1], [])
    return found


def _signal(pids: list[int], sig: int) -> None:
    for pid in pids:
        try:
            os.kill(pid, sig)
        except ProcessLookupError:
            pass


def _figures_equal(a: dict, b: dict, path: str = "") -> None:
    """Every figure of ``a`` in ``b`` to 1e-8 (round-off figures to 1e-12 absolute); times not compared."""
    if isinstance(a, dict):
        for k, v in a.items():
            if not any(t in k for t in TIMES) and k not in ("pid", "started", "restarted_from"):
                _figures_equal(v, b[k], f"{path}/{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), path
        for i, (x, y) in enumerate(zip(a, b)):
            _figures_equal(x, y, f"{path}[{i}]")
    elif isinstance(a, float):
        assert np.isclose(b, a, rtol=1e-8, atol=1e-12), (path, a, b)
    else:
        assert a == b, (path, a, b)


@serial
@pytest.mark.parametrize("ranks", [1, 2], ids=["serial", "mpirun-2"])
@pytest.mark.parametrize("how", ["SIGTERM", "SIGKILL"])
def test_killed_demo_keeps_its_steps_and_restarts_to_the_same_figures(how, ranks, tmp_path, uninterrupted):
    """Stopped after k >= 3 completed steps, then killed (SIGTERM to the demo or mpirun; SIGKILL to every process of
    the run): the fields hold the steps completed, readable by h5py and dolfinx; the summary says ``interrupted``
    (SIGTERM) or ``running`` at step k by a dead writer (SIGKILL); a second run into the folder is refused while the
    first runs, and after it; ``--restart`` ends with the uninterrupted run's figures."""
    if ranks > 1 and not Path("/proc/self").exists():
        pytest.skip("no /proc (a chroot without it): the ranks of mpirun cannot be found to be stopped and killed")
    out = tmp_path / "ironing"
    # no standard input: mpirun forwards it to rank 0, and a test runner's worker may have none to give
    proc = subprocess.Popen(_demo(ranks, out), env=_env(), stdin=subprocess.DEVNULL, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    everyone = [proc.pid]
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline:  # until 3 steps are done
            try:
                if summary(out).get("load_steps", 0) >= 3:
                    break
            except (FileNotFoundError, ValueError):
                pass  # not written yet
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.02)
        everyone = _processes(proc.pid)  # mpirun puts its ranks in process groups of their own
        _signal(everyone, signal.SIGSTOP)  # the run holds still, alive, at some point of a step
        if how == "SIGKILL":
            second = subprocess.run(_demo(ranks, out, "--overwrite"), capture_output=True, text=True, env=_env(),
                                    timeout=300)
            assert second.returncode == 1 and "in use by another run" in second.stderr, second.stderr
            _signal(everyone, signal.SIGKILL)  # a crash: every process of the run at once
        else:
            proc.send_signal(signal.SIGTERM)  # to the demo, or to mpirun (which sends it on to every rank)
            _signal(everyone, signal.SIGCONT)
        _, err = proc.communicate(timeout=60)
        for pid in everyone[1:]:  # the ranks have ended too
            deadline = time.monotonic() + 30
            while process_alive(pid, socket.gethostname()) and time.monotonic() < deadline:
                time.sleep(0.05)
    finally:
        if proc.poll() is None:
            _signal(everyone, signal.SIGKILL)
            proc.wait()
    s = summary(out)
    k = s["load_steps"]
    assert 3 <= k < 12, k
    if how == "SIGTERM":
        assert s["status"] == "interrupted" and s["signal"] == "SIGTERM" and not (out / ".lock").exists()
        assert ranks > 1 or f"interrupted by SIGTERM after step {k}" in err  # mpirun may drop a dying rank's line
    else:
        assert s["status"] == "running" and process_alive(s["pid"], s["host"]) is False
        assert (out / ".lock").exists()
    times = read_fields(out / "ironing.xdmf", MPI.COMM_SELF)
    assert times[:k] == [r["load"] for r in s["steps"]] and len(times) in (k, k + 1)  # k + 1: its summary unwritten
    if ranks == 1:  # the same refusal on any number of ranks
        again = subprocess.run(_demo(ranks, out), capture_output=True, text=True, env=_env(), timeout=300)
        assert again.returncode == 1 and "holds the files of another run" in again.stderr, again.stderr
    restarted = subprocess.run(_demo(ranks, out, "--restart"), capture_output=True, text=True, env=_env(),
                               timeout=300)
    assert restarted.returncode == 0, restarted.stderr
    s = summary(out)
    assert s["status"] == "converged" and s["restarted_from"]["step"] == k
    assert read_fields(out / "ironing.xdmf", MPI.COMM_SELF) == [r["load"] for r in s["steps"]]
    _figures_equal(uninterrupted(ranks), s)
