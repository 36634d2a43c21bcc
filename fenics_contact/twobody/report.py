"""Figures of a two-body surface at its slave points, gathered on every rank, and the seconds it spent.

Sign convention: the gap is positive for penetration, the pressure positive in compression; nominal pressures
are per reference slave area.
"""
from __future__ import annotations

import contextlib
import time
from typing import Iterator

import numpy as np
from dolfinx import fem

from ..laws import ContactLaw
from .facets import FacetData, SlavePoints

__all__ = ["Timings", "PointReport"]


class Timings(dict):
    """Seconds this rank spent per kind of work: ``search_s`` (projection, mirror fields), ``exchange_s``
    (master exchange) and ``coupling_s`` (coupling operator or element assembly)."""

    def __init__(self):
        super().__init__(search_s=0.0, exchange_s=0.0, coupling_s=0.0)

    @contextlib.contextmanager
    def measure(self, key: str) -> Iterator[None]:
        """Add the seconds of the ``with`` block to ``key``."""
        start = time.perf_counter()
        try:
            yield
        finally:
            self[key] += time.perf_counter() - start


class PointReport:
    """Values at the slave points ``points`` of the slave facets ``slave``: the law's pressure from the gaps,
    and tables of positions, gaps and pressures gathered on every rank.

    ``scalar_dofs`` (nf, nq): the dofs of the points' nodes in the law's field space (P1 at the vertices, DG1,
    or P2 at the three nodes of a quadratic facet)."""

    def __init__(self, comm, slave: FacetData, points: SlavePoints, scalar_dofs: np.ndarray):
        self.comm, self.slave, self.points, self.scalar_dofs = comm, slave, points, scalar_dofs

    def field_values(self, f: fem.Function, ends_only: bool = False) -> np.ndarray:
        """Values (nf, nq) of the scalar field ``f`` at the slave points. ``ends_only``: ``f`` is P1 on quadratic
        facets; the middle node gets the mean of the ends."""
        if not ends_only:
            return self.points.values(f.x.array[self.scalar_dofs])
        sd = self.slave
        ends = f.x.array[np.array([f.function_space.dofmap.cell_dofs(cell)[lo] for cell, lo in
                                   zip(sd.cells, sd.vertex_local)], dtype=np.int32).reshape(-1, 2)]
        return np.stack([ends[:, 0], ends.mean(axis=1), ends[:, 1]], axis=1) if len(ends) else np.zeros((0, 3))

    def law_pressure(self, law: ContactLaw, constants: dict, fields: dict, gap: np.ndarray, open_gap: float,
                     ends_only: bool = False) -> np.ndarray:
        """The law's pressure (nf, nq) (> 0 compression, per reference area) from the gaps ``gap`` (nf, nq) (> 0
        penetration; non-finite: unpaired, pressure 0) with its ``constants`` and ``fields`` (Functions, see
        :meth:`field_values`); an unpaired point is evaluated at the gap ``-open_gap`` of the UFL gap."""
        c = {k: float(v.value) for k, v in constants.items()}
        for k, f in fields.items():
            c[k] = self.field_values(f, ends_only)
        gg = np.where(np.isfinite(gap), gap, -open_gap)  # the UFL gap of an unpaired point
        return np.where(np.isfinite(gap), law.force(gg, c), 0.0) if gap.size else np.zeros_like(gap)

    def table(self, x: np.ndarray, gap: np.ndarray, pressure: np.ndarray) -> tuple[np.ndarray, np.ndarray,
                                                                                   np.ndarray, np.ndarray]:
        """Reference position (n, gdim), current position ``x``, ``gap`` and ``pressure`` at the slave points of
        the owned slave facets, from local arrays (nf, nq, ...), gathered on every rank and sorted by reference
        position (a node shared by two facets once). Collective."""
        X = self.points.reference()
        own = self.slave.owned
        d = X.shape[-1]
        data = [np.concatenate(a) for a in zip(*self.comm.allgather(
            (X[own].reshape(-1, d), x[own].reshape(-1, d), gap[own].ravel(), pressure[own].ravel())))]
        Xr = np.round(data[0], 12)
        _, first = np.unique(Xr, axis=0, return_index=True)
        order = first[np.lexsort(Xr[first].T[::-1])]
        return tuple(a[order] for a in data)

    def reference_points(self) -> np.ndarray:
        """Reference positions (n, gdim) of all slave points, every rank's, on every rank. Collective."""
        X = self.points.reference()
        return np.concatenate(self.comm.allgather(X.reshape(-1, X.shape[-1])))
