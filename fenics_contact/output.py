"""Output a killed run leaves readable: the fields of every converged step (XDMF), the summary (JSON), a lock.

Nothing is referred to before it is complete. Each step's fields go to a file of their own; the index
``<name>.xdmf`` that lists them, and ``summary.json``, are written under a temporary name and renamed over the old
file (``os.replace``). A process killed at any point (SIGKILL too) leaves every step it completed readable and the
last complete summary; a write that fails (a full disk) leaves the previous file whole.
"""
from __future__ import annotations

import json
import os
import socket
import time
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Callable, Sequence
from xml.sax.saxutils import quoteattr

from dolfinx import fem, io
from mpi4py import MPI

from . import compat

__all__ = ["OutputError", "XDMFWriter", "write_summary", "write_atomically", "on_rank0", "RunLock", "process_alive",
           "hdf5_incomplete"]

# every step's grids take their topology and geometry from the index's first grid, the mesh
_MESH = "xpointer(/Xdmf/Domain/Grid[@GridType='Uniform'][1]/*[self::Topology or self::Geometry])"
_HEAD = '<?xml version="1.0"?>\n<!DOCTYPE Xdmf SYSTEM "Xdmf.dtd" []>\n'


class OutputError(ValueError):
    """A file of a run could not be written (the previous version is kept), or an output folder is refused. A
    ``ValueError``, which the command line reports in one line."""


def write_atomically(path: str | os.PathLike, data: bytes | str) -> None:
    """``data`` into ``path`` through a temporary file in the same folder renamed over it: ``path`` holds the old
    content or the new, never a part. ``OSError`` if the write fails (the temporary file is removed)."""
    path = Path(path)
    view = memoryview(data.encode() if isinstance(data, str) else data)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_TRUNC, 0o666)
    try:
        while view:
            view = view[os.write(fd, view):]
        os.close(fd)
        fd = -1
        os.replace(tmp, path)
    except BaseException:
        if fd >= 0:
            os.close(fd)
        tmp.unlink(missing_ok=True)
        raise


def on_rank0(comm: MPI.Comm, what: str, action: Callable[[], object]):
    """``action()`` on rank 0, its result on every rank; an ``OSError`` there is an :class:`OutputError` (naming
    ``what``) on every rank. Collective."""
    result = error = None
    if comm.rank == 0:
        try:
            result = action()
        except OSError as exc:
            error = f"could not write {what}: {exc.strerror or exc} (the previous file is unchanged)"
        except OutputError as exc:
            error = str(exc)
    result, error = comm.bcast((result, error), root=0)
    if error is not None:
        raise OutputError(error)
    return result


def write_summary(path: str | os.PathLike, summary: dict, comm: MPI.Comm) -> None:
    """``summary`` (identical on every rank) as JSON, written by rank 0 through :func:`write_atomically`.
    :class:`OutputError` on every rank if it cannot be written. Collective.

    Args:
        path: the JSON file.
        summary: the figures (JSON-serializable, identical on every rank).
        comm: the communicator.
    """
    def write() -> None:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        write_atomically(path, json.dumps(summary, indent=1, default=float))

    on_rank0(comm, str(path), write)


# the families XDMF output takes (dolfinx writes their values at the vertices, or per cell for degree 0); others
# (a quadrature element, Nedelec) would crash it
_WRITABLE = {"lagrange", "p", "q", "discontinuous lagrange", "dg", "dq"}


def element_family(V) -> str:
    """The element family of the space ``V`` (of its blocks for a vector space), lower case."""
    element = V.ufl_element()
    family = getattr(element, "family_name", None)  # dolfinx >= 0.7 (basix.ufl)
    return str(family if family is not None else element.family()).lower()


