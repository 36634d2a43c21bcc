"""The output read back without dolfinx: the mesh and every step's fields of an XDMF time series written by
:class:`~fenics_contact.output.XDMFWriter` (its index and HDF5 files, read with h5py), for plots without ParaView
(matplotlib's ``tripcolor``, a pressure profile) in any process, serial, after the run."""
from __future__ import annotations

import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

__all__ = ["XDMFSeries", "read_xdmf"]


@dataclass
class XDMFSeries:
    """An XDMF time series: the mesh and each field's values at each written step.

    Args:
        points: the mesh's nodes (n, gdim), reference coordinates.
        cells: the cells' nodes (nc, nodes per cell), indices into ``points``.
        cell_type: the XDMF topology type (``Triangle``, ``Quadrilateral``, ``Tetrahedron``, ...).
        times: the steps' times (the load parameter ``t``), in the order written.
        fields: name -> one array per step: nodal values (n,) or (n, components) (vectors and tensors padded to 3
            and 9 components as XDMF stores them), or cell values (nc, ...) for a degree-0 field (``centers``).
        centers: name -> ``Node`` or ``Cell``.
        tensor_padding: where a 2D tensor's 4 values sit in the 9 stored: ``rows`` (as rows of a 3 x 3 matrix) or
            ``end`` (first), as the writer's dolfinx pads them.
    """

    points: np.ndarray
    cells: np.ndarray
    cell_type: str
    times: list[float] = field(default_factory=list)
    fields: dict[str, list[np.ndarray]] = field(default_factory=dict)
    centers: dict[str, str] = field(default_factory=dict)
    tensor_padding: str = "rows"

    def at(self, name: str, step: int = -1) -> np.ndarray:
        """The values of field ``name`` at step ``step`` (an index into :attr:`times`; -1: the last): (n,) for a
        scalar, (n, gdim) for a vector, (n, gdim, gdim) for a tensor (a 2D mesh's without XDMF's padding to 3
        and 9 components)."""
        if name not in self.fields:
            raise ValueError(f"no field {name!r} in the series; it has {sorted(self.fields)}")
        values = self.fields[name][step]
        gdim = self.points.shape[1]
        if values.ndim == 2 and values.shape[1] == 9:
            if self.tensor_padding == "end":
                return values[:, :gdim * gdim].reshape(-1, gdim, gdim)
            return values.reshape(-1, 3, 3)[:, :gdim, :gdim]
        return values[:, :gdim] if values.ndim == 2 and values.shape[1] == 3 else values


def _dataset(item: ET.Element, folder: Path) -> np.ndarray:
    import h5py

    name, path = item.text.strip().split(":")
    with h5py.File(folder / name, "r") as f:
        return np.asarray(f[path][...])


def read_xdmf(path: str | os.PathLike) -> XDMFSeries:
    """Read the XDMF time series ``path`` (``<name>.xdmf``, as :class:`~fenics_contact.output.XDMFWriter` wrote
    it: the steps complete when it was last written; a killed run's too). Needs h5py. Not collective: call it on
    one rank (``if MPI.COMM_WORLD.rank == 0``) or in another process.

    Args:
        path: the index file.

    Returns:
        The :class:`XDMFSeries`.
    """
    path = Path(path)
    root = ET.parse(path).getroot()
    grids = root.findall("Domain/Grid")
    mesh = next(g for g in grids if g.get("GridType") == "Uniform")
    topology, geometry = mesh.find("Topology"), mesh.find("Geometry")
    series = XDMFSeries(points=_dataset(geometry.find("DataItem"), path.parent),
                        cells=_dataset(topology.find("DataItem"), path.parent).astype(np.int64),
                        cell_type=topology.get("TopologyType"))
    padding = root.find("Domain/Information[@Name='tensor_padding']")
    if padding is not None:
        series.tensor_padding = padding.get("Value")
    times: list[float] = []
    for collection in (g for g in grids if g.get("GridType") == "Collection"):
        for grid in collection.findall("Grid"):
            t = float(grid.find("Time").get("Value"))
            if t not in times:
                times.append(t)
            for attribute in grid.findall("Attribute"):
                name = attribute.get("Name")
                series.fields.setdefault(name, []).append(_dataset(attribute.find("DataItem"), path.parent))
                series.centers[name] = attribute.get("Center")
    series.times = times
    return series
