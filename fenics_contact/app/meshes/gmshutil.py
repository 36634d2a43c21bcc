"""gmsh plumbing shared by the mesh builders: the .geo sources (``app/geo``), build on rank 0, distribute."""
from __future__ import annotations

import hashlib
import inspect
import math
import os
import tempfile
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from mpi4py import MPI

from ...compat import model_to_mesh
from ...domain import NamedTags, physical_names

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
    """The gmsh geometry source ``<name>.geo`` of a scene: in ``$FENICS_CONTACT_MESHES`` if set, else the
    package's own (``fenics_contact/app/geo``, package data). ``FileNotFoundError`` naming the path if it is
    missing."""
    folder = Path(os.environ.get("FENICS_CONTACT_MESHES") or resources.files("fenics_contact.app") / "geo")
    path = folder / f"{name}.geo"
    if not path.is_file():
        raise FileNotFoundError(f"gmsh geometry {str(path)!r} not found: the mesh builders read the .geo sources "
                                "of fenics_contact/app/geo (or of $FENICS_CONTACT_MESHES)")
    return path


def _load_geo(path: Path, **parameters: float) -> None:
    """Merge the gmsh geometry ``path`` into the current model, its ``DefineConstant`` parameters (ONELAB names
    ``Parameters/<name>``) set to ``parameters``; synchronise the built-in kernel."""
    gmsh.onelab.clear()  # the values of an earlier .geo of this session must not leak into this one
    for name, value in parameters.items():
        gmsh.onelab.setNumber(f"Parameters/{name}", [float(value)])
    gmsh.merge(str(path))
    gmsh.model.geo.synchronize()


# Folder of the meshes built in a child process (``isolate``), kept across runs when set (the scaling run sets it:
# its serial and 2-rank runs then mesh once); unset: a temporary file, removed after reading.
CACHE_VARIABLE = "FC_MESH_CACHE"


def _from_gmsh(comm: MPI.Comm, build, what: str, gdim: int = 2, isolate: bool = False,
               key: str = "") -> tuple[Mesh, NamedTags, NamedTags]:
    """Run ``build()`` (adds and meshes a ``gdim``-dimensional gmsh model with named physical groups) on rank 0;
    distribute the mesh and its tags. Returns ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).

    Initialises and finalises gmsh on every rank; a gmsh failure raises ``RuntimeError`` on every rank.
    ``isolate``: mesh in a forked child of rank 0 that writes a binary .msh (physical names included), which
    rank 0 then reads: the mesher's peak memory (Delaunay structures, ~5 times the finished mesh: 1.2 GB at 1e6
    dofs) stays out of this process, whose peak memory the scaling run measures. With ``$FC_MESH_CACHE`` set,
    the .msh is kept there under a name hashing ``key`` (the builder's parameters and geometry source) and the
    builder module's source, and reused.
    """
    path, error = None, ""
    if isolate and comm.rank == 0:
        try:
            path = _mesh_in_child(build, what, key)
        except RuntimeError as exc:
            error = str(exc)
    error = comm.bcast(error, root=0)
    if error:
        raise RuntimeError(error)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        error, names = "", {}
        if comm.rank == 0:
            try:
                if path is not None:
                    gmsh.open(str(path))
                else:
                    build()
                names = physical_names(gmsh)
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh {what}: {exc}"
            finally:
                if path is not None and not os.environ.get(CACHE_VARIABLE):
                    path.unlink(missing_ok=True)
        error = comm.bcast(error, root=0)
        if error:
            raise RuntimeError(error)
        names = comm.bcast(names, root=0)
        mesh, cell_tags, facet_tags = model_to_mesh(gmsh.model, comm, 0, gdim)
    finally:
        gmsh.finalize()
    tdim = mesh.topology.dim
    return mesh, NamedTags(cell_tags, names.get(tdim, {})), NamedTags(facet_tags, names.get(tdim - 1, {}))


def _mesh_in_child(build, what: str, key: str) -> Path:
    """Path of a binary .msh of ``build()``'s model, meshed by a forked child (this rank only; no MPI in the
    child), or found in ``$FC_MESH_CACHE``. ``RuntimeError`` if the child fails."""
    folder = os.environ.get(CACHE_VARIABLE)
    if folder:
        source = inspect.getsource(inspect.getmodule(build))
        digest = hashlib.sha256(f"{what}|{key}|{source}".encode()).hexdigest()[:16]
        path = Path(folder) / f"{digest}.msh"
        if path.exists():
            return path
        path.parent.mkdir(parents=True, exist_ok=True)
    else:
        fd, name = tempfile.mkstemp(suffix=".msh")
        os.close(fd)
        path = Path(name)
    partial = path.with_name(f"{path.stem}.{os.getpid()}.part.msh")
    failure = path.with_suffix(".err")
    pid = os.fork()
    if pid == 0:  # the child: gmsh only, then _exit (no MPI, no atexit handlers of the parent)
        code = 1
        try:
            gmsh.initialize()
            gmsh.option.setNumber("General.Terminal", 0)
            build()
            gmsh.option.setNumber("Mesh.Binary", 1)  # exact coordinates
            gmsh.write(str(partial))
            gmsh.finalize()
            os.replace(partial, path)
            code = 0
        except BaseException as exc:  # noqa: BLE001 (gmsh raises bare Exception; anything must reach _exit)
            failure.write_text(str(exc))
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    if os.waitstatus_to_exitcode(status) != 0:
        message = failure.read_text() if failure.exists() else f"the mesher exited with status {status}"
        failure.unlink(missing_ok=True)
        partial.unlink(missing_ok=True)
        path.unlink(missing_ok=True)
        raise RuntimeError(f"gmsh failed to mesh {what}: {message}")
    return path
