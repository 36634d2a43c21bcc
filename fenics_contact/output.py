"""Output: XDMF time series of the fields and the machine-readable summary."""
from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Sequence

from dolfinx import fem, io
from mpi4py import MPI

__all__ = ["XDMFWriter", "write_summary"]


class XDMFWriter:
    """Writes the mesh once and the given P1 functions at every call (time = load parameter)."""

    def __init__(self, path: str | os.PathLike, mesh, functions: Sequence[fem.Function]):
        self.path = Path(path)
        if mesh.comm.rank == 0:
            self.path.parent.mkdir(parents=True, exist_ok=True)
        mesh.comm.barrier()
        self.file = io.XDMFFile(mesh.comm, str(self.path), "w")
        self.file.write_mesh(mesh)
        self.functions = list(functions)

    def write(self, t: float) -> None:
        for f in self.functions:
            self.file.write_function(f, t)

    def close(self) -> None:
        self.file.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


def write_summary(path: str | os.PathLike, summary: dict, comm: MPI.Comm) -> None:
    """``summary`` (identical on every rank) as JSON, written by rank 0."""
    if comm.rank == 0:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        with open(path, "w") as fh:
            json.dump(summary, fh, indent=1, default=float)
    comm.barrier()