def _written(f: fem.Function) -> fem.Function:
    """``f`` itself where XDMF takes it (degree 0, or the mesh's geometry degree), else a function of the mesh's
    degree (1 for straight cells: its vertex values, exact for a Lagrange field; 2 for 9-node quadrilaterals, which
    dolfinx >= 0.7 requires of nodal output) of its family and name that :meth:`XDMFWriter.write` interpolates ``f``
    into."""
    V = f.function_space
    degree, mesh_degree = compat.space_degree(V), int(V.mesh.geometry.cmap.degree)
    if degree == 0 or degree == mesh_degree:
        return f
    discontinuous = element_family(V) in ("discontinuous lagrange", "dg", "dq")
    family = "DG" if discontinuous else "Lagrange"
    return fem.Function(compat.function_space(V.mesh, family, mesh_degree, f.ufl_shape or None), name=f.name)


class XDMFWriter:
    """The given Lagrange functions (any degree: their vertex values; degree 0: cell values) at every
    :meth:`write` (time = load parameter) as an XDMF time series ``path``
    (``<name>.xdmf``): the mesh once into ``<name>.h5`` (where dolfinx reads it from), each step into a file of
    its own in the folder ``<name>_fields``, which the index ``path`` lists once complete. ``resume=n``: go on
    after step n of an earlier writer into ``path`` (its later steps are dropped). Collective.

    Args:
        path: the index file ``<name>.xdmf``.
        mesh: the mesh.
        functions: the Functions written at every step, each of a (discontinuous) Lagrange space of ``mesh``;
            another family is refused (``ValueError`` naming the function).
        resume: go on after step ``resume`` of an earlier writer (0: a new series).
    """

    def __init__(self, path: str | os.PathLike, mesh, functions: Sequence[fem.Function], resume: int = 0):
        for f in functions:
            family = element_family(f.function_space)
            if family not in _WRITABLE:
                raise ValueError(f"XDMFWriter: function {f.name!r} is of the {family!r} family; XDMF takes "
                                 f"Lagrange functions (interpolate it into one first)")
        self.path, self.comm, self.functions = Path(path), mesh.comm, list(functions)
        self._written = [_written(f) for f in self.functions]
        self.folder = self.path.with_name(self.path.stem + "_fields")
        self.steps = resume
        self._mesh, self._grids = "", []  # the index's mesh grid and each step's grids (rank 0)

        def prepare() -> bool:
            self.folder.mkdir(parents=True, exist_ok=True)
            for f in self.folder.glob("step_??????.*"):
                if f.name[5:11].isdigit() and int(f.name[5:11]) > resume:
                    f.unlink()
            return resume > 0 and self.path.exists() and self.path.with_suffix(".h5").exists()

        if not on_rank0(self.comm, str(self.folder), prepare):
            with io.XDMFFile(self.comm, str(self.path), "w") as f:  # <name>.h5, and <name>.xdmf until replaced
                f.write_mesh(mesh)
        on_rank0(self.comm, str(self.path), self._start)

    def _start(self) -> None:
        """Read the index (and, going on after step n, check steps 1 to n's files), then write it. Rank 0."""
        try:
            mesh = next(g for g in _xml(self.path).iterfind("Domain/Grid") if g.get("GridType") == "Uniform")
        except (ET.ParseError, StopIteration) as exc:
            raise OutputError(f"cannot go on with {self.path}: not an XDMF index of fields "
                              f"({str(exc) or 'no mesh in it'})") from None
        _check_data(mesh, self.path.parent, f"cannot go on with {self.path}: the mesh's")
        self._mesh = self._text(mesh, 2, "")
        for k in range(1, self.steps + 1):
            step = self._step_file(k)
            if not step.exists():
                raise OutputError(f"cannot go on with {self.path}: the fields of step {k} are missing")
            try:
                root = _xml(step)
            except ET.ParseError as exc:
                raise OutputError(f"cannot go on with {self.path}: {step} is not an XDMF file ({exc})") from None
            _check_data(root, self.folder, f"cannot go on with {self.path}: the fields of step {k}:")
            self._grids.append(self._step_grids(k))
        self._write_index()

    def write(self, t: float) -> None:
        """The functions at time ``t``: a complete file for the step, then the index that lists it. Collective."""
        step = self.steps + 1
        with io.XDMFFile(self.comm, str(self._step_file(step)), "w") as f:
            for u, w in zip(self.functions, self._written):
                if w is not u:
                    w.interpolate(u)
                f.write_function(w, t, mesh_xpath="/Xdmf/Domain")  # the index supplies the mesh

        def index() -> None:
            self._grids.append(self._step_grids(step))
            self._write_index()

        on_rank0(self.comm, str(self.path), index)
        self.steps = step

    def close(self) -> None:
        """Nothing is held open between steps."""

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    def _step_file(self, step: int) -> Path:
        return self.folder / f"step_{step:06d}.xdmf"

    def _step_grids(self, step: int) -> list[tuple[str, str]]:
        """(function name, grid text) of each function of step ``step``'s file."""
        out = []
        for collection in _xml(self._step_file(step)).iterfind("Domain/Grid"):
            for grid in collection.iterfind("Grid"):
                for include in [c for c in grid if c.tag.endswith("include")]:
                    grid.remove(include)
                text = self._text(grid, 3, f"{self.folder.name}/")
                close = text.index(">") + 1
                out.append((collection.get("Name"), f"{text[:close]}\n{' ' * 8}<xi:include xpointer="
                                                    f"{quoteattr(_MESH)} />{text[close:]}"))
        return out

    def _text(self, element: ET.Element, level: int, folder: str) -> str:
        """``element`` indented at ``level``, its HDF5 files' names preceded by ``folder``."""
        for item in element.iter("DataItem"):
            item.text = f"{folder}{item.text.strip()}"
        ET.indent(element, "  ", level)
        return "  " * level + ET.tostring(element, encoding="unicode").rstrip()

    def _write_index(self) -> None:
        names = list(dict.fromkeys(name for grids in self._grids for name, _ in grids))
        # how a 2D tensor's 4 values sit in XDMF's 9 (fenics_contact.reading reads them back by it)
        padding = f'    <Information Name="tensor_padding" Value="{compat.xdmf_tensor_padding()}" />\n'
        parts = [_HEAD, '<Xdmf Version="3.0" xmlns:xi="http://www.w3.org/2001/XInclude">\n  <Domain>\n',
                 padding, self._mesh, "\n"]
        for name in names:
            parts.append(f'    <Grid Name={quoteattr(name)} GridType="Collection" CollectionType="Temporal">\n')
            parts += [text + "\n" for grids in self._grids for n, text in grids if n == name]
            parts.append("    </Grid>\n")
        parts.append("  </Domain>\n</Xdmf>\n")
        write_atomically(self.path, "".join(parts))


