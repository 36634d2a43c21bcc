"""Collective calls: every result method of every contact surface says "Collective" in its docstring, the parallel
guide lists them, and with ``FENICS_CONTACT_COLLECTIVE_TIMEOUT`` set a rank left alone in one ends the job with a
message naming the call instead of waiting for ever."""
import importlib
import os
import pkgutil
import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

import fenics_contact as fc
from fenics_contact.collective import ENV
from fenics_contact.surface import COLLECTIVE, Surface

ROOT = Path(__file__).resolve().parents[1]


def _surface_classes() -> list[type]:
    for info in pkgutil.walk_packages(fc.__path__, "fenics_contact."):
        if not info.name.startswith("fenics_contact.app"):
            importlib.import_module(info.name)
    found, todo = set(), [Surface]
    while todo:
        for sub in todo.pop().__subclasses__():
            if sub not in found:
                found.add(sub)
                todo.append(sub)
    return sorted(found | {Surface}, key=lambda c: f"{c.__module__}.{c.__qualname__}")


def _doc(cls: type, name: str) -> str:
    """The docstring a user reads: the first one along the class's method resolution order."""
    return next((vars(k)[name].__doc__ for k in cls.__mro__ if name in vars(k) and vars(k)[name].__doc__), "")


def test_every_collective_result_method_says_so():
    classes = _surface_classes()
    assert len(classes) > 10
    missing = [f"{c.__qualname__}.{name}" for c in classes for name in COLLECTIVE
               if callable(getattr(c, name, None)) and "Collective" not in _doc(c, name)]
    assert missing == []
    # and is checked by the guard wherever it is defined
    unchecked = [f"{c.__qualname__}.{name}" for c in classes for name in COLLECTIVE
                 if name in vars(c) and not getattr(vars(c)[name], "collective", False)]
    assert unchecked == []


def test_parallel_guide_lists_them():
    guide = (ROOT / "docs" / "guide" / "parallel.md").read_text()
    assert all(f"`{name}" in guide for name in COLLECTIVE) and ENV in guide


def test_guard_is_off_by_default_and_refuses_a_bad_timeout(monkeypatch):
    from fenics_contact.collective import _timeout

    monkeypatch.delenv(ENV, raising=False)
    assert _timeout() is None
    monkeypatch.setenv(ENV, "-1")
    with pytest.raises(ValueError, match=ENV):
        _timeout()


ALONE = """
import sys
sys.path.insert(0, {tests!r})
from mpi4py import MPI
from test_user_guidance import block
problem, contact = block()
if MPI.COMM_WORLD.rank == 0:
    contact.total_force()  # rank 0 alone
MPI.COMM_WORLD.Barrier()
"""


@pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="starts its own mpirun: from the serial lane only")
def test_a_rank_alone_in_a_collective_call_ends_the_job_with_a_message():
    # the job's own variables of this process (a singleton MPI) would make the child's ranks singletons
    env = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_", "ORTE_"))
           or k.startswith("OMPI_ALLOW")}
    env.update({ENV: "3", "OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
                "OMPI_MCA_rmaps_base_oversubscribe": "1", "OMP_NUM_THREADS": "1", "OPENBLAS_NUM_THREADS": "1"})
    proc = subprocess.run(["mpirun", "-n", "2", sys.executable, "-c", ALONE.format(tests=str(ROOT / "tests"))],
                          capture_output=True, text=True, timeout=300, cwd=ROOT, env=env)
    assert proc.returncode != 0
    assert "ContactSurface.total_force() is collective: rank 0 waited 3 s" in proc.stderr, proc.stderr[-2000:]


def test_meet_passes_when_every_rank_calls():
    from fenics_contact.collective import meet

    meet(MPI.COMM_WORLD, "test", 60.0, abort=False)
