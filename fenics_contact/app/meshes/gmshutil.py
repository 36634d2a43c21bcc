"""gmsh plumbing shared by the mesh builders: the .geo sources (``app/geo``), build on rank 0, distribute."""
from __future__ import annotations

import hashlib
import inspect
import math
import os
import signal
import sys
import tempfile
from importlib import resources
from pathlib import Path
from typing import TYPE_CHECKING

from mpi4py import MPI

from ...domain import NamedTags, distribute, physical_names
from ...gmshmodel import prepare
from ..memory import available_memory

if TYPE_CHECKING:
    from dolfinx.mesh import Mesh

__all__: list[str] = []  # plumbing of the mesh builders: nothing public


class _Lazy:
    """gmsh, imported on first use (inside a mesh builder): importing the package does not load gmsh."""

    def __getattr__(self, name: str):
        import gmsh as module

        return getattr(module, name)


gmsh = _Lazy()


class MeshingError(RuntimeError):
    """gmsh failed to mesh a scene's geometry (raised on every rank)."""


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


# Significant digits of a .geo parameter. A length over the scale is the same ratio in any units only to round-off
# (R / 400 over R with R = 0.05: 0.0025000000000000005), and gmsh's mesh is not continuous in its sizes (a graded
# size field's last layer: 12 more dofs); rounded, the mesh is the same in any units.
_DIGITS = 12


def _rounded(value: float) -> float:
    """``value`` rounded to :data:`_DIGITS` significant digits (0, infinities and NaN as they are)."""
    value = float(value)
    return float(f"{value:.{_DIGITS}g}") if math.isfinite(value) else value


def _load_geo(path: Path, **parameters: float) -> None:
    """Merge the gmsh geometry ``path`` into the current model, its ``DefineConstant`` parameters (ONELAB names
    ``Parameters/<name>``) set to ``parameters`` (dimensionless: lengths over the model's scale, counts, flags),
    each rounded to :data:`_DIGITS` significant digits; synchronise the built-in kernel."""
    gmsh.onelab.clear()  # the values of an earlier .geo of this session must not leak into this one
    for name, value in parameters.items():
        gmsh.onelab.setNumber(f"Parameters/{name}", [_rounded(value)])
    gmsh.merge(str(path))
    gmsh.model.geo.synchronize()


# Folder of the meshes built in a child process (``isolate``), kept across runs when set (the scaling run sets it:
# its serial and 2-rank runs then mesh once); unset: a temporary file, removed after reading.
CACHE_VARIABLE = "FC_MESH_CACHE"


def _from_gmsh(comm: MPI.Comm, build, what: str, gdim: int = 2, isolate: bool = True,
               key: str = "", scale: float = 1.0, balance: tuple[str, ...] = ()) -> tuple[Mesh, NamedTags, NamedTags]:
    """Run ``build()`` (adds and meshes a ``gdim``-dimensional gmsh model with named physical groups) on rank 0;
    distribute the mesh and its tags. Returns ``(mesh, cells, facets)`` (:class:`~fenics_contact.domain.NamedTags`).
    ``scale``: the model is built with its lengths over ``scale`` and its coordinates are multiplied by it (gmsh's
    tolerances are absolute: the same mesh, to round-off, in any units). ``balance``: the facet regions (by name)
    whose cells are split evenly over the ranks too (the contact surfaces; :func:`~fenics_contact.domain.distribute`).

    Initialises and finalises gmsh on every rank; a gmsh failure raises :class:`MeshingError` on every rank,
    gmsh running out of memory ``MemoryError``. ``isolate`` (default): mesh in a forked child of rank 0 that writes a
    binary .msh (physical names included; the mesh read back is the same, bit for bit), which rank 0 then
    reads: the mesher's peak memory (Delaunay structures, ~5 times the finished mesh: 1.2 GB at 1e6 dofs) stays
    out of this process, whose peak memory the scaling run measures, and a mesher that runs out of memory
    (``std::bad_alloc`` in a parallel region of gmsh aborts its process) is a ``MemoryError`` here instead of the
    end of the run. With ``$FC_MESH_CACHE`` set and a ``key`` given, the .msh is kept there under a name
    hashing ``key`` (the builder's parameters and geometry source) and the builder module's source, and reused.
    """
    path, error = None, ("", "")
    if isolate and comm.rank == 0:
        try:
            path = _mesh_in_child(build, what, key)
        except (RuntimeError, MemoryError) as exc:
            error = (type(exc).__name__, str(exc))
    kind, error = comm.bcast(error, root=0)
    if error:
        raise (MemoryError if kind == "MemoryError" else MeshingError)(error)
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.option.setNumber("General.NoPopup", 1)  # gmsh's questions (a very large mesh?) answered, never asked
        error, names = "", {}
        if comm.rank == 0:
            try:
                if path is not None:
                    gmsh.open(str(path))
                else:
                    build()
                names = physical_names(gmsh)
                prepare(gmsh, what, check=False)  # node tags 1..n, as dolfinx reads them
            except Exception as exc:  # noqa: BLE001 (gmsh raises bare Exception)
                error = f"gmsh failed to mesh {what}: {exc}"
            finally:
                if path is not None and not _cached(key):
                    path.unlink(missing_ok=True)
        error = comm.bcast(error, root=0)
        if error:
            raise MeshingError(error)
        names = comm.bcast(names, root=0)
        mesh, cell_tags, facet_tags = distribute(gmsh.model, comm, gdim, names, balance)
    finally:
        gmsh.finalize()
    mesh.geometry.x[:] *= scale
    tdim = mesh.topology.dim
    return mesh, NamedTags(cell_tags, names.get(tdim, {})), NamedTags(facet_tags, names.get(tdim - 1, {}))


