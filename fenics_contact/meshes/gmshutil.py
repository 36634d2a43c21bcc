"""gmsh plumbing shared by the mesh builders: the .geo sources of ``meshes/``, build on rank 0, distribute."""
from __future__ import annotations

import math
import os
from pathlib import Path
from typing import TYPE_CHECKING

from mpi4py import MPI

from ..compat import model_to_mesh
from ..domain import NamedTags, physical_names

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

__all__: list[str] = []  # plumbing of the mesh builders: nothing public


class _Lazy:
    """gmsh, imported on first use (inside a mesh builder): importing the package does not load gmsh."""

    def __getattr__(self, name: str):
        import gmsh as module

        return getattr(module, name)


gmsh = _Lazy()


def _positive(**values: float) -> None:
    """Raise a ValueError naming the first of ``values`` that is not a finite number > 0."""
    for name, v in values.items():
        if not (math.isfinite(v) and v > 0):
            raise ValueError(f"{name} must be a finite number > 0, got {v!r}")


def _graded(h_contact: float, h_far: float) -> None:
    """Raise a ValueError unless the far mesh size is at least the contact one."""
    if h_far < h_contact:
        raise ValueError(f"h_far={h_far} must be >= h_contact={h_contact}")


# Slope of the mesh size with distance in the graded zone (size / length; the .geo sources' ``grading``).
_GRADING = 0.25


def geo_path(name: str) -> Path:
    """The gmsh geometry source ``<name>.geo`` of a scene: in ``$FENICS_CONTACT_MESHES`` if set, else in the
    top-level ``meshes/`` folder of the checkout next to the package. ``FileNotFoundError`` naming the path
    if it is missing (an installed wheel has no ``meshes/``: run from a checkout, or set the variable)."""
    folder = Path(os.environ.get("FENICS_CONTACT_MESHES") or Path(__file__).resolve().parents[2] / "meshes")
    path = folder / f"{name}.geo"
    if not path.is_file():
        raise FileNotFoundError(f"gmsh geometry {str(path)!r} not found: the mesh builders read the .geo sources "
                                "of the top-level meshes/ folder of a fenics_contact checkout (or of "
                                "$FENICS_CONTACT_MESHES)")
    return path


def _load_geo(path: Path, **parameters: float) -> None:
    """Merge the gmsh geometry ``path`` into the current model, its ``DefineConstant`` parameters (ONELAB names
    ``Parameters/<name>``) set to ``parameters``; synchronise the built-in kernel."""
    gmsh.onelab.clear()  # the values of an earlier .geo of this session must not leak into this one
    for name, value in parameters.items():
        gmsh.onelab.setNumber(f"Parameters/{name}", [float(value)])
    gmsh.merge(str(path))
    gmsh.model.geo.synchronize()


def _from_gmsh(comm: MPI.Comm, build, what: str, gdim: int = 2) -> tuple[Mesh, NamedTags, NamedTags]:
    """Run ``build()`` (adds and meshes a ``gdim``-dimensional gmsh model with named physical groups) on rank 0;
    distribute the mesh and its tags. Returns ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).

    Initialises and finalises gmsh on every rank; a gmsh failure raises ``RuntimeError`` on every rank.
    """
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error, names = "", {}
        if comm.rank == 0:
            try:
                build()
                names = physical_names(gmsh)
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh {what}: {exc}"
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        names = comm.bcast(names, root=0)
        mesh, cell_tags, facet_tags = model_to_mesh(gmsh.model, comm, 0, gdim)
    finally:
        gmsh.finalize()
    tdim = mesh.topology.dim
    return mesh, NamedTags(cell_tags, names.get(tdim, {})), NamedTags(facet_tags, names.get(tdim - 1, {}))