def _xml(path: Path) -> ET.Element:
    return ET.parse(path).getroot()


_HDF5_SIGNATURE = b"\x89HDF\r\n\x1a\n"


def hdf5_incomplete(path: str | os.PathLike) -> str | None:
    """Why ``path`` is not a whole HDF5 file (missing, empty, no HDF5 signature, shorter than the end of file its
    superblock records: truncated), or None. Reads the superblock alone."""
    path = Path(path)
    try:
        size = path.stat().st_size
        with open(path, "rb") as f:
            head = f.read(4096)
    except FileNotFoundError:
        return "missing"
    except OSError as exc:
        return f"unreadable ({exc.strerror or exc})"
    if size == 0:
        return "empty"
    # the superblock starts at 0, 512, 1024, 2048, ... (HDF5 format specification, section II.A)
    at = next((k for k in (0, 512, 1024, 2048) if head[k:k + 8] == _HDF5_SIGNATURE), None)
    if at is None:
        return "not an HDF5 file"
    version = head[at + 8]
    # where the size of addresses and the base and end-of-file addresses are, by superblock version
    width, base = (head[at + 13], at + (24 if version == 0 else 28)) if version < 2 else (head[at + 9], at + 12)
    fields = head[base:base + 3 * width]
    if len(fields) < 3 * width or width not in (2, 4, 8):
        return "truncated"
    start, end = (int.from_bytes(fields[i * width:(i + 1) * width], "little") for i in (0, 2))
    if start + end > size:
        return f"truncated ({size} of its {start + end} bytes)"
    return None