def _cached(key: str) -> bool:
    """Whether the .msh of a build with ``key`` is kept in ``$FC_MESH_CACHE`` (only a build that has a key: the
    hash must tell its parameters apart)."""
    return bool(key and os.environ.get(CACHE_VARIABLE))


def _mesh_in_child(build, what: str, key: str) -> Path:
    """Path of a binary .msh of ``build()``'s model, meshed by a forked child (this rank only; no MPI in the
    child), or found in ``$FC_MESH_CACHE``. ``MemoryError`` if the child ran out of memory (its standard error,
    kept in a file, says ``bad_alloc`` or ``MemoryError``), :class:`MeshingError` if it failed otherwise."""
    folder = os.environ.get(CACHE_VARIABLE) if _cached(key) else None
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
    stderr = path.with_suffix(".stderr")
    pid = os.fork()
    if pid == 0:  # the child: gmsh only, then _exit (no MPI, no atexit handlers of the parent)
        code = 1
        try:
            # its standard error (a C++ abort's message and the MPI library's backtrace) to a file the parent reads
            fd = os.open(stderr, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o600)
            os.dup2(fd, 2)
            os.close(fd)
            gmsh.initialize()
            gmsh.option.setNumber("General.Terminal", 0)
            gmsh.option.setNumber("General.NoPopup", 1)
            build()
            gmsh.option.setNumber("Mesh.Binary", 1)  # exact coordinates
            gmsh.write(str(partial))
            gmsh.finalize()
            os.replace(partial, path)
            code = 0
        except BaseException as exc:  # noqa: BLE001 (gmsh raises bare Exception; anything must reach _exit)
            failure.write_text(f"MemoryError: {exc}" if isinstance(exc, MemoryError) else str(exc))
        finally:
            os._exit(code)
    _, status = os.waitpid(pid, 0)
    code = os.waitstatus_to_exitcode(status)
    said = stderr.read_text(errors="replace") if stderr.exists() else ""
    stderr.unlink(missing_ok=True)
    if code != 0:
        text = failure.read_text().strip() if failure.exists() else None
        if text:
            message = text
        elif text is not None or code < 0:  # likely out of memory where a memory cap is in force
            # gmsh 4.13's API raises Exception('') where an allocation failed; a crash (a signal) under a cap is most
            # likely an allocation that failed unchecked
            message = ("gmsh raised an error without a message" if text is not None else
                       f"the mesher was killed by signal {-code} ({signal.Signals(-code).name})")
            nbytes, phrase = available_memory()
            if "ulimit" in phrase or "control group" in phrase:
                message += f", likely out of memory ({phrase})"
        else:
            message = f"the mesher exited with status {code}"
        failure.unlink(missing_ok=True)
        partial.unlink(missing_ok=True)
        path.unlink(missing_ok=True)
        if "bad_alloc" in said or message.startswith(("MemoryError", "std::bad_alloc")):
            raise MemoryError(f"gmsh ran out of memory meshing {what} (std::bad_alloc in the mesher process)")
        raise MeshingError(f"gmsh failed to mesh {what}: {message}")
    if said.strip():  # what gmsh or the child printed, shown as it was before (the child's stderr was ours)
        sys.stderr.write(said)
    return path
