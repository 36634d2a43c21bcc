"""The test lanes end instead of hanging (tests/conftest.py): a test past ``FC_TEST_TIMEOUT`` prints its traceback
and fails the session; under mpirun, a test that fails on one rank before a collective call aborts the job after
``FC_TEST_DESYNC``, printing the test and its failure. Each is a pytest session of its own, with this suite's
conftest, on a test made to hang."""
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from mpi4py import MPI

ROOT = Path(__file__).resolve().parents[1]

pytestmark = pytest.mark.skipif(MPI.COMM_WORLD.size > 1, reason="sessions of their own: serial lane")

HANGS = """
import time

def test_ends():
    pass

def test_never_ends():
    time.sleep(600)
"""

FAILS_ON_RANK_0 = """
from mpi4py import MPI

def test_rank_0_fails_before_a_collective_call():
    assert MPI.COMM_WORLD.rank == 1
    MPI.COMM_WORLD.barrier()

def test_next():
    MPI.COMM_WORLD.barrier()
"""


def session(tmp_path: Path, source: str, launcher: list[str], **env: str) -> subprocess.CompletedProcess:
    """pytest on ``source`` (a test file) with this suite's conftest, under ``launcher`` (empty or mpirun)."""
    shutil.copy(ROOT / "tests" / "conftest.py", tmp_path / "conftest.py")
    (tmp_path / "test_made_to_hang.py").write_text(source)
    # not this process's own MPI environment (a singleton's PMIx variables would make mpirun's ranks join it)
    mine = {k: v for k, v in os.environ.items() if not k.startswith(("OMPI_", "PMIX_", "PMI_"))}
    environment = {**mine, "PYTHONPATH": str(ROOT), "OMPI_ALLOW_RUN_AS_ROOT": "1",
                   "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1", "OMPI_MCA_rmaps_base_oversubscribe": "1", **env}
    return subprocess.run([*launcher, sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           "test_made_to_hang.py"], cwd=tmp_path, env=environment, capture_output=True, text=True,
                          timeout=300)


def test_a_test_that_does_not_end_fails_the_session_with_its_traceback(tmp_path):
    proc = session(tmp_path, HANGS, [], FC_TEST_TIMEOUT="3")
    assert proc.returncode != 0
    assert "Timeout" in proc.stderr and 'test_made_to_hang.py", line 8 in test_never_ends' in proc.stderr


@pytest.mark.skipif(shutil.which("mpirun") is None, reason="no mpirun")
def test_a_failure_on_one_rank_aborts_the_mpi_job_naming_it(tmp_path):
    proc = session(tmp_path, FAILS_ON_RANK_0, ["mpirun", "-n", "2"], FC_TEST_DESYNC="3")
    said = proc.stdout + proc.stderr
    assert proc.returncode != 0
    assert "rank 0: test_made_to_hang.py::test_rank_0_fails_before_a_collective_call failed: AssertionError" in said
    assert "another rank was still inside it 3 s later" in said