def _check_data(element: ET.Element, folder: Path, what: str) -> None:
    """:class:`OutputError` (``what`` + the file and why) if an HDF5 file a ``DataItem`` of ``element`` names is
    not whole (:func:`hdf5_incomplete`)."""
    for name in dict.fromkeys((item.text or "").strip().split(":", 1)[0] for item in element.iter("DataItem")
                              if item.get("Format") == "HDF"):
        why = hdf5_incomplete(folder / name) if name else "not named"
        if why is not None:
            raise OutputError(f"{what} {folder / name} is {why}")


# --- the lock of an output folder -------------------------------------------------------------------------------

def _start_ticks(pid: int) -> int | None:
    """When process ``pid`` started (clock ticks since boot), or None where ``/proc`` does not say; a zombie is
    not running (-1)."""
    try:
        fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return None
    return -1 if fields[0] in "ZX" else int(fields[19])


def process_alive(pid: int, host: str, start: int | None = None) -> bool | None:
    """Whether the process ``pid`` of ``host`` (started at ``start`` ticks, if known: a reused pid is another
    process) still runs; None for another host (it cannot be told from here)."""
    if host != socket.gethostname():
        return None
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:
        pass
    ticks = _start_ticks(pid)
    return ticks != -1 and (start is None or ticks is None or ticks == start)


class RunLock:
    """``folder/.lock``: the pid, host and start of the process writing into ``folder`` (JSON). Rank 0's."""

    def __init__(self, folder: str | os.PathLike):
        self.path = Path(folder) / ".lock"
        self.mine = {"pid": os.getpid(), "host": socket.gethostname(), "start": _start_ticks(os.getpid()),
                     "since": time.strftime("%Y-%m-%d %H:%M:%S")}

    def holder(self) -> dict | None:
        """The lock's content; None if there is no lock. A lock that is not one (unreadable, or without a pid and
        host: not written by :meth:`acquire`, which writes it whole) is stale: ``{"stale": why}``."""
        try:
            text = self.path.read_text()
        except FileNotFoundError:
            return None
        except OSError as exc:
            return {"stale": f"unreadable: {exc.strerror or exc}"}
        try:
            held = json.loads(text)
        except ValueError:
            return {"stale": "not a lock's content"}
        if not (isinstance(held, dict) and isinstance(held.get("pid"), int) and isinstance(held.get("host"), str)):
            return {"stale": "not a lock's content"}
        return held

    def alive(self, holder: dict) -> bool | None:
        """Whether the holder runs (:func:`process_alive`); False for a stale lock."""
        if "stale" in holder:
            return False
        return process_alive(holder["pid"], holder["host"], holder.get("start"))

    def acquire(self, replace: bool = False) -> bool:
        """Take the lock: False if another process holds it (``replace``: a dead holder's lock is replaced)."""
        tmp = self.path.with_name(f".lock.{os.getpid()}.tmp")
        write_atomically(tmp, json.dumps(self.mine))
        try:
            if replace:
                os.replace(tmp, self.path)
                return True
            os.link(tmp, self.path)  # fails if the lock exists: one of two runs starting together wins
            return True
        except FileExistsError:
            return False
        finally:
            tmp.unlink(missing_ok=True)

    def release(self) -> None:
        """Remove the lock if this process holds it."""
        held = self.holder()
        if held and held.get("pid") == self.mine["pid"] and held.get("host") == self.mine["host"]:
            self.path.unlink(missing_ok=True)
