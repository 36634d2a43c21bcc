"""A scene solved once per test session and communicator size, shared by the tests of a module."""
from __future__ import annotations

from typing import Callable

from mpi4py import MPI

import fenics_contact as fc
import fenics_contact.app as app

_CACHE: dict = {}


def solved(name: str, build: Callable[[MPI.Comm], app.Setup], comm: MPI.Comm = MPI.COMM_WORLD,
           converged: bool = True, **solver_options) -> tuple:
    """``(setup, solver, figures)`` of ``build(comm)`` run over its loads by ``fc.Solver(problem, quiet=True,
    **solver_options)``, cached under ``(name, comm.size)``; ``converged``: assert that every step converged."""
    key = (name, comm.size)
    if key not in _CACHE:
        setup = build(comm)
        solver = fc.Solver(setup.problem, quiet=True, **solver_options)
        solver.run(setup.loads)
        if converged:
            assert all(r.converged for r in solver.records), name
        _CACHE[key] = (setup, solver, setup.figures())
    return _CACHE[key]
