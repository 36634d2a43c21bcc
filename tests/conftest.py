import logging
import os
import tempfile

import pytest
from mpi4py import MPI

# FFCx/UFL chatter at INFO level on every JIT compile.
logging.getLogger().setLevel(logging.WARNING)
logging.getLogger("UFL").setLevel(logging.ERROR)


@pytest.fixture
def comm():
    return MPI.COMM_WORLD


def pytest_configure(config):
    # Under mpirun every rank runs pytest: give each its own base temporary folder, or the
    # ranks clean up each other's folders. Tests that write from all ranks broadcast rank 0's path.
    comm = MPI.COMM_WORLD
    if comm.size > 1 and config.option.basetemp is None:
        config.option.basetemp = os.path.join(tempfile.gettempdir(), f"pytest-fc-rank{comm.rank}-of-{comm.size}")
