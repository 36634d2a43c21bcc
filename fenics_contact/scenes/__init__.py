"""Benchmark scenes: data plus one builder each, shared by demos, tests and benchmarks.

A builder returns a :class:`Setup`; ``figures()`` returns the scene's figures
(reduced over all ranks) after a solve.
"""
from __future__ import annotations

import importlib
import pkgutil
import time
from dataclasses import dataclass, field
from typing import Callable, Sequence

from dolfinx import fem
from mpi4py import MPI

from ..problem import ContactProblem
from ..surface import Surface

__all__ = ["Setup", "scene_names", "build"]


@dataclass
class Setup:
    """What a scene builder returns."""

    name: str
    problem: ContactProblem
    contacts: list[Surface]
    loads: Sequence[float]
    parameters: dict
    figures: Callable[[], dict]
    fields: list[fem.Function] = field(default_factory=list)
    build_time_s: float = 0.0  # mesh, spaces and form compilation (max over ranks)

    @property
    def displacement(self) -> fem.Function:
        """The displacement Function (``fields[0]``; a collapsed copy when the unknown is mixed)."""
        return self.fields[0]

    @property
    def dofs(self) -> int:
        """Global number of unknowns: with multipliers, the displacement and the pressures on the contact
        surfaces (the pressure dofs pinned to 0 off the surfaces are not counted, see :mod:`multipliers`)."""
        V = self.problem.u.function_space
        pinned = sum(c.pinned_dofs for c in self.contacts)
        return V.dofmap.index_map.size_global * V.dofmap.index_map_bs - pinned


def scene_names() -> list[str]:
    """Every scene module of this package (each defines ``build``)."""
    return sorted(m.name for m in pkgutil.iter_modules(__path__) if not m.name.startswith("_"))


def build(name: str, **kwargs) -> Setup:
    """Build scene ``name`` (see :func:`scene_names`) with keyword arguments of its builder."""
    if name not in scene_names():
        raise ValueError(f"unknown scene {name!r}; accepted: {', '.join(scene_names())}")
    b = importlib.import_module(f"{__name__}.{name}").build
    start = time.perf_counter()
    setup = b(**kwargs)
    comm = setup.problem.comm
    setup.build_time_s = comm.allreduce(time.perf_counter() - start, op=MPI.MAX)
    return setup
