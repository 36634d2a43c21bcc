import logging

import pytest
from mpi4py import MPI

# FFCx/UFL chatter at INFO level on every JIT compile.
logging.getLogger().setLevel(logging.WARNING)
logging.getLogger("UFL").setLevel(logging.ERROR)


@pytest.fixture
def comm():
    return MPI.COMM_WORLD
